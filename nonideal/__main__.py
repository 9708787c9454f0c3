"""``python -m nonideal`` is the ``nonideal`` command.

Ctrl-C and SIGTERM end it quietly (exit 130 / 143) even while the package is being imported;
during a command :mod:`nonideal.cli.terminal` takes over (and removes temporary files)."""

import signal
import sys


def _early_stop(signum, frame):  # pragma: no cover - exercised through a subprocess
    raise SystemExit(128 + signum)


if __name__ == "__main__":     # not on import (the documentation imports every module)
    signal.signal(signal.SIGTERM, _early_stop)
    try:
        from .cli import main
    except KeyboardInterrupt:  # pragma: no cover
        sys.stderr.write("nonideal: interrupted; nothing was written\n")
        sys.exit(130)

    sys.exit(main())
