"""The tippe top with Coulomb friction over a contact patch: it turns over.

Leine & Glocker 2003 (Eur. J. Mech. A/Solids 22, sec. 5) for the top: m = 6 g, a sphere of
radius R = 15 mm whose centre lies a = 3 mm above the centre of mass on the symmetry axis,
A = 8e-7, C = 7e-7 kg m^2, mu = 0.3, released tilted by 0.1 rad and spun at 180 rad/s about
its axis.  The friction is Coulomb's law over a circular contact patch of radius rho = 0.5 mm
(``friction = "contensou"``, Contensou 1963): each point of the patch slides at
v + omega_n x r, the patch's resultant is a force -mu N f(d) v/|v| and a pivoting torque
-mu N rho m(d) sign(omega_n), d = |v|/(rho |omega_n|) (:mod:`nonideal.numeric.contensou`).

**Why this law.**  With Coulomb's law at a point (``tippe-top``, ``build(exact=True)``) the
initial slip dies after 36 ms and the top rolls without turning over: rolling conserves energy
and nothing lifts the centre of mass.  Over a patch the sliding force of a pivoting body is
continuous in the slip -- it falls to zero only linearly, as -mu N v/(rho omega_n) -- so the
slip never stops while the top spins, and the sliding friction turns it over, as the
inverting tops of Leine & Glocker 2003 do with the same coupling.

**Jellett's integral** lambda = L_G . (a k - R e_z) (L_G the angular momentum about the centre
of mass, k the symmetry axis) is no longer constant: the friction force acts at the contact
point, on the line of a k - R e_z, and drops out, but the pivoting torque M e_z does not:

    d(lambda)/dt = M (a k_z - R) = M (a cos(theta) - R).

What is checked (``run``; ``tests/literature/test_leine2003_tippe_top_contensou.py``): the
inversion (theta from 0.1 to > 2.9 rad in 3 s, the centre of mass raised by > 1.8 a), the
balance of lambda above integrated along the run, the energy balance and friction that never
does positive work; the test also compares theta(t) with an independent Newton-Euler
integration to 1e-8 rad.
"""

from __future__ import annotations

import math

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, CoulombContensou
from ..modeling.frames import Frame
from ..modeling.model import Model
from ..modeling.points import Point
from ..modeling.shapes import Sphere
from .tippe_top import invariants

NAME = "tippe-top-contensou"
ORDER = 236
TITLE = "Tippe top with Coulomb friction over a contact patch (Contensou): it turns over"
FILE = "tippe_top_contensou.toml"

PARAMETERS = {"m": 0.006, "R": 0.015, "a": 0.003, "A": 8.0e-7, "C": 7.0e-7, "g": 9.81, "mu": 0.3,
              "rho": 5.0e-4, "theta0": 0.1, "W": 180.0}
E = ["e0", "e1", "e2", "e3"]


def build(t_end: float = 3.0, speeds: dict | None = None, name: str = "tippe top (Coulomb-Contensou friction)",
          **parameters) -> Model:
    """The top with the Python API (the model file for the defaults); *speeds*: generalized
    speeds (``[speeds]``), the initial state then given in them."""
    initial = {"x": 0.0, "y": 0.0, "z": "R - a*cos(theta0)", "e0": "cos(theta0/2)", "e1": "sin(theta0/2)",
               "e2": 0.0, "e3": 0.0}
    if speeds:
        initial.update({"u1": 0.0, "u2": 0.0, "u3": 0.0, "w1": 0.0, "w2": 0.0, "w3": "W"})
    else:
        initial.update({"x'": 0.0, "y'": 0.0, "z'": 0.0, "e0'": 0.0, "e1'": 0.0,
                        "e2'": "-W*sin(theta0/2)/2", "e3'": "W*cos(theta0/2)/2"})
    return Model(
        name=name, coordinates=["x", "y", "z", *E],
        parameters={**PARAMETERS, **parameters},
        frames=[Frame("B", quaternion=E)],
        points=[Point("G", ["x", "y", "z"])],
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G")],
        gravity=["0", "0", "-g"],
        contacts=[Contact("table", body="top", shape=Sphere("R", center=(0, 0, "a")),
                          friction=CoulombContensou("mu", "rho"))],
        initial=initial, simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12},
        **({"speeds": speeds} if speeds else {}))


def jellett_balance(t, theta, jellett, torque, p: dict) -> float:
    """max |lambda(t) - lambda(0) - int M (a cos(theta) - R) dt| / |lambda(0)| (Simpson's rule on
    uniform samples *t*, an odd number of them)."""
    rate = torque * (p["a"] * np.cos(theta) - p["R"])
    h = t[1] - t[0]
    integral = np.zeros_like(t)
    # cumulative Simpson's rule over pairs of intervals: at every even sample to O(h^4)
    integral[2::2] = np.cumsum(h / 3 * (rate[:-2:2] + 4 * rate[1:-1:2] + rate[2::2]))
    even = slice(0, None, 2)
    return float(np.max(np.abs(jellett[even] - jellett[0] - integral[even])) / abs(jellett[0]))


def check(model: Model | None = None, t_end: float = 3.0, samples: int = 3001) -> dict:
    """Simulate on *samples* uniform times; theta, Jellett's balance, the energy balance and the
    friction work."""
    from .. import gallery
    from ..simulation.hybrid import simulate

    model = model or gallery.load(NAME)
    p = {k: float(v) for k, v in model.parameter_values.items()}
    t = np.linspace(0.0, t_end, samples)
    tr = simulate(model, times=t)
    inv = invariants(tr, p)
    torque = np.asarray(tr.contacts["table"]["friction"])[:, 2] * p["rho"]   # F3 rho = M
    work = np.asarray(tr.energy["friction_work"])
    return {"t": t, "theta": inv["theta"], "z": tr.coordinate("z"), "trajectory": tr,
            "jellett": inv["jellett"], "pivoting_torque": torque,
            "jellett_balance": jellett_balance(t, inv["theta"], inv["jellett"], torque, p),
            "jellett_change": float(abs(inv["jellett"][-1] - inv["jellett"][0]) / abs(inv["jellett"][0])),
            "energy_balance": float(tr.diagnostics["energy_balance_relative"]),
            "friction_work_increase": float(np.max(np.diff(work))), "slip_min": float(inv["slip"].min()),
            "events": tr.events, "p": p}


def run(verbose: bool = True) -> dict:
    r = check()
    p = r["p"]
    rise = (r["z"][-1] - r["z"][0]) / p["a"]
    ok = (r["theta"][-1] > 2.9 and rise > 1.8 and r["jellett_balance"] < 1e-6 and r["jellett_change"] > 1e-3
          and r["energy_balance"] < 1e-8 and r["friction_work_increase"] <= 1e-15 and not r["events"])
    if verbose:
        k = int(np.argmax(r["theta"] > math.pi / 2))
        print(TITLE)
        print(f"theta: {r['theta'][0]:.3f} -> {r['theta'][-1]:.4f} rad in {r['t'][-1]:g} s (pi/2 passed at "
              f"t = {r['t'][k]:.3f} s); the centre of mass rose by {rise:.3f} a")
        print(f"slip never below {r['slip_min']:.3e} m/s (no stick); Jellett's lambda changed by "
              f"{r['jellett_change']:.2%}, its balance with the pivoting torque closes to {r['jellett_balance']:.1e}")
        print(f"energy balance {r['energy_balance']:.1e}; friction work never increases")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "theta_end": float(r["theta"][-1]), "rise": float(rise),
            "jellett_balance": r["jellett_balance"], "energy_balance": r["energy_balance"]}
