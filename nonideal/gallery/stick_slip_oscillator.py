"""Stick-slip oscillator: a block on a moving belt, held by a spring (static > kinetic friction).

Source: the classical model of friction-induced oscillations (Den Hartog, *Mechanical
Vibrations*, 1934/1985, sec. on self-excited vibrations; Popp & Stelter, *Phil. Trans. R. Soc.
A* 332 (1990) 89-105); the closed form of the limit cycle is derived here.

Model.  A block of mass m on a conveyor belt moving at the constant speed v_b, tied to a fixed
wall by a spring of stiffness k.  Coordinates: x, the extension of the spring (the block's
position, x = 0 with the spring relaxed, +x in the direction of the belt), and y, the height
of the block above the belt (the gap; its multiplier is the normal force N = m g):

    T = m (x'^2 + y'^2) / 2,        V = k x^2 / 2 + m g y.

Contact ``belt``: gap ``y``, slip velocity = velocity of the block RELATIVE to the belt,
``U = x' - v_b`` (linear in the velocities with a constant term); Coulomb friction, kinetic mu,
static mu_s > mu.  The support moves: the friction force F does the work ``F x'`` on the
block, positive while the block sticks and is carried along; of it ``F U <= 0`` is dissipated
(the library's ``friction_work``, never positive) and ``F v_b`` is what the belt's drive puts
in (counted with the work of the reactions, ``reaction_work``, as a moving support's is).

Closed form.  omega = sqrt(k/m); ``x_s = mu_s m g / k`` (end of sticking),
``x_k = mu m g / k`` (centre of the sliding oscillation), ``d = x_s - x_k``.

* Sticking (U = 0): ``x = x_a + v_b (t - t_a)``; friction needed ``F = k x`` (it balances the
  spring); it holds while ``k x <= mu_s m g``: slip starts at ``x = x_s``.
* Slipping: the block is slower than the belt (U < 0), friction ``+mu m g``:
  ``m x'' = -k (x - x_k)``, harmonic about x_k starting at ``x_s`` with ``x' = v_b``:
  ``x - x_k = A cos(omega tau + phi)``, ``A = sqrt(d^2 + (v_b/omega)^2)``,
  ``phi = -atan(v_b / (omega d))``.  ``x' = v_b`` again when ``omega tau = pi - 2 phi``, at
  ``x = x_k - d``: the slip lasts ``T_slip = (pi + 2 atan(v_b omega / ((mu_s - mu) g))) / omega``.
* There sticking is consistent (``|k (x_k - d)| = |2 mu - mu_s| m g <= mu_s m g``) and the block
  rides with the belt from ``x_k - d`` to ``x_s``: ``T_stick = 2 d / v_b = 2 (mu_s - mu) g /
  (omega^2 v_b)``.

Every slip starts at the same state (x_s, v_b), so the motion is exactly periodic from the
first slip on (the limit cycle is reached in finite time, not asymptotically):

    T = T_stick + T_slip,        x in [x_k - A, x_k + A]  (amplitude A about x_k),

the extremes at ``tau = atan(v_b / (omega d)) / omega`` (x_k + A) and
``tau = (pi + atan(v_b / (omega d))) / omega`` (x_k - A) after each slip onset.

Work and heat per cycle.  Friction work on the block: sticking ``k (x_s^2 - (x_k - d)^2) / 2 =
2 d mu m g``, slipping ``-2 d mu m g``: zero per cycle (the energy ``T + V`` is periodic).  Heat
``-int F U dt = mu m g (2 d + v_b T_slip)`` per cycle, all of it while slipping (``friction_work``
falls by that much in each slip phase and stays constant while sticking), supplied by the
belt's drive: ``int F v_b dt`` = ``2 d mu m g`` sticking plus ``mu m g v_b T_slip`` slipping.

Default (m = 1, k = 10, mu = 0.25, mu_s = 0.4, v_b = 0.5, g = 9.81), starting on the belt with
the spring relaxed: slip at ``t = x_s / v_b = 0.7848``, then ``T_slip = 1.51289380558``,
``T_stick = 0.5886``, ``T = 2.10149380558``.  Started at rest instead (x' = 0, sliding), the
block first catches up with the belt at ``t = asin(v_b / (omega x_k)) / omega`` and joins the
same cycle at its next slip.
"""

from __future__ import annotations

import numpy as np

from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "stick-slip-oscillator"
ORDER = 43
TITLE = ("Stick-slip oscillator on a moving belt: limit cycle T = 2d/v_b + (pi + 2 atan(v_b "
         "omega/((mu_s-mu) g)))/omega")
FILE = "stick_slip_oscillator.toml"


def build(m: float = 1.0, k: float = 10.0, g: float = 9.81, mu: float = 0.25, mu_s: float = 0.4,
          v_b: float = 0.5, x0: float = 0.0, xd0=None, t_end: float = 7.0) -> Model:
    """The oscillator with the Python API (same as the model file for the default values);
    ``xd0`` defaults to the belt speed (the block starts carried along)."""
    return Model(
        name="Stick-slip oscillator: block on a moving belt, held by a spring",
        coordinates=["x", "y"],
        parameters={"m": m, "k": k, "g": g, "mu": mu, "mu_s": mu_s, "v_b": v_b},
        kinetic="m/2*(x'^2 + y'^2)",
        potential="k/2*x^2 + m*g*y",
        contacts=[Contact("belt", "y", ("x' - v_b",), Coulomb("mu", "mu_s"))],
        initial={"x": x0, "y": 0.0, "x'": "v_b" if xd0 is None else xd0, "y'": 0.0},
        simulation={"t_end": t_end},
    )


def closed_form(p: dict) -> dict:
    """Limit cycle: durations, period, amplitude, works (see the docstring)."""
    m, k, g, mu, mu_s, vb = p["m"], p["k"], p["g"], p["mu"], p["mu_s"], p["v_b"]
    w = np.sqrt(k / m)
    x_s, x_k = mu_s * m * g / k, mu * m * g / k
    d = x_s - x_k
    A = np.hypot(d, vb / w)
    beta = np.arctan(vb / (w * d))
    T_slip = (np.pi + 2 * beta) / w
    T_stick = 2 * d / vb
    return {"omega": w, "x_s": x_s, "x_k": x_k, "d": d, "A": A, "T_slip": T_slip,
            "T_stick": T_stick, "T": T_slip + T_stick, "x_max": x_k + A, "x_min": x_k - A,
            "tau_max": beta / w, "tau_min": (np.pi + beta) / w,
            "work_stick": 2 * d * mu * m * g, "work_slip": -2 * d * mu * m * g,
            "heat_per_cycle": mu * m * g * (2 * d + vb * T_slip),
            "belt_work_stick": 2 * d * mu * m * g, "belt_work_slip": mu * m * g * vb * T_slip}


def first_slip(p: dict, x0: float = 0.0, xd0=None) -> tuple[float, list]:
    """Time of the first slip onset (and the events before it) for a start at ``x0`` carried
    along (``xd0`` None) or at rest (``xd0 = 0``, sliding; needs ``omega x_k > v_b``)."""
    cf = closed_form(p)
    if xd0 is None:
        return (cf["x_s"] - x0) / p["v_b"], []
    # at rest, sliding backwards relative to the belt: x = x_k + (x0 - x_k) cos(omega t)
    w, c = cf["omega"], x0 - cf["x_k"]
    t_c = np.arcsin(p["v_b"] / (-c * w)) / w            # catches up with the belt
    x_a = cf["x_k"] + c * np.cos(w * t_c)
    return t_c + (cf["x_s"] - x_a) / p["v_b"], [(t_c, "stick")]


def schedule(p: dict, t_end: float, x0: float = 0.0, xd0=None) -> list[tuple[float, str]]:
    """Events ``(t, kind)`` up to ``t_end``: "slip" (stick ends) and "stick" (slip ends)."""
    cf = closed_form(p)
    t, out = first_slip(p, x0, xd0)
    out = list(out)
    while t <= t_end:
        out.append((t, "slip"))
        if t + cf["T_slip"] <= t_end:
            out.append((t + cf["T_slip"], "stick"))
        t += cf["T"]
    return out


def check(model: Model, x0: float = 0.0, xd0=None) -> dict:
    """Simulate *model* and compare with the closed form."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    cf = closed_form(p)
    t_end = model.simulation.t_end
    full = simulate(model)
    expected = schedule(p, t_end, x0, xd0)
    ev = full.events
    kinds_ok = [(e["type"], e["contact"]) for e in ev] == [(k, "belt") for _, k in expected]
    err_t = max((abs(e["t"] / t - 1) for e, (t, _) in zip(ev, expected)), default=np.inf) if kinds_ok else np.inf
    slips = np.array([e["t"] for e in ev if e["type"] == "slip"])
    periods = np.diff(slips)
    # extremes of the cycle and the friction work at the event times
    t_slip1 = slips[0]
    t_ext = [t_slip1 + cf["tau_max"], t_slip1 + cf["tau_min"]]
    times = np.union1d([0.0], [e["t"] for e in ev] + t_ext)
    tr = simulate(model, times=times)
    x = tr.coordinate("x")
    i_max, i_min = (int(np.argmin(np.abs(times - s))) for s in t_ext)
    # per phase: the heat (friction_work, only while slipping) and what the belt puts in
    # (reaction_work); their sum is the work of friction on the block
    W, WR = tr.energy["friction_work"], tr.energy["reaction_work"]
    ie = [int(np.argmin(np.abs(times - e["t"]))) for e in ev]
    dW = {"stick": [], "slip": []}
    heat = {"stick": [], "slip": []}
    belt = {"stick": [], "slip": []}
    for a, b, e in zip(ie[:-1], ie[1:], ev[:-1]):  # phase from event e to the next
        phase = "slip" if e["type"] == "slip" else "stick"
        dW[phase].append(W[b] - W[a] + WR[b] - WR[a])
        heat[phase].append(W[b] - W[a])
        belt[phase].append(WR[b] - WR[a])
    # the first sticking phase of a start at rest begins off the cycle (not at x_k - d)
    full_sticks = dW["stick"][0 if xd0 is None else 1:]
    E = full.energy
    return {
        "events": [(e["t"], e["type"]) for e in ev], "expected": expected,
        "event_times_relative_error": float(err_t),
        "periods": periods.tolist(), "period": cf["T"],
        "period_max_relative_error": float(np.max(np.abs(periods / cf["T"] - 1))) if periods.size else np.inf,
        "x_max": float(x[i_max]), "x_max_closed_form": cf["x_max"],
        "x_min": float(x[i_min]), "x_min_closed_form": cf["x_min"],
        "work_slip_phases": dW["slip"], "work_stick_phases": full_sticks,
        "max_error_work_phases": float(max([abs(w - cf["work_slip"]) for w in dW["slip"]]
                                           + [abs(w - cf["work_stick"]) for w in full_sticks] + [0.0])),
        "heat_slip_phases": heat["slip"],
        "max_error_heat_phases": float(max([abs(w + cf["heat_per_cycle"]) for w in heat["slip"]]
                                           + [abs(w) for w in heat["stick"]] + [0.0])),
        "max_error_belt_work": float(max([abs(w - cf["belt_work_slip"]) for w in belt["slip"]]
                                         + [abs(w - cf["belt_work_stick"]) for w in belt["stick"][0 if xd0 is None else 1:]]
                                         + [0.0])),
        "friction_work_never_increases": bool(np.max(np.diff(E["friction_work"])) <= 1e-12),
        "energy_balance_relative": full.diagnostics["energy_balance_relative"],
        "energy_balance_max": full.diagnostics["energy_balance_max"],
        "constraint_residual_max": full.diagnostics["constraint_residual_max"],
        "max_error_normal": float(np.max(np.abs(np.array(full.contacts["belt"]["normal"]) - p["m"] * p["g"]))),
    }


def _ok(r: dict) -> bool:
    return (r["event_times_relative_error"] < 1e-8 and r["period_max_relative_error"] < 1e-8
            and abs(r["x_max"] - r["x_max_closed_form"]) < 1e-9
            and abs(r["x_min"] - r["x_min_closed_form"]) < 1e-9
            and r["max_error_work_phases"] < 1e-9 and r["friction_work_never_increases"]
            and r["max_error_heat_phases"] < 1e-9 and r["max_error_belt_work"] < 1e-9
            and r["energy_balance_relative"] < 1e-8 and r["constraint_residual_max"] < 1e-10
            and r["max_error_normal"] < 1e-10)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms

    model = gallery.load(NAME)
    p = model.parameter_values
    cf = closed_form(p)
    carried = check(model)
    rest = check(build(xd0=0.0), xd0=0.0)
    cross = {state: compare_forms(model, contact_state=state).worst() for state in ("slide", "stick")}
    ok = _ok(carried) and _ok(rest) and max(cross.values()) < 1e-10
    out = {"ok": bool(ok), "closed_form": cf, "carried_along": carried, "from_rest": rest,
           "forms_disagreement": cross}
    if verbose:
        print(TITLE)
        print(f"closed form: omega = {cf['omega']:.10f}, slip at k x = mu_s m g (x_s = {cf['x_s']:.6f}), "
              f"slip oscillation about x_k = {cf['x_k']:.6f}")
        print(f"  T_slip = {cf['T_slip']:.12f}, T_stick = {cf['T_stick']:.12f}, period T = {cf['T']:.12f}, "
              f"amplitude A = {cf['A']:.12f}")
        for label, r in (("start carried along (x' = v_b)", carried), ("start at rest (x' = 0)", rest)):
            print(f"{label}:")
            for (t, kind), (te, ke) in zip(r["events"], r["expected"]):
                print(f"  {kind:5s} at t = {t:.12f}   (closed form {te:.12f}, {ke})")
            print(f"  event times max rel. error {r['event_times_relative_error']:.1e}; periods "
                  f"{np.round(r['periods'], 12).tolist()} (rel. error {r['period_max_relative_error']:.1e})")
            print(f"  x_max {r['x_max']:.12f} (closed form {r['x_max_closed_form']:.12f}), x_min "
                  f"{r['x_min']:.12f} ({r['x_min_closed_form']:.12f})")
            print(f"  friction work per phase: slip {np.round(r['work_slip_phases'], 12).tolist()}, "
                  f"stick {np.round(r['work_stick_phases'], 12).tolist()} (closed form "
                  f"-/+ 2 d mu m g = {cf['work_slip']:.12f}); energy balance {r['energy_balance_relative']:.1e}")
            print(f"  heat per slip phase (friction_work): {np.round(r['heat_slip_phases'], 12).tolist()}, "
                  f"none while sticking (error {r['max_error_heat_phases']:.1e}); the belt's work per phase "
                  f"(reaction_work) error {r['max_error_belt_work']:.1e}")
        print(f"heat per cycle (supplied by the belt): {cf['heat_per_cycle']:.12f} J")
        print(f"all forms vs Lagrange I (sliding, sticking): {cross['slide']:.1e}, {cross['stick']:.1e}")
        print("ok" if ok else "FAILED")
    return out
