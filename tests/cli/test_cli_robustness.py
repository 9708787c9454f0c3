"""The command line under hostile use: escape sequences from a model file are shown escaped,
Ctrl-C and SIGTERM end a run quietly (exit 130 / 143, no traceback, no temporary file left),
a run that cannot finish is refused, and the real cause of a stalled run is named."""

import signal
import subprocess
import time

import pytest

from nonideal.cli.terminal import printable
from nonideal.gallery import model_path
from tests.helpers import DATA_DIR, cli_command, cli_env, run_cli


def test_escape_sequences_from_a_model_file_are_escaped(tmp_path):
    text = model_path("block-on-incline").read_text().replace(
        'name = "plane"', 'name = "pl\\u001b[31mane\\u0007\\u001b]0;title\\u0007"')
    path = tmp_path / "esc.toml"
    path.write_text(text)
    proc = run_cli("check", path)
    assert proc.returncode == 2
    assert "\x1b" not in proc.stderr and "\x07" not in proc.stderr
    assert "pl\\x1b[31mane\\x07" in proc.stderr


def test_printable_keeps_newlines_and_tabs():
    assert printable("a\tb\nc\x1b\x9b\x7f") == "a\tb\nc\\x1b\\x9b\\x7f"


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signals_end_the_run_quietly_and_leave_no_temporary(tmp_path, sig, code):
    out = tmp_path / "out.json"
    # the numba loop (the C loop takes these 4e5 s in a few seconds: over before the signal)
    proc = subprocess.Popen([*cli_command(), "simulate", str(DATA_DIR / "pendulum_long.toml"),
                             "--t-end", "4e5", "--json", str(out)], cwd=tmp_path,
                            env=dict(cli_env(), NONIDEAL_C_LOOP="0"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4)  # into the run (4e5 s of pendulum: ~7 s in numba's loop), or still importing
    # or compiling: quiet there too
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == code, stderr
    assert "Traceback" not in stderr
    assert not out.exists() and not list(tmp_path.glob(".nonideal-*"))


def test_a_run_that_cannot_finish_is_refused_quickly():
    start = time.perf_counter()
    proc = run_cli("simulate", DATA_DIR / "pendulum_long.toml")
    assert proc.returncode == 2 and "cannot finish" in proc.stderr
    assert time.perf_counter() - start < 60


def test_the_stall_of_a_vanishing_mass_is_explained():
    proc = run_cli("simulate", DATA_DIR / "vanishing_mass.toml")
    assert proc.returncode == 2
    assert "mass matrix becomes singular" in proc.stderr and "not smooth" not in proc.stderr


def test_at_overflow_is_a_message_not_a_traceback():
    proc = run_cli("evaluate", model_path("block-on-incline"), "--at", "x=exp(exp(exp(exp(10))))")
    assert proc.returncode == 2 and "--at x: the expression overflows" in proc.stderr
    assert "Traceback" not in proc.stderr
