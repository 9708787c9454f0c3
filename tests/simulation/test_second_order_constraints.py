"""Second-order constraints (``''`` in expr): linear ones with the ideal reaction
``(d phi / d q'')^T lambda`` or a servo direction, and ones nonlinear in the accelerations with a
reaction direction and a root rule."""

import numpy as np
import pytest

from nonideal.errors import MechanicsError, ModelError
from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

TIMES = np.linspace(0.0, 2.0, 41)


def _pendulum(constraint, **initial):
    init = {"x": 0.6, "y": -0.8, "x'": 0.8 * 1.5, "y'": 0.6 * 1.5}
    init.update(initial)
    return Model(name="pendulum", coordinates=["x", "y"], parameters={"m": 1.3, "g": 9.81, "l": 1.0},
                 kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y", constraints=[constraint],
                 initial=init, simulation={"t_end": 2.0, "rtol": 1e-12, "atol": 1e-13})


def test_second_derivative_of_a_holonomic_constraint_gives_the_same_motion_and_multiplier():
    # (x^2 + y^2 - l^2)/2 = 0 and its second derivative x x'' + y y'' + x'^2 + y'^2 = 0 have
    # the same gradient (x, y) at acceleration level: the same motion, the same multiplier
    hol = simulate(_pendulum(Constraint.holonomic("rod", "(x^2 + y^2 - l^2)/2")), times=TIMES)
    sec = simulate(_pendulum(Constraint("rod", "x*x'' + y*y'' + x'^2 + y'^2")), times=TIMES)
    assert np.max(np.abs(sec.q - hol.q)) < 1e-9
    assert np.max(np.abs(sec.multipliers["rod"] - hol.multipliers["rod"])) < 1e-8
    # and the length is kept (the second-order constraint with r . v = 0 at t0 keeps |r| = l)
    assert np.max(np.abs(np.hypot(sec.q[:, 0], sec.q[:, 1]) - 1.0)) < 1e-9
    # the tension: m (v^2/l + g cos) = -lambda l (closed form of the pendulum)
    v2 = sec.qd[:, 0] ** 2 + sec.qd[:, 1] ** 2
    tension = 1.3 * (v2 + 9.81 * (-sec.q[:, 1]))
    assert np.max(np.abs(-sec.multipliers["rod"] - tension)) < 1e-8


def test_linear_second_order_servo_constraint_closed_form():
    # x'' = a cos t realized by a force along (1, 1): m x'' = u, m y'' = -m g + u
    model = Model(name="servo2", coordinates=["x", "y"], parameters={"m": 2.0, "g": 9.81, "a": 0.7},
                  kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                  constraints=[Constraint.servo("prog", "x'' - a*cos(t)", ["1", "1"])],
                  initial={"x": 0, "y": 0, "x'": 0.3, "y'": 1.0},
                  simulation={"t_end": 2.0, "rtol": 1e-12, "atol": 1e-13})
    tr = simulate(model, times=TIMES)
    t = TIMES
    assert np.max(np.abs(tr.coordinate("x") - (0.3 * t + 0.7 * (1 - np.cos(t))))) < 1e-9
    assert np.max(np.abs(tr.coordinate("y") - (t - 9.81 * t ** 2 / 2 + 0.7 * (1 - np.cos(t))))) < 1e-9
    assert np.max(np.abs(tr.controls["prog"]["force"] - 2.0 * 0.7 * np.cos(t))) < 1e-9


def _rocket(g, w, root=None, t_end=1.0):
    kw = {} if root is None else {"root": root}
    return Model(name="rocket", coordinates=["x", "y"],
                 parameters={"m": 2.0, "g": g, "w": w},
                 kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                 constraints=[Constraint.servo("thrust", "x''^2 + y''^2 - w^2",
                                               ["x'/sqrt(x'^2 + y'^2)", "y'/sqrt(x'^2 + y'^2)"], **kw)],
                 initial={"x": 0, "y": 0, "x'": 3.0, "y'": 4.0},
                 simulation={"t_end": t_end, "rtol": 1e-12, "atol": 1e-13})


@pytest.mark.parametrize("root, sign", [(None, 1.0), ("largest", 1.0), ("smallest", -1.0)])
def test_root_rule_picks_the_branch_free_space(root, sign):
    # no gravity: T = +- m w along the velocity; the speed is 5 +- w t on a straight line
    tr = simulate(_rocket(0.0, 2.0, root), times=np.linspace(0, 1, 11))
    speed = np.hypot(tr.qd[:, 0], tr.qd[:, 1])
    assert np.max(np.abs(speed - (5.0 + sign * 2.0 * tr.t))) < 1e-9
    assert np.max(np.abs(tr.multipliers["thrust"] - sign * 4.0)) < 1e-9


def test_a_root_rule_that_selects_nothing_is_exit_3_with_the_state():
    with pytest.raises(MechanicsError, match="root rule root = \"largest\" selects nothing") as info:
        simulate(_rocket(9.81, 5.0))   # w^2 < g^2 cos^2(theta0): no real thrust at t0
    assert info.value.exit_code == 3 and info.value.t == 0.0 and "x'" in info.value.state


def test_nonlinear_second_order_constraint_needs_a_reaction_and_a_valid_rule():
    with pytest.raises(ModelError, match="nonlinear in the accelerations needs 'reaction'"):
        Model(name="r", coordinates=["x", "y"], parameters={"w": 1.0}, kinetic="(x'^2 + y'^2)/2",
              constraints=[Constraint("c", "x''^2 + y''^2 - w^2")],
              initial={"x": 0, "y": 0, "x'": 1, "y'": 0})
    with pytest.raises(ModelError, match="root must be one of largest, smallest"):
        _rocket(0.0, 2.0, "biggest")
    with pytest.raises(ModelError, match="'root' applies only to a constraint nonlinear"):
        Model(name="r", coordinates=["x"], kinetic="x'^2/2",
              constraints=[Constraint.servo("c", "x'' - 1", ["1"], root="largest")],
              initial={"x": 0, "x'": 0})


def test_linear_second_order_ideal_constraint_that_is_no_derivative_closed_form():
    # x'' + y'' = c in gravity, ideal: the reaction is (1, 1) lambda (d expr/d q''), so
    # m x'' = lambda, m y'' = -m g + lambda and lambda = m (c + g)/2 (constant); evaluate agrees
    from nonideal.analysis.evaluation import evaluate
    model = Model(name="acc", coordinates=["x", "y"], parameters={"m": 1.5, "g": 9.81, "c": 0.4},
                  kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                  constraints=[Constraint("sum", "x'' + y'' - c")],
                  initial={"x": 0, "y": 0, "x'": 1.0, "y'": 2.0},
                  simulation={"t_end": 2.0, "rtol": 1e-12, "atol": 1e-13})
    assert model.constraints[0].order == 2 and model.constraints[0].reaction_kind == "ideal"
    tr = simulate(model, times=TIMES)
    lam = 1.5 * (0.4 + 9.81) / 2
    t = TIMES
    assert np.max(np.abs(tr.multipliers["sum"] - lam)) < 1e-9
    assert np.max(np.abs(tr.coordinate("x") - (t + lam / 1.5 * t ** 2 / 2))) < 1e-9
    assert np.max(np.abs(tr.coordinate("y") - (2 * t + (lam / 1.5 - 9.81) * t ** 2 / 2))) < 1e-9
    ev = evaluate(model)
    assert ev.multipliers["sum"] == pytest.approx(lam, rel=1e-12)
    assert tr.diagnostics["energy_balance_relative"] < 1e-10
