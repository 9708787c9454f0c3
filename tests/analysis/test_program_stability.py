"""Stability along a programmed (servo) motion: A(t) on the constraint manifold, the verdict
from the fundamental matrix / Persidsky's bound, the time-varying controllability W(t)."""

import numpy as np
import pytest

from nonideal.analysis.stability.program import linearize_program
from nonideal.modeling.model import Constraint, Model

K, B_, V = 4.0, 0.5, 0.8


def servo_model(b=B_):
    """x follows the programme x = v t (a servo force along x); y is a damped oscillator whose
    stiffness grows along the programme: A(t) = [[0, 1], [-k (1 + x(t)), -b]]."""
    return Model("programmed stiffness", ["x", "y"], {"k": K, "b": b, "v": V, "u": 0.0},
                 kinetic="(x'^2 + y'^2)/2", potential="k*(1 + x)*y^2/2", forces={"y": "-b*y' + u"},
                 constraints=[Constraint.servo("programme", "x - v*t", reaction=["1", "0"])],
                 initial={"x": 0.0, "y": 0.0, "x'": V, "y'": 0.0}, simulation={"t_end": 4.0})


def test_A_of_t_follows_the_programme_and_the_servo_coordinate_is_eliminated():
    p = linearize_program(servo_model(), controls=["u"], samples=41)
    assert p.variables == ("y", "y'") and p.dependent == ("x", "x'")
    for t, A in zip(p.t, p.A):
        assert np.allclose(A, [[0, 1], [-K * (1 + V * t), -B_]], atol=1e-10)
    assert np.allclose(p.B[:, :, 0], [0, 1])
    assert p.verdict == "asymptotically stable" and p.exponent < 0
    assert np.all(p.controllability_rank == 2)     # W = [B, -A B] = [[0, -1], [1, b]]


def test_undamped_growing_stiffness_is_not_asymptotically_stable():
    p = linearize_program(servo_model(b=0.0), samples=41)
    assert p.verdict != "asymptotically stable"
    # negative damping: the perturbations grow
    q = linearize_program(servo_model(b=-0.4), samples=41)
    assert q.verdict == "unstable" and q.exponent > 0.1


# ---------------------------------------------------------------- a control through the dynamics


def _regulators(M2=0.2):
    """The friction speed regulator's model file (program phi2' = w0 realized by a force on the
    wheel's axle: relative degree 2, order 3) and the reduced programme regulator_persidsky
    (the condition of dynamics n w0 rho rho' = M2 + rho M1/R as a servo-constraint on rho,
    Manglieva & Beknazarov 2022, (3.5)), with the same parameter values."""
    from nonideal import gallery

    full = gallery.load("friction-speed-regulator")
    full = full.replace(parameters={**full.parameters, "M2": M2})
    red = gallery.load("regulator-persidsky")
    pv = full.parameter_values
    red = red.replace(parameters={**red.parameters, "M2": M2, "M1": pv["M1"], "omega0": pv["w0"],
                                  "J1": pv["J1"], "J": pv["J"], "R": pv["R"], "r": pv["r"]},
                      initial={"rho": pv["rho0"]})
    return full, red, pv


def test_a_control_through_the_dynamics_is_linearized_on_the_closed_loop():
    """Manglieva & Beknazarov 2022, (3.11)-(3.13) from the full regulator: the perturbation
    variable is rho (phi2' is held by the program, rho' is fixed by the condition of dynamics),
    A(t) = d/drho [(M2 + rho M1/R)/(n w0 rho)] = -M2/(n w0 rho0(t)^2), the same numbers as the
    reduced programme, and Persidsky's verdict."""
    full, red, pv = _regulators()
    a = linearize_program(full, t_end=1.0, samples=41)
    b = linearize_program(red, t_end=1.0, samples=41)
    assert a.variables == ("rho",) == b.variables
    assert "phi2'" in a.dependent and "rho'" in a.dependent
    assert [k for k, _ in a.held] == ["speed"] and "held_by_program" in a.to_dict()
    n = pv["J1"] / pv["R"] ** 2 + pv["J"] / pv["r"] ** 2
    rho = a.q["rho"]
    assert np.max(np.abs(rho - b.q["rho"])) < 1e-9
    closed = -pv["M2"] / (n * pv["w0"] * rho ** 2)                     # (3.13), derived
    assert np.max(np.abs(a.A[:, 0, 0] - closed)) < 1e-9 * np.abs(closed).max()
    assert np.max(np.abs(a.A - b.A)) < 1e-9 * np.abs(closed).max()
    assert a.exponent == pytest.approx(b.exponent, rel=1e-9, abs=1e-12)
    assert a.persidsky_alpha == pytest.approx(b.persidsky_alpha, rel=1e-9)
    assert a.verdict == b.verdict == "asymptotically stable"
    # M2 < 0 with M1 large enough for the programme to run: both unstable
    a2 = linearize_program(_regulators(M2=-0.05)[0].replace(
        parameters={**full.parameters, "M2": -0.05, "M1": 0.6}), t_end=0.5, samples=21)
    assert a2.verdict == "unstable" and np.all(a2.A[:, 0, 0] > 0)


def test_the_closed_loop_linearization_follows_the_nonlinear_regulator():
    """Independent check by simulation: the nonlinear regulator started from rho0 + d (phi2'
    still w0) departs from the programme by d exp(int A dt), A from the library."""
    from nonideal.simulation import simulate

    full, _, pv = _regulators()
    lin = linearize_program(full, t_end=1.0, samples=41)
    d = 1e-6
    pert = full.replace(parameters={**full.parameters, "rho0": pv["rho0"] + d})
    t0 = simulate(full, t_end=1.0, times=lin.t)
    t1 = simulate(pert, t_end=1.0, times=lin.t)
    j = list(full.coordinates).index("rho")
    ratio = (t1.q[:, j] - t0.q[:, j]) / d
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (lin.A[1:, 0, 0] + lin.A[:-1, 0, 0]) * np.diff(lin.t))])
    assert np.max(np.abs(ratio - np.exp(integral))) < 5e-4
    assert ratio[-1] < 0.8          # the deviation decays (asymptotic stability)
