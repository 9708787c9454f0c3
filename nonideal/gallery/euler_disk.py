"""Euler's disk in steady precession: Omega^2 = 4 g / (a sin alpha) (Moffatt 2000).

Moffatt, *Euler's disk and its finite-time singularity*, Nature 404 (2000) 833.  A uniform thin
disk (mass m, radius a; central moments m a^2/4 about a diameter, m a^2/2 about its axis e)
rolls without slipping on its rim (the contact from the ``disk`` shape, ``mu = "inf"``) with
its centre G at rest and its plane inclined at alpha to the table.

Steady condition (derived here).  G at rest and rolling: the contact point P has zero velocity,
so omega is parallel to u = (P - G)/a, the downward direction in the disk's plane: omega = w u.
With the configuration precessing at Omega about the vertical e_z = cos(alpha) e - sin(alpha) u,
omega = Omega e_z + s e and omega . e = 0 give s = -Omega cos(alpha), w = -Omega sin(alpha).
The angular momentum about G is L = (m a^2/4) w u (omega lies in the disk's plane) and turns
with u: dL/dt = (m a^2/4) w Omega e_z x u; the only torque about G is that of the normal force
m g at P: a u x m g e_z.  Both are along u x e; equating them,

    (m a^2/4) Omega^2 sin(alpha) = m g a,        Omega^2 = 4 g / (a sin alpha).

The file starts the disk in this state (psi' = Omega, phi' = -Omega cos(alpha)); the run keeps
the inclination, the precession rate and the centre constant.  The decay of the real disk
(rolling and spin friction, Moffatt's finite-time singularity) takes friction torques at the
contact: :mod:`nonideal.gallery.euler_disk_decay`.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Disk
from .rotations import body_rotation

NAME = "euler-disk"
ORDER = 234
TITLE = "Euler's disk: steady precession at Omega^2 = 4 g/(a sin alpha) (Moffatt 2000)"
FILE = "euler_disk.toml"


def build(m: float = 0.4, a: float = 0.04, g: float = 9.81, alpha: float = 0.3, t_end: float = 1.0,
          Omega: float | str = "sqrt(4*g/(a*sin(alpha)))") -> Model:
    """The disk with the Python API (the model file for the default values); a different
    *Omega* starts it off the steady motion."""
    return Model(
        name="Euler's disk, steady precession", coordinates=["x", "y", "z", "psi", "theta", "phi"],
        parameters={"m": m, "a": a, "g": g, "alpha": alpha, "Omega": Omega},
        bodies=[RigidBody("disk", "m", [["m*a^2/4", 0, 0], [0, "m*a^2/2", 0], [0, 0, "m*a^2/4"]],
                          ["x", "y", "z"], body_rotation("zxy", ("psi", "theta", "phi")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="disk", shape=Disk("a", (0, 1, 0)), friction=IdealRolling())],
        initial={"x": 0.0, "y": 0.0, "psi": 0.0, "theta": "pi/2 - alpha", "phi": 0.0,
                 "psi'": "Omega", "theta'": 0.0, "phi'": "-Omega*cos(alpha)"},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-13})


def check(model: Model) -> dict:
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    times = np.linspace(model.t0, model.simulation.t_end, 41)
    tr = simulate(model, times=times)
    Omega = np.sqrt(4 * p["g"] / (p["a"] * np.sin(p["alpha"])))
    return {"Omega": float(Omega), "Omega_given": float(p["Omega"]),
            "inclination_drift": float(np.max(np.abs(tr.q[:, 4] - (np.pi / 2 - p["alpha"])))),
            "precession_error": float(np.max(np.abs(tr.qd[:, 3] / Omega - 1))),
            "centre_drift": float(np.max(np.abs(tr.q[:, :3] - tr.q[0, :3]))),
            "turns": float(tr.q[-1, 3] / (2 * np.pi)), "events": tr.events}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    r = check(gallery.load(NAME))
    off = check(build(Omega=1.05 * np.sqrt(4 * 9.81 / (0.04 * np.sin(0.3)))))
    ok = (max(r["inclination_drift"], r["precession_error"], r["centre_drift"]) < 1e-8
          and not r["events"] and off["inclination_drift"] > 1e-4)
    if verbose:
        print(TITLE)
        print(f"alpha = 0.3 rad, a = 0.04 m: Omega = {r['Omega']:.10f} rad/s; over {r['turns']:.2f} turns "
              f"the inclination drifts {r['inclination_drift']:.1e} rad, the precession rate "
              f"{r['precession_error']:.1e} (relative), the centre {r['centre_drift']:.1e} m")
        print(f"started 5 % faster: the inclination wanders by {off['inclination_drift']:.2e} rad (not steady)")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), **{k: v for k, v in r.items() if k != "events"},
            "off_steady_inclination_drift": off["inclination_drift"]}
