"""Manglieva & Beknazarov 2022, sec. 3.2: the released regulator along its programme -- A(t)
against the corrected (3.29), the controllability matrix W(t) (3.30)-(3.32) against its
derivation, and optimal stabilization by the differential Riccati equation (3.33)-(3.37)."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from nonideal import gallery
from nonideal.analysis.stability.control import program_lqr
from nonideal.analysis.stability.program import linearize_program

MOD = gallery.module("regulator-release")


def test_A_W_and_optimal_stabilization_along_the_programme():
    prog = linearize_program(gallery.load("regulator-release"), controls=["u1"], samples=81)
    rho, rd, A_ref, W_ref = MOD.closed_forms(prog.t)
    assert prog.variables == ("rho", "phi2'", "rho'") and set(prog.ignorable) == {"phi1", "phi", "phi2"}
    assert np.max(np.abs(prog.q["rho"] - rho)) < 1e-8 and np.max(np.abs(prog.qdot["phi2"] - 20.0)) < 1e-8
    assert np.max(np.abs(prog.A - A_ref)) < 1e-8 * np.max(np.abs(A_ref))
    inner = slice(8, -8)
    scale = np.max(np.abs(W_ref[inner]))
    assert np.max(np.abs(prog.W[inner] - W_ref[inner])) < 1e-4 * scale
    assert np.all(prog.controllability_rank == 3)
    reg = program_lqr(prog)
    # P solves the differential Riccati equation: check with its spline derivative inside
    dP = CubicSpline(reg.t, reg.P, axis=0).derivative()(reg.t)
    for k in range(10, len(reg.t) - 10, 10):
        A, B, P = prog.A[k], prog.B[k], reg.P[k]
        res = dP[k] + A.T @ P + P @ A - P @ B @ B.T @ P + np.eye(3)
        terms = np.max(np.abs(A.T @ P)) + np.max(np.abs(P @ B @ B.T @ P)) + 1.0
        assert np.max(np.abs(res)) < 1e-4 * terms
    assert reg.exponent_open > 1.0 and reg.exponent_closed < 0


def test_3_37_feedback_on_z_is_the_z_squared_coefficient():
    """u1 = -B^T P x: the feedback on z = rho'_dot is the coefficient of z^2 in V = x^T P x
    (C22 in the labelling of (3.35), as the printed dB/du1 = 0 says), not the rho'^2 one (C33,
    as (3.37) prints it).  In the library's order (rho, phi2', rho'): K = P[2, :]/m."""
    prog = linearize_program(gallery.load("regulator-release"), controls=["u1"], samples=41)
    reg = program_lqr(prog)
    m = MOD.DEFAULTS["m"]
    for k in range(5, len(reg.t) - 5, 5):
        P, K = reg.P[k], reg.K[k]
        assert np.allclose(K[0], P[2] / m, rtol=1e-9, atol=1e-12)
        assert abs(K[0, 2] - P[0, 0] / m) > 0.1 * abs(K[0, 2])


def test_det_W_along_the_programme():
    """det W = (M2 R n rho0 - J2 M1)/(R m^3 D^2) (derived for any M1): at M1 = 0 it is the
    determinant of the library's W(t); with M1 = 0.75 it vanishes at rho0 = J2 M1/(M2 R n) =
    0.125 m for the example's numbers (the paper's "rank W = 3" fails there)."""
    prog = linearize_program(gallery.load("regulator-release"), controls=["u1"], samples=81)
    inner = slice(8, -8)
    dets = np.linalg.det(prog.W[inner])
    ref = MOD.det_W(prog.q["rho"][inner])
    assert np.max(np.abs(dets - ref)) < 1e-3 * np.max(np.abs(ref))
    p = MOD.DEFAULTS
    n = p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2
    star = p["J2"] * 0.75 / (p["M2"] * p["R"] * n)
    assert star == np.float64(0.125) or abs(star - 0.125) < 1e-12
    assert abs(MOD.det_W(star, M1=0.75)) < 1e-12
    assert MOD.det_W(0.9 * star, M1=0.75) < 0 < MOD.det_W(1.1 * star, M1=0.75)


def _model_m1():
    from nonideal.modeling.modelfile import load_model

    return load_model(gallery.HERE / MOD.FILE_M1)


def test_M1_programme_3_10_and_W_before_the_lost_rank():
    """M1 = 0.3 (fig. 3.2's numbers): the programme is the implicit (3.10), rho0(t) a Lambert-W
    time law; on [0, 1] (before rho0 = 0.125) the library follows it, its W(t) is the derived
    one and det W = (M2 R n rho0 - J2 M1)/(R m^3 D^2) (negative: rho0 < 0.125), rank 3."""
    model = _model_m1()
    p = model.parameter_values
    prog = linearize_program(model, controls=["u1"], samples=81)
    rho, rd = MOD.programme_m1(prog.t, p)
    assert np.max(np.abs(prog.q["rho"] - rho)) < 1e-9 and np.max(np.abs(prog.qdot["rho"] - rd)) < 1e-9
    assert MOD.t_of_rho(rho[-1], p) == pytest.approx(prog.t[-1], rel=1e-9)       # (3.10) itself
    inner = slice(8, -8)
    W = MOD.closed_forms_m1(prog.q["rho"], p)
    assert np.max(np.abs(prog.W[inner] - W[inner])) < 1e-4 * np.max(np.abs(W[inner]))
    ref = MOD.det_W(prog.q["rho"][inner], p, M1=p["M1"])
    assert np.all(ref < 0)
    assert np.max(np.abs(np.linalg.det(prog.W[inner]) - ref)) < 1e-4 * np.max(np.abs(ref))
    assert np.all(prog.controllability_rank == 3)


def test_M1_lost_rank_at_rho0_0_125_is_reported():
    """Over [0, 2.5] the programme passes rho0* = J2 M1/(M2 R n) = 0.125 m at t* from (3.10)
    (1.6762 s): det W changes sign there and the library stops with a MechanicsError (exit 3)
    naming the instant and the state, instead of "rank 3" and a stabilization built on it."""
    from nonideal.errors import MechanicsError

    model = _model_m1()
    p = model.parameter_values
    star = p["J2"] * p["M1"] / (p["M2"] * p["R"] * MOD._n(p))
    assert star == pytest.approx(0.125, rel=1e-12)
    t_star = float(MOD.t_of_rho(star, p))
    assert t_star == pytest.approx(1.67617, abs=1e-4)
    with pytest.raises(MechanicsError) as err:
        linearize_program(model, t_end=2.5, controls=["u1"], samples=201)
    e = err.value
    assert e.t == pytest.approx(t_star, abs=1e-4)
    assert e.state["rho"] == pytest.approx(star, rel=1e-4)
    assert "loses controllability" in str(e) and "det W changes sign" in str(e)


def test_M1_lost_rank_cli_exit_3_and_runs_before_it():
    from tests.helpers import run_cli

    path = str(gallery.HERE / MOD.FILE_M1)
    out = run_cli("stability", path, "--about", "program", "--controls", "u1", "--t-end", "2.5")
    assert out.returncode == 3 and "rho = 0.125" in out.stderr and "t = 1.676" in out.stderr
    assert out.stdout == ""
    out = run_cli("stability", path, "--about", "program", "--controls", "u1")
    assert out.returncode == 0 and "rank 3 to 3 of 3" in out.stdout
