"""``python -m nonideal`` is the ``nonideal`` command."""

import sys

from .cli import main

sys.exit(main())
