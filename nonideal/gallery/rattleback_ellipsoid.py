"""The rattleback of Kane & Levinson 1982: an ellipsoid bottom rolling on a plane.

Kane & Levinson 1982 (Int. J. Non-Linear Mech. 17, 175) model the rattleback as the ellipsoid
x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 with a = 20, b = 3, c = 2 cm, its centre h = 1 cm above the
centre of mass, and the moments per unit mass A = 2, B = 16, C = 17 cm^2 with the product of
inertia D = -0.2 cm^2 in the plane of the long axes: the principal axes of inertia turned by
(1/2) atan(2 D/(B - A)) = -0.0143 rad from the ellipsoid's.  The file gives these data in SI
units (m = 1 kg).  The contact is declared by the shape alone (``ellipsoid`` with ``center =
[0, 0, h]``) and rolls without slipping.

Behaviour (no dissipation: energy is conserved).  At rest the body rocks in two modes: pitching
about the short axis (radius of curvature a^2/c = 2 m, 33.8 rad/s) and rolling about the long
axis (b^2/c = 4.5 cm, 107.2 rad/s).  Spun at w0 = -3 rad/s from a pitch of 0.01 rad, the rolling
mode grows, the spin stops and reverses (t_r ~ 2.2 s) and settles near +3.3 rad/s.  The test
compares the spin with an independent Newton-Euler derivation, and the linear analysis about the
steady spin with the closed-form frequencies at rest and with the independent linearization
(tests/literature/test_kane1982_rattleback.py).
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Ellipsoid
from .rattleback import reversal_time
from .rotations import body_rotation

NAME = "rattleback-ellipsoid"
ORDER = 239
TITLE = "Rattleback with an ellipsoid bottom: Kane & Levinson's 1982 data, spin reversal"
FILE = "rattleback_ellipsoid.toml"

PARAMETERS = {"m": 1.0, "a": 0.20, "b": 0.03, "c": 0.02, "h": 0.01, "A": 2.0e-4, "B": 1.6e-3,
              "C": 1.7e-3, "D": -2.0e-5, "g": 9.81, "w0": -3.0}


def build(t_end: float = 10.0, pitch: float = 0.01, **params) -> Model:
    """The rattleback with the Python API (the model file for the default values)."""
    p = {**PARAMETERS, **params}
    return Model(
        name="rattleback-ellipsoid", coordinates=["x", "y", "z", "psi", "roll", "pitch"], parameters=p,
        bodies=[RigidBody("shell", "m", [["A", "D", 0], ["D", "B", 0], [0, 0, "C"]], ["x", "y", "z"],
                          body_rotation("zxy", ("psi", "roll", "pitch")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="shell", shape=Ellipsoid(("a", "b", "c"), (0, 0, "h")),
                          friction=IdealRolling())],
        initial={"x": 0.0, "y": 0.0, "psi": 0.0, "roll": 0.0, "pitch": pitch, "psi'": "w0", "roll'": 0.0,
                 "pitch'": 0.0},
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12})


def spin(traj) -> np.ndarray:
    """The angular velocity about the vertical, omega . e_z = psi' + pitch' sin(roll) (R = Rz Rx Ry)."""
    return traj.velocity("psi") + traj.velocity("pitch") * np.sin(traj.coordinate("roll"))


def rocking_frequencies(p: dict) -> np.ndarray:
    """The two frequencies of small rocking at rest (rad/s, ascending): the potential of the
    centre of mass, m g [(c - h) + ((a^2/c - c + h) n1^2 + (b^2/c - c + h) n2^2)/2] for the tilt
    n1 = -pitch, n2 = roll, and the inertia about the contact point, I + m (c - h)^2 for the
    horizontal axes; omega^2 are the eigenvalues of M^-1 K."""
    hG = p["c"] - p["h"]
    M = np.array([[p["A"] + p["m"] * hG ** 2, p["D"]], [p["D"], p["B"] + p["m"] * hG ** 2]])
    K = p["m"] * p["g"] * np.diag([p["b"] ** 2 / p["c"] - hG, p["a"] ** 2 / p["c"] - hG])
    return np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real))


def check(model: Model, t_end: float | None = None, samples: int = 2001) -> dict:
    from ..simulation.hybrid import simulate

    t_end = t_end or model.simulation.t_end
    times = np.linspace(model.t0, t_end, samples)
    tr = simulate(model, times=times)
    w = spin(tr)
    E = tr.energy["kinetic"] + tr.energy["potential"]
    return {"t": times, "spin": w, "reversal_time": reversal_time(times, w), "trajectory": tr,
            "energy_drift": float(np.max(np.abs(E - E[0])) / abs(E[0])),
            "normal_min": float(np.min(tr.contacts["table"]["normal"])), "events": tr.events}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    out = check(gallery.load(NAME), t_end=4.0, samples=801)
    ok = (out["reversal_time"] is not None and 1.8 < out["reversal_time"] < 2.6 and out["spin"][-1] > 2.0
          and out["energy_drift"] < 1e-6 and out["normal_min"] > 0 and not out["events"])
    if verbose:
        print(TITLE)
        print(f"spun at w0 = -3 rad/s: the spin reverses at t_r = {out['reversal_time']:.6f} s, "
              f"then {out['spin'][-1]:+.4f} rad/s at t = 4 s")
        print(f"energy drift {out['energy_drift']:.1e} (rolling: conserved)")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "reversal_time": out["reversal_time"], "energy_drift": out["energy_drift"]}
