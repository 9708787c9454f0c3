"""A block thrown up a rough incline: sliding up, stopping, then sticking or sliding back.

Source: the classical textbook problem (e.g. Meriam & Kraige, *Engineering Mechanics:
Dynamics*, ch. 3; Targ, *Theoretical Mechanics*, dynamics of a point); the closed form is
elementary and derived here.

Model.  A block of mass m on a plane inclined at the angle alpha.  Coordinates: x along the
incline, measured UP the slope, and y, the distance of the block from the plane (the gap of
the contact, so its multiplier is the normal force N).  Gravity has the components
``-g sin(alpha)`` along x and ``-g cos(alpha)`` along y:

    T = m (x'^2 + y'^2) / 2,        V = m g (x sin(alpha) + y cos(alpha)).

Contact ``plane``: gap ``y >= 0``, slip velocity ``U = x'``, Coulomb friction with kinetic
coefficient mu and static coefficient mu_s >= mu.

Closed form.  Thrown up the slope with speed v0 > 0 (y = 0 held, N = m g cos(alpha)):

* sliding up (U > 0, friction ``-mu N``): ``x'' = -a_up``, ``a_up = g (sin(alpha) + mu cos(alpha))``,
  ``x = v0 t - a_up t^2 / 2``;
* it stops (``U = 0``) at ``t1 = v0 / a_up`` after ``d = v0^2 / (2 a_up)``;
* if ``tan(alpha) <= mu_s`` static friction holds it: the needed friction ``F = m g sin(alpha)``
  stays below ``mu_s N`` for ever; mode ``stick``, no further event;
* if ``tan(alpha) > mu_s`` it slides back down (mode ``slide-``, friction ``+mu N``):
  ``x'' = -a_down``, ``a_down = g (sin(alpha) - mu cos(alpha)) > 0``,
  ``x = d - a_down (t - t1)^2 / 2`` -- no further event (the block never stops again).

Note the case ``mu < tan(alpha) <= mu_s`` (the default: tan 0.4 = 0.4228, mu = 0.3,
mu_s = 0.5): kinetic friction alone could not hold the block, static friction does.

Work of friction.  The plane is fixed, so the friction power is ``F U = -mu N |U| <= 0`` while
sliding and zero while sticking: ``W_f = -mu m g cos(alpha) * (path length)``, the path being
``d`` (sticks) or ``2 d - x(t)`` (slides back).  Energy balance:
``T + V - (T + V)(0) = W_f``.

Switching.  At ``t1`` the event is the slip velocity reaching zero; mode selection then decides
between sticking (consistent iff ``m g sin(alpha) <= mu_s N``; the event is recorded as "stick")
and sliding down (recorded as "reverse").  Exactly one event, no chattering, in both regimes.
"""

from __future__ import annotations

import numpy as np

from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "block-on-incline"
ORDER = 40
TITLE = ("Block thrown up a rough incline: stops at t1 = v0/(g(sin a + mu cos a)), sticks iff tan "
         "a <= mu_s")
FILE = "block_on_incline.toml"


def build(m: float = 2.0, g: float = 9.81, alpha: float = 0.4, mu: float = 0.3, mu_s: float = 0.5,
          v0: float = 3.0, t_end: float = 1.5) -> Model:
    """The block with the Python API (same as the model file for the default values)."""
    return Model(
        name="Block thrown up a rough incline",
        coordinates=["x", "y"],
        parameters={"m": m, "g": g, "alpha": alpha, "mu": mu, "mu_s": mu_s, "v0": v0},
        kinetic="m/2*(x'^2 + y'^2)",
        potential="m*g*(x*sin(alpha) + y*cos(alpha))",
        contacts=[Contact("plane", "y", ("x'",), Coulomb("mu", "mu_s"))],
        initial={"x": 0.0, "y": 0.0, "x'": "v0", "y'": 0.0},
        simulation={"t_end": t_end},
    )


def closed_form(p: dict) -> dict:
    """Stop time, distance, regime and accelerations for parameters *p* (see the docstring)."""
    g, a, mu, mu_s, v0 = p["g"], p["alpha"], p["mu"], p["mu_s"], p["v0"]
    a_up = g * (np.sin(a) + mu * np.cos(a))
    t1 = v0 / a_up
    d = v0 * v0 / (2 * a_up)
    sticks = bool(np.tan(a) <= mu_s)
    a_down = 0.0 if sticks else g * (np.sin(a) - mu * np.cos(a))
    return {"a_up": a_up, "t1": t1, "d": d, "sticks": sticks, "a_down": a_down,
            "N": p["m"] * g * np.cos(a), "F_stick": p["m"] * g * np.sin(a)}


def motion(t, p: dict):
    """``x(t), x'(t)`` and the friction work ``W_f(t)`` of the closed form."""
    cf = closed_form(p)
    t = np.asarray(t, dtype=float)
    up = t <= cf["t1"]
    s = np.where(up, 0.0, t - cf["t1"])
    x = np.where(up, p["v0"] * t - cf["a_up"] * t * t / 2, cf["d"] - cf["a_down"] * s * s / 2)
    xd = np.where(up, p["v0"] - cf["a_up"] * t, -cf["a_down"] * s)
    path = np.where(up, x, 2 * cf["d"] - x)
    return x, xd, -p["mu"] * cf["N"] * path


def check(model: Model, t_end: float | None = None) -> dict:
    """Simulate *model* and compare with the closed form (errors, events, energy)."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    cf = closed_form(p)
    t_end = t_end or model.simulation.t_end
    times = np.linspace(0.0, t_end, 31)
    tr = simulate(model, times=times)
    full = simulate(model)  # every step: friction power and the events
    x, xd, W = motion(times, p)
    ev = full.events
    plane = tr.contacts["plane"]
    sliding = np.array([m.startswith("slide") for m in plane["mode"]])
    F = np.array(plane["friction"])[:, 0]
    F_expected = np.where(sliding, -p["mu"] * cf["N"] * np.sign(tr.velocity("x") + 0.0), cf["F_stick"])
    return {
        "t1": cf["t1"], "d": cf["d"], "sticks": cf["sticks"],
        "events": [(e["t"], e["type"], e["mode"]) for e in ev],
        "t1_simulated": ev[0]["t"] if ev else None,
        "t1_relative_error": abs(ev[0]["t"] / cf["t1"] - 1) if ev else np.inf,
        "final_mode": full.modes[-1],
        "max_error_x": float(np.max(np.abs(tr.coordinate("x") - x))),
        "max_error_xdot": float(np.max(np.abs(tr.velocity("x") - xd))),
        "max_error_friction_work": float(np.max(np.abs(tr.energy["friction_work"] - W))),
        "friction_work_end": float(tr.energy["friction_work"][-1]),
        "friction_work_closed_form": float(W[-1]),
        "max_error_normal": float(np.max(np.abs(np.array(plane["normal"]) - cf["N"]))),
        "max_error_friction": float(np.max(np.abs(F - F_expected))),
        "friction_power_max": float(np.max(np.diff(full.energy["friction_work"]))),
        "energy_balance_relative": full.diagnostics["energy_balance_relative"],
        "constraint_residual_max": full.diagnostics["constraint_residual_max"],
    }


def _ok(r: dict, expected_modes: list[str]) -> bool:
    return (r["t1_relative_error"] < 1e-9 and [e[2] for e in r["events"]] == expected_modes
            and max(r["max_error_x"], r["max_error_xdot"], r["max_error_friction_work"],
                    r["max_error_normal"], r["max_error_friction"]) < 1e-8
            and r["friction_power_max"] <= 1e-12 and r["energy_balance_relative"] < 1e-8)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms

    model = gallery.load(NAME)
    cases = {
        "sticks (mu < tan a <= mu_s)": (model, ["plane:stick"]),
        "slides back (tan a > mu_s)": (build(alpha=0.6), ["plane:slide-"]),
        "slides back (mu_s = mu)": (build(mu_s=0.3), ["plane:slide-"]),
    }
    results = {}
    ok = True
    for label, (m, modes) in cases.items():
        r = check(m)
        r["ok"] = _ok(r, modes)
        ok &= r["ok"]
        results[label] = r
    cross = {state: compare_forms(model, contact_state=state).worst() for state in ("slide", "stick")}
    ok &= max(cross.values()) < 1e-10
    out = {"ok": bool(ok), "cases": results, "forms_disagreement": cross}
    if verbose:
        print(TITLE)
        for label, r in results.items():
            print(f"{label}:")
            print(f"  stop time t1 = v0/(g(sin a + mu cos a)) = {r['t1']:.12f}; simulated "
                  f"{r['t1_simulated']:.12f} (rel. error {r['t1_relative_error']:.1e})")
            print(f"  distance up d = {r['d']:.12f}; events {[(round(e[0], 9), e[1], e[2]) for e in r['events']]}")
            print(f"  friction work at t_end: {r['friction_work_end']:.12f} (closed form "
                  f"{r['friction_work_closed_form']:.12f} = -mu N * path)")
            print(f"  max errors: x {r['max_error_x']:.1e}, x' {r['max_error_xdot']:.1e}, "
                  f"N {r['max_error_normal']:.1e}, F {r['max_error_friction']:.1e}; energy balance "
                  f"{r['energy_balance_relative']:.1e}; friction power max {r['friction_power_max']:.1e}")
        print(f"all forms vs Lagrange I (sliding, sticking): {cross['slide']:.1e}, {cross['stick']:.1e}")
        print("ok" if ok else "FAILED")
    return out
