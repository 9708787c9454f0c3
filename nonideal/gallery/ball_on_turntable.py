"""A ball rolling on a turntable: its centre circles at (2/7) W.

Earnshaw 1844; Routh, *Advanced Rigid Dynamics* (1905), §243.  A homogeneous ball (mass m,
radius r, I = 2 m r^2/5) rolls without slipping on a plane turning at the constant rate W about
the vertical through the origin.  The contact is declared by the shape (a sphere) and the
moving plane (``omega = [0, 0, W]``); the library derives the rolling constraint
``v - r omega x e_z = W e_z x rho`` (rho the horizontal position of the contact point).

Closed form.  Differentiating the rolling condition and eliminating the friction force F
(m v' = F, I omega' = -r e_z x F, so (omega' x e_z) r = -(r^2/I) F):
``v' (1 + m r^2/I) = W e_z x v``, i.e. ``v' = (2/7) W e_z x v``: the velocity of the centre
turns at the constant rate (2/7) W and the centre moves on a circle

    rho(t) = c + Rot((2/7) W t) (rho0 - c),     c = rho0 + e_z x v0 / ((2/7) W),

whatever the initial spin (the vertical spin is constant).  Placed at rest on the table
(omega = 0), v0 = W e_z x rho0 (completed by the rolling contact from the initial state).
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Plane, Sphere
from .rotations import body_rotation

NAME = "ball-on-turntable"
ORDER = 230
TITLE = "Ball on a turntable: the centre circles at (2/7) W (sphere on a turning plane, ideal rolling)"
FILE = "ball_on_turntable.toml"


def build(m: float = 0.2, r: float = 0.1, g: float = 9.81, W: float = 2.0, x0: float = 0.02,
          spin=(0.0, 0.0, 0.0), t_end: float = 3.0) -> Model:
    """The ball with the Python API (the model file for the default values); *spin* gives the
    initial (a', b', c')."""
    I = "2*m*r^2/5"
    return Model(
        name="ball on a turntable", coordinates=["x", "y", "z", "a", "b", "c"],
        parameters={"m": m, "r": r, "g": g, "W": W},
        bodies=[RigidBody("ball", "m", [[I, 0, 0], [0, I, 0], [0, 0, I]], ["x", "y", "z"],
                          body_rotation("zyx", ("c", "b", "a")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="ball", shape=Sphere("r"), surface=Plane(omega=(0, 0, "W")),
                          friction=IdealRolling())],
        initial={"x": x0, "y": 0.0, "z": "r", "a": 0.0, "b": 0.0, "c": 0.0,
                 "a'": spin[0], "b'": spin[1], "c'": spin[2]},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-13})


def closed_form(t, rho0, v0, W: float):
    """Horizontal position and velocity of the centre at times *t*: shape (len(t), 2) each."""
    Om = 2.0 * W / 7.0
    rho0, v0 = np.asarray(rho0, float), np.asarray(v0, float)
    c = rho0 + np.array([-v0[1], v0[0]]) / Om
    th = Om * np.asarray(t, float)[:, None]
    d = rho0 - c
    pos = c + np.column_stack([np.cos(th[:, 0]) * d[0] - np.sin(th[:, 0]) * d[1],
                               np.sin(th[:, 0]) * d[0] + np.cos(th[:, 0]) * d[1]])
    vel = np.column_stack([np.cos(th[:, 0]) * v0[0] - np.sin(th[:, 0]) * v0[1],
                           np.sin(th[:, 0]) * v0[0] + np.cos(th[:, 0]) * v0[1]])
    return pos, vel


def check(model: Model) -> dict:
    """Simulate and compare the centre's motion with the closed form."""
    from ..simulation.hybrid import simulate

    times = np.linspace(model.t0, model.simulation.t_end, 31)
    tr = simulate(model, times=times)
    W = model.parameter_values["W"]
    pos, vel = closed_form(times - times[0], tr.q[0, :2], tr.qd[0, :2], W)
    heading = np.unwrap(np.arctan2(tr.qd[:, 1], tr.qd[:, 0]))
    rate = np.polyfit(times, heading, 1)[0]
    return {"position_error": float(np.max(np.abs(tr.q[:, :2] - pos))),
            "velocity_error": float(np.max(np.abs(tr.qd[:, :2] - vel))),
            "circling_rate": float(rate), "closed_form_rate": 2 * W / 7,
            "v0": tr.qd[0, :2].tolist(), "height_error": float(np.max(np.abs(tr.q[:, 2] - model.parameter_values["r"]))),
            "events": tr.events}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    r = check(gallery.load(NAME))
    spun = check(build(spin=(0.0, 0.0, 3.0)))
    ok = all(x["position_error"] < 1e-8 and x["velocity_error"] < 1e-8 and not x["events"]
             and abs(x["circling_rate"] / x["closed_form_rate"] - 1) < 1e-8 for x in (r, spun))
    if verbose:
        print(TITLE)
        for label, x in (("placed at rest", r), ("spinning at c' = 3 rad/s", spun)):
            print(f"{label}: v0 = {np.round(x['v0'], 12).tolist()}, circling rate {x['circling_rate']:.12f} "
                  f"= (2/7) W = {x['closed_form_rate']:.12f}; max error position {x['position_error']:.1e} m, "
                  f"velocity {x['velocity_error']:.1e} m/s")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "at_rest": r, "spinning": spun}
