"""Command-line options: --help everywhere, check's report, bad --form / --at / --times /
--method / --t-end / --rtol, and --times giving exactly the times asked for."""

import json

import pytest

from nonideal.cli import main
from nonideal.equations.formalisms import FORMS
from tests.helpers import DATA_DIR

DATA = DATA_DIR
PENDULUM = DATA / "pendulum_xy.toml"


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("command", [[], ["check"], ["derive"], ["evaluate"], ["simulate"],
                                     ["examples"]])
def test_every_command_has_help(capsys, command):
    code, out, err = cli(capsys, *command, "--help")
    assert code == 0 and err == ""
    assert out.startswith("usage: nonideal")
    if not command:
        assert "Exit codes: 0 success, 2 bad input, 3 mechanics" in out
        for sub in ("check", "derive", "evaluate", "simulate", "examples"):
            assert sub in out
    else:
        assert f"nonideal {command[0]}" in out


def test_check_prints_degrees_of_freedom_and_determinacy(capsys):
    code, out, err = cli(capsys, "check", PENDULUM)
    assert code == 0 and err == ""
    assert "  coordinates (2): x, y" in out
    assert "  degrees of freedom: configuration 1, velocities 1" in out
    assert "  determinacy: all constraints ideal: the motion is determinate" in out
    assert "  note: completed from the constraints: y'" in out
    code, out, _ = cli(capsys, "check", PENDULUM, "--json")
    report = json.loads(out)
    assert report["counts"]["dof"] == 1 and report["counts"]["configuration_dof"] == 1
    assert report["determinacy"].startswith("all constraints ideal")
    assert report["initial_state"]["y'"] == 0.0


def test_unknown_form_with_suggestion(capsys):
    for command in ("derive", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, PENDULUM, "--form", "lagrnge1")
        assert code == 2 and out == ""
        assert (f"argument --form: unknown form 'lagrnge1' (did you mean 'lagrange1'?); choose "
                f"one of {', '.join(FORMS)}") in err


def test_unknown_form_python_api():
    from nonideal.errors import FormNotApplicable
    from nonideal.analysis.derivation import derive
    from nonideal.modeling.modelfile import load_model

    with pytest.raises(FormNotApplicable) as info:
        derive(load_model(PENDULUM), "mggi")
    assert str(info.value) == ("--form: unknown form 'mggi' (did you mean 'maggi'?); choose one "
                               "of " + ", ".join(FORMS))
    assert info.value.exit_code == 2


def test_unknown_method_with_suggestion(capsys):
    code, _, err = cli(capsys, "simulate", PENDULUM, "--method", "rk45")
    assert code == 2
    assert "argument --method: unknown integrator 'rk45' (did you mean 'RK45'?)" in err


@pytest.mark.parametrize("at, messages", [
    ("x=0.6 y=-0.8", ["--at: 'x=0.6 y=-0.8' has more than one '='; separate the pairs with commas"]),
    ("x=0.6, z=1", ["--at: 'z' is not a coordinate or velocity; allowed: x, y, x', y'"]),
    ("x=0.6, yy=1", ["--at: 'yy' is not a coordinate or velocity (did you mean 'y'?)"]),
    ("x=0.6, x'=foo", ["--at x': unknown symbol 'foo'"]),
    ("x", ["--at: 'x' is not of the form name=value"]),
    ("x=1, x=2", ["--at: 'x' is given twice"]),
    ("x=(1, z=2, y=3*", ["--at x: malformed expression at column 1: '(' is never closed",
                         "--at: 'z' is not a coordinate or velocity",
                         "--at y: malformed expression at column 3: unexpected end"]),
    ("", ["--at: empty state"]),
])
def test_bad_at_syntax_every_problem(capsys, at, messages):
    code, out, err = cli(capsys, "evaluate", PENDULUM, "--at", at)
    assert code == 2 and out == ""
    assert err.startswith("error: ")
    for message in messages:
        assert message in err, err
    problems = [line for line in err.split("\n") if line.startswith(("error: --at", "--at"))]
    assert len(problems) == len(messages)


def test_at_accepts_expressions_in_the_parameters(capsys):
    code, out, err = cli(capsys, "evaluate", PENDULUM, "--at", "x=l*0.6, y=-0.8*l, x'=0", "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["q"] == {"x": 0.6, "y": -0.8}


def test_at_moving_a_coordinate_completes_the_dependent_ones(capsys):
    # x moved: y is completed from the rod, one initial velocity is kept, the other completed
    import math

    code, out, err = cli(capsys, "evaluate", PENDULUM, "--at", "x=0.3", "--json")
    assert code == 0, err
    r = json.loads(out)
    assert r["q"]["y"] == pytest.approx(-math.sqrt(1 - 0.09), rel=1e-12)
    assert r["q"]["x"] * r["qdot"]["x"] + r["q"]["y"] * r["qdot"]["y"] == pytest.approx(0, abs=1e-12)


def test_at_inconsistent_names_at_not_initial(capsys):
    code, out, err = cli(capsys, "evaluate", PENDULUM, "--at", "x=0.3, y=0.1")
    assert code == 2
    assert "--at (other values from [initial]): constraint 'rod' is violated" in err


@pytest.mark.parametrize("times, message", [
    ("0,a,1", "--times: 'a' is not a finite number; write comma-separated numbers, e.g. --times 0,0.5,1"),
    ("0,nan", "--times: 'nan' is not a finite number"),
    ("1,0.5", "--times: the times must increase strictly, but 0.5 follows 1"),
    ("0,0.5,0.5", "--times: the times must increase strictly, but 0.5 follows 0.5"),
    ("", "--times: no times given"),
    (" , ", "--times: no times given"),
    ("-1,0.5", "--times: -1 is before the initial time t0 = 0"),
])
def test_bad_times(capsys, tmp_path, times, message):
    code, out, err = cli(capsys, "simulate", PENDULUM, f"--times={times}",
                         "--json", tmp_path / "out.json")
    assert code == 2 and out == ""
    assert message in err
    assert not (tmp_path / "out.json").exists()


def test_times_after_t_end(capsys):
    code, _, err = cli(capsys, "simulate", PENDULUM, "--times", "0,2", "--t-end", "1")
    assert code == 2
    assert "--times: the last time 2 is after --t-end 1" in err


@pytest.mark.parametrize("argv, message", [
    (["--t-end", "0"], "--t-end: must be later than t0 = 0 (got 0)"),
    (["--t-end", "-1"], "--t-end: must be later than t0 = 0 (got -1)"),
    (["--rtol", "0"], "--rtol: must be a number in [2.3e-14, 1)"),
    (["--atol", "2"], "--atol: must be a number in (0, 1)"),
    (["--t-end", "abc"], "argument --t-end: invalid float value: 'abc'"),
])
def test_bad_numbers(capsys, argv, message):
    code, _, err = cli(capsys, "simulate", PENDULUM, *argv)
    assert code == 2 and message in err


def test_times_are_exactly_the_times_asked_for(capsys):
    code, out, err = cli(capsys, "simulate", PENDULUM, "--times", "0,0.5,1", "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["t"] == [0.0, 0.5, 1.0]
    for name in ("x", "y"):
        assert len(result["q"][name]) == 3 and len(result["qdot"][name]) == 3
    assert len(result["multipliers"]["rod"]) == 3
    assert result["q"]["x"][0] == 0.6 and result["q"]["y"][0] == -0.8


def test_times_not_starting_at_t0(capsys):
    code, out, _ = cli(capsys, "simulate", PENDULUM, "--times", "0.25,0.75", "--json")
    assert code == 0
    assert json.loads(out)["t"] == [0.25, 0.75]


def test_unknown_example_with_suggestion(capsys):
    from nonideal import gallery

    name = gallery.names()[0]
    code, _, err = cli(capsys, "examples", "show", name[:-1])
    assert code == 2
    assert f"examples: no example '{name[:-1]}' (did you mean '{name}'?)" in err


def test_independent_must_be_coordinates(capsys):
    code, _, err = cli(capsys, "derive", PENDULUM, "--form", "maggi", "--independent", "theta")
    assert code == 2
    assert "--independent: 'theta' is not a coordinate; coordinates: x, y" in err
