"""Manglieva & Beknazarov 2022, sec. 3.2: the released regulator along its programme -- A(t)
against the corrected (3.29), the controllability matrix W(t) (3.30)-(3.32) against its
derivation, and optimal stabilization by the differential Riccati equation (3.33)-(3.37)."""

import numpy as np
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
