"""``nonideal sweep``: the JSON and CSV of SPEC's contract, failing points, the journal and
--resume (after a real interruption), and the errors a user can act on."""

import csv
import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

from tests.helpers import cli_command, cli_env, run_cli

BLOCK = "block-on-incline"


def test_json_rows_hold_parameters_exit_codes_and_summaries(tmp_path):
    out = tmp_path / "s.json"
    r = run_cli("sweep", BLOCK, "--vary", "alpha=0.3,0.5", "--vary", "mu_s=0.3:0.5:2",
                "--what", "simulate", "--workers", "1", "--json", out)
    assert r.returncode == 0, r.stderr
    data = json.loads(out.read_text())
    assert set(data) == {"model", "what", "vary", "rows"}
    assert data["what"] == "simulate" and data["vary"] == {"alpha": [0.3, 0.5], "mu_s": [0.3, 0.5]}
    assert [row["parameters"] for row in data["rows"]] == [
        {"alpha": a, "mu_s": m} for a in (0.3, 0.5) for m in (0.3, 0.5)]
    for row in data["rows"]:
        assert row["exit_code"] == 0 and row["message"] == "ok"
        s = row["summary"]
        assert {"t_end", "q", "qdot", "events", "friction_heat"} <= set(s)
        assert set(s["q"]) == {"x", "y"} and s["events"][0]["type"] in ("stick", "reverse")
        assert s["friction_heat"] > 0
    assert not (tmp_path / "s.json.journal").exists()
    assert "4 points" in r.stdout and "0 failed" in r.stdout


def test_csv_flattens_the_summary_and_records_failures(tmp_path):
    out = tmp_path / "s.csv"
    r = run_cli("sweep", BLOCK, "--vary", "m=-1,2", "--what", "evaluate", "--workers", "1",
                "--csv", out)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert list(rows[0])[:3] == ["m", "exit_code", "message"]
    assert {"qddot.x", "qddot.y", "contacts.plane.mode", "contacts.plane.normal"} <= set(rows[0])
    assert rows[0]["exit_code"] == "2" and rows[0]["qddot.x"] == ""
    assert rows[1]["exit_code"] == "0" and float(rows[1]["qddot.x"]) < 0
    assert "exit 2 at 1 point" in r.stdout


def test_bad_options_exit_2_naming_them(tmp_path):
    r = run_cli("sweep", BLOCK, "--vary", "mus=0.1,0.2", "--what", "simulate", "--json",
                tmp_path / "s.json")
    assert r.returncode == 2 and "--vary mus" in r.stderr and "mu_s" in r.stderr
    r = run_cli("sweep", BLOCK, "--vary", "mu=0:1", "--what", "simulate", "--json",
                tmp_path / "s.json")
    assert r.returncode == 2 and "START:STOP:N" in r.stderr
    r = run_cli("sweep", BLOCK, "--vary", "mu=0:1:3", "--what", "evaluate", "--t-end", "1",
                "--json", tmp_path / "s.json")
    assert r.returncode == 2 and "--t-end" in r.stderr
    r = run_cli("sweep", BLOCK, "--vary", "mu=0:1:3", "--what", "simulate", "--about", "steady",
                "--json", tmp_path / "s.json")
    assert r.returncode == 2 and "--about: an option of --what stability" in r.stderr
    r = run_cli("sweep", BLOCK, "--vary", "mu=0:1:3", "--what", "evaluate", "--json", "-",
                cwd=tmp_path)
    assert r.returncode == 2 and "give a file name" in r.stderr and not list(tmp_path.iterdir())
    assert not (tmp_path / "s.json").exists() and not (tmp_path / "s.json.journal").exists()


def test_a_journal_left_behind_needs_resume(tmp_path):
    out = tmp_path / "s.json"
    journal = tmp_path / "s.json.journal"
    journal.write_text('{"sweep": {"model": "x"}}\n')
    r = run_cli("sweep", BLOCK, "--vary", "mu=0.1,0.2", "--what", "evaluate", "--json", out)
    assert r.returncode == 2 and "--resume" in r.stderr
    r = run_cli("sweep", BLOCK, "--vary", "mu=0.1,0.2", "--what", "evaluate", "--json", out,
                "--resume")
    assert r.returncode == 2 and "another sweep" in r.stderr
    assert not out.exists()


@pytest.mark.slow
def test_an_interrupted_sweep_resumes_from_its_journal(tmp_path):
    """Kill a sweep after some points, resume it: the journaled rows are reused, the output is
    the one of an uninterrupted sweep."""
    out = tmp_path / "s.json"
    journal = tmp_path / "s.json.journal"
    args = ["sweep", BLOCK, "--vary", "alpha=0.2:0.6:30", "--what", "simulate", "--workers", "1",
            "--json", str(out)]
    proc = subprocess.Popen([*cli_command(), *args], env=cli_env(), stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 120
        while time.time() < deadline:
            if journal.exists() and len(journal.read_text().splitlines()) >= 4:
                break
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait()
    assert not out.exists()
    lines = journal.read_text().splitlines()
    assert 4 <= len(lines) < 31
    kept = len(lines) - 1
    r = run_cli(*args, "--resume")
    assert r.returncode == 0, r.stderr
    assert f"{30 - kept} run" in r.stdout
    resumed = json.loads(out.read_text())
    whole = tmp_path / "whole.json"
    assert run_cli(*args[:-1], whole).returncode == 0
    assert resumed["rows"] == json.loads(whole.read_text())["rows"]
    assert not journal.exists()


def test_stability_sweep_finds_maievski_bound(tmp_path):
    """The sleeping top's steady spin is stable in the first approximation (critical: purely
    imaginary eigenvalues) above Maievski's w_c = 2 sqrt(A_O m g l)/C = 11.44 rad/s."""
    out = tmp_path / "top.json"
    r = run_cli("sweep", "sleeping-top", "--vary", "w=10,13", "--what", "stability", "--about",
                "steady", "--workers", "1", "--json", out)
    assert r.returncode == 0, r.stderr
    rows = json.loads(out.read_text())["rows"]
    assert [row["summary"]["verdict"] for row in rows] == ["unstable", "critical"]
    A_O, mgl, C = 0.03, 0.981, 0.03
    for row in rows:
        w = row["parameters"]["w"]
        roots = np.roots([A_O ** 2, C ** 2 * w ** 2 - 2 * A_O * mgl, mgl ** 2]).astype(complex)
        ref = np.concatenate([np.sqrt(roots), -np.sqrt(roots)])
        eig = [complex(re, im) for re, im in row["summary"]["eigenvalues"]]
        assert max(min(abs(z - r) for r in ref) for z in eig if abs(z) > 1e-9) < 1e-8


def test_a_mistyped_quantity_is_refused_before_the_sweep_runs(tmp_path):
    """--quantity is checked on the first point: the other points never run, no journal is
    left to block the next run, and the corrected command then succeeds."""
    out, png = tmp_path / "s.json", tmp_path / "m.png"
    args = ["sweep", BLOCK, "--vary", "alpha=0.2:0.6:12", "--what", "simulate", "--workers", "1",
            "--json", out, "--plot", png]
    r = run_cli(*args, "--quantity", "events.cuont", "--no-progress")
    assert r.returncode == 2
    assert "--quantity events.cuont: not a column" in r.stderr and "events.count" in r.stderr
    assert not list(tmp_path.iterdir())
    r = run_cli(*args, "--quantity", "events.count", "--no-progress")
    assert r.returncode == 0, r.stderr
    assert "12 points (12 run, 0 failed)" in r.stdout and png.exists()


@pytest.mark.slow
def test_an_interrupted_sweep_names_resume(tmp_path):
    """Ctrl-C in the middle of a sweep: the finished points stay journaled and the message says
    to run the same command with --resume (not "nothing was written")."""
    out = tmp_path / "s.json"
    journal = tmp_path / "s.json.journal"
    args = ["sweep", BLOCK, "--vary", "alpha=0.2:0.6:40", "--what", "simulate", "--workers", "1",
            "--json", str(out), "--no-progress"]
    proc = subprocess.Popen([*cli_command(), *args], env=cli_env(), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.time() + 120
        while time.time() < deadline:
            if journal.exists() and len(journal.read_text().splitlines()) >= 3:
                break
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert "--resume" in err and str(journal) in err and "nothing was written" not in err
    assert journal.exists() and not out.exists()


@pytest.mark.parametrize("vary", [["mu_s=0:1:10000000"], ["mu_s=0:1:10000000000"],
                                  ["mu_s=0:1:5000", "alpha=0.1:0.5:5000"]])
def test_a_grid_beyond_the_limit_is_refused_at_once_without_a_journal(tmp_path, vary):
    """10^7 points ended in a MemoryError traceback after 42 s (10^9: at once), with a journal
    left behind; the grid's size is known from its axes before any value is made."""
    from nonideal.analysis.studies.sweep import MAX_POINTS

    out = tmp_path / "s.json"
    args = [a for v in vary for a in ("--vary", v)]
    start = time.perf_counter()
    r = run_cli("sweep", BLOCK, *args, "--what", "evaluate", "--json", out)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert f"{MAX_POINTS:,}" in r.stderr and "the limit" in r.stderr
    assert time.perf_counter() - start < 60
    assert list(tmp_path.iterdir()) == []


def test_resume_with_a_journal_row_without_parameters_names_the_row(tmp_path):
    from nonideal.cli.sweep import _read_journal
    from nonideal.errors import ModelError

    header = {"model": "m.toml", "what": "simulate"}
    journal = tmp_path / "s.json.journal"
    journal.write_text(json.dumps({"sweep": header}) + "\n"
                       + json.dumps({"parameters": {"mu": 0.1}, "exit_code": 0}) + "\n"
                       + json.dumps({"exit_code": 0}) + "\n")
    with pytest.raises(ModelError, match=r"s.json.journal, line 3: a row without its 'parameters'"):
        _read_journal(journal, header)
