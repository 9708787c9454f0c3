"""The rattleback with Kane & Levinson's 1982 data (ellipsoid bottom, semi-axes 20, 3, 2 cm,
centre 1 cm above the centre of mass, A, B, C, D = 2, 16, 17, -0.2 cm^2 per unit mass), the
contact declared by its shape only; and the linear analysis of both gallery rattlebacks.

Cross-checks, each independent of the library:

* the Newton-Euler equations of a body rolling on a horizontal plane written by hand in the
  body frame (state: the up normal n and omega in body axes; r(n) = h e_z - D^2 n / sqrt(n^T
  D^2 n) the vector from the centre of mass to the ellipsoid's support point, D = diag(a, b, c)),

      n' = n x omega,
      [I + m (|r|^2 E - r r^T)] omega' = -omega x I omega + m r x (-omega x r' - omega x (omega x r) + g n),

  integrated with SciPy: the spin omega . n and its reversal time;
* the same equations linearized (a numerical Jacobian) about the steady spin n = e_z, omega =
  s e_z: their four nonzero eigenvalues against those of ``nonideal stability --about steady``
  (called once from the command line);
* at rest, the two rocking frequencies in closed form, omega^2 = eig(M^-1 K) with the inertia
  about the contact point M = I_xy + m h_G^2 E and the stiffness K = m g diag(rho_y - h_G,
  rho_x - h_G) (rho the radii of curvature of the bottom at its lowest point, h_G the height of
  the centre of mass over it).
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from nonideal import gallery
from nonideal.analysis.stability.linearize import linearize as stability
from nonideal.gallery import rattleback as paraboloid_example
from nonideal.gallery import rattleback_ellipsoid as example

ROOT = Path(__file__).resolve().parents[2]
P = {k: float(v) for k, v in gallery.load(example.NAME).parameter_values.items()}


def _ellipsoid_r(p):
    n = sp.Matrix(sp.symbols("n1:4"))
    d2 = [p["a"] ** 2, p["b"] ** 2, p["c"] ** 2]
    eps = sp.sqrt(sum(d2[i] * n[i] ** 2 for i in range(3)))
    return n, sp.Matrix([-d2[0] * n[0] / eps, -d2[1] * n[1] / eps, p["h"] - d2[2] * n[2] / eps])


def _hand_derived_rhs(p, n, r, I):
    r_f = sp.lambdify([n], r, "numpy")
    J_f = sp.lambdify([n], r.jacobian(n), "numpy")
    m, g = p["m"], p["g"]

    def rhs(t, y):
        nb, w = y[:3], y[3:]
        rv = np.asarray(r_f(nb), float).ravel()
        nd = np.cross(nb, w)
        rd = np.asarray(J_f(nb), float) @ nd
        K = I + m * (rv @ rv * np.eye(3) - np.outer(rv, rv))
        f = -np.cross(w, I @ w) + m * np.cross(rv, -np.cross(w, rd) - np.cross(w, np.cross(w, rv)) + g * nb)
        return np.concatenate([nd, np.linalg.solve(K, f)])
    return rhs


def _ellipsoid_rhs(p):
    n, r = _ellipsoid_r(p)
    I = np.array([[p["A"], p["D"], 0], [p["D"], p["B"], 0], [0, 0, p["C"]]])
    return _hand_derived_rhs(p, n, r, I)


def _paraboloid_rhs(p):
    n = sp.Matrix(sp.symbols("n1:4"))
    r = sp.Matrix([-p["ra"] * n[0] / n[2], -p["rb"] * n[1] / n[2],
                   (p["ra"] * n[0] ** 2 + p["rb"] * n[1] ** 2) / (2 * n[2] ** 2) - p["h"]])
    d = p["delta"]
    Rd = np.array([[np.cos(d), -np.sin(d), 0], [np.sin(d), np.cos(d), 0], [0, 0, 1]])
    return _hand_derived_rhs(p, n, r, Rd @ np.diag([p["A"], p["B"], p["C"]]) @ Rd.T)


def _linearized(rhs, s):
    """The four nonzero eigenvalues of the hand-derived equations about n = e_z, omega = s e_z."""
    y0 = np.array([0, 0, 1, 0, 0, s], float)
    J = np.empty((6, 6))
    for k in range(6):
        e = np.zeros(6)
        e[k] = 1e-6
        J[:, k] = (rhs(0, y0 + e) - rhs(0, y0 - e)) / 2e-6
    lam = np.linalg.eigvals(J)
    return np.sort_complex(lam[np.argsort(np.abs(lam))][2:])  # |n| and the spin level: two zeros


def _sorted(values):
    return np.sort_complex(np.array(values, dtype=complex))


@pytest.fixture(scope="module")
def reversal():
    return example.check(gallery.load(example.NAME), t_end=4.0, samples=801)


def test_spin_reverses_as_the_independent_derivation_says(reversal):
    t = reversal["t"]
    Ry = np.array([[np.cos(0.01), 0, np.sin(0.01)], [0, 1, 0], [-np.sin(0.01), 0, np.cos(0.01)]])
    y0 = np.concatenate([Ry.T @ [0, 0, 1], Ry.T @ [0, 0, P["w0"]]])
    sol = solve_ivp(_ellipsoid_rhs(P), (t[0], t[-1]), y0, t_eval=t, method="DOP853", rtol=1e-11, atol=1e-13)
    w_ref = np.einsum("ij,ij->j", sol.y[:3], sol.y[3:])
    assert np.max(np.abs(reversal["spin"] - w_ref)) < 1e-5
    t_ref = paraboloid_example.reversal_time(t, w_ref)
    assert reversal["reversal_time"] == pytest.approx(t_ref, rel=1e-5)
    assert 2.0 < reversal["reversal_time"] < 2.4        # 2.2 s for Kane & Levinson's data at w0 = -3
    assert reversal["spin"][-1] > 2.0                     # reversed, not merely stopped (2.43 at t = 4 s)
    assert reversal["energy_drift"] < 1e-6 and reversal["normal_min"] > 0 and not reversal["events"]


def test_rocking_frequencies_at_rest_are_the_closed_form():
    res = stability(gallery.load(example.NAME), about="equilibrium", at={"roll": 0.0, "pitch": 0.0, "psi'": 0.0})
    lam = _sorted(res.eigenvalues)
    assert np.max(np.abs(lam.real)) < 1e-8
    freqs = np.sort(lam.imag[lam.imag > 1e-6])  # (and the spin's zero: a family of steady spins)
    assert freqs == pytest.approx(example.rocking_frequencies(P), rel=1e-8)
    assert freqs == pytest.approx([33.829, 107.208], abs=1e-3)  # pitching, rolling (rad/s)


@pytest.mark.parametrize("s", [-3.0, -0.5, 0.5, 3.0])
def test_linear_analysis_about_steady_spin_matches_the_independent_linearization(s):
    res = stability(gallery.load(example.NAME), about="steady", at={"roll": 0.0, "pitch": 0.0, "psi'": s})
    ref = _linearized(_ellipsoid_rhs(P), s)
    assert np.max(np.abs(_sorted(res.eigenvalues) - ref)) < 1e-5 * np.max(np.abs(ref))
    # the steady spin is unstable in both directions (a reversal either way without dissipation)
    assert max(np.real(res.eigenvalues)) > 1e-3 * abs(s)


def test_paraboloid_rattleback_linear_analysis_matches_too():
    p = {k: float(v) for k, v in gallery.load(paraboloid_example.NAME).parameter_values.items()}
    res = stability(gallery.load(paraboloid_example.NAME), about="steady", at={"a": 0.0, "b": 0.0, "psi'": -2.0})
    ref = _linearized(_paraboloid_rhs(p), -2.0)
    assert np.max(np.abs(_sorted(res.eigenvalues) - ref)) < 1e-5 * np.max(np.abs(ref))


def test_command_line_stability_about_the_steady_spin():
    out = subprocess.run([sys.executable, "-m", "nonideal", "stability", example.NAME, "--about", "steady",
                          "--at", "psi'=-3, roll=0, pitch=0", "--json"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    lam = _sorted([complex(re, im) for re, im in data["eigenvalues"]])
    ref = _linearized(_ellipsoid_rhs(P), -3.0)
    assert np.max(np.abs(lam - ref)) < 1e-5 * np.max(np.abs(ref))
    assert "unstable" in json.dumps(data)
