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
import os
import signal
import sys
import threading

__all__ = ["printable", "EscapedOutput", "escaped_output", "output_failed", "signals", "Terminated", "EXIT_INTERRUPTED", "EXIT_TERMINATED"]

EXIT_INTERRUPTED = 130  # 128 + SIGINT
EXIT_TERMINATED = 143   # 128 + SIGTERM

_CONTROL = {c: f"\\x{c:02x}" for c in range(32) if chr(c) not in "\n\t"}
_CONTROL[127] = "\\x7f"
_CONTROL.update({c: f"\\x{c:02x}" for c in range(0x80, 0xA0)})  # C1 controls (CSI, OSC ...)
# the bidirectional formatting characters: a right-to-left override in a name would reorder
# the rest of the message on the screen (the "Trojan source" trick)
_CONTROL.update({c: f"\\u{c:04x}" for c in (0x061C, 0x200E, 0x200F, *range(0x202A, 0x202F),
                                                *range(0x2066, 0x206A))})


def printable(text: str) -> str:
    """*text* with its control characters (but newline and tab) escaped.

    Examples
    --------
    >>> printable("pl\\x1b[31mane\\x07")
    'pl\\\\x1b[31mane\\\\x07'
    >>> printable("block\\u202egnp.exe")
    'block\\\\u202egnp.exe'
    """
    return str(text).translate(_CONTROL)


class EscapedOutput:
    """The standard output with :func:`printable` applied to all that is written: a model's
    name or a constraint's, echoed in a report, cannot drive the terminal or reorder the line
    (JSON escapes them itself)."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text: str) -> int:
        return self._stream.write(printable(text))

    def __getattr__(self, name):
        return getattr(self._stream, name)


@contextlib.contextmanager
def escaped_output():
    """Route the standard output through :class:`EscapedOutput` while the command runs."""
    previous = sys.stdout
    sys.stdout = EscapedOutput(previous)
    try:
        yield
    finally:
        sys.stdout = previous


def output_failed(exc: OSError) -> int:
    """The standard output could not be written (``> /dev/full``: no space left on the device):
    one line on the standard error, exit code 2; what is still buffered is dropped, so that
    the interpreter's own flush at exit raises nothing more."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # pragma: no cover - stdout without a descriptor
        pass
    print(f"error: cannot write the output to the standard output: {exc.strerror or exc}",
          file=sys.stderr)
    return 2


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
