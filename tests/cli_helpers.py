"""Running the command line from the tests: the ``nonideal`` script of the interpreter that runs
the tests (so that a ``nonideal`` elsewhere on the PATH is never the one tested), or
``python -m nonideal`` when the package is not installed."""

import json
import subprocess
import sys
from pathlib import Path


def cli_command() -> list[str]:
    """The command that starts the CLI of the package under test."""
    script = Path(sys.executable).with_name("nonideal")
    return [str(script)] if script.exists() else [sys.executable, "-m", "nonideal"]


def run_cli(*argv, cwd=None, timeout=300) -> subprocess.CompletedProcess:
    """Run ``nonideal *argv`` and return the finished process (output captured as text)."""
    return subprocess.run([*cli_command(), *map(str, argv)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd)


def cli_json(*argv, cwd=None):
    """Run ``nonideal *argv``, require exit code 0, and parse its standard output as JSON."""
    out = run_cli(*argv, cwd=cwd)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)
