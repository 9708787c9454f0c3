"""The rattleback (Garcia & Hubbard 1988; Lindberg & Longman 1983): spin reversal of a
paraboloid bottom rolling on a plane, the contact declared by its shape only.

Cross-check: the Newton-Euler equations of a body rolling on a horizontal plane, written here
by hand in the body frame (state: the up normal n and the angular velocity omega in body
axes; r = r(n) the vector from the centre of mass to the support point of the paraboloid),

    n' = n x omega,
    [I + m (|r|^2 E - r r^T)] omega' = -omega x I omega
                                       + m r x (-omega x r' - omega x (omega x r) + g n),

integrated with SciPy: the spin omega . n and its reversal time agree with the library's.
"""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from nonideal import gallery
from nonideal.gallery import rattleback as example

P = example.PARAMETERS


def _hand_derived_rhs(p):
    n = sp.Matrix(sp.symbols("n1:4"))
    ra, rb, h = p["ra"], p["rb"], p["h"]
    r = sp.Matrix([-ra * n[0] / n[2], -rb * n[1] / n[2],
                   (ra * n[0] ** 2 + rb * n[1] ** 2) / (2 * n[2] ** 2) - h])
    r_f = sp.lambdify([n], r, "numpy")
    J_f = sp.lambdify([n], r.jacobian(n), "numpy")
    d = p["delta"]
    Rd = np.array([[np.cos(d), -np.sin(d), 0], [np.sin(d), np.cos(d), 0], [0, 0, 1]])
    I = Rd @ np.diag([p["A"], p["B"], p["C"]]) @ Rd.T
    m, g = p["m"], p["g"]

    def rhs(t, y):
        nb, w = y[:3], y[3:]
        r = np.asarray(r_f(nb), float).ravel()
        nd = np.cross(nb, w)
        rd = np.asarray(J_f(nb), float) @ nd
        K = I + m * (r @ r * np.eye(3) - np.outer(r, r))
        f = -np.cross(w, I @ w) + m * np.cross(r, -np.cross(w, rd) - np.cross(w, np.cross(w, r)) + g * nb)
        return np.concatenate([nd, np.linalg.solve(K, f)])
    return rhs


def _independent(w0, pitch, t):
    # R = Rz(psi) Rx(a) Ry(b) at psi = a = 0, b = pitch: n_b = R^T e_z; omega = w0 e_z in N
    Ry = np.array([[np.cos(pitch), 0, np.sin(pitch)], [0, 1, 0], [-np.sin(pitch), 0, np.cos(pitch)]])
    y0 = np.concatenate([Ry.T @ [0, 0, 1], Ry.T @ [0, 0, w0]])
    sol = solve_ivp(_hand_derived_rhs(P), (t[0], t[-1]), y0, t_eval=t, method="DOP853", rtol=1e-11, atol=1e-13)
    return np.einsum("ij,ij->j", sol.y[:3], sol.y[3:])


@pytest.fixture(scope="module")
def unstable():
    return example.check(gallery.load(example.NAME))


def test_spin_reverses_at_the_time_of_the_independent_derivation(unstable):
    t = unstable["t"]
    w_ref = _independent(P["w0"], 0.01, t)
    assert np.max(np.abs(unstable["spin"] - w_ref)) < 1e-6
    t_ref = example.reversal_time(t, w_ref)
    assert unstable["reversal_time"] == pytest.approx(t_ref, rel=1e-6)
    assert 2.7 < unstable["reversal_time"] < 2.8          # 2.7472 s for the file's data
    assert unstable["spin"][-1] > 1.9                     # the spin reversed, not merely stopped


def test_the_other_direction_keeps_spinning_much_longer(unstable):
    other = example.check(example.build(w0=2.0, t_end=8.0), samples=801)
    assert other["reversal_time"] is None or other["reversal_time"] > 2.5 * unstable["reversal_time"]
    assert example.reversal_time(other["t"][other["t"] <= 5.0], other["spin"][other["t"] <= 5.0]) is None
    w_ref = _independent(2.0, 0.01, other["t"])
    assert np.max(np.abs(other["spin"] - w_ref)) < 1e-6


def test_rolling_conserves_energy_and_stays_in_contact(unstable):
    assert unstable["energy_drift"] < 1e-8
    assert unstable["normal_min"] > 0 and not unstable["events"]
