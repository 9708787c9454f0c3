"""What the tests share: the folder of test models (:data:`DATA_DIR`) and running the command
line -- ``python -m nonideal`` with the package under test first on the path (never another
``nonideal`` installed or on the PATH)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import nonideal

#: the model files made for the tests
DATA_DIR = Path(__file__).parent / "data"

#: the folder holding the package under test
PACKAGE_ROOT = str(Path(nonideal.__file__).resolve().parent.parent)


def cli_command() -> list[str]:
    """The command that starts the CLI of the package under test."""
    return [sys.executable, "-m", "nonideal"]


def cli_env() -> dict[str, str]:
    """The environment of a CLI run: the package under test first on ``PYTHONPATH``."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([PACKAGE_ROOT] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    return env


def run_cli(*argv, cwd=None, timeout=300) -> subprocess.CompletedProcess:
    """Run ``nonideal *argv`` and return the finished process (output captured as text)."""
    return subprocess.run([*cli_command(), *map(str, argv)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env=cli_env())


def cli_json(*argv, cwd=None):
    """Run ``nonideal *argv``, require exit code 0, and parse its standard output as JSON."""
    out = run_cli(*argv, cwd=cwd)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)
