"""The heavy symmetric top in Euler parameters: through the gimbal lock of Euler angles.

The top of :mod:`nonideal.gallery.heavy_symmetric_top` with its frame given by Euler
parameters e = (e0, e1, e2, e3) (``quaternion = [...]``, scalar first, the rotation of
SymPy's ``orient_quaternion``; Kane & Levinson 1985, sec. 1.13).  The library keeps |e| = 1
with no constraint: the rotation is that of e/|e| and the kinetic energy gains c/2 (e . e')^2,
so the equation along e is (e . e')' = 0 -- |e| is conserved by the motion, the mass matrix is
positive definite, and no multiplier is solved for (:mod:`nonideal.modeling.kinematics`).

The top starts upright, e = (1, 0, 0, 0) -- theta = 0 of the Z-X-Z Euler angles, where their
equations are singular (the coefficient sin^2 theta of psi'' vanishes) -- spinning at
10 rad/s and tipped at 1.5 rad/s: it falls to theta = 2.2 and swings back through the upright
position, again and again.

What is checked (``run``):

1. The motion runs through theta = 0 (three times in 2 s): |e| - 1 stays at the level of the
   integration tolerance (rtol 1e-10: < 1e-8, 5e-10 measured);
2. the same motion in Euler angles, away from the lock: between two passages (theta > 0.1),
   from the state where theta first exceeds 0.1 (converted to psi, theta, phi and their rates: theta = acos(R33), psi = atan2(R13, -R23),
   phi = atan2(R31, R32)), the Euler-angle model (:mod:`~nonideal.gallery.heavy_symmetric_top`)
   gives the same symmetry axis R e3 and body angular velocity until theta falls below 0.1
   again (< 1e-8);
3. the invariants of the heavy top -- the energy and the cyclic momenta p_psi = H_O . N.z and
   p_phi = C w3 -- stay constant along the motion through the lock (relative drift < 1e-8,
   1.4e-9 measured at rtol 1e-10).
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.frames import Frame
from ..modeling.model import Model
from ..modeling.points import Point
from .heavy_symmetric_top import PARAMETERS

NAME = "heavy-top-euler-parameters"
ORDER = 206
TITLE = "Heavy symmetric top in Euler parameters: through the gimbal lock of Euler angles"
FILE = "heavy_top_euler_parameters.toml"

E = ["e0", "e1", "e2", "e3"]


def build(**parameters) -> Model:
    """The top with the Python API (same as the model file)."""
    return Model(
        name="Heavy symmetric top in Euler parameters", coordinates=E,
        parameters={**PARAMETERS, **parameters},
        frames=[Frame("B", quaternion=E)],
        points=[Point("G", ["0", "0", "l"], frame="B")],
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G")],
        gravity=["0", "0", "-g"],
        initial={"e0": 1.0, "e1": 0.0, "e2": 0.0, "e3": 0.0,
                 "e0'": 0.0, "e1'": 0.75, "e2'": 0.0, "e3'": 5.0},
        simulation={"t_end": 3.0})


def rotation(e) -> np.ndarray:
    """R(e) (columns: the body axes in N), as ``orient_quaternion``."""
    e0, e1, e2, e3 = e
    return np.array([
        [e0**2 + e1**2 - e2**2 - e3**2, 2 * (e1 * e2 - e0 * e3), 2 * (e0 * e2 + e1 * e3)],
        [2 * (e1 * e2 + e0 * e3), e0**2 - e1**2 + e2**2 - e3**2, 2 * (e2 * e3 - e0 * e1)],
        [2 * (e1 * e3 - e0 * e2), 2 * (e0 * e1 + e2 * e3), e0**2 - e1**2 - e2**2 + e3**2]])


def body_rate(e, ed) -> np.ndarray:
    """The body angular velocity 2 (e0 e' - e0' e - e x e')."""
    v, vd = np.asarray(e[1:]), np.asarray(ed[1:])
    return 2 * (e[0] * vd - ed[0] * v - np.cross(v, vd))


def euler_angles(e, ed) -> dict[str, float]:
    """Z-X-Z Euler angles and their rates of the state (e, e') (away from theta = 0)."""
    R, w = rotation(e), body_rate(e, ed)
    th = np.arccos(np.clip(R[2, 2], -1, 1))
    ps, ph = np.arctan2(R[0, 2], -R[1, 2]), np.arctan2(R[2, 0], R[2, 1])
    psd = (w[0] * np.sin(ph) + w[1] * np.cos(ph)) / np.sin(th)
    return {"psi": ps, "theta": th, "phi": ph, "psi'": psd,
            "theta'": w[0] * np.cos(ph) - w[1] * np.sin(ph), "phi'": w[2] - psd * np.cos(th)}


def invariants(p: dict, e, ed) -> dict[str, float]:
    """Energy and the vertical angular momentum about O of the state (e, e')."""
    R, w = rotation(e), body_rate(e, ed)
    A_O = p["A"] + p["m"] * p["l"] ** 2
    I_O = np.diag([A_O, A_O, p["C"]])
    H = R @ (I_O @ w)
    return {"E": 0.5 * w @ I_O @ w + p["m"] * p["g"] * p["l"] * R[2, 2], "p_z": H[2],
            "p_phi": p["C"] * w[2]}


def _states(traj):
    return [(np.array([traj.coordinate(n)[k] for n in E]), np.array([traj.velocity(n)[k] for n in E]))
            for k in range(len(traj.t))]


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    times = np.linspace(0.0, 2.0, 201)
    traj = simulate(model, t_end=2.0, times=times)
    states = _states(traj)
    unit = float(max(abs(np.linalg.norm(e) - 1) for e, _ in states))
    thetas = [np.arccos(np.clip(rotation(e)[2, 2], -1, 1)) for e, _ in states]
    inv = [invariants(p, e, ed) for e, ed in states]
    drift = {k: float(max(abs(i[k] - inv[0][k]) for i in inv) / max(abs(inv[0][k]), 1e-300)) for k in inv[0]}

    # the same motion in Euler angles between two passages through the lock (theta > 0.1)
    k1 = next(k for k, th in enumerate(thetas) if th > 0.1)
    k2 = next(k for k in range(k1, len(thetas)) if thetas[k] < 0.1)
    euler = gallery.load("heavy-symmetric-top")
    start = euler_angles(*states[k1])
    later = times[k1:k2] - times[k1]
    ref = simulate(euler.replace(initial=start), t_end=float(later[-1]), times=later)
    err_axis = err_rate = 0.0
    for j, k in enumerate(range(k1, k2)):
        e, ed = states[k]
        ps, th, ph = (ref.coordinate(n)[j] for n in ("psi", "theta", "phi"))
        axis = np.array([np.sin(th) * np.sin(ps), -np.sin(th) * np.cos(ps), np.cos(th)])
        psd, thd, phd = (ref.velocity(n)[j] for n in ("psi", "theta", "phi"))
        w = np.array([psd * np.sin(th) * np.sin(ph) + thd * np.cos(ph),
                      psd * np.sin(th) * np.cos(ph) - thd * np.sin(ph), psd * np.cos(th) + phd])
        err_axis = max(err_axis, float(np.max(np.abs(rotation(e)[:, 2] - axis))))
        err_rate = max(err_rate, float(np.max(np.abs(body_rate(e, ed) - w)) / np.linalg.norm(w)))
    result = {"theta_min": float(min(thetas)), "window": [float(times[k1]), float(times[k2 - 1])],
              "lock_passages": int(sum(1 for a, b, c in zip(thetas, thetas[1:], thetas[2:])
                                       if b < a and b < c and b < 0.05)) + 1,
              "unit_norm_error": unit, "invariant_drift": drift,
              "axis_vs_euler_angles": err_axis, "rate_vs_euler_angles": err_rate,
              "constraint_residual_max": traj.diagnostics["constraint_residual_max"]}
    result["ok"] = bool(min(thetas) == 0.0 and unit < 1e-8 and max(drift.values()) < 1e-8
                        and err_axis < 1e-8 and err_rate < 1e-8)
    if verbose:
        print(TITLE)
        print(f"through theta = {min(thetas):.1e} (the lock of Z-X-Z Euler angles) at t = 0: "
              f"max ||e| - 1| = {unit:.1e}")
        print("invariants, relative drift: " + ", ".join(f"{k} {v:.1e}" for k, v in drift.items()))
        print(f"passes theta ~ 0 {result['lock_passages']} times in 2 s; between two passages "
              f"(t = {times[k1]:.2f} .. {times[k2 - 1]:.2f} s, theta > 0.1) against the Euler-angle "
              f"model: symmetry axis {err_axis:.1e}, body angular velocity {err_rate:.1e} (relative)")
        print("ok" if result["ok"] else "FAILED")
    return result
