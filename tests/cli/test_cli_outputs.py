"""Outputs of the command line: nothing is written unless the run succeeded (also when it
fails late, in the integration), everything is written when it succeeds, --json without OUT
prints to standard output, and the JSON keys of the SPEC are there.  A few end-to-end checks
run the installed ``nonideal`` executable in a subprocess."""

import json
from pathlib import Path

import pytest

from nonideal.cli import main
from tests.helpers import run_cli
from tests.helpers import DATA_DIR

DATA = DATA_DIR
PENDULUM = DATA / "pendulum_xy.toml"
OUTPUTS = ("out.json", "out.csv", "out.png")

SIMULATE_KEYS = {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
                 "diagnostics"}
ENERGY_KEYS = {"kinetic", "potential", "friction_work", "reaction_work"}
EVALUATE_KEYS = {"model", "form", "t", "q", "qdot", "qddot", "multipliers", "reactions",
                 "contacts"}


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def outputs_argv(directory: Path):
    return ["--json", directory / "out.json", "--csv", directory / "out.csv",
            "--plot", directory / "out.png"]


def created(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


@pytest.mark.parametrize("model, argv, message", [
    ("blowup.toml", [], "integration failed at t = 0.29744774"),          # fails late
    ("singular_mass.toml", [], "singular mass matrix"),                   # fails at t0
    ("missing_parameters.toml", [], "missing parameters: b, c, g, k"),   # fails on loading
    ("pendulum_xy.toml", ["--times", "1,0"], "--times: the times must increase"),  # bad option
    ("pendulum_xy.toml", ["--method", "Euler"], "unknown integrator 'Euler'"),     # usage error
])
def test_failed_run_writes_nothing(capsys, tmp_path, model, argv, message):
    code, out, err = cli(capsys, "simulate", DATA / model, *outputs_argv(tmp_path), *argv)
    assert code == 2 and out == ""
    assert message in err
    assert created(tmp_path) == []


def test_failed_run_keeps_existing_outputs(capsys, tmp_path):
    for name in OUTPUTS:
        (tmp_path / name).write_text("previous result")
    code, _, _ = cli(capsys, "simulate", DATA / "blowup.toml", *outputs_argv(tmp_path))
    assert code == 2
    assert created(tmp_path) == sorted(OUTPUTS)
    assert all((tmp_path / n).read_text() == "previous result" for n in OUTPUTS)


def test_failure_writing_one_output_writes_none(capsys, tmp_path):
    blocker = tmp_path / "not_a_directory"
    blocker.write_text("")
    code, out, err = cli(capsys, "simulate", PENDULUM, "--json", tmp_path / "out.json",
                         "--csv", tmp_path / "out.csv", "--plot", blocker / "out.png")
    assert code == 2 and out == ""
    assert f"--plot {blocker / 'out.png'}: cannot write" in err
    assert created(tmp_path) == ["not_a_directory"]


@pytest.mark.parametrize("argv, message", [
    (["--json", "{model}"], "--json {model}: this is the model file itself; choose another output path"),
    (["--json", "{d}/a.json", "--csv", "{d}/a.json"], "--csv {d}/a.json: the same path as --json"),
    (["--plot", "{d}/plot.xyz"], "--plot {d}/plot.xyz: matplotlib cannot write '.xyz' files"),
    (["--csv", "{d}"], "--csv {d}: is a directory; give a file name"),
])
def test_output_paths_checked_before_running(capsys, tmp_path, argv, message):
    model = tmp_path / "model.toml"
    model.write_text(PENDULUM.read_text())
    argv = [a.format(d=tmp_path, model=model) for a in argv]
    code, out, err = cli(capsys, "simulate", model, *argv)
    assert code == 2 and out == ""
    assert message.format(d=tmp_path, model=model) in err
    assert created(tmp_path) == ["model.toml"]
    assert model.read_text() == PENDULUM.read_text()


def test_successful_run_writes_every_output(capsys, tmp_path):
    code, out, err = cli(capsys, "simulate", PENDULUM, *outputs_argv(tmp_path), "--times", "0,0.5,1")
    assert (code, out, err) == (0, "", "")
    assert created(tmp_path) == sorted(OUTPUTS)
    result = json.loads((tmp_path / "out.json").read_text())
    assert SIMULATE_KEYS <= set(result)
    assert ENERGY_KEYS <= set(result["energy"])
    assert "constraint_residual_max" in result["diagnostics"]
    assert result["diagnostics"]["constraint_residual_max"] < 1e-9
    assert result["model"] == "pendulum in x, y"
    assert result["t"] == [0.0, 0.5, 1.0]
    assert set(result["q"]) == set(result["qdot"]) == {"x", "y"}
    assert set(result["multipliers"]) == {"rod"}
    assert result["contacts"] == {} and result["events"] == []
    csv = (tmp_path / "out.csv").read_text().splitlines()
    assert len(csv) == 1 + 3 and csv[0].startswith("t,")
    assert (tmp_path / "out.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_json_without_out_prints_to_stdout(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = cli(capsys, "simulate", PENDULUM, "--json", "--times", "0,1")
    assert code == 0 and err == ""
    assert json.loads(out)["t"] == [0.0, 1.0]
    assert created(tmp_path) == []
    code, out, err = cli(capsys, "simulate", PENDULUM, "--times", "0,1", "--json", "result.json")
    assert code == 0 and out == "" and err == ""
    assert json.loads((tmp_path / "result.json").read_text())["t"] == [0.0, 1.0]


def test_evaluate_json_keys(capsys, tmp_path):
    code, out, err = cli(capsys, "evaluate", PENDULUM, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert EVALUATE_KEYS <= set(result)
    assert result["form"] == "lagrange1" and result["t"] == 0.0
    assert set(result["qddot"]) == {"x", "y"}
    reaction = result["reactions"]["rod"]
    assert {"generalized", "constraint_part", "friction_part"} <= set(reaction)
    # pendulum at rest: the rod holds the weight, lambda * grad f = (0, m g) along the rod
    assert result["qddot"]["x"] == pytest.approx(-0.6 * 0.8 * 9.81, rel=1e-9)
    assert reaction["friction_part"] == pytest.approx([0.0, 0.0], abs=1e-12)
    code, out, err = cli(capsys, "evaluate", PENDULUM, "--json", tmp_path / "ev.json")
    assert (code, out) == (0, "")
    assert EVALUATE_KEYS <= set(json.loads((tmp_path / "ev.json").read_text()))


def test_check_and_derive_json_out(capsys, tmp_path):
    assert cli(capsys, "check", PENDULUM, "--json", tmp_path / "check.json")[0] == 0
    assert json.loads((tmp_path / "check.json").read_text())["ok"] is True
    assert cli(capsys, "derive", PENDULUM, "--json", tmp_path / "eom.json")[0] == 0
    assert (tmp_path / "eom.json").stat().st_size > 0
    assert cli(capsys, "check", DATA / "singular_mass.toml", "--json", tmp_path / "bad.json")[0] == 2
    assert not (tmp_path / "bad.json").exists()


# ----------------------------------------------------------------------------- end to end


def run(*argv, cwd):
    return run_cli(*argv, cwd=cwd, timeout=120)


def test_end_to_end_failure_late_in_the_run(tmp_path):
    proc = run("simulate", DATA / "blowup.toml", "--json", "out.json", "--csv", "out.csv",
               "--plot", "out.png", cwd=tmp_path)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.startswith(f"error: {DATA / 'blowup.toml'}: integration failed at t = 0.29744774")
    assert "Traceback" not in proc.stderr
    assert created(tmp_path) == []


def test_end_to_end_success(tmp_path):
    proc = run("simulate", PENDULUM, "--times", "0,0.5,1", "--json", "out.json", "--csv",
               "out.csv", "--plot", "out.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert created(tmp_path) == sorted(OUTPUTS)
    assert json.loads((tmp_path / "out.json").read_text())["t"] == [0.0, 0.5, 1.0]


def test_end_to_end_malicious_file_has_no_side_effects(tmp_path):
    model = tmp_path / "malicious.toml"
    model.write_text((DATA / "malicious.toml").read_text())
    for command in ("check", "simulate"):
        proc = run(command, model, cwd=tmp_path)
        assert proc.returncode == 2, command
        assert "malformed expression" in proc.stderr and "Traceback" not in proc.stderr
        assert created(tmp_path) == ["malicious.toml"], command


def test_end_to_end_usage_error_and_mechanics_exit_codes(tmp_path):
    proc = run("simulate", PENDULUM, "--form", "lagrnge1", cwd=tmp_path)
    assert proc.returncode == 2
    assert "unknown form 'lagrnge1' (did you mean 'lagrange1'?)" in proc.stderr
    proc = run("check", DATA / "typo_thetta.toml", cwd=tmp_path)
    assert proc.returncode == 2
    assert proc.stderr == (f"error: {DATA / 'typo_thetta.toml'}: constraint 'knife_edge': expr: "
                           "unknown symbol 'thetta' (did you mean 'theta'?)\n")


def test_contact_keys_in_simulate_and_evaluate_json(capsys):
    path = DATA / "painleve_rod_sliding.toml"
    code, out, err = cli(capsys, "simulate", path, "--times", "0,0.05,0.1", "--json")
    assert code == 0, err
    result = json.loads(out)
    floor = result["contacts"]["floor"]
    assert {"normal", "friction", "slip", "mode"} <= set(floor)
    assert len(floor["normal"]) == len(floor["mode"]) == 3
    assert floor["mode"][0].startswith("slide")
    event = result["events"][0]
    assert {"t", "type", "contact"} <= set(event) and event["contact"] == "floor"
    code, out, err = cli(capsys, "evaluate", path, "--json")
    assert code == 0, err
    contact = json.loads(out)["contacts"]["floor"]
    assert {"mode", "normal", "friction", "slip"} <= set(contact)
    assert contact["normal"] > 0


def test_outputs_get_the_usual_file_mode(capsys, tmp_path):
    # staged through a 0600 temporary file, the outputs must still honour the umask
    import os
    import stat

    mask = os.umask(0o022)
    try:
        code, _, _ = cli(capsys, "simulate", PENDULUM, "--t-end", "0.1", *outputs_argv(tmp_path))
    finally:
        os.umask(mask)
    assert code == 0
    for name in OUTPUTS:
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o644, name


def test_csv_holds_the_contact_forces(capsys, tmp_path):
    # the sphere's contact has two slip components: N, F_1, F_2, U_1, U_2, gap and mode columns
    import csv as csvlib

    code, _, err = cli(capsys, "simulate", "sphere-sliding-on-plane", "--times", "0,0.1,0.5",
                       "--csv", tmp_path / "s.csv", "--json", tmp_path / "s.json")
    assert code == 0, err
    rows = list(csvlib.DictReader((tmp_path / "s.csv").open()))
    data = json.loads((tmp_path / "s.json").read_text())["contacts"]["plane"]
    assert len(rows) == 3
    for k, row in enumerate(rows):
        assert float(row["N_plane"]) == data["normal"][k]
        assert [float(row["F_plane_1"]), float(row["F_plane_2"])] == data["friction"][k]
        assert [float(row["U_plane_1"]), float(row["U_plane_2"])] == data["slip"][k]
        assert row["mode_plane"] == data["mode"][k]


def test_csv_without_times_is_the_output_grid_with_the_events(capsys, tmp_path):
    # a parabolic slide takes a handful of integrator steps; by default the table, as the JSON,
    # has 1001 rows at uniform times (the dense output of the run) and two rows at each event,
    # the states before and after its switch; --every-step gives the steps
    import numpy as np

    from nonideal import gallery

    path = gallery.model_path("block-on-incline")
    code, _, err = cli(capsys, "simulate", path, "--csv", tmp_path / "out.csv", "--json", tmp_path / "out.json")
    assert code == 0, err
    rows = (tmp_path / "out.csv").read_text().splitlines()
    assert rows[0].startswith("t,")
    t = np.array([float(r.split(",")[0]) for r in rows[1:]])
    data = json.loads((tmp_path / "out.json").read_text())
    events = [e["t"] for e in data["events"]]
    assert np.array_equal(t, data["t"])
    assert len(t) == 1001 + 2 * len(events) and np.all(np.diff(t) >= 0)
    uniform = np.array([s for s in t if not any(s == e for e in events)])
    assert np.allclose(np.diff(uniform), t[-1] / 1000, rtol=1e-9)
    assert all((t == e).sum() == 2 for e in events) and events
    code, _, err = cli(capsys, "simulate", path, "--every-step", "--json", tmp_path / "steps.json")
    steps = json.loads((tmp_path / "steps.json").read_text())["t"]
    assert code == 0 and len(steps) < 100 and steps[-1] == pytest.approx(t[-1], rel=1e-14)

