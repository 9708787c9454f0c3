"""Third-order constraints (``x'''`` in expr): the force that realizes one is part of the state
(Yushkov 1999, ch. IV) -- along a given reaction (R = B lambda, linear or nonlinear in q''' with
a root rule) or ideal (R' = Lambda (d f/d q''')^T, the Gauss principle of third order)."""

import numpy as np
import pytest

from nonideal.cli import main
from nonideal.errors import MechanicsError, ModelError
from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

TIMES = np.linspace(0.0, 1.5, 16)
P = {"m": 2.0, "g": 9.81, "j": 0.8}


def _point(constraint, **kw):
    return Model(name="point", coordinates=["x", "y"], parameters=dict(P, **kw.pop("parameters", {})),
                 kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y", constraints=[constraint],
                 initial={"x": 0, "y": 0, "x'": 0.3, "y'": 1.0},
                 simulation={"t_end": 1.5, "rtol": 1e-12, "atol": 1e-13})


def test_linear_along_a_reaction_closed_form_and_the_second_order_program():
    # m x'' = lambda, m y'' = -m g + lambda; x''' = j makes lambda' = m j: lambda = 0.4 + m j t
    tr = simulate(_point(Constraint.servo("jerk", "x''' - j", ["1", "1"], initial=0.4)), times=TIMES)
    t = TIMES
    a0 = 0.4 / 2.0
    assert np.max(np.abs(tr.coordinate("x") - (0.3 * t + a0 * t ** 2 / 2 + 0.8 * t ** 3 / 6))) < 1e-10
    assert np.max(np.abs(tr.coordinate("y") - (t + (a0 - 9.81) * t ** 2 / 2 + 0.8 * t ** 3 / 6))) < 1e-10
    assert np.max(np.abs(tr.multipliers["jerk"] - (0.4 + 2.0 * 0.8 * t))) < 1e-10
    assert tr.controls["jerk"]["order"] == 3 and tr.coordinates == ("x", "y")
    # another formalism: the same motion as the second-order program x'' = a0 + j t with the
    # same control direction (its multiplier is the same force)
    sec = simulate(_point(Constraint.servo("jerk", "x'' - m*0.4/m^2 - j*t", ["1", "1"])), times=TIMES)
    assert np.max(np.abs(sec.q - tr.q)) < 1e-10
    assert np.max(np.abs(sec.multipliers["jerk"] - tr.multipliers["jerk"])) < 1e-9
    # the drive's work is in reaction_work (moved from the extended model's active forces) and the
    # model's energy balances; gravity's work stays in the potential
    E = tr.energy["energy"]
    assert np.max(np.abs(tr.energy["active_work"])) < 1e-3 * np.max(np.abs(E))
    assert tr.diagnostics["energy_balance_relative"] < 1e-10
    assert tr.energy["kinetic"][0] == pytest.approx(2.0 / 2 * (0.3 ** 2 + 1.0), rel=1e-14)


@pytest.mark.parametrize("root, sign", [("largest", 1.0), ("smallest", -1.0)])
def test_nonlinear_in_the_third_derivatives_with_a_root_rule(root, sign):
    # |r'''| = J with a thrust of fixed direction d = (3, 4)/5 in gravity: r''' = lambda' d/m, so
    # lambda' = +-m J; the root rule picks the sign
    c = Constraint.servo("jerk", "x'''^2 + y'''^2 - j^2", ["3/5", "4/5"], root=root, initial=25.0)
    tr = simulate(_point(c), times=TIMES)
    lam = 25.0 + sign * 2.0 * 0.8 * TIMES
    assert np.max(np.abs(tr.multipliers["jerk"] - lam)) < 1e-9
    ax = 0.6 * 25.0 / 2.0
    x = 0.3 * TIMES + ax * TIMES ** 2 / 2 + sign * 0.6 * 0.8 * TIMES ** 3 / 6
    assert np.max(np.abs(tr.coordinate("x") - x)) < 1e-10


def test_a_root_rule_that_selects_nothing_stops_with_the_state():
    # x'''^2 = j^2 - t: real roots while t < j^2 = 0.64 only
    c = Constraint.servo("jerk", "x'''^2 - j^2 + t", ["1", "0"], root="largest", initial=1.0)
    with pytest.raises(MechanicsError, match="root rule root = \"largest\" selects nothing") as info:
        simulate(_point(c), t_end=1.5)
    assert info.value.exit_code == 3 and info.value.t == pytest.approx(0.64, abs=1e-6)
    assert "x'" in info.value.state


def test_ideal_third_order_keeps_the_magnitude_of_the_acceleration_in_a_central_field():
    # Yushkov 1999, appendix D: a satellite whose acceleration keeps its magnitude, the constraint
    # |r''|^2 = const differentiated, x'' x''' + y'' y''' = 0, ideal: R' = Lambda (x'', y'')
    model = Model(name="satellite", coordinates=["x", "y"], parameters={"m": 1.0, "k": 1.0},
                  kinetic="m/2*(x'^2 + y'^2)", potential="-k*m/sqrt(x^2 + y^2)",
                  constraints=[Constraint("thrust", "x''*x''' + y''*y'''", initial=(0.3, 0.2))],
                  initial={"x": 1.0, "y": 0.0, "x'": 0.0, "y'": 1.1},
                  simulation={"t_end": 3.0, "rtol": 1e-12, "atol": 1e-13})
    times = np.linspace(0.0, 3.0, 121)
    tr = simulate(model, times=times)
    a = np.hypot(tr.qdd[:, 0], tr.qdd[:, 1])
    assert np.max(np.abs(a - a[0])) < 1e-8 and np.ptp(tr.qdd[:, 0]) > 0.5   # |a| kept, a turns
    # the reported reaction is m r'' minus gravity
    r3 = np.hypot(tr.q[:, 0], tr.q[:, 1]) ** 3
    R = np.column_stack([tr.controls["thrust"]["u_1"], tr.controls["thrust"]["u_2"]])
    F = -np.column_stack([tr.q[:, 0], tr.q[:, 1]]) / r3[:, None]
    assert np.max(np.abs(R - (tr.qdd - F))) < 1e-9
    # R' = Lambda r'': the reaction is its initial value plus the integral of Lambda r''
    from scipy.integrate import cumulative_simpson
    integral = cumulative_simpson(tr.multipliers["thrust"][:, None] * tr.qdd, x=times, axis=0, initial=0.0)
    assert np.max(np.abs(R - R[0] - integral)) < 1e-6 * np.max(np.abs(R))
    assert np.max(np.abs(R[0] - [0.3, 0.2])) < 1e-14
    assert tr.diagnostics["energy_balance_relative"] < 1e-8


def _errors(**kw):
    with pytest.raises(ModelError) as info:
        Model(name="p", coordinates=["x", "y"], parameters={"m": 1.0, "j": 1.0},
              kinetic="m/2*(x'^2 + y'^2)", initial={"x": 0, "y": 0, "x'": 0, "y'": 0, **kw.pop("initial", {})},
              **kw)
    return str(info.value)


def test_bad_third_order_input_is_named():
    msg = _errors(constraints=[Constraint.servo("c", "x''' - j", ["1", "0"])])
    assert "[initial] lambda_c: required by the third-order constraint 'c'" in msg
    msg = _errors(constraints=[Constraint("c", "x''' - j")])
    assert "[initial] lambda_c: required" in msg and "list of 2 numbers" in msg
    msg = _errors(constraints=[Constraint("c", "x''' - j")], initial={"lambda_c": 1.0})
    assert "lambda_c: must be a list of 2 numbers" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x''' - j", ["1", "0"])], initial={"lambda_c": [1, 2]})
    assert "lambda_c: must be one number" in msg
    msg = _errors(constraints=[Constraint("c", "x'''^2 - j", initial=(0, 0))])
    assert "nonlinear in the third derivatives needs 'reaction'" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x''' - j", ["1", "0"], initial=1.0)],
                  initial={"lambda_d": 1.0})
    assert "[initial] lambda_d: not a coordinate or velocity" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x" + "'" * 9 + " - j", ["1", "0"], initial=1.0)])
    assert "only first (x') and second (x'') derivatives" in msg and "up to order 8 there" in msg
    msg = _errors(potential="x'''")
    assert "x''': only first (x') and second (x'') derivatives can be written" in msg


def test_cli_missing_initial_force_is_exit_2_naming_the_key(tmp_path, capsys):
    text = (tmp_path / "m.toml")
    text.write_text('[model]\nname = "j"\n[parameters]\nm = 1.0\n[coordinates]\nq = ["x"]\n'
                    '[energy]\nkinetic = "m/2*x\'^2"\n[[constraints]]\nname = "jerk"\ntype = "servo"\n'
                    'expr = "x\'\'\' - 1"\nreaction = ["1"]\n[initial]\nx = 0\n"x\'" = 0\n')
    code = main(["simulate", str(text), "--t-end", "1", "--json", str(tmp_path / "o.json")])
    err = capsys.readouterr().err
    assert code == 2 and "lambda_jerk" in err and not (tmp_path / "o.json").exists()
    with open(text, "a") as fh:
        fh.write("lambda_jerk = 2.0\n")
    code = main(["simulate", str(text), "--t-end", "1", "--json", str(tmp_path / "o.json")])
    assert code == 0
    import json
    out = json.loads((tmp_path / "o.json").read_text())
    assert list(out["q"]) == ["x"] and out["multipliers"]["jerk"][-1] == pytest.approx(3.0, rel=1e-10)
    assert out["controls"]["jerk"]["order"] == 3


def test_parameter_override_reaches_the_force_direction():
    # the drive's power u B . q' with B = (cos(alpha), sin(alpha)) read at the overridden alpha
    from nonideal.gallery import jerk_programmed_drive as drive
    times = np.linspace(0.0, 1.0, 41)
    a = simulate(drive.build(alpha=0.9), times=times)
    b = simulate(drive.build(), times=times, parameters={"alpha": 0.9})
    assert np.max(np.abs(a.q - b.q)) < 1e-10
    assert np.max(np.abs(a.controls["drive"]["power"] - b.controls["drive"]["power"])) < 1e-9
    E = a.energy["energy"]
    assert a.energy["reaction_work"][-1] == pytest.approx(E[-1] - E[0], rel=1e-6)   # Simpson, 41 samples


def test_analyses_on_states_q_qdot_refuse_a_third_order_constraint_by_name(capsys):
    assert main(["stability", "jerk-programmed-drive", "--about", "equilibrium"]) == 2
    assert "constraint 'drive' is of third order" in capsys.readouterr().err
    assert main(["derive", "jerk-programmed-drive", "--form", "lagrange1"]) == 0
    assert "drive_impulse'' = lambda_drive" in capsys.readouterr().out
