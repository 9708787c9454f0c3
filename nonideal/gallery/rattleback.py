"""The rattleback: spin reversal of a paraboloid-bottomed body rolling on a plane.

Garcia & Hubbard 1988 (Proc. R. Soc. Lond. A 418, 165); Lindberg & Longman 1983 (Acta Mech.
49, 81); Kondo & Nakanishi 2017 (Phys. Rev. E 95, 062207).  The bottom is the paraboloid
z = x^2/(2 ra) + y^2/(2 rb) of the body's axes with its vertex h below the centre of mass; the
principal axes of inertia (moments A, B about the horizontal axes, C about the vertical) are
turned by delta about the vertical from the axes of curvature -- the misalignment that couples
spin with pitching and rolling.  The contact is declared by the shape alone (``paraboloid``
with ``center = [0, 0, -h]``) and rolls without slipping (``mu = "inf"``); the library derives
the support point, the gap and the rolling rows.

The moments A, B, C are Kane & Levinson's 1982 values (2, 16, 17 cm^2 per unit mass) and h their
height of the centre of mass over the bottom; the radii of curvature and the misalignment delta
are the file's own (Kane & Levinson's ellipsoid has radii of curvature a^2/c = 2 m and b^2/c =
4.5 cm at its lowest point and a misalignment of -0.0143 rad: the ``rattleback-ellipsoid``
example).

Behaviour (no dissipation: energy is conserved).  Spun one way (here w0 < 0) from a small
pitch, the pitching oscillation grows exponentially at the expense of the spin, the spin stops
and reverses (t_r ~ 2.8 s for the data of the file); spun the other way it keeps spinning
several times longer.  Without dissipation the preferred direction too reverses eventually
through the rolling mode (Garcia & Hubbard 1988; Kondo & Nakanishi 2017 show both times); the
test compares the reversal times with an independent derivation, the Newton-Euler equations of
the rolling body written by hand in the body frame and integrated with SciPy
(tests/literature/test_garcia1988_rattleback.py).
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Paraboloid
from .rotations import body_rotation

NAME = "rattleback"
ORDER = 232
TITLE = "Rattleback: spin reversal of a paraboloid rolling on a plane (Garcia & Hubbard 1988)"
FILE = "rattleback.toml"

PARAMETERS = {"m": 1.0, "A": 2.0e-4, "B": 1.6e-3, "C": 1.7e-3, "delta": 0.1, "ra": 0.2,
              "rb": 0.03, "h": 0.01, "g": 9.81, "w0": -2.0}


def build(t_end: float = 5.0, pitch: float = 0.01, **params) -> Model:
    """The rattleback with the Python API (the model file for the default values)."""
    p = {**PARAMETERS, **params}
    I = [["A*cos(delta)^2 + B*sin(delta)^2", "(A - B)*sin(delta)*cos(delta)", 0],
         ["(A - B)*sin(delta)*cos(delta)", "A*sin(delta)^2 + B*cos(delta)^2", 0], [0, 0, "C"]]
    return Model(
        name="rattleback", coordinates=["x", "y", "z", "psi", "a", "b"], parameters=p,
        bodies=[RigidBody("shell", "m", I, ["x", "y", "z"], body_rotation("zxy", ("psi", "a", "b")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="shell", shape=Paraboloid(("ra", "rb"), (0, 0, "-h")),
                          friction=IdealRolling())],
        initial={"x": 0.0, "y": 0.0, "psi": 0.0, "a": 0.0, "b": pitch, "psi'": "w0", "a'": 0.0, "b'": 0.0},
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12})


def spin(traj, roll: str = "a", pitch: str = "b") -> np.ndarray:
    """The angular velocity about the vertical, omega . e_z = psi' + b' sin(a) (R = Rz Rx Ry)."""
    return traj.velocity("psi") + traj.velocity(pitch) * np.sin(traj.coordinate(roll))


def reversal_time(t, w) -> float | None:
    """The first time the spin *w* changes sign (linear interpolation), or None."""
    s = np.sign(w)
    k = np.nonzero(s[1:] != s[0])[0]
    if not len(k):
        return None
    i = k[0]
    return float(t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i]))


def check(model: Model, t_end: float | None = None, samples: int = 2001, roll: str = "a",
          pitch: str = "b") -> dict:
    """Simulate on *samples* uniform times: the spin about the vertical, its first reversal,
    the energy drift, the least normal force and the events (*roll*, *pitch*: the angles' names)."""
    from ..simulation.hybrid import simulate

    t_end = t_end or model.simulation.t_end
    times = np.linspace(model.t0, t_end, samples)
    tr = simulate(model, times=times)
    w = spin(tr, roll, pitch)
    E = tr.energy["kinetic"] + tr.energy["potential"]
    return {"t": times, "spin": w, "reversal_time": reversal_time(times, w), "trajectory": tr,
            "energy_drift": float(np.max(np.abs(E - E[0])) / abs(E[0])),
            "normal_min": float(np.min(tr.contacts["table"]["normal"])), "events": tr.events}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    neg = check(gallery.load(NAME))
    pos = check(build(w0=2.0), t_end=5.0)
    ok = (neg["reversal_time"] is not None and 2.0 < neg["reversal_time"] < 4.0
          and pos["reversal_time"] is None and max(neg["energy_drift"], pos["energy_drift"]) < 1e-8
          and min(neg["normal_min"], pos["normal_min"]) > 0 and not neg["events"] and not pos["events"])
    if verbose:
        print(TITLE)
        print(f"spun at w0 = -2 rad/s: the spin reverses at t_r = {neg['reversal_time']:.6f} s, "
              f"then {neg['spin'][-1]:+.4f} rad/s at t = {neg['t'][-1]:g} s")
        print(f"spun at w0 = +2 rad/s: no reversal in 5 s (spin {pos['spin'][-1]:+.4f} rad/s at t = 5 s)")
        print(f"energy drift {max(neg['energy_drift'], pos['energy_drift']):.1e} (rolling: conserved)")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "reversal_time": neg["reversal_time"], "other_direction": pos["reversal_time"],
            "energy_drift": max(neg["energy_drift"], pos["energy_drift"])}
