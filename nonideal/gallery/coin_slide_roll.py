"""A coin that slides, then rolls: the event time and the rolling velocity in closed form.

A thin uniform disk (mass m, radius r; I = m r^2/2 about its axis) stands upright on a rough
table (Coulomb, mu) and is launched along x with velocity v0 and spin w0 about its axis.  The
contact is declared as the rim of a disk; the library derives the gap and the slip
``U = x' - r phi'`` (upright, heading along x).  While sliding (s = sign U0), N = m g and

    x'' = -mu g s,      I phi'' = mu m g r s   =>   U' = -mu g s - 2 mu g s = -3 mu g s,

so the slip vanishes at ``t* = |U0| / (3 mu g)`` and the coin then rolls at

    v_f = v0 - U0/3 = (2 v0 + r w0)/3,      w_f = v_f / r,

the friction having dissipated ``m U0^2 / 6`` (the kinetic energy lost).  The upright motion
stays in the vertical plane by symmetry; rolling continues because |F| = 0 <= mu N.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model
from ..modeling.shapes import Disk
from .rotations import body_rotation

NAME = "coin-slide-roll"
ORDER = 231
TITLE = "Coin that slides then rolls: t* = U0/(3 mu g), v_f = v0 - U0/3 (the rim of a disk)"
FILE = "coin_slide_roll.toml"


def build(m: float = 0.0085, r: float = 0.0129, g: float = 9.81, mu: float = 0.3,
          v0: float = 1.0, w0: float = -50.0, t_end: float = 0.5) -> Model:
    """The coin with the Python API (the model file for the default values)."""
    return Model(
        name="coin that slides, then rolls", coordinates=["x", "y", "z", "psi", "theta", "phi"],
        parameters={"m": m, "r": r, "g": g, "mu": mu},
        bodies=[RigidBody("coin", "m", [["m*r^2/4", 0, 0], [0, "m*r^2/2", 0], [0, 0, "m*r^2/4"]],
                          ["x", "y", "z"], body_rotation("zxy", ("psi", "theta", "phi")))],
        gravity=[0, 0, "-g"],
        contacts=[Contact("table", body="coin", shape=Disk("r", (0, 1, 0)), friction=Coulomb("mu"))],
        initial={"x": 0.0, "y": 0.0, "z": "r", "psi": 0.0, "theta": 0.0, "phi": 0.0, "x'": v0,
                 "y'": 0.0, "z'": 0.0, "psi'": 0.0, "theta'": 0.0, "phi'": w0},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-13})


def closed_form(p: dict, v0: float, w0: float) -> dict:
    U0 = v0 - p["r"] * w0
    return {"U0": U0, "t_star": abs(U0) / (3 * p["mu"] * p["g"]), "v_f": v0 - U0 / 3,
            "w_f": (v0 - U0 / 3) / p["r"], "energy_loss": p["m"] * U0 ** 2 / 6}


def check(model: Model) -> dict:
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    v0, w0 = model.numeric_initial()["x'"], model.numeric_initial()["phi'"]
    cf = closed_form(p, v0, w0)
    tr = simulate(model)
    ev = tr.events
    return {"closed_form": cf, "events": [(e["t"], e["type"]) for e in ev],
            "t_star_error": abs(ev[0]["t"] / cf["t_star"] - 1) if ev else np.inf,
            "v_f": float(tr.qd[-1, 0]), "v_f_error": abs(tr.qd[-1, 0] / cf["v_f"] - 1),
            "w_f_error": abs(tr.qd[-1, 5] / cf["w_f"] - 1),
            "friction_work": float(tr.energy["friction_work"][-1]),
            "lean_max": float(np.max(np.abs(tr.q[:, 4]))),
            "energy_balance_relative": tr.diagnostics["energy_balance_relative"]}


def run(verbose: bool = True) -> dict:
    from .. import gallery

    r = check(gallery.load(NAME))
    fwd = check(build(v0=0.5, w0=0.0, t_end=0.3))
    ok = all(x["t_star_error"] < 1e-9 and x["v_f_error"] < 1e-9 and x["w_f_error"] < 1e-9
             and [e[1] for e in x["events"]] == ["stick"]
             and abs(x["friction_work"] / x["closed_form"]["energy_loss"] + 1) < 1e-8 for x in (r, fwd))
    if verbose:
        print(TITLE)
        for label, x in (("v0 = 1 m/s, backspin 50 rad/s", r), ("v0 = 0.5 m/s, no spin", fwd)):
            cf = x["closed_form"]
            print(f"{label}: U0 = {cf['U0']:.6f} m/s; t* = {cf['t_star']:.12f} s "
                  f"(simulated: rel. error {x['t_star_error']:.1e}); v_f = {cf['v_f']:.12f} m/s "
                  f"(rel. error {x['v_f_error']:.1e}); heat {-x['friction_work']:.3e} J = m U0^2/6 "
                  f"= {cf['energy_loss']:.3e} J")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "backspin": r, "forward": fwd}
