"""A ball dropped on a floor, bouncing lower each time: infinitely many impacts before a finite
time (Zeno behaviour), then at rest.

Source: the classical example of a hybrid system with an accumulation of impacts (Newton's
impact law; e.g. Brogliato, *Nonsmooth Mechanics*, 3rd ed. 2016, sec. 7.1; Acary & Brogliato,
*Numerical Methods for Nonsmooth Dynamical Systems*, 2008, sec. 1.1).  The closed form is
derived here.

Model.  A ball of mass m; coordinates x (horizontal position) and y (height above the floor,
the gap of the contact ``floor``; the floor is smooth):

    T = m (x'^2 + y'^2) / 2,        V = m g y.

Newton's impact law with restitution e: at an impact ``y'(+) = -e y'(-)``.

Closed form.  Dropped from h0 at rest, the ball falls for ``t_1 = sqrt(2 h0 / g)`` and hits the
floor with the speed ``v_1 = g t_1``.  It leaves the k-th impact (k = 1, 2, ...) with the speed
``e^k v_1``, flies for ``2 e^k v_1 / g`` and rises to ``e^(2k) h0``.  So the impacts come at

    t_k = t_1 + (2 v_1 / g) (e + e^2 + ... + e^(k-1)),

a geometric series whose intervals shrink by the ratio e and which accumulates at

    t_inf = t_1 + 2 v_1 e / (g (1 - e)) = t_1 (1 + e) / (1 - e).

Infinitely many impacts happen before t_inf; an event-driven simulation cannot take them one by
one.  The simulation takes them until the series is recognisably geometric, then jumps to its
limit t_inf (an event of type ``zeno``, with the number of impacts taken and the ratio found),
and the ball rests on the floor from then on.  All the energy ``m g h0`` is lost in the impacts
(``impact_work``, the skipped ones included).  With the defaults (h0 = 1 m, e = 0.5):
t_1 = 0.451524 s, t_inf = 3 t_1 = 1.354571 s.
"""

from __future__ import annotations

import numpy as np

from ..modeling.contacts import Contact, Coulomb, Newton
from ..modeling.model import Model

NAME = "bouncing-ball"
ORDER = 45
TITLE = ("Ball dropped on a floor, bouncing lower each time (restitution e = 0.5): infinitely many "
         "impacts before t = t_1 (1 + e)/(1 - e) = 1.3546 s, then at rest")
FILE = "bouncing_ball.toml"


def build(m: float = 1.0, g: float = 9.81, h0: float = 1.0, e: float = 0.5,
          t_end: float = 3.0) -> Model:
    """The ball with the Python API (same as the model file for the default values)."""
    return Model(
        name="Ball bouncing on a floor",
        coordinates=["x", "y"],
        parameters={"m": m, "g": g, "h0": h0, "e": e},
        kinetic="m/2*(x'^2 + y'^2)",
        potential="m*g*y",
        contacts=[Contact("floor", "y", ("x'",), Coulomb(0), Newton(e))],
        initial={"x": 0.0, "y": "h0", "x'": 0.0, "y'": 0.0},
        simulation={"t_end": t_end},
    )


def closed_form(p: dict, count: int = 0) -> dict:
    """First impact, impact speed, the first *count* impact times and the accumulation time."""
    g, h0, e = p["g"], p["h0"], p["e"]
    t1 = np.sqrt(2 * h0 / g)
    v1 = g * t1
    times = [t1 + 2 * v1 / g * sum(e ** j for j in range(1, k + 1)) for k in range(count)]
    return {"t1": float(t1), "v1": float(v1), "impacts": times,
            "speeds": [float(v1 * e ** k) for k in range(count)],
            "t_inf": float(t1 * (1 + e) / (1 - e)), "energy_lost": p["m"] * g * h0}


def check(model: Model) -> dict:
    """Simulate *model* to its end time and compare with the closed form."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    traj = simulate(model)
    impacts = [ev for ev in traj.events if ev["type"] == "touch"]
    zeno = [ev for ev in traj.events if ev["type"] == "zeno"]
    cf = closed_form(p, len(impacts))
    t_imp = np.array([ev["t"] for ev in impacts])
    speeds = np.array([-ev["normal_velocity"] for ev in impacts])
    # the tops of the first bounces: e^(2k) h0, half-way between two impacts
    tops = 0.5 * (t_imp[:-1] + t_imp[1:])
    at = simulate(model, times=np.concatenate((tops, [p_end := model.simulation.t_end])))
    heights = at.coordinate("y")[:-1]
    expected_heights = p["h0"] * p["e"] ** (2 * np.arange(1, len(tops) + 1))
    E = traj.energy
    return {
        "impacts": len(impacts), "impact_times": t_imp.tolist(), "closed_form": cf,
        "max_error_impact_times": float(np.max(np.abs(t_imp - cf["impacts"]))) if impacts else np.inf,
        "max_error_impact_speeds": float(np.max(np.abs(speeds - cf["speeds"]))) if impacts else np.inf,
        "max_error_heights": float(np.max(np.abs(heights - expected_heights))) if tops.size else np.inf,
        "zeno_events": len(zeno),
        "zeno_t": zeno[0]["t"] if zeno else None, "zeno_ratio": zeno[0]["ratio"] if zeno else None,
        "error_zeno_t": abs(zeno[0]["t"] - cf["t_inf"]) if zeno else np.inf,
        "final_t": float(traj.t[-1]), "end": p_end,
        "final_height": float(traj.coordinate("y")[-1]), "final_speed": float(np.max(np.abs(traj.qd[-1]))),
        "final_mode": traj.modes[-1],
        "impact_work": float(E["impact_work"][-1]),
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
    }


def run(verbose: bool = True) -> dict:
    from .. import gallery

    model = gallery.load(NAME)
    r = check(model)
    cf = r["closed_form"]
    ok = (r["impacts"] >= 5 and r["max_error_impact_times"] < 1e-11 and r["max_error_impact_speeds"] < 1e-10
          and r["max_error_heights"] < 1e-10 and r["zeno_events"] == 1 and r["error_zeno_t"] < 1e-11
          and abs(r["zeno_ratio"] - model.parameter_values["e"]) < 1e-9
          and r["final_t"] == r["end"] and abs(r["final_height"]) < 1e-12 and r["final_speed"] < 1e-12
          and abs(r["impact_work"] + cf["energy_lost"]) < 1e-9 * cf["energy_lost"]
          and abs(r["energy_balance_relative"]) < 1e-9)
    out = {"ok": bool(ok), **r}
    if verbose:
        print(TITLE)
        print(f"closed form: first impact t_1 = {cf['t1']:.12f} s at v_1 = {cf['v1']:.12f} m/s; impacts "
              f"t_k = t_1 + (2 v_1/g)(e + ... + e^(k-1)); accumulation t_inf = {cf['t_inf']:.12f} s")
        for k, (t, tc) in enumerate(zip(r["impact_times"], cf["impacts"]), 1):
            print(f"  impact {k:2d} at t = {t:.12f}   (closed form {tc:.12f})")
        print(f"  {r['impacts']} impacts simulated: times max error {r['max_error_impact_times']:.1e} s, "
              f"speeds {r['max_error_impact_speeds']:.1e} m/s, bounce heights e^(2k) h0 "
              f"{r['max_error_heights']:.1e} m")
        print(f"  zeno event at t = {r['zeno_t']:.12f} (closed form {cf['t_inf']:.12f}, ratio "
              f"{r['zeno_ratio']:.9f}): the rest of the series skipped")
        print(f"  at rest from then on: at t = {r['final_t']:g} y = {r['final_height']:.1e}, speed "
              f"{r['final_speed']:.1e}, mode [{r['final_mode']}]")
        print(f"  energy lost in the impacts {-r['impact_work']:.12f} J (m g h0 = {cf['energy_lost']:.12f} J); "
              f"energy balance {r['energy_balance_relative']:.1e}")
        print("ok" if ok else "FAILED")
    return out
