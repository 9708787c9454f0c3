"""Command-line robustness (red-team findings): outputs through symbolic links and into files
that are not regular files (a FIFO, /dev/null, a descriptor of the process) without replacing
them, write errors reported as bad input, times and tolerances that must be finite and in
range, malformed lists in options, extra arguments.

Safety: the only device node used is /dev/null (and it is restored if a regression replaced
it); nothing here writes to /dev/full or any other device."""

import errno
import io
import json
import os
import socket
import stat
import threading
from pathlib import Path

import pytest

from tests.helpers import run_cli
from nonideal.cli import check as cli_check
from nonideal.cli import outputs as cli_outputs
from nonideal.cli import main
from tests.helpers import DATA_DIR

DATA = DATA_DIR
PENDULUM = DATA / "pendulum_xy.toml"
BLOCK = DATA / "friction" / "spring_rough_floor.toml"
SHORT = ("--t-end", "0.1")
# a block on a rough floor held by a spring: it sticks after one swing, and asked to run to
# t = 1e300 the integration fails near t = 2.4e15 -- with NumPy overflow warnings on the way
STUCK_BLOCK = """
[model]
name = "block on a rough floor with a spring"
[parameters]
m = 1.0
k = 10.0
g = 9.81
mu = 0.3
[coordinates]
q = ["x", "y"]
[energy]
kinetic = "m/2*(x'^2 + y'^2)"
potential = "k/2*x^2 + m*g*y"
[[contacts]]
name = "floor"
gap = "y"
slip = ["x'"]
mu = "mu"
[initial]
x = 0.4
y = 0
"x'" = 0
"y'" = 0
"""


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def entries(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


# ------------------------------------------------------------------ outputs: links and nodes


def test_output_through_a_symlink_writes_the_target_and_keeps_the_link(tmp_path):
    (tmp_path / "target.json").write_text("previous result")
    (tmp_path / "links").mkdir()
    link = tmp_path / "links" / "link.json"
    link.symlink_to("../target.json")
    out = run_cli("simulate", PENDULUM, *SHORT, "--json", "links/link.json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert link.is_symlink() and os.readlink(link) == "../target.json"
    assert "diagnostics" in json.loads((tmp_path / "target.json").read_text())
    assert entries(tmp_path / "links") == ["link.json"]      # no temporary file left


def test_output_through_a_dangling_symlink_creates_its_target(tmp_path):
    link = tmp_path / "out.csv"
    link.symlink_to("results/run.csv")
    out = run_cli("simulate", PENDULUM, *SHORT, "--csv", "out.csv", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert link.is_symlink()
    assert (tmp_path / "results" / "run.csv").read_text().startswith("t,")


def test_failed_run_leaves_a_symlinks_target_alone(tmp_path):
    (tmp_path / "target.json").write_text("previous result")
    (tmp_path / "link.json").symlink_to("target.json")
    out = run_cli("simulate", DATA / "blowup.toml", "--json", "link.json", cwd=tmp_path)
    assert out.returncode == 2
    assert (tmp_path / "link.json").is_symlink()
    assert (tmp_path / "target.json").read_text() == "previous result"


def test_symlink_loop_is_bad_input(tmp_path):
    (tmp_path / "a.json").symlink_to("b.json")
    (tmp_path / "b.json").symlink_to("a.json")
    out = run_cli("simulate", PENDULUM, *SHORT, "--json", "a.json", cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == ""
    assert "--json a.json: cannot write: Too many levels of symbolic links" in out.stderr
    assert "Traceback" not in out.stderr
    assert (tmp_path / "a.json").is_symlink() and (tmp_path / "b.json").is_symlink()


def test_output_into_a_fifo_keeps_the_fifo(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    received = []

    def reader():
        with open(fifo, "rb") as f:
            received.append(f.read())

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    try:
        out = run_cli("simulate", PENDULUM, *SHORT, "--csv", fifo, timeout=120)
    finally:
        if thread.is_alive():       # the CLI never opened the FIFO: unblock the reader
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        thread.join(10)
    assert out.returncode == 0, out.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert received and received[0].startswith(b"t,")
    assert entries(tmp_path) == ["pipe.csv"]


def _restore_dev_null():
    """A regression must not leave the machine without /dev/null."""
    if not stat.S_ISCHR(os.lstat("/dev/null").st_mode) and os.geteuid() == 0:
        os.unlink("/dev/null")
        os.mknod("/dev/null", stat.S_IFCHR | 0o666, os.makedev(1, 3))
        os.chmod("/dev/null", 0o666)


def test_output_into_dev_null_keeps_the_device():
    assert stat.S_ISCHR(os.lstat("/dev/null").st_mode)
    try:
        out = run_cli("simulate", PENDULUM, *SHORT, "--json", "/dev/null")
    finally:
        restored = not stat.S_ISCHR(os.lstat("/dev/null").st_mode)
        _restore_dev_null()
    assert not restored, "/dev/null was replaced by a regular file"
    assert out.returncode == 0, out.stderr
    assert (out.stdout, out.stderr) == ("", "")


def test_output_into_a_descriptor_of_the_process():
    # /dev/fd/1 is standard output, here a pipe: the JSON arrives through it
    out = run_cli("simulate", PENDULUM, *SHORT, "--json", "/dev/fd/1")
    assert out.returncode == 0, out.stderr
    assert "diagnostics" in json.loads(out.stdout)


def test_unwritable_special_file_is_bad_input_and_writes_nothing_else(tmp_path):
    # a socket cannot be opened for writing: the error comes when the outputs are committed,
    # after the run, and the regular output must not have been written either
    path = tmp_path / "s"
    server = socket.socket(socket.AF_UNIX)
    try:
        server.bind(str(path))
        out = run_cli("simulate", PENDULUM, *SHORT, "--json", tmp_path / "out.json",
                      "--csv", path)
    finally:
        server.close()
    assert out.returncode == 2 and out.stdout == ""
    assert f"--csv {path}: cannot write: No such device or address" in out.stderr
    assert stat.S_ISSOCK(os.lstat(path).st_mode)
    assert entries(tmp_path) == ["s"]


def test_write_error_names_the_path(capsys, tmp_path, monkeypatch):
    # what /dev/full does (ENOSPC), simulated: the device itself is never used in the tests
    def full(data, target):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(cli_outputs, "write_into", full)
    code, out, err = run(capsys, "simulate", PENDULUM, *SHORT, "--json", "/dev/null",
                         "--csv", tmp_path / "out.csv")
    assert code == 2 and out == ""
    assert "--json /dev/null: cannot write: No space left on device" in err
    assert entries(tmp_path) == []


def test_parent_that_is_a_file_is_named(tmp_path):
    (tmp_path / "h.py").write_text("# a file, not a directory\n")
    out = run_cli("simulate", PENDULUM, *SHORT, "--json", "h.py/a.json", cwd=tmp_path)
    assert out.returncode == 2 and out.stdout == ""
    assert "--json h.py/a.json: cannot write: h.py is not a directory" in out.stderr
    assert entries(tmp_path) == ["h.py"]


def test_missing_directories_are_still_created(capsys, tmp_path):
    code, _, err = run(capsys, "simulate", PENDULUM, *SHORT, "--json", tmp_path / "new" / "sub" / "a.json")
    assert code == 0, err
    assert json.loads((tmp_path / "new" / "sub" / "a.json").read_text())["t"][0] == 0


# ------------------------------------------------------------------ numbers


@pytest.mark.parametrize("argv, message", [
    (["simulate", PENDULUM, "--t-end", "inf"], "--t-end: must be a finite number"),
    (["simulate", PENDULUM, "--t-end", "nan"], "--t-end: must be a finite number"),
    (["simulate", PENDULUM, "--t-end", "1e400"], "--t-end: must be a finite number"),
    (["evaluate", PENDULUM, "--t", "nan"], "--t: must be a finite number"),
    (["evaluate", PENDULUM, "--t=-inf"], "--t: must be a finite number"),
    (["realizability", BLOCK, "--t", "inf"], "--t: must be a finite number"),
    (["simulate", PENDULUM, "--rtol", "1e-300"], "--rtol: must be a number in [2.3e-14, 1)"),
    (["simulate", PENDULUM, "--rtol", "nan"], "--rtol: must be a number in [2.3e-14, 1)"),
    (["simulate", PENDULUM, "--atol", "nan"], "--atol: must be a number in (0, 1)"),
])
def test_times_and_tolerances_must_be_finite_and_in_range(capsys, tmp_path, argv, message):
    code, out, err = run(capsys, *argv, "--json", tmp_path / "out.json")
    assert code == 2 and out == ""
    assert message in err
    assert "Warning" not in err
    assert entries(tmp_path) == []


def test_every_bad_number_is_reported_at_once(capsys):
    code, _, err = run(capsys, "simulate", PENDULUM, "--t-end", "nan", "--rtol", "1e-20",
                       "--atol", "0")
    assert code == 2
    assert "--t-end: must be a finite number" in err
    assert "--rtol: must be a number in [2.3e-14, 1)" in err
    assert "--atol: must be a number in (0, 1)" in err


def test_smallest_rtol_runs_without_a_warning():
    out = run_cli("simulate", PENDULUM, *SHORT, "--rtol", "2.3e-14")
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""


def test_huge_end_time_fails_without_numpy_warnings(tmp_path):
    # finite but far beyond what the integration reaches: the error explains, no
    # RuntimeWarning with a source path on the way
    model = tmp_path / "block.toml"
    model.write_text(STUCK_BLOCK)
    out = run_cli("simulate", model, "--times", "0,1e300", "--json", tmp_path / "out.json")
    assert out.returncode == 2
    assert "integration failed" in out.stderr
    assert "RuntimeWarning" not in out.stderr and ".py:" not in out.stderr
    assert entries(tmp_path) == ["block.toml"]


def test_numerical_warnings_of_a_successful_command_are_one_clean_line(capsys, monkeypatch):
    import numpy as np

    def noisy(args):
        np.float64(1e308) * np.float64(10)
        np.float64(1e308) * np.float64(10)
        return 0

    monkeypatch.setattr(cli_check, "run", noisy)
    code, out, err = run(capsys, "check", PENDULUM)
    assert code == 0
    assert err == "warning: overflow encountered in scalar multiply\n"


# ------------------------------------------------------------------ lists and arguments


@pytest.mark.parametrize("times, message", [
    ("0,,0.5", "--times: item 2 of 3 is empty (got '0,,0.5')"),
    ("0,0.5,", "--times: item 3 of 3 is empty"),
    (",0.5", "--times: item 1 of 2 is empty"),
])
def test_empty_time_is_named(capsys, tmp_path, times, message):
    code, out, err = run(capsys, "simulate", PENDULUM, f"--times={times}",
                         "--json", tmp_path / "out.json")
    assert code == 2 and out == ""
    assert message in err
    assert entries(tmp_path) == []


@pytest.mark.parametrize("argv, messages", [
    (["derive", PENDULUM, "--form", "maggi", "--independent", "x,x"],
     ["--independent: 'x' is given 2 times; name each independent coordinate once"]),
    (["derive", PENDULUM, "--form", "maggi", "--independent", "x,,theta"],
     ["--independent: item 2 of 3 is empty", "--independent: 'theta' is not a coordinate"]),
    (["derive", PENDULUM, "--form", "maggi", "--independent", ""],
     ["--independent: no coordinates given"]),
    (["derive", PENDULUM, "--independent", "x"],
     ["--independent: the form lagrange1 keeps every coordinate",
      "drop --independent or use a reduced form: --form lagrange2, maggi, appell, shulgin"]),
    (["evaluate", PENDULUM, "--independent", "x"],
     ["--independent: the form lagrange1 keeps every coordinate"]),
    (["evaluate", PENDULUM, "--form", "gauss", "--independent", "x"],
     ["--independent: the form gauss keeps every coordinate"]),
])
def test_independent_coordinates_are_checked(capsys, argv, messages):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    for message in messages:
        assert message in err


def test_independent_coordinate_for_a_reduced_form_still_works(capsys):
    code, out, err = run(capsys, "derive", PENDULUM, "--form", "maggi", "--independent", "x")
    assert code == 0, err
    assert "independent velocities: x'" in out


def test_examples_list_takes_no_name(capsys):
    code, out, err = run(capsys, "examples", "list", "foo")
    assert code == 2 and out == ""
    assert "examples list takes no name (got 'foo')" in err


@pytest.mark.parametrize("argv, message", [
    (["--t-end", "1"], "--t-end: is the end of the motion followed by --along"),
    (["--along", "--t-end", "-1"], "--t-end: must be later than t0 = 0 (got -1)"),
    (["--along", "--t", "1"], "--along follows the motion from the model's initial state; drop --t"),
])
def test_realizability_options_that_do_not_go_together(capsys, argv, message):
    code, out, err = run(capsys, "realizability", BLOCK, *argv)
    assert code == 2 and out == ""
    assert message in err


class FullDevice:
    """A standard output on a full device (what ``> /dev/full`` gives), without a descriptor
    (so that nothing of the test process is redirected)."""

    def write(self, text):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def flush(self):
        pass

    def fileno(self):
        raise io.UnsupportedOperation("no descriptor")


def test_a_full_standard_output_is_one_line_and_exit_2(capsys, monkeypatch):
    monkeypatch.setattr("sys.stdout", FullDevice())
    code = main(["simulate", str(PENDULUM), *SHORT])
    err = capsys.readouterr().err
    assert code == 2
    assert err == "error: cannot write the output to the standard output: No space left on device\n"


def test_a_right_to_left_override_in_a_name_is_shown_escaped(tmp_path):
    text = PENDULUM.read_text()
    name = next(line for line in text.splitlines() if line.startswith("name ="))
    path = tmp_path / "bidi.toml"
    path.write_text(text.replace(name, 'name = "pendulum\u202e1lmth.exe"'))
    for args in (("check", path), ("simulate", path, *SHORT)):
        out = run_cli(*args)
        assert out.returncode == 0, out.stderr
        assert "\u202e" not in out.stdout + out.stderr
    assert "pendulum\\u202e1lmth.exe" in run_cli("check", path).stdout
