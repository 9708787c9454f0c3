"""The heavy symmetric top in body speeds, oriented by Euler parameters (no gimbal lock).

Source: the Lagrange top (Lagrange 1788); Kane & Levinson 1985, ch. 6 (generalized speeds as
the body components of the angular velocity); Euler parameters as in SymPy's
``orient_quaternion``.

Model.  A top B (mass m, moments of inertia A, A, C about its centre of mass G) turns about
its fixed tip O; G is at distance l along the symmetry axis B.z.  Its orientation is the unit
quaternion (e0, e1, e2, e3): the frame turns by the rotation of e/|e| and the library holds the
radial rate e . e' at zero (no constraint), so the three speeds w1, w2, w3 = omega(B) . B.x,
B.y, B.z stand for the four rates.  The initial
state is given in speeds.

Invariants.  The energy T + V, the vertical component of the angular momentum about O and its
component along the symmetry axis (``C w3``) are conserved.  The motion is compared with the
same top oriented by Euler angles (body ZXZ, psi, theta, phi: the classical description,
singular at theta = 0), started in the same state: the nutation angle acos(B.z . N.z) agrees.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.frames import Frame
from ..modeling.model import Model
from ..modeling.points import Point

NAME = "heavy-symmetric-top-speeds"
ORDER = 11.5
TITLE = "Heavy symmetric top in body speeds with Euler parameters: invariants, same motion as Euler angles"
FILE = "heavy_symmetric_top_speeds.toml"

PARAMETERS = {"m": 1.0, "A": 0.02, "C": 0.03, "l": 0.1, "g": 9.81, "th0": 0.5}
OUTPUTS = {"E": "T + V", "H_vertical": "dot(angular_momentum(top, O), N.z)",
           "H_axis": "dot(angular_momentum(top, O), B.z)", "nutation": "acos(dot(B.z, N.z))"}


def _top(coordinates, frame: Frame, initial, speeds, t_end) -> Model:
    return Model(
        name="heavy symmetric top in body speeds (Euler parameters)", coordinates=coordinates,
        parameters=dict(PARAMETERS), frames=[frame], points=[Point("G", ("0", "0", "l"), frame="B")],
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G")],
        gravity=["0", "0", "-g"], speeds=speeds, outputs=dict(OUTPUTS), initial=initial,
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-12},
    )


SPEEDS = {"w1": "dot(omega(B), B.x)", "w2": "dot(omega(B), B.y)", "w3": "dot(omega(B), B.z)"}


def build(w2: float = 2.0, w3: float = 40.0, t_end: float = 2.0) -> Model:
    """The model with the Python API (the model file for the default values)."""
    return _top(["e0", "e1", "e2", "e3"], Frame("B", quaternion=("e0", "e1", "e2", "e3")),
                {"e0": "cos(th0/2)", "e1": "sin(th0/2)", "e2": 0.0, "e3": 0.0,
                 "w1": 0.0, "w2": w2, "w3": w3}, SPEEDS, t_end)


def euler_angles(w2: float = 2.0, w3: float = 40.0, t_end: float = 2.0) -> Model:
    """The same top oriented by Euler angles (body ZXZ), same initial state and speeds."""
    return _top(["psi", "theta", "phi"], Frame("B", rotation="body ZXZ", angles=("psi", "theta", "phi")),
                {"psi": 0.0, "theta": "th0", "phi": 0.0, "w1": 0.0, "w2": w2, "w3": w3}, SPEEDS, t_end)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    times = np.linspace(0.0, model.simulation.t_end, 41)
    tq = simulate(model, times=times)
    te = simulate(euler_angles(), times=times)
    drift = {k: float(np.ptp(tq.outputs[k])) for k in ("E", "H_vertical", "H_axis")}
    nutation = float(np.max(np.abs(tq.outputs["nutation"] - te.outputs["nutation"])))
    speeds = max(float(np.max(np.abs(tq.speeds[k] - te.speeds[k]))) for k in SPEEDS)
    result = {
        "ok": max(drift.values()) < 1e-8 and nutation < 1e-8 and speeds < 1e-7
        and tq.diagnostics["constraint_residual_max"] < 1e-9,
        "invariant_drift": drift, "nutation_vs_euler_angles": nutation, "speeds_vs_euler_angles": speeds,
        "nutation_range": [float(tq.outputs["nutation"].min()), float(tq.outputs["nutation"].max())],
        "constraint_residual_max": tq.diagnostics["constraint_residual_max"],
    }
    if verbose:
        print(TITLE)
        for k, v in drift.items():
            print(f"  drift of {k:<10} over t in [0, {times[-1]:g}] = {v:.1e}")
        print(f"  nutation: Euler parameters vs Euler angles, max difference {nutation:.1e} "
              f"(nutation from {result['nutation_range'][0]:.6f} to {result['nutation_range'][1]:.6f} rad)")
        print(f"  body speeds: max difference {speeds:.1e}")
        print("ok" if result["ok"] else "FAILED")
    return result
