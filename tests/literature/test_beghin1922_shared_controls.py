"""Béghin 1922 (Appell 1911, servo-constraints): r programs realized by one set of j controls
(``[[controls]]``).  A point in gravity keeps a cruise speed x' = v and a height z = h with the
controls u1 (along x), u2 (along z) and u3 along a slanted unit direction d = (a, b, c):
r = 2 < j = 3 is indeterminate and the library takes the least weighted norm; r = j is
determinate; r > j impossible (exit 3, the programs named)."""

import numpy as np
import pytest

from nonideal.cli import main
from nonideal.errors import MechanicsError, ModelError
from nonideal.modeling.declarations import Control
from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

A, B, C = 0.6, 0.48, 0.64
P = {"m": 2.0, "g": 9.81, "v": 1.5, "h": 1.0}
TIMES = np.linspace(0.0, 1.0, 6)


def _model(controls, extra=()):
    return Model(name="hover", coordinates=["x", "y", "z"], parameters=P,
                 kinetic="m/2*(x'^2 + y'^2 + z'^2)", potential="m*g*z",
                 constraints=[Constraint("cruise", "x' - v", "servo"), Constraint("hover", "z - h", "servo"),
                              *extra],
                 initial={"x": 0, "y": 0, "z": 1.0, "x'": 1.5, "y'": 0, "z'": 0},
                 simulation={"t_end": 1.0, "rtol": 1e-12, "atol": 1e-13}, controls=controls)


def _three(w=(1, 1, 1)):
    return (Control("u1", ("1", "0", "0"), w[0]), Control("u2", ("0", "0", "1"), w[1]),
            Control("u3", (str(A), str(B), str(C)), w[2]))


@pytest.mark.parametrize("w", [(1, 1, 1), (2.0, 0.5, 3.0)])
def test_more_controls_than_programs_least_weighted_norm(w):
    # m x'' = u1 + a u3 = 0, m z'' = -m g + u2 + c u3 = 0: u1 = -a u3, u2 = m g - c u3; the least
    # w1 u1^2 + w2 u2^2 + w3 u3^2 has u3 = w2 c m g / (w1 a^2 + w2 c^2 + w3), and y'' = b u3 / m
    m, g = P["m"], P["g"]
    u3 = w[1] * C * m * g / (w[0] * A ** 2 + w[1] * C ** 2 + w[2])
    tr = simulate(_model(_three(w)), times=TIMES)
    ctl = tr.controls
    assert np.max(np.abs(ctl["u3"]["force"] - u3)) < 1e-9
    assert np.max(np.abs(ctl["u1"]["force"] + A * u3)) < 1e-9
    assert np.max(np.abs(ctl["u2"]["force"] - (m * g - C * u3))) < 1e-9
    assert np.max(np.abs(tr.coordinate("y") - B * u3 / m * TIMES ** 2 / 2)) < 1e-9
    assert np.max(np.abs(tr.coordinate("z") - 1.0)) < 1e-10
    # the controls' work adds up to the programs' reactions' work
    total = sum(ctl[u]["work"] for u in ("u1", "u2", "u3"))
    assert np.max(np.abs(total - ctl["cruise"]["work"] - ctl["hover"]["work"])) < 1e-9
    assert ctl["u1"]["programs"] == ["cruise", "hover"]


def test_as_many_controls_as_programs_is_determinate():
    tr = simulate(_model(_three()[:2]), times=TIMES)
    assert np.max(np.abs(tr.controls["u1"]["force"])) < 1e-9
    assert np.max(np.abs(tr.controls["u2"]["force"] - P["m"] * P["g"])) < 1e-9
    assert np.max(np.abs(tr.coordinate("y"))) < 1e-12


def test_more_programs_than_controls_is_impossible_naming_them():
    extra = [Constraint("lane", "y'", "servo")]
    with pytest.raises(MechanicsError, match=r"3 programs \('cruise', 'hover', 'lane'\) but only 2") as info:
        simulate(_model(_three()[:2], extra), t_end=1.0)
    assert info.value.exit_code == 3 and info.value.details["r"] == 3


def test_per_constraint_reaction_still_works_beside_shared_controls():
    # 'hover' keeps its own direction (0, 0, 1); 'cruise' alone shares u1 and u3
    model = Model(name="mixed", coordinates=["x", "y", "z"], parameters=P,
                  kinetic="m/2*(x'^2 + y'^2 + z'^2)", potential="m*g*z",
                  constraints=[Constraint("cruise", "x' - v", "servo"),
                               Constraint.servo("hover", "z - h", ["0", "0", "1"])],
                  initial={"x": 0, "y": 0, "z": 1.0, "x'": 1.5, "y'": 0, "z'": 0},
                  controls=(Control("u1", ("1", "0", "0")), Control("u3", (str(A), str(B), str(C)))))
    tr = simulate(model, times=TIMES)
    # cruise: x'' = 0 needs u1 + a u3 = 0 (hover's own control takes the vertical part), whose
    # least-norm solution is u1 = u3 = 0; hover's control holds the weight
    assert np.max(np.abs(tr.controls["u3"]["force"])) < 1e-9
    assert np.max(np.abs(tr.multipliers["hover"] - P["m"] * P["g"])) < 1e-9


def test_model_file_controls_table(tmp_path, capsys):
    text = """[model]
name = "hover"
[parameters]
m = 2.0
g = 9.81
v = 1.5
h = 1.0
[coordinates]
q = ["x", "y", "z"]
[energy]
kinetic = "m/2*(x'^2 + y'^2 + z'^2)"
potential = "m*g*z"
[[controls]]
name = "u1"
direction = ["1", "0", "0"]
[[controls]]
name = "u2"
direction = ["0", "0", "1"]
weight = 2
[[controls]]
name = "u3"
direction = ["0.6", "0.48", "0.64"]
[[constraints]]
name = "cruise"
type = "servo"
expr = "x' - v"
[[constraints]]
name = "hover"
type = "servo"
expr = "z - h"
[initial]
x = 0
y = 0
z = 1.0
"x'" = 1.5
"y'" = 0
"z'" = 0
"""
    path = tmp_path / "hover.toml"
    path.write_text(text)
    out = tmp_path / "out.csv"
    assert main(["simulate", str(path), "--t-end", "1", "--csv", str(out)]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert {"u_u1", "P_u3", "W_u2"} <= set(header)
    summary = capsys.readouterr().out
    assert "control u2: force at t_end = " in summary and "work = " in summary
    assert "control hover" not in summary        # a program: its multiplier is no force
    assert main(["check", str(path)]) == 0
    assert "share the controls u1, u2, u3 (r = 2, j = 3" in capsys.readouterr().out
    path.write_text(text.replace("weight = 2", "weight = -1"))
    assert main(["check", str(path)]) == 2
    assert "control 'u2': weight must be > 0" in capsys.readouterr().err
    path.write_text(text.replace('direction = ["0", "0", "1"]', 'direction = ["0", "1"]'))
    assert main(["check", str(path)]) == 2
    assert "direction" in capsys.readouterr().err


def test_a_servo_constraint_without_reaction_needs_controls():
    with pytest.raises(ModelError, match="needs 'reaction'.*or the model's \\[\\[controls\\]\\]"):
        _model(())


def test_programs_report_the_controls_not_their_multipliers(tmp_path):
    """u = C mu: with two controls along x and z, the hover control is m g = 19.62 at m = 2;
    the program's multiplier (39.24 here) is no force.  The CSV's u_<name> columns, the
    trajectory's ``force`` entries and Béghin's statics (check at rest) give the control."""
    import csv

    from nonideal.analysis.contact.statics import servo_equilibrium

    m, g = P["m"], P["g"]
    tr = simulate(_model(_three()[:2]), times=TIMES)
    assert "force" not in tr.controls["hover"] and "force" not in tr.controls["cruise"]
    assert np.allclose(tr.controls["hover"]["multiplier"], tr.multipliers["hover"])
    out = tmp_path / "hover.csv"
    tr.to_csv(out)
    rows = list(csv.DictReader(out.open()))
    assert "u_hover" not in rows[0] and "u_cruise" not in rows[0]
    assert {"P_hover", "W_hover"} <= set(rows[0])
    assert float(rows[-1]["u_u2"]) == pytest.approx(m * g, rel=1e-12)
    assert float(rows[-1]["u_u1"]) == pytest.approx(0.0, abs=1e-12)
    rest = Model(name="hover at rest", coordinates=["x", "y", "z"], parameters={**P, "v": 0.0},
                 kinetic="m/2*(x'^2 + y'^2 + z'^2)", potential="m*g*z",
                 constraints=[Constraint("cruise", "x' - v", "servo"), Constraint("hover", "z - h", "servo")],
                 initial={"x": 0, "y": 0, "z": 1.0, "x'": 0, "y'": 0, "z'": 0}, controls=_three()[:2])
    eq = servo_equilibrium(rest)
    assert eq.equilibrium
    assert eq.controls == pytest.approx({"u1": 0.0, "u2": m * g})
    assert "hover = 39.24" not in eq.note() and "u2 = 19.62" in eq.note()
