"""The rattleback of Kane & Levinson 1982 (half an ellipsoid, their parameters), the contact
declared by its shape only: spun at -5 rad/s it reverses, spun at +5 rad/s it does not.

Cross-check: the Newton-Euler equations of a body rolling on a horizontal plane, written here
by hand in the body frame (state: the up normal n and the angular velocity omega in body
axes; r(n) = (0, 0, h) - D^2 n / sqrt(n^T D^2 n), D = diag(a, b, c), the vector from the
centre of mass to the support point of the ellipsoid):

    n' = n x omega,
    [I + m (|r|^2 E - r r^T)] omega' = -omega x I omega
                                       + m r x (-omega x r' - omega x (omega x r) + g n),

integrated with SciPy (rtol 1e-11): the spin omega . n agrees with the library's, and so do the
reversal time and the growth of the pitching mode.
"""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from nonideal import gallery
from nonideal.gallery import rattleback_ellipsoid as example

P = example.PARAMETERS


def _hand_derived_rhs(p):
    n = sp.Matrix(sp.symbols("n1:4"))
    d2 = [p["a"] ** 2, p["b"] ** 2, p["c"] ** 2]
    r = sp.Matrix([0, 0, p["h"]]) - sp.Matrix([d2[i] * n[i] for i in range(3)]) / sp.sqrt(
        sum(d2[i] * n[i] ** 2 for i in range(3)))
    r_f = sp.lambdify([n], r, "numpy")
    J_f = sp.lambdify([n], r.jacobian(n), "numpy")
    I = np.array([[p["A"], p["D"], 0], [p["D"], p["B"], 0], [0, 0, p["C"]]])
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


def _independent(w0, t):
    # R = Rz(psi) Rx(al) Ry(be) at psi = 0, al = be = tilt: n_b = R^T e_z; omega = w0 e_z in N
    c, s = np.cos(P["tilt"]), np.sin(P["tilt"])
    Rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    Ry = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    R = Rx @ Ry
    y0 = np.concatenate([R.T @ [0, 0, 1], R.T @ [0, 0, w0]])
    sol = solve_ivp(_hand_derived_rhs(P), (t[0], t[-1]), y0, t_eval=t, method="DOP853",
                    rtol=1e-11, atol=1e-13)
    return np.einsum("ij,ij->j", sol.y[:3], sol.y[3:]), sol.y[:3]


@pytest.fixture(scope="module")
def reversing():
    return example.check(gallery.load(example.NAME))


@pytest.fixture(scope="module")
def reference(reversing):
    return _independent(P["w0"], reversing["t"])


def test_spin_reverses_as_in_the_independent_derivation(reversing, reference):
    t = reversing["t"]
    w_ref, _ = reference
    assert np.max(np.abs(reversing["spin"] - w_ref)) < 1e-6
    t_ref = example.reversal_time(t, w_ref)
    assert reversing["reversal_time"] == pytest.approx(t_ref, rel=1e-6)
    assert 2.7 < reversing["reversal_time"] < 2.8          # 2.7605 s
    assert reversing["spin"][-1] > 5.0                     # reversed, not merely stopped


def test_the_normal_follows_the_independent_derivation(reversing, reference):
    # the pitch/roll motion itself, not only the spin: the up normal in body axes
    tr = reversing["trajectory"]
    _, n_ref = reference
    al, be = tr.coordinate("al"), tr.coordinate("be")
    n = np.array([-np.cos(al) * np.sin(be), np.sin(al), np.cos(al) * np.cos(be)])  # (Rx Ry)^T e_z
    assert np.max(np.abs(n - n_ref)) < 1e-7
    assert np.max(np.abs(n_ref[0])) > 5 * abs(n_ref[0, 0])       # the pitching grew 6-fold


def test_spun_the_other_way_it_keeps_spinning():
    other = example.check(example.build(w0=5.0), samples=601)
    assert other["reversal_time"] is None and other["spin"].min() > 3.5
    w_ref, _ = _independent(5.0, other["t"])
    assert np.max(np.abs(other["spin"] - w_ref)) < 1e-6


def test_rolling_conserves_energy_and_stays_in_contact(reversing):
    assert reversing["energy_drift"] < 1e-7
    assert reversing["normal_min"] > 0 and not reversing["events"]


def test_the_command_line_runs_the_file(tmp_path):
    import json
    import subprocess
    import sys

    out = tmp_path / "r.json"
    subprocess.run([sys.executable, "-m", "nonideal", "simulate", example.NAME,
                    "--t-end", "4.0", "--times", "0,2,4", "--json", str(out)], check=True,
                   capture_output=True)
    d = json.loads(out.read_text())
    w = np.array(d["qdot"]["psi"]) + np.array(d["qdot"]["be"]) * np.sin(np.array(d["q"]["al"]))
    assert w[0] == -5.0 and w[1] < -1.0 and w[2] > 2.5       # reversed between 2 and 4 s


def _stability(tmp_path, spin):
    import json
    import subprocess
    import sys

    out = tmp_path / f"s{spin}.json"
    subprocess.run([sys.executable, "-m", "nonideal", "stability", example.NAME, "--about", "steady",
                    "--at", f"al=0, be=0, psi'={spin}", "--json", str(out)], check=True, capture_output=True)
    d = json.loads(out.read_text())
    return np.array([complex(re, im) for re, im in d["eigenvalues"]]), d


def _sorted(ev):
    return np.array(sorted(ev, key=lambda z: (round(abs(z.imag), 6), z.imag)))


def test_at_rest_the_rocking_frequencies_are_the_closed_form(tmp_path):
    # small rocking about the lowest point: M x'' + K x = 0 with the radii of curvature of the
    # bottom a^2/c (pitch, about y) and b^2/c (roll, about x) and l = c - h the height of G
    p = P
    l = p["c"] - p["h"]
    M = np.array([[p["A"] + p["m"] * l ** 2, p["D"]], [p["D"], p["B"] + p["m"] * l ** 2]])
    K = p["m"] * p["g"] * np.diag([p["b"] ** 2 / p["c"] - l, p["a"] ** 2 / p["c"] - l])
    w = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    ev, _ = _stability(tmp_path, 0)
    ev = ev[np.abs(ev) > 1e-6]                # at rest the spin is one more variable: a zero
    assert len(ev) == 4 and np.max(np.abs(ev.real)) < 1e-9
    assert np.sort(np.abs(ev.imag))[::2] == pytest.approx(w, rel=1e-9)    # 33.83, 107.21 rad/s


@pytest.mark.parametrize("spin", [-5.0, -0.5, 0.5, 5.0])
def test_the_linearized_spin_is_the_independent_one(tmp_path, spin):
    rhs = _hand_derived_rhs(P)
    y = np.array([0, 0, 1, 0, 0, spin], float)
    h = 1e-6
    J = np.column_stack([(rhs(0, y + h * e) - rhs(0, y - h * e)) / (2 * h) for e in np.eye(6)])
    ref = np.linalg.eigvals(J)
    ref = ref[np.abs(ref) > 1e-3]            # |n| = 1 and the family of spins: two zeros
    ev, d = _stability(tmp_path, spin)
    assert np.max(np.abs(_sorted(ev) - _sorted(ref))) < 1e-5
    growing = max(ev, key=lambda z: z.real)
    # spun one way the pitching mode (107 rad/s) grows ten times faster than the rolling mode
    # (34 rad/s) grows when spun the other way: the rattleback's preferred direction
    assert growing.real > 0 and (abs(growing.imag) > 100) == (spin < 0)
    assert d["verdict"] == "unstable"
