"""The tippe top: a spinning eccentric sphere turns over on its stem -- and why Coulomb's law
alone does not turn it.

Parameters of Leine & Glocker 2003 (Eur. J. Mech. A/Solids 22, sec. 5): a sphere of radius
R = 15 mm whose centre of mass G lies a = 3 mm below its centre O on the symmetry axis k
(body z; O = G + a k), m = 6 g, A = 8e-7 kg m^2 (transverse, about G), C = 7e-7 kg m^2, on a
horizontal table, mu = 0.3, tilted by theta0 = 0.1 rad and spun at 180 rad/s about k, G at
rest.  The contact is the sphere itself (``shape = {type = "sphere", center = [0, 0, a]}``); the
library derives the support point P = O - R e_z, the gap and the slip; the frame turns by Euler
parameters, so theta = 0 and theta = pi (where Z-X-Z angles are singular) are ordinary states.

**Jellett's integral.**  Every contact force F (normal force and friction, whatever the
law) acts at P, so dL/dt = (P - G) x F for the angular momentum L = I omega about G, and with
d = P - G = a k - R e_z,

    d/dt (L . d) = L . d' = a L . (omega x k) = a (A omega + (C - A)(omega . k) k) . (omega x k) = 0

(A = B: L is a combination of omega and k, both orthogonal to omega x k).  Hence

    lambda = L . (a k - R e_z)

is conserved while the sphere touches the table, sliding or rolling (Jellett 1872; at
theta = 0, lambda = -C w3 (R - a)).  ``jellett`` evaluates it from the coordinates and their
rates; the test holds it to the integration tolerance over the whole run.

**When the top can turn over.**  The spinning states theta = 0 and theta = pi with the same
lambda have the energies E_0 = lambda^2/(2 C (R - a)^2) + m g (R - a) and E_pi =
lambda^2/(2 C (R + a)^2) + m g (R + a).  Friction only dissipates, so the inverted state is
reachable only if E_pi < E_0, i.e. lambda^2 > m g C (R^2 - a^2)^2 / R -- here the spin must
exceed ``spin_threshold`` (42.6 rad/s; 180 is given).  The linear stability of the two
states under sliding friction (Bou-Rabee, Marsden & Romero 2004, SIAM J. Appl. Dyn. Syst. 3;
Ueda, Sasaki & Watanabe 2005, their group II) makes theta = 0 unstable and theta = pi stable
for a fast spin exactly when 1 - alpha < C/A < 1 + alpha, alpha = a/R: here 0.8 < 0.875 < 1.2.

**Which friction.**  The inversion needs sliding all the way: in ideal rolling the energy is
conserved and nothing lifts the centre of mass.  With Coulomb's exact law (``build(exact=True)``,
stick/slip switched by events) the initial slip -- the contact point lies off the spin axis,
U0 = W R sin(theta0) = 0.27 m/s -- dies at t* = 36.1 ms; the top then rolls, the friction
staying inside the cone, and does not turn over (theta stays below 0.2 rad).  This is the
rigid point contact's answer under the exact law.  The inverting tops of the literature keep
sliding: Or 1994 and Bou-Rabee et al. with viscous sliding friction, Ueda et al. with a
"modified Coulomb law" continuous at U = 0, Leine & Glocker with Contensou's coupling of
sliding and pivoting friction over a finite contact disk -- the gallery's
``tippe-top-contensou``, exact Coulomb friction over a patch of radius 0.5 mm, turns over (a
time-stepping scheme's numerical creep also keeps the slip alive).  The model file therefore uses the smooth Coulomb law
``friction = "regularized"``: F = -mu N U/sqrt(abs(U)^2 + eps^2) with eps = 0.05 m/s (full
Coulomb friction above ~0.1 m/s); the top turns over, theta passing pi/2 at t = 0.97 s and
reaching 3.0 rad at t = 3 s, the centre of mass rising by 1.985 a, half the energy gone as heat.

What is checked (``run``, ``tests/literature/test_leine2003_tippe_top.py``):

1. the smooth law: the inversion (theta from 0.1 to > 2.8 rad by t = 3 s; the centre of mass
   higher by > 1.8 a), Jellett's lambda constant (relative drift < 1e-8), the friction work
   never increasing (friction only dissipates), the energy balance E + heat = E0, and theta(t)
   against an independent Newton-Euler integration written here (``newton_euler``: the
   centre of mass and Euler's equations in N axes, the normal force from the gap's second
   derivative, SciPy's DOP853 at rtol 1e-11) to 1e-6 rad over the whole run (2.1e-9 measured);
   Jellett's drift 2.0e-10 and the balance 3.7e-10 measured at rtol 1e-10;
2. the exact law: the stick event at the time the independent integration's slip vanishes
   (36.14492 ms both, relative 5e-9), lambda conserved through sliding and rolling (drift
   6.6e-10), and no inversion (theta never above its initial 0.1 rad in 1 s).
"""

from __future__ import annotations

import math

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, Coulomb, RegularizedCoulomb
from ..modeling.frames import Frame
from ..modeling.model import Model
from ..modeling.points import Point
from ..modeling.shapes import Sphere

NAME = "tippe-top"
ORDER = 235
TITLE = "Tippe top (Leine & Glocker 2003): inversion under sliding friction, Jellett's integral"
FILE = "tippe_top.toml"

PARAMETERS = {"m": 0.006, "R": 0.015, "a": 0.003, "A": 8.0e-7, "C": 7.0e-7, "g": 9.81, "mu": 0.3,
              "theta0": 0.1, "W": 180.0}
EPS = 0.05
E = ["e0", "e1", "e2", "e3"]


def build(exact: bool = False, eps: float = EPS, t_end: float = 3.0, **parameters) -> Model:
    """The top with the Python API: the model file for the defaults; ``exact=True`` for
    Coulomb's exact law (stick/slip events)."""
    law = Coulomb("mu") if exact else RegularizedCoulomb("mu", eps)
    return Model(
        name="tippe top", coordinates=["x", "y", "z", *E], parameters={**PARAMETERS, **parameters},
        frames=[Frame("B", quaternion=E)],
        points=[Point("G", ["x", "y", "z"])],
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G")],
        gravity=["0", "0", "-g"],
        contacts=[Contact("table", body="top", shape=Sphere("R", center=(0, 0, "a")), friction=law)],
        initial={"x": 0.0, "y": 0.0, "z": "R - a*cos(theta0)", "e0": "cos(theta0/2)",
                 "e1": "sin(theta0/2)", "e2": 0.0, "e3": 0.0, "x'": 0.0, "y'": 0.0, "z'": 0.0,
                 "e0'": 0.0, "e1'": 0.0, "e2'": "-W*sin(theta0/2)/2", "e3'": "W*cos(theta0/2)/2"},
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12})


def _rotation(e) -> np.ndarray:
    e0, e1, e2, e3 = e
    return np.array([[1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                     [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
                     [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)]])


def _body_omega(e, ed) -> np.ndarray:
    """omega in body axes from e' = e (x) (0, omega)/2: omega = 2 (e0 v' - e0' v - v x v')."""
    e, ed = np.asarray(e), np.asarray(ed)
    return 2 * (e[0] * ed[1:] - ed[0] * e[1:] - np.cross(e[1:], ed[1:]))


def invariants(traj, p: dict) -> dict:
    """theta (the axis from the vertical), Jellett's lambda, the energy and the slip speed
    along a trajectory of the model (q = x, y, z, e0..e3)."""
    out = {k: [] for k in ("theta", "jellett", "energy", "slip")}
    ez = np.array([0.0, 0.0, 1.0])
    Ib = np.diag([p["A"], p["A"], p["C"]])
    for q, qd in zip(traj.q, traj.qd):
        e = q[3:7] / np.linalg.norm(q[3:7])
        Rm, wb = _rotation(e), _body_omega(q[3:7], qd[3:7])
        k, w = Rm[:, 2], Rm @ wb
        d = p["a"] * k - p["R"] * ez
        L = Rm @ (Ib @ wb)
        U = qd[:3] + np.cross(w, d)
        out["theta"].append(math.acos(max(-1.0, min(1.0, k[2]))))
        out["jellett"].append(L @ d)
        out["energy"].append(0.5 * (p["m"] * qd[:3] @ qd[:3] + wb @ Ib @ wb) + p["m"] * p["g"] * q[2])
        out["slip"].append(math.hypot(U[0], U[1]))
    return {k: np.array(v) for k, v in out.items()}


def spin_threshold(p: dict) -> float:
    """The spin about the axis at theta = 0 above which E_pi < E_0 at equal lambda."""
    R, a = p["R"], p["a"]
    lam2 = 2 * p["m"] * p["g"] * a * p["C"] * (R * R - a * a) ** 2 / (2 * R * a)
    return math.sqrt(lam2) / (p["C"] * (R - a))


def newton_euler(p: dict, t_end: float, times, eps: float | None = EPS, rtol: float = 1e-11):
    """An independent integration: G's motion and Euler's equations in N axes, the quaternion
    from the body angular velocity, the normal force N from gap'' = 0 (the gap z + a k_z - R),
    sliding friction F = -mu N U/sqrt(abs(U)^2 + eps^2) (``eps=None``: -mu N U/abs(U), sliding only;
    the integration stops where abs(U) vanishes).  Returns (t, theta, slip, t_stop)."""
    from scipy.integrate import solve_ivp

    m, R, a, g, mu = p["m"], p["R"], p["a"], p["g"], p["mu"]
    Ib = np.array([p["A"], p["A"], p["C"]])

    def state(y):
        Rm = _rotation(y[6:10] / np.linalg.norm(y[6:10]))
        k = Rm[:, 2]
        w = Rm @ y[10:13]
        d = a * k - np.array([0.0, 0.0, R])
        U = y[3:6] + np.cross(w, d)
        return Rm, k, w, d, U

    def rhs(t, y):
        Rm, k, w, d, U = state(y)
        s = math.hypot(U[0], U[1])
        den = s if eps is None else math.sqrt(s * s + eps * eps)
        f = np.array([-mu * U[0] / den, -mu * U[1] / den, 1.0])   # contact force per unit N
        Iinv = Rm @ np.diag(1 / Ib) @ Rm.T
        I = Rm @ np.diag(Ib) @ Rm.T
        wd_N = Iinv @ np.cross(d, f)                  # omega' per unit N
        wd_0 = Iinv @ -np.cross(w, I @ w)
        # gap'' = z'' + a (w' x k + w x (w x k))_z = 0, linear in N
        c1 = f[2] / m + a * np.cross(wd_N, k)[2]
        c0 = -g + a * (np.cross(wd_0, k) + np.cross(w, np.cross(w, k)))[2]
        N = -c0 / c1
        wd = N * wd_N + wd_0
        e0, e1, e2, e3 = y[6:10]
        wx, wy, wz = y[10:13]
        qd = 0.5 * np.array([-e1 * wx - e2 * wy - e3 * wz, e0 * wx + e2 * wz - e3 * wy,
                             e0 * wy + e3 * wx - e1 * wz, e0 * wz + e1 * wy - e2 * wx])
        return np.concatenate([y[3:6], N * f / m - [0, 0, g], qd, Rm.T @ wd])

    def stuck(t, y):
        return math.hypot(*state(y)[4][:2]) - 1e-9
    stuck.terminal = True

    th0 = p["theta0"]
    y0 = np.concatenate([[0, 0, R - a * math.cos(th0), 0, 0, 0],
                         [math.cos(th0 / 2), math.sin(th0 / 2), 0, 0], [0, 0, p["W"]]])
    sol = solve_ivp(rhs, (0, t_end), y0, method="DOP853", rtol=rtol, atol=1e-13, dense_output=True,
                    events=stuck if eps is None else None)
    t_stop = float(sol.t[-1])
    ts = np.asarray([t for t in times if t <= t_stop])
    theta = np.array([math.acos(max(-1.0, min(1.0, _rotation(y[6:10] / np.linalg.norm(y[6:10]))[2, 2])))
                      for y in sol.sol(ts).T])
    slip = np.array([math.hypot(*state(y)[4][:2]) for y in sol.sol(ts).T])
    return ts, theta, slip, t_stop


def _crossing(t, theta, after) -> float:
    """The time theta passes pi/2 (linear interpolation between samples)."""
    if not after.size:
        return math.inf
    i = after[0]
    return float(t[i - 1] + (t[i] - t[i - 1]) * (math.pi / 2 - theta[i - 1]) / (theta[i] - theta[i - 1]))


def check(model: Model | None = None, t_end: float = 3.0, compare_until: float = 3.0) -> dict:
    """The smooth law: inversion, Jellett's integral, dissipation, the independent integration."""
    from .. import gallery
    from ..simulation.hybrid import simulate

    model = model or gallery.load(NAME)
    p = model.parameter_values
    times = np.linspace(0.0, t_end, int(round(t_end / 0.02)) + 1)
    tr = simulate(model, t_end=t_end, times=times)
    inv = invariants(tr, p)
    heat = np.asarray(tr.energy["friction_work"])
    ts, theta_ne, _, _ = newton_euler(p, compare_until, [t for t in times if t <= compare_until + 1e-12],
                                      eps=model.contacts[0].friction.eps)
    n = len(ts)
    crossing = np.flatnonzero(inv["theta"] > math.pi / 2)
    return {"theta": inv["theta"], "t": np.asarray(tr.t), "theta_end": float(inv["theta"][-1]),
            "theta_max": float(inv["theta"].max()),
            "t_half": _crossing(tr.t, inv["theta"], crossing),
            "rise": float((tr.q[-1, 2] - tr.q[0, 2]) / p["a"]),
            "jellett0": float(inv["jellett"][0]),
            "jellett_drift": float(np.max(np.abs(inv["jellett"] / inv["jellett"][0] - 1))),
            "energy0": float(inv["energy"][0]), "energy_end": float(inv["energy"][-1]),
            "heat": float(-heat[-1]),
            "balance": float(np.max(np.abs(inv["energy"] - heat - inv["energy"][0])) / inv["energy"][0]),
            "friction_work_increase": float(np.max(np.diff(heat))),
            "theta_vs_newton_euler": float(np.max(np.abs(inv["theta"][:n] - theta_ne))),
            "compared_until": float(ts[-1]), "events": tr.events,
            "spin_threshold": spin_threshold(p),
            "C_over_A": p["C"] / p["A"], "alpha": p["a"] / p["R"]}


def check_exact(t_end: float = 1.0) -> dict:
    """Coulomb's exact law: the stick time against the independent integration; no inversion."""
    from ..simulation.hybrid import simulate

    model = build(exact=True, t_end=t_end)
    p = model.parameter_values
    times = np.linspace(0.0, t_end, 201)
    tr = simulate(model, t_end=t_end, times=times)
    inv = invariants(tr, p)
    _, _, _, t_stop = newton_euler(p, 0.1, [0.0], eps=None)
    stick = [e["t"] for e in tr.events if e["type"] == "stick"]
    return {"events": [(e["t"], e["type"]) for e in tr.events], "t_stick": stick[0] if stick else math.inf,
            "t_slip_vanishes": t_stop, "U0": p["W"] * p["R"] * math.sin(p["theta0"]),
            "theta_max": float(inv["theta"].max()),
            "jellett_drift": float(np.max(np.abs(inv["jellett"] / inv["jellett"][0] - 1))),
            "balance": tr.diagnostics["energy_balance_relative"]}


def run(verbose: bool = True) -> dict:
    r = check()
    x = check_exact()
    ok = (r["theta_end"] > 2.8 and r["rise"] > 1.8 and r["jellett_drift"] < 1e-8
          and r["friction_work_increase"] <= 0 and r["balance"] < 1e-8
          and r["theta_vs_newton_euler"] < 1e-6 and 1 - r["alpha"] < r["C_over_A"] < 1 + r["alpha"]
          and abs(x["t_stick"] / x["t_slip_vanishes"] - 1) < 1e-7 and x["theta_max"] < 0.11
          and x["jellett_drift"] < 1e-8)
    if verbose:
        print(TITLE)
        print(f"C/A = {r['C_over_A']:.3f} in (1 - a/R, 1 + a/R) = ({1 - r['alpha']:.2f}, {1 + r['alpha']:.2f}); "
              f"spin 180 rad/s > threshold {r['spin_threshold']:.1f} rad/s")
        print(f"smooth Coulomb law (eps = {EPS} m/s): theta passes pi/2 at t = {r['t_half']:.2f} s, "
              f"reaches {r['theta_end']:.3f} rad at t = {r['t'][-1]:.1f} s; centre of mass up by "
              f"{r['rise']:.3f} a; heat {r['heat']:.4e} J of E0 = {r['energy0']:.4e} J")
        print(f"Jellett lambda = {r['jellett0']:.6e} kg m^3/s, relative drift {r['jellett_drift']:.1e}; "
              f"energy balance {r['balance']:.1e}; theta against the Newton-Euler integration "
              f"{r['theta_vs_newton_euler']:.1e} rad up to t = {r['compared_until']:.1f} s")
        print(f"exact Coulomb law: U0 = {x['U0']:.4f} m/s; stick at t = {x['t_stick'] * 1e3:.4f} ms "
              f"(the independent integration's slip vanishes at {x['t_slip_vanishes'] * 1e3:.4f} ms); "
              f"then rolling, theta <= {x['theta_max']:.3f} rad (no inversion); Jellett drift "
              f"{x['jellett_drift']:.1e}")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "smooth": {k: v for k, v in r.items() if k not in ("theta", "t", "events")},
            "exact": x}
