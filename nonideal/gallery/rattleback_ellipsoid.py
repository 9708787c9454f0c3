"""The rattleback of Kane & Levinson 1982: half an ellipsoid rolling on a plane.

Kane & Levinson 1982 (J. Appl. Mech. 49, 2nd "realistic" model) -- the parameter set most
later studies reuse: semi-axes a = 0.2, b = 0.03, c = 0.02 m, the centre of mass h = 0.01 m
below the ellipsoid's centre, m = 1 kg, A = 2e-4, B = 1.6e-3, C = 1.7e-3 and the product of
inertia D = -2e-5 kg m^2 in the ellipsoid's axes, released rolled and pitched by 0.5 deg and
spun at -5 rad/s.  The contact is declared by its shape (``ellipsoid`` with ``center = [0, 0,
h]``) rolling without slipping; the library derives the support point
-D^2 n_b / sqrt(n_b^T D^2 n_b), the gap and the rolling rows.

Behaviour (no dissipation).  Spun at -5 rad/s the pitching oscillation grows at the expense of
the spin; the spin stops and reverses at t_r = 2.765 s and reaches +5.27 rad/s at t = 6 s.
Spun at +5 rad/s it keeps spinning (no reversal in 6 s).  Without dissipation the reversed spin
eventually reverses again through the rolling mode (Garcia & Hubbard 1988; at t = 17.7 s here).
Linearized about the steady spin (``nonideal stability rattleback-ellipsoid --about steady --at
"al=0, be=0, psi'=-0.5"``): at rest the rocking frequencies are the closed form of the small
oscillations on the radii of curvature a^2/c and b^2/c, 33.83 and 107.21 rad/s; spun at -0.5
rad/s the pitching mode grows at 0.213 1/s, spun at +0.5 rad/s the rolling mode at 0.0212 1/s
-- ten times slower: the preferred direction.
The test compares the spin and the linearization with an independent derivation: the Newton-Euler equations of the
rolling ellipsoid written by hand and integrated with SciPy
(tests/literature/test_kane1982_rattleback.py).
"""

from __future__ import annotations

import math

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, IdealRolling
from ..modeling.model import Model
from ..modeling.shapes import Ellipsoid
from . import rattleback
from .rattleback import reversal_time  # noqa: F401 -- the tests read it here
from .rotations import body_rotation

NAME = "rattleback-ellipsoid"
ORDER = 233
TITLE = "Rattleback as half an ellipsoid: Kane & Levinson 1982's data, the spin reverses"
FILE = "rattleback_ellipsoid.toml"

PARAMETERS = {"m": 1.0, "a": 0.20, "b": 0.03, "c": 0.02, "h": 0.01, "A": 2.0e-4, "B": 1.6e-3,
              "C": 1.7e-3, "D": -2.0e-5, "g": 9.81, "w0": -5.0, "tilt": math.radians(0.5)}


def build(t_end: float = 6.0, **params) -> Model:
    """The rattleback with the Python API (the model file for the default values)."""
    p = {**PARAMETERS, **params}
    return Model(
        name="rattleback (ellipsoid, Kane & Levinson 1982)",
        coordinates=["x", "y", "z", "psi", "al", "be"], parameters=p,
        bodies=[RigidBody("shell", "m", [["A", "D", 0], ["D", "B", 0], [0, 0, "C"]], ["x", "y", "z"],
                          body_rotation("zxy", ("psi", "al", "be")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="shell", shape=Ellipsoid(("a", "b", "c"), (0, 0, "h")),
                          friction=IdealRolling())],
        initial={"x": 0.0, "y": 0.0, "psi": 0.0, "al": "tilt", "be": "tilt", "psi'": "w0",
                 "al'": 0.0, "be'": 0.0},
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12})


def check(model: Model, t_end: float | None = None, samples: int = 1201) -> dict:
    """:func:`nonideal.gallery.rattleback.check` with this model's angle names."""
    return rattleback.check(model, t_end, samples, roll="al", pitch="be")


def run(verbose: bool = True) -> dict:
    from .. import gallery

    neg = check(gallery.load(NAME))
    pos = check(build(w0=5.0))
    ok = (neg["reversal_time"] is not None and 2.7 < neg["reversal_time"] < 2.8 and neg["spin"][-1] > 4.5
          and pos["reversal_time"] is None and max(neg["energy_drift"], pos["energy_drift"]) < 1e-7
          and min(neg["normal_min"], pos["normal_min"]) > 0 and not neg["events"] and not pos["events"])
    if verbose:
        print(TITLE)
        print(f"spun at -5 rad/s: the spin reverses at t_r = {neg['reversal_time']:.6f} s, "
              f"{neg['spin'][-1]:+.4f} rad/s at t = {neg['t'][-1]:g} s")
        print(f"spun at +5 rad/s: no reversal in {pos['t'][-1]:g} s (spin {pos['spin'][-1]:+.4f} rad/s)")
        print(f"energy drift {max(neg['energy_drift'], pos['energy_drift']):.1e} (rolling: conserved)")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "reversal_time": neg["reversal_time"], "other_direction": pos["reversal_time"],
            "energy_drift": max(neg["energy_drift"], pos["energy_drift"])}
