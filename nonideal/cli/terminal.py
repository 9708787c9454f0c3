"""What the command line writes to a terminal, and how it stops when asked to.

* :func:`printable`: text from a model file may hold escape sequences (ESC, BEL, an OSC title
  sequence) that a terminal would obey; every control character but newline and tab is shown
  escaped (``\\x1b``) in the messages.
* :func:`signals`: Ctrl-C (SIGINT) and SIGTERM end the run quietly with the conventional exit
  codes 130 and 143 -- no traceback -- after the ``finally`` clauses have run, so that the
  temporary files of the outputs (:mod:`nonideal.cli.outputs`) are removed and nothing is left
  half-written.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading

__all__ = ["printable", "signals", "Terminated", "EXIT_INTERRUPTED", "EXIT_TERMINATED"]

EXIT_INTERRUPTED = 130  # 128 + SIGINT
EXIT_TERMINATED = 143   # 128 + SIGTERM

_CONTROL = {c: f"\\x{c:02x}" for c in range(32) if chr(c) not in "\n\t"}
_CONTROL[127] = "\\x7f"
_CONTROL.update({c: f"\\x{c:02x}" for c in range(0x80, 0xA0)})  # C1 controls (CSI, OSC ...)


def printable(text: str) -> str:
    """*text* with its control characters (but newline and tab) escaped.

    Examples
    --------
    >>> printable("pl\\x1b[31mane\\x07")
    'pl\\\\x1b[31mane\\\\x07'
    """
    return str(text).translate(_CONTROL)


class Terminated(BaseException):
    """SIGTERM received (a BaseException, like KeyboardInterrupt: no ``except Exception``
    swallows it)."""


def _terminate(signum, frame):  # pragma: no cover - exercised through a subprocess
    raise Terminated


@contextlib.contextmanager
def signals():
    """Turn SIGTERM into :class:`Terminated` while the command runs (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def stopped(kind: str) -> int:
    """Say that the run was stopped, on standard error; the exit code."""
    with contextlib.suppress(Exception):
        print(f"nonideal: {kind}; nothing was written", file=sys.stderr)
    return EXIT_INTERRUPTED if kind == "interrupted" else EXIT_TERMINATED
