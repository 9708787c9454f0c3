"""Constraints of order n >= 4 (``x''''``, ``x'''''``): the force and its derivatives up to order
n - 3 are part of the state (Yushkov 1999, ch. IV, secs. 5 and 7) -- along a given reaction
(R = B lambda, lambda^(n-2) fixed by the program) or ideal (the generalized Gauss principle of
order n: R^(n-2) = Lambda (d f/d q^(n))^T).  Closed forms derived here, the same motion as the
equivalent lower-order programs, the energy balance, and bad input named."""

import json

import numpy as np
import pytest
from numpy.polynomial import Polynomial
from scipy.integrate import cumulative_simpson

from nonideal.cli import main
from nonideal.errors import ModelError
from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

TIMES = np.linspace(0.0, 1.5, 16)
M, G, S = 2.0, 9.81, 0.8


def _point(*constraints, **kw):
    """A point of mass m in gravity (x along, y up)."""
    return Model(name="point", coordinates=["x", "y"], parameters={"m": M, "g": G, "s": S},
                 kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y", constraints=list(constraints),
                 initial={"x": 0, "y": 0, "x'": 0.3, "y'": 1.0, **kw.pop("initial", {})},
                 simulation={"t_end": 1.5, "rtol": 1e-12, "atol": 1e-13}, **kw)


def test_order_4_along_a_reaction_closed_form_and_the_lower_order_programs():
    # m x'' = lambda, m y'' = -m g + lambda; x'''' = s makes lambda'' = m s:
    # lambda = 0.4 - 0.3 t + m s t^2/2, x = 0.3 t + lambda(0) t^2/(2m) + lambda'(0) t^3/(6m) + s t^4/24
    tr = simulate(_point(Constraint.servo("snap", "x'''' - s", ["1", "1"], initial=(0.4, -0.3))), times=TIMES)
    t = TIMES
    lam = Polynomial([0.4, -0.3, M * S / 2])
    x = Polynomial([0.0, 0.3, 0.4 / (2 * M), -0.3 / (6 * M), S / 24])
    y = Polynomial([0.0, 1.0, 0.4 / (2 * M) - G / 2, -0.3 / (6 * M), S / 24])
    assert np.max(np.abs(tr.coordinate("x") - x(t))) < 1e-11
    assert np.max(np.abs(tr.coordinate("y") - y(t))) < 1e-11
    assert np.max(np.abs(tr.multipliers["snap"] - lam(t))) < 1e-11
    c = tr.controls["snap"]
    assert c["order"] == 4 and np.max(np.abs(c["force'"] - lam.deriv()(t))) < 1e-11
    assert tr.coordinates == ("x", "y") and np.max(np.abs(tr.qdd[:, 0] - x.deriv(2)(t))) < 1e-11
    # the drive's work integrated with the motion: int lambda (x' + y') dt, a polynomial
    work = (lam * (x.deriv() + y.deriv())).integ()
    assert np.max(np.abs(c["work"] - work(t))) < 1e-10
    E = tr.energy
    assert np.max(np.abs(E["reaction_work"] - work(t))) < 1e-10 and np.max(np.abs(E["active_work"])) < 1e-12
    assert tr.diagnostics["energy_balance_relative"] < 1e-12
    # the same motion and force as the third- and second-order programs that this one integrates
    third = simulate(_point(Constraint.servo("snap", "x''' + 0.3/m - s*t", ["1", "1"], initial=0.4)), times=TIMES)
    second = simulate(_point(Constraint.servo("snap", "x'' - 0.4/m + 0.3/m*t - s*t^2/2", ["1", "1"])),
                      times=TIMES)
    for other in (third, second):
        assert np.max(np.abs(other.q - tr.q)) < 1e-10
        assert np.max(np.abs(other.multipliers["snap"] - tr.multipliers["snap"])) < 1e-9


@pytest.mark.parametrize("root, sign", [("largest", 1.0), ("smallest", -1.0)])
def test_order_4_nonlinear_with_a_root_rule(root, sign):
    # |r''''| = s along d = (3, 4)/5: r'''' = lambda'' d/m, lambda'' = +-m s
    c = Constraint.servo("snap", "x''''^2 + y''''^2 - s^2", ["3/5", "4/5"], root=root, initial=(25.0, 1.0))
    tr = simulate(_point(c), times=TIMES)
    lam = Polynomial([25.0, 1.0, sign * M * S / 2])
    assert np.max(np.abs(tr.multipliers["snap"] - lam(TIMES))) < 1e-9
    x = Polynomial([0.0, 0.3, 0.6 * 25.0 / (2 * M), 0.6 * 1.0 / (6 * M), sign * 0.6 * S / 24])
    assert np.max(np.abs(tr.coordinate("x") - x(TIMES))) < 1e-10


def _sprung(constraint, **p):
    par = {"m": 2.0, "kx": 3.0, "ky": 5.0, "c0": 0.9, **p}
    return Model(name="sprung", coordinates=["x", "y"], parameters=par,
                 kinetic="m/2*(x'^2 + y'^2)", potential="kx/2*x^2 + ky/2*y^2", constraints=[constraint],
                 initial={"x": 0.1, "y": 0.0, "x'": 0.2, "y'": 0.0},
                 simulation={"t_end": 2.0, "rtol": 1e-12, "atol": 1e-13})


def test_order_5_ideal_sprung_mass_closed_form():
    # m x'' + kx x = R_x, m y'' + ky y = R_y, x''''' = c0 ideal: R''' = Lambda (1, 0), so R_y is
    # the quadratic R_y(0) + R_y'(0) t + R_y''(0) t^2/2 and x is the quintic of its initial
    # derivatives x'' = (R_x - kx x)/m, x''' = (R_x' - kx x')/m, x'''' = (R_x'' - kx x'')/m
    m, kx, ky, c0 = 2.0, 3.0, 5.0, 0.9
    R = ((1.5, 0.5), (0.2, -0.4), (-0.7, 0.3))
    tr = simulate(_sprung(Constraint("crackle", "x''''' - c0", initial=R)), times=np.linspace(0, 2, 21))
    t = tr.t
    a0 = (R[0][0] - kx * 0.1) / m
    j0 = (R[1][0] - kx * 0.2) / m
    s0 = (R[2][0] - kx * a0) / m
    x = Polynomial([0.1, 0.2, a0 / 2, j0 / 6, s0 / 24, c0 / 120])
    Rx = m * x.deriv(2) + kx * x
    P = Polynomial([R[0][1], R[1][1], R[2][1] / 2]) / m
    w2 = ky / m
    yp = P / w2 - P.deriv(2) / w2 ** 2
    w = np.sqrt(w2)
    y = yp(t) - yp(0.0) * np.cos(w * t) - yp.deriv()(0.0) / w * np.sin(w * t)
    assert np.max(np.abs(tr.coordinate("x") - x(t))) < 1e-9
    assert np.max(np.abs(tr.coordinate("y") - y)) < 1e-9
    c = tr.controls["crackle"]
    assert c["order"] == 5
    assert np.max(np.abs(c["u_1"] - Rx(t))) < 1e-9 and np.max(np.abs(c["u_2"] - P(t) * m)) < 1e-9
    assert np.max(np.abs(c["u_1'"] - Rx.deriv()(t))) < 1e-9 and np.max(np.abs(c["u_2''"] - R[2][1])) < 1e-9
    # Lambda = R_x''' = m x''''' + kx x'''
    assert np.max(np.abs(tr.multipliers["crackle"] - (m * c0 + kx * x.deriv(3)(t)))) < 1e-9
    assert tr.diagnostics["energy_balance_relative"] < 1e-10
    E = tr.energy
    assert np.max(np.abs(E["reaction_work"] - c["work"])) < 1e-10 and np.max(np.abs(E["active_work"])) < 1e-12


def test_ideal_orders_agree_where_their_principles_do():
    # order 4 ideal R'' = Lambda (1, 0) and order 3 ideal R' = Lambda (1, 0) give one motion when
    # R_y'(0) = 0 and the programs agree: x'''' = 0 with x'''(0) = j against x''' = j
    j = 0.35
    Rx1 = 2.0 * j + 3.0 * 0.2        # R_x'(0) = m x'''(0) + kx x'(0)
    four = simulate(_sprung(Constraint("p", "x''''", initial=((1.5, 0.5), (Rx1, 0.0)))),
                    times=np.linspace(0, 2, 11))
    three = simulate(_sprung(Constraint("p", f"x''' - {j}", initial=(1.5, 0.5))), times=np.linspace(0, 2, 11))
    assert np.max(np.abs(four.q - three.q)) < 1e-9
    assert np.max(np.abs(four.controls["p"]["u_1"] - three.controls["p"]["u_1"])) < 1e-9


def test_satellite_with_a_constant_magnitude_jerk():
    # the derivative of |r'''|^2 = const, x''' x'''' + y''' y'''' = 0, ideal of order 4 (the
    # generalized Gauss principle: R'' = Lambda (x''', y''')), in a central field
    model = Model(name="satellite", coordinates=["x", "y"], parameters={"m": 1.0, "k": 1.0},
                  kinetic="m/2*(x'^2 + y'^2)", potential="-k*m/sqrt(x^2 + y^2)",
                  constraints=[Constraint("jerk", "x'''*x'''' + y'''*y''''",
                                          initial=((0.3, 0.2), (0.1, -0.2)))],
                  initial={"x": 1.0, "y": 0.0, "x'": 0.0, "y'": 1.1},
                  simulation={"t_end": 3.0, "rtol": 1e-12, "atol": 1e-13})
    times = np.linspace(0.0, 3.0, 481)   # fine: R' is checked against a quadrature below
    tr = simulate(model, times=times)
    c = tr.controls["jerk"]
    R = np.column_stack([c["u_1"], c["u_2"]])
    dR = np.column_stack([c["u_1'"], c["u_2'"]])
    r = np.hypot(tr.q[:, 0], tr.q[:, 1])
    F = -tr.q / r[:, None] ** 3
    assert np.max(np.abs(R - (tr.qdd - F))) < 1e-9              # m r'' = F + R
    # r''' = F' + R' (m = 1), with F' = -r'/|r|^3 + 3 (r . r') r/|r|^5: its magnitude is kept
    rr = np.einsum("ki,ki->k", tr.q, tr.qd)
    jerk = -tr.qd / r[:, None] ** 3 + 3 * rr[:, None] * tr.q / r[:, None] ** 5 + dR
    size = np.hypot(jerk[:, 0], jerk[:, 1])
    assert np.max(np.abs(size - size[0])) < 1e-8 and np.ptp(jerk[:, 0]) > 0.1
    # R'' = Lambda r''': R' is its initial value plus the integral of Lambda r'''
    integral = cumulative_simpson(tr.multipliers["jerk"][:, None] * jerk, x=times, axis=0, initial=0.0)
    assert np.max(np.abs(dR - dR[0] - integral)) < 1e-6 * np.max(np.abs(dR))
    assert tr.diagnostics["energy_balance_relative"] < 1e-8


def _errors(constraints=(), **kw):
    with pytest.raises(ModelError) as info:
        _point(*constraints, **kw)
    return str(info.value)


def test_bad_high_order_input_is_named():
    msg = _errors(constraints=[Constraint.servo("c", "x'''' - s", ["1", "0"])], initial={"lambda_c": 1.0})
    assert "[initial] lambda_c': required by the order-4 constraint 'c': give a number" in msg
    msg = _errors(constraints=[Constraint("c", "x''''' - s")],
                  initial={"lambda_c": [1, 0], "lambda_c''": [0, 0]})
    assert "[initial] lambda_c': required by the order-5 constraint 'c': give a list of 2 numbers" in msg
    assert "(lambda_c, lambda_c', lambda_c'')" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x'''' - s", ["1", "0"], initial=(1.0, 0.0))],
                  initial={"lambda_c''": 1.0})
    assert "[initial] lambda_c'': the constraint 'c' is of order 4" in msg and "lambda_c and lambda_c' only" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x'''' - s", ["1", "0"], initial=1.0)])
    assert "constraint 'c': initial must be 2 numbers" in msg
    msg = _errors(constraints=[Constraint("c", "x'''' - s", initial=(1.0, 0.0))])
    assert "constraint 'c': initial must be 2 lists of 2 numbers" in msg
    msg = _errors(constraints=[Constraint("c", "x''''^2 - s", initial=((0, 0), (0, 0)))])
    assert "order-4 constraint nonlinear in the derivatives of order 4 needs 'reaction'" in msg
    msg = _errors(constraints=[Constraint.servo("c", "x'''' - s", ["1", "0"], initial=(1.0, 0.0))],
                  initial={"lambda_c'": [1, 2]})
    assert "[initial] lambda_c': must be one number" in msg
    msg = _errors(forces={"x": "x''''"})
    assert "x'''': only first (x') and second (x'') derivatives can be written" in msg


def test_mixed_orders_are_refused_naming_both():
    model = _point(Constraint.servo("a", "x''' - s", ["1", "0"], initial=1.0),
                   Constraint.servo("b", "y'''' - s", ["0", "1"], initial=(1.0, 0.0)))
    with pytest.raises(ModelError, match=r"'a' \(order 3\), 'b' \(order 4\): constraints of order three"):
        simulate(model, t_end=0.1)


TOML = """[model]
name = "snap"
[parameters]
m = 2.0
s0 = 0.8
[coordinates]
q = ["x"]
[energy]
kinetic = "m/2*x'^2"
[[constraints]]
name = "snap"
type = "servo"
expr = "x'''' - s0"
reaction = ["1"]
[initial]
x = 0
"x'" = 0.3
lambda_snap = 0.4
"""


def test_cli_missing_derivative_of_the_force_is_exit_2_naming_the_key(tmp_path, capsys):
    path = tmp_path / "m.toml"
    path.write_text(TOML)
    out = tmp_path / "o.json"
    assert main(["simulate", str(path), "--t-end", "1", "--json", str(out)]) == 2
    err = capsys.readouterr().err
    assert "[initial] lambda_snap': required by the order-4 constraint 'snap'" in err and not out.exists()
    path.write_text(TOML + "\"lambda_snap'\" = -0.3\n")
    assert main(["simulate", str(path), "--times", "0,0.5,1", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    lam = Polynomial([0.4, -0.3, M * S / 2])
    assert list(data["q"]) == ["x"] and data["multipliers"]["snap"] == pytest.approx(lam([0, 0.5, 1]), abs=1e-10)
    assert data["controls"]["snap"]["order"] == 4
    assert data["controls"]["snap"]["force'"] == pytest.approx(lam.deriv()([0, 0.5, 1]), abs=1e-10)


@pytest.mark.parametrize("expr, initial", [("x''' - s", 0.4), ("x'''' - s", (0.4, -0.3))])
def test_outputs_and_speeds_are_the_models_own(expr, initial):
    # T of the model (not of the extended one with its auxiliary energy), the multiplier lambda
    # (not the extended program's lambda^(n-2)), and the speeds, at every sample
    model = _point(Constraint.servo("p", expr, ["1", "1"], initial=initial),
                   speeds={"u1": "x'", "u2": "x' + y'"}, outputs={"kin": "T", "lam": "lambda_p", "s": "u2"})
    tr = simulate(model, times=TIMES)
    assert np.max(np.abs(tr.outputs["kin"] - tr.energy["kinetic"])) < 1e-12
    assert np.max(np.abs(tr.outputs["lam"] - tr.multipliers["p"])) < 1e-12
    assert np.max(np.abs(tr.outputs["s"] - tr.qd[:, 0] - tr.qd[:, 1])) < 1e-12
    assert np.max(np.abs(tr.speeds["u2"] - tr.qd[:, 0] - tr.qd[:, 1])) < 1e-12
    assert tr.energy["kinetic"][0] == pytest.approx(M / 2 * (0.3 ** 2 + 1.0), rel=1e-14)


def test_a_body_declared_by_its_frame_and_centre():
    # a wheel spinning about z and sliding along x: th'''' = j (ideal, R'' along th) with the
    # torque and the force and their rates given; C th'' = R_th, m x'' = R_x
    from nonideal.modeling.bodies import RigidBody
    from nonideal.modeling.frames import Frame
    from nonideal.modeling.points import Point

    model = Model(name="wheel", coordinates=["th", "x"], parameters={"m": 2.0, "C": 0.5, "j": 0.3},
                  frames=[Frame("B", axis=[0, 0, 1], angle="th")], points=[Point("G", ["x", 0, 0])],
                  bodies=[RigidBody("w", "m", [["C", 0, 0], [0, "C", 0], [0, 0, "C"]], frame="B", center="G")],
                  constraints=[Constraint("p", "th'''' - j", initial=((0.1, 0.2), (0.0, 0.1)))],
                  initial={"th": 0, "x": 0, "th'": 1.0, "x'": 0.5})
    t = np.linspace(0.0, 1.0, 5)
    tr = simulate(model, times=t)
    assert np.max(np.abs(tr.q[:, 0] - (t + 0.1 / 0.5 * t ** 2 / 2 + 0.3 * t ** 4 / 24))) < 1e-12
    assert np.max(np.abs(tr.q[:, 1] - (0.5 * t + 0.2 / 2 * t ** 2 / 2 + 0.1 / 2 * t ** 3 / 6))) < 1e-12


def test_ideal_with_a_time_dependent_mass_matrix_is_refused_with_the_fix():
    # the covariant derivatives of the ideal force need M(q); with M(t) the basis' rate is not in
    # M -- refused, naming the way out (a reaction direction), which then runs
    kw = dict(name="p", coordinates=["x"], parameters={"s": 0.5}, kinetic="(2 + sin(t))/2*x'^2",
              initial={"x": 0, "x'": 0}, simulation={"t_end": 0.5})
    with pytest.raises(ModelError, match="mass matrix that does not depend on time.*reaction"):
        simulate(Model(constraints=[Constraint("p", "x'''' - s", initial=((1.0,), (0.0,)))], **kw))
    tr = simulate(Model(constraints=[Constraint.servo("p", "x'''' - s", ["1"], initial=(1.0, 0.0))], **kw),
                  times=[0.0, 0.5])
    assert tr.controls["p"]["order"] == 4 and tr.diagnostics["energy_balance_relative"] < 1e-8
