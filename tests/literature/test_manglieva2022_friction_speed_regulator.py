"""The friction speed regulator of Manglieva & Beknazarov 2022, ch. 3 ((3.1)-(3.10), fig. 3.3):
a servo-constraint phi2' = w0 whose control (a force on the wheel's axle) reaches the program
only through the dynamics.  The library differentiates the program until the control appears
(order 3) and the tests check the paper's equations, as derived (misprints documented in the
gallery module), against the simulated motion."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from nonideal import gallery
from nonideal.analysis.checks import check_model
from nonideal.equations.dynamics import dynamics_of
from nonideal.errors import IndeterminateSystem, InconsistentInitialConditions, MechanicsError
from nonideal.gallery import friction_speed_regulator as reg
from nonideal.modeling.model import Constraint, Model
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

TIMES = np.linspace(0.0, 1.0, 101)


@pytest.fixture(scope="module")
def regulator():
    model = gallery.load(reg.NAME)
    return model, simulate(model, times=TIMES)


def test_the_control_appears_in_the_third_derivative(regulator):
    model, _ = regulator
    reach = dynamics_of(model).servo_reach["speed"]
    assert reach.order == 3 and reach.differentiated == 1
    report = check_model(model)
    assert [c["control_order"] for c in report.constraints if c["name"] == "speed"] == [3]
    assert any("order 3" in note and "(3.3)" in note for note in report.notes)
    # rho'(0) is fixed by the condition of dynamics (3.3), not given in the file
    assert report.initial["rho'"] == pytest.approx(reg.riccati_rate(model.parameter_values["rho0"],
                                                                    model.parameter_values), rel=1e-12)


def test_appell_equations_3_3_along_the_motion(regulator):
    model, tr = regulator
    p = model.parameter_values
    rho, rhod = tr.coordinate("rho"), tr.velocity("rho")
    assert np.max(np.abs(tr.velocity("phi2") - p["w0"])) < 1e-9          # the program (3.1)
    lhs = p["w0"] * rho * rhod * (p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2)
    assert np.max(np.abs(lhs - (p["M2"] + rho * p["M1"] / p["R"]))) < 1e-9
    u = tr.multipliers["speed"]
    assert np.max(np.abs(p["m"] * tr.qdd[:, 3] - (-p["f"] * (p["N1"] + p["N2"]) + u))) < 1e-10


def test_riccati_3_5_quadrature_3_10_and_control_force_3_9(regulator):
    model, tr = regulator
    p = model.parameter_values
    rho = tr.coordinate("rho")
    assert np.max(np.abs(tr.velocity("rho") - reg.riccati_rate(rho, p))) < 1e-10
    assert np.max(np.abs(reg.quadrature_time(rho, p) - TIMES)) < 1e-8        # (3.10)
    assert rho[-1] - rho[0] > 0.04                                           # it moved
    u = tr.controls["speed"]["force"]
    assert np.max(np.abs(u - reg.control_force(rho, p))) < 1e-8              # (3.9), corrected
    # the printed sign of the friction term in (3.9) would be off by 2 f (N1 + N2)
    printed = reg.control_force(rho, p) - 2 * p["f"] * (p["N1"] + p["N2"])
    assert np.min(np.abs(u - printed)) > 1.0


def test_eps_series_3_7_3_8_error_is_third_order():
    # the two-term series rho0 + eps rho1 + eps^2 rho2 misses O(eps^3): doubling w0 (eps/2)
    # divides the error by 8
    e1 = reg._series_error(2000.0, 1.0)
    e2 = reg._series_error(4000.0, 1.0)
    assert 7.0 < e1 / e2 < 9.0
    assert e1 < 1e-7


def test_second_regulator_of_fig_3_3_against_its_scalar_equation():
    model = load_model(gallery.HERE / reg.FILE_2)
    p = model.parameter_values
    tr = simulate(model, times=TIMES)
    ref = solve_ivp(lambda t, y: reg.second_regulator_rate(y, p), (0.0, 1.0), [p["rho0"]],
                    t_eval=TIMES, rtol=1e-12, atol=1e-14, method="DOP853")
    assert np.max(np.abs(tr.coordinate("rho") - ref.y[0])) < 1e-9
    assert tr.velocity("rho").max() < 0          # towards shaft 1: the printed sign is wrong
    # m rho'' = u + f (N1 + N2), as printed (the friction acts along +rho since rho' < 0)
    u = tr.controls["speed"]["force"]
    assert np.max(np.abs(p["m"] * tr.qdd[:, 3] - u - p["f"] * (p["N1"] + p["N2"]))) < 1e-10


def test_control_outputs_power_and_work(regulator, tmp_path):
    model, tr = regulator
    c = tr.controls["speed"]
    assert c["order"] == 3
    # the rolling constraints are ideal and scleronomic: the reactions' work is the control's
    np.testing.assert_allclose(c["work"], tr.energy["reaction_work"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(c["power"], c["force"] * tr.velocity("rho"), rtol=1e-13)
    d = tr.to_dict()
    assert set(d["controls"]["speed"]) == {"force", "power", "work", "order"}
    tr.to_csv(tmp_path / "out.csv")
    header = (tmp_path / "out.csv").read_text().splitlines()[0].split(",")
    assert {"u_speed", "P_speed", "W_speed"} <= set(header)


def test_a_wrong_programmed_speed_at_t0_is_named():
    model = reg.build(t_end=0.1)
    bad = model.replace(initial={**model.initial, "phi2'": 19})
    with pytest.raises(InconsistentInitialConditions, match="'speed' is violated by the initial velocities"):
        simulate(bad)


def _oscillators(program, reaction):
    return Model(name="two oscillators", coordinates=["x", "y"], parameters={"m": 1.0, "k": 2.0, "g": 9.81},
                 kinetic="m/2*(x'^2 + y'^2)", potential="k/2*(x^2 + y^2)",
                 constraints=[Constraint.servo("prog", program, reaction)],
                 initial={"x": 0, "y": 0, "x'": 0, "y'": 0.1}, simulation={"t_end": 0.5})


def test_a_program_the_control_never_reaches_is_exit_3_with_the_order_tried():
    # uncoupled: the force on x never appears in any derivative of y
    with pytest.raises(MechanicsError, match="'prog'.*up to order 10") as info:
        simulate(_oscillators("y - 0.1*sin(t)", ["1", "0"]))
    assert info.value.exit_code == 3 and info.value.details["order_tried"] == 10


def test_a_program_kept_by_the_motion_itself_leaves_the_control_indeterminate():
    # x'' = -k x/m does not involve the control along y at any order; x' = 0 with x = 0 is
    # kept by itself: the control is not determined (Beghin: indeterminate)
    model = Model(name="free", coordinates=["x", "y"], parameters={"m": 1.0},
                  kinetic="m/2*(x'^2 + y'^2)",
                  constraints=[Constraint.servo("prog", "x' - 1", ["0", "1"])],
                  initial={"x": 0, "y": 0, "x'": 1, "y'": 0}, simulation={"t_end": 0.5})
    with pytest.raises(IndeterminateSystem, match="'prog'.*order 2 is 0 = 0, identically"):
        simulate(model)


def test_an_ordinary_servo_constraint_is_not_differentiated():
    model = load_model(DATA_DIR / "servo_parabola.toml")
    reach = dynamics_of(model).servo_reach["program"]
    assert reach.order == 2 and reach.conditions == ()


def test_beghin_remark_the_motion_ignores_the_auxiliary_system():
    # Beghin's special cases 3-4 (Appell 1911, servo-constraints, remark 2): when the reactions
    # of the second kind come from an auxiliary body (here the wheel's carriage, moved by u),
    # the programmed motion does not depend on that body's inertia nor on the forces on it --
    # only the control does
    times = np.linspace(0.0, 0.5, 6)
    base = simulate(reg.build(t_end=0.5), times=times)
    other = simulate(reg.build(t_end=0.5, m=5.0, f=0.6), times=times)
    assert np.max(np.abs(other.q - base.q)) < 1e-10
    u_base, u_other = base.controls["speed"]["force"], other.controls["speed"]["force"]
    p = reg.DEFAULTS
    # u = m rho'' + f (N1 + N2): the difference is the carriage's own inertia and friction
    expected = (5.0 - p["m"]) * base.qdd[:, 3] + (0.6 - p["f"]) * (p["N1"] + p["N2"])
    assert np.max(np.abs(u_other - u_base - expected)) < 1e-9


def test_a_program_unreachable_at_t0_is_exit_3_with_the_order_tried():
    # with the wheel at the axis of shaft 2 (rho = 0) it transmits no torque: the condition of
    # dynamics (3.3) reads M2 = 0 whatever rho' -- the control cannot keep phi2' = w0 from there
    with pytest.raises(MechanicsError, match="'speed' cannot be kept from the initial state") as info:
        simulate(reg.build(t_end=0.1, rho0=0.0))
    assert info.value.exit_code == 3
    assert info.value.details == {"program": "speed", "order_tried": 3}
