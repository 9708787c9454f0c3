"""Command line for contacts with friction: evaluate/simulate outputs, realizability,
friction law, equations with friction, the Gauss solver, Painleve's paradox (exit code 3)."""

import json

import numpy as np
import pytest

from nonideal import gallery
from nonideal.cli import main
from tests.helpers import DATA_DIR

DATA = DATA_DIR / "friction"
ROUGH = gallery.model_path("painleve-two-points-rough")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_evaluate_json_reports_mode_forces_and_split(capsys):
    code, out, _ = run(capsys, "evaluate", ROUGH, "--json")
    assert code == 0
    d = json.loads(out)
    line = d["contacts"]["line"]
    assert line["mode"] == "slide+"
    assert line["friction"][0] == pytest.approx(-0.3 * line["normal"], rel=1e-12)
    assert line["slip"] == [1.0]
    parts = d["reactions"]["line"]
    assert set(parts) >= {"generalized", "constraint_part", "friction_part"}


def test_evaluate_with_gauss_equals_lagrange1(capsys):
    a = json.loads(run(capsys, "evaluate", ROUGH, "--json")[1])
    b = json.loads(run(capsys, "evaluate", ROUGH, "--json",
                       "--form", "gauss")[1])
    for c in a["qddot"]:
        assert b["qddot"][c] == pytest.approx(a["qddot"][c], rel=1e-10, abs=1e-12)


def test_simulate_json_has_contacts_modes_and_events(capsys, tmp_path):
    png = tmp_path / "rod.png"
    code, out, _ = run(capsys, "simulate", DATA / "rod_two_ends.toml", "--json", "--plot", png)
    assert code == 0 and png.stat().st_size > 10_000
    d = json.loads(out)
    assert [e["type"] for e in d["events"]] == ["stick", "slip", "touch"]
    assert d["events"][0]["t"] == pytest.approx(0.222981158733, rel=1e-9)
    A = d["contacts"]["A"]
    assert {"normal", "friction", "slip", "mode"} <= set(A)
    assert A["mode"][0] == "slide-" and A["mode"][-1] == "stick"
    assert np.all(np.diff(d["energy"]["friction_work"]) <= 1e-10)  # never positive (round-off aside)
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8


def test_painleve_paradox_exits_3_with_critical_coefficient(capsys, tmp_path):
    out_json = tmp_path / "never.json"
    code, out, err = run(capsys, "simulate", DATA / "rod_paradox.toml", "--json", out_json)
    assert code == 3 and not out_json.exists()
    assert "Painleve paradox (inconsistency) at contact(s) floor" in err
    theta = 1.1
    mu_c = (1 + 3 * np.cos(theta) ** 2) / (3 * np.sin(theta) * np.cos(theta))
    assert f"critical friction coefficient: {mu_c:.6g}" in err


def test_realizability_at_a_state_and_along(capsys):
    code, out, _ = run(capsys, "realizability", DATA / "cylinder_on_incline.toml", "--json")
    assert code == 0
    c = json.loads(out)["contacts"]["incline"]
    F = 1.0 * 9.81 * np.sin(0.5) / 3           # rolling cylinder: F* = m g sin(a)/3
    N = 1.0 * 9.81 * np.cos(0.5)
    assert abs(c["friction_needed"][0]) == pytest.approx(F, rel=1e-12)
    assert c["friction_available"] == pytest.approx(0.25 * N, rel=1e-12)
    assert c["margin"] == pytest.approx(0.25 * N - F, rel=1e-12)
    assert c["realizable"] is True and c["condition"] == "|f*| < f0"
    code, out, _ = run(capsys, "realizability", DATA / "cylinder_on_incline.toml", "--along")
    assert code == 0 and "realizable up to t = 2" in out


def test_realizability_reports_when_rolling_is_not_realizable(capsys):
    # tan(a) > 3 mu: the cylinder cannot roll without slipping
    code, out, _ = run(capsys, "realizability", DATA / "cylinder_on_incline.toml", "--at", "x=0",
                       "--json")
    base = json.loads(out)["contacts"]["incline"]
    assert base["ratio"] == pytest.approx(np.tan(0.5) / (3 * 0.25), rel=1e-12)


def test_friction_law_command(capsys):
    code, out, _ = run(capsys, "friction-law", ROUGH,
                       "--contact", "line", "--substitute", "x1 = x + l*cos(theta), y1 = y + l*sin(theta)",
                       "--json")
    assert code == 0
    d = json.loads(out)
    assert d["effective_mass"] == "m + m1*cos(theta)**2"
    assert "f" in d["mu"] and "lambda_line" in d["mu"]


def test_derive_with_contact_states_and_painleve_representation(capsys):
    code, out, _ = run(capsys, "derive", ROUGH, "--contact",
                       "line=slide-", "--form", "lagrange1")
    assert code == 0 and "sliding (slide-)" in out and "f*lambda_line" in out
    code, out, _ = run(capsys, "derive", ROUGH, "--friction",
                       "painleve", "--form", "maggi")
    assert code == 0 and "mu_1" in out
    code, _, err = run(capsys, "derive", ROUGH, "--contact", "lin=stick")
    assert code == 2 and "did you mean 'line'" in err


def test_painleve_representation_closes_only_the_touching_contacts(capsys):
    # the rod touches with A only; closing B too would lay it flat (theta eliminated)
    code, out, _ = run(capsys, "derive", DATA / "rod_two_ends.toml", "--friction", "painleve", "--form", "maggi")
    assert code == 0 and "eliminated: A\n" in out and "unknowns: x'', theta''" in out
    code, out, _ = run(capsys, "derive", DATA / "rod_two_ends.toml", "--friction", "painleve", "--form", "maggi",
                       "--contact", "B=slide+")
    assert code == 0 and "eliminated: A, B" in out and "unknowns: x''\n" in out
    code, _, err = run(capsys, "derive", DATA / "rod_two_ends.toml", "--friction", "painleve",
                       "--contact", "A=separated")
    assert code == 2 and "no contact to close" in err
