"""Chaplygin's ball: a dynamically asymmetric balanced sphere rolling on a plane.

Chaplygin 1903 (Mat. Sbornik 24); Borisov & Mamaev 2002 (Regul. Chaotic Dyn. 7).  A sphere of
radius r whose centre of mass is its geometric centre, with unequal principal moments A, B, C,
rolls without slipping on a horizontal plane (the contact from the shape, ``mu = "inf"``).  The
contact force acts at the contact point P and gravity through the centre, so the angular
momentum about P,

    K = I omega + m r^2 (omega - (omega . n) n)       (n the vertical, I in N axes),

is conserved (P moves parallel to the velocity of the centre), and so is the energy
``T = (omega . I omega + m |v|^2)/2`` with ``v = omega x r n`` (rolling).  The ball wanders in
the plane in a quasi-periodic way; these integrals are the test.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Sphere
from .rotations import body_rotation

NAME = "chaplygin-ball"
ORDER = 233
TITLE = "Chaplygin's ball: energy and the angular momentum about the contact point conserved"
FILE = "chaplygin_ball.toml"


def build(m: float = 1.0, r: float = 0.1, A: float = 0.002, B: float = 0.003, C: float = 0.005,
          g: float = 9.81, omega0=(0.6, -0.4, 5.0), t_end: float = 3.0) -> Model:
    """The ball with the Python API (the model file for the default values)."""
    return Model(
        name="Chaplygin ball", coordinates=["x", "y", "z", "a", "b", "c"],
        parameters={"m": m, "r": r, "A": A, "B": B, "C": C, "g": g},
        bodies=[RigidBody("ball", "m", [["A", 0, 0], [0, "B", 0], [0, 0, "C"]], ["x", "y", "z"],
                          body_rotation("zyx", ("c", "b", "a")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("floor", body="ball", shape=Sphere("r"), friction=IdealRolling())],
        initial={"x": 0.0, "y": 0.0, "z": "r", "a": 0.0, "b": 0.0, "c": 0.0,
                 "a'": omega0[0], "b'": omega0[1], "c'": omega0[2]},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-13})


def _rot(axis, angle):
    c, s = np.cos(angle), np.sin(angle)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def integrals(traj, p: dict) -> tuple[np.ndarray, np.ndarray]:
    """Energy and K (N axes) along the trajectory, computed here from the angles and rates
    (R = Rz(c) Ry(b) Rx(a): omega = c' e_z + b' Rz e_y + a' Rz Ry e_x)."""
    I_b = np.diag([p["A"], p["B"], p["C"]])
    n = np.array([0.0, 0.0, 1.0])
    E, K = [], []
    for q, qd in zip(traj.q, traj.qd):
        a, b, c = q[3:6]
        Rz, Ry, Rx = _rot("z", c), _rot("y", b), _rot("x", a)
        R = Rz @ Ry @ Rx
        w = qd[5] * n + qd[4] * Rz[:, 1] + qd[3] * (Rz @ Ry)[:, 0]
        I = R @ I_b @ R.T
        v = qd[:3]
        E.append(0.5 * (w @ I @ w + p["m"] * v @ v) + p["m"] * p["g"] * q[2])
        K.append(I @ w + p["m"] * p["r"] ** 2 * (w - (w @ n) * n))
    return np.array(E), np.array(K)


def check(model: Model) -> dict:
    from ..simulation.hybrid import simulate

    times = np.linspace(model.t0, model.simulation.t_end, 61)
    tr = simulate(model, times=times)
    E, K = integrals(tr, model.parameter_values)
    v_roll = np.max(np.abs(np.array(tr.contacts["floor"]["slip"])))
    return {"energy_drift": float(np.max(np.abs(E - E[0])) / abs(E[0])),
            "K_drift": float(np.max(np.abs(K - K[0])) / np.linalg.norm(K[0])), "K0": K[0].tolist(),
            "slip_max": float(v_roll), "wandered": float(np.hypot(*tr.q[-1, :2])), "events": tr.events}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    r = check(gallery.load(NAME))
    ok = r["energy_drift"] < 1e-9 and r["K_drift"] < 1e-9 and r["slip_max"] < 1e-9 and not r["events"]
    if verbose:
        print(TITLE)
        print(f"K0 = {np.round(r['K0'], 9).tolist()}; relative drift of K {r['K_drift']:.1e}, of the "
              f"energy {r['energy_drift']:.1e}; the centre wandered {r['wandered']:.4f} m")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), **{k: v for k, v in r.items() if k != "events"}}
