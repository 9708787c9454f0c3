"""[speeds] and [outputs]: what is refused (exit 2, naming the key and the fix) and what a speed
name means in the other expressions."""

import numpy as np
import pytest

from nonideal import Constraint, Model, ModelError, evaluate
from nonideal.errors import InconsistentInitialConditions
from tests.helpers import run_cli


def sleigh(**changes):
    spec = dict(
        name="sleigh", coordinates=["x", "y", "th"], parameters={"m": 1.0, "J": 0.2},
        speeds={"v": "x'*cos(th) + y'*sin(th)", "w": "th'", "s": "-x'*sin(th) + y'*cos(th)"},
        kinetic="m/2*(v^2 + s^2) + J/2*w^2",
        constraints=[Constraint.nonholonomic("knife", "s")],
        initial={"x": 0.0, "y": 0.0, "th": 0.4, "v": 1.0, "w": 0.5},
    )
    spec.update(changes)
    return Model(**spec)


def test_speed_names_stand_for_their_definitions():
    import sympy as sp

    m = sleigh()
    x, y, th = m.q
    xd, yd, thd = m.qd
    assert sp.expand(m.constraints[0].expr - (-xd * sp.sin(th) + yd * sp.cos(th))) == 0
    ev = evaluate(m)
    assert ev.qd == pytest.approx([np.cos(0.4), np.sin(0.4), 0.5], rel=1e-14)


def test_dependent_speeds_are_named():
    with pytest.raises(ModelError) as exc:
        sleigh(speeds={"v": "x'*cos(th) + y'*sin(th)", "w": "th'", "w2": "2*th'"},
               kinetic="m/2*v^2 + J/2*w^2",
               constraints=[Constraint.nonholonomic("knife", "-x'*sin(th) + y'*cos(th)")])
    msg = str(exc.value)
    assert "[speeds]: the speeds w, w2 are linearly dependent" in msg
    assert "remove one of them" in msg


def test_incomplete_speeds_name_the_velocities_they_cannot_express():
    with pytest.raises(ModelError) as exc:
        sleigh(speeds={"v": "x'*cos(th) + y'*sin(th)", "w": "th'"}, kinetic="m/2*v^2 + J/2*w^2",
               constraints=[Constraint.nonholonomic("knife", "-x'*sin(th) + y'*cos(th)")])
    msg = str(exc.value)
    assert "do not determine the velocities x', y'" in msg
    assert "add a speed that involves x' or y'" in msg


def test_holonomic_constraints_complete_a_speed_set():
    # a pendulum in Cartesian coordinates: the angular speed alone, with the rod's length fixed
    m = Model(name="pendulum", coordinates=["x", "y"], parameters={"l": 1.0, "g": 9.81},
              speeds={"w": "(x*y' - y*x')/l^2"}, kinetic="(x'^2 + y'^2)/2", potential="g*y",
              constraints=[Constraint.holonomic("rod", "x^2 + y^2 - l^2")],
              initial={"x": 0.6, "y": -0.8, "w": 2.0})
    ev = evaluate(m, form="kane")
    assert ev.speeds["w"] == pytest.approx(2.0, rel=1e-14)
    # pendulum: w' = -g/l sin(angle from the downward vertical) = -g x / l^2
    assert ev.speeds_dot["w"] == pytest.approx(-9.81 * 0.6, rel=1e-12)


@pytest.mark.parametrize("speeds, fragment", [
    ({"v": "x'^2"}, "not linear in the velocities"),
    ({"v": "th"}, "contains no velocity"),
    ({"x": "x'"}, "'x' is also a coordinate"),
    ({"m": "x'"}, "'m' is also a parameter"),
    ({"v": "w + x'", "w": "th'"}, "uses the speed 'w'"),
    ({"v": "x'*cos(th) + y'*sin(tth)"}, "tth"),
])
def test_bad_speed_definitions(speeds, fragment):
    with pytest.raises(ModelError, match="speeds") as exc:
        sleigh(speeds=speeds, kinetic="m/2*(x'^2 + y'^2)", constraints=[], initial={})
    assert fragment in str(exc.value)


def test_speed_and_velocity_given_inconsistently():
    with pytest.raises(InconsistentInitialConditions) as exc:
        evaluate(sleigh(initial={"x": 0.0, "y": 0.0, "th": 0.4, "v": 1.0, "w": 0.5, "th'": 0.7}))
    assert "speed 'w' = 0.5 contradicts the velocities given with it" in str(exc.value)
    # consistent: accepted
    ev = evaluate(sleigh(initial={"x": 0.0, "y": 0.0, "th": 0.4, "v": 1.0, "w": 0.5, "th'": 0.5}))
    assert ev.qd[2] == 0.5


def test_unknown_initial_and_at_names():
    with pytest.raises(ModelError, match=r"\[initial\] vv: not a coordinate or velocity or speed \(did you mean 'v'\?\)"):
        sleigh(initial={"x": 0.0, "y": 0.0, "th": 0.4, "vv": 1.0, "w": 0.5})
    with pytest.raises(ModelError, match="at: 'ww' is not a coordinate or velocity or speed"):
        evaluate(sleigh(), at={"ww": 1.0})


@pytest.mark.parametrize("outputs, fragment", [
    ({"energy": "T"}, "a column of every simulation's output"),
    ({"x": "T"}, "already a coordinate or speed"),
    ({"r": "lambda_knif"}, "lambda_knif"),
    ({"r": "T + zz"}, "zz"),
])
def test_bad_outputs(outputs, fragment):
    with pytest.raises(ModelError, match="outputs") as exc:
        sleigh(outputs=outputs)
    assert fragment in str(exc.value)


def test_cli_exit_codes(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("""
[model]
name = "dependent speeds"
[parameters]
m = 1.0
[coordinates]
q = ["x", "y"]
[speeds]
u = "x' + y'"
v = "2*x' + 2*y'"
[energy]
kinetic = "m/2*(x'^2 + y'^2)"
[initial]
x = 0.0
y = 0.0
"x'" = 1.0
"y'" = 0.0
""")
    r = run_cli("check", bad)
    assert r.returncode == 2
    assert "bad.toml" in r.stderr and "[speeds]: the speeds u, v are linearly dependent" in r.stderr
    assert "do not determine the velocities x', y'" in r.stderr
    from nonideal import gallery

    r = run_cli("evaluate", gallery.model_path("chaplygin-sleigh-speeds"), "--at", "v=1, theta'=2, w=3")
    assert r.returncode == 2 and "speed 'w' = 3 contradicts" in r.stderr
