"""Two points on a rod whose midpoint moves along the rod, M1 in a ROUGH guide: the friction
law of the system, Lagrange II with friction, static friction -- when M1 stays put.

Source: Manglieva & Beknazarov (2022), sec. 1.3, problem 1, eqs. (1.66)-(1.100) (the problem
is from Dobronravov's book, ref. [72] of the paper).  The smooth system (f = 0) is the example
``painleve-conditional-constraint``; its docstring lists the misprints of the frictionless
formulas ((1.92), (1.96), (1.99), the constraint forces after (1.80), lambda_1 at rest).

Model (Oy DOWN, gravity +g along y).  M1 (mass m1) at (x1, y1) in a rough horizontal guide
y1 = 0 (Coulomb, coefficient f, static = kinetic; two-sided, as the absolute values of (1.100)
imply), pushed by the horizontal force X; M2 (mass m2) at (x2, y2) on a rigid massless rod of
length l, x2 = x1 + l cos(theta), y2 = l sin(theta); the velocity of the rod's midpoint is
directed along the rod (1.67).  Constraints and multipliers (Manglieva & Beknazarov's):

    rod:       sqrt((x2 - x1)^2 + (y2 - y1)^2) - l = 0          lambda_1: lambda_1 (c, s) on M2,
    midpoint:  ((x2 - x1)(y2' + y1') - (y2 - y1)(x2' + x1'))/l = 0     lambda_2: lambda_2 (-s, c) on each,
    line:      contact, gap -y1 (bilateral), slip x1'.           N = upward normal force,

with s, c = sin(theta), cos(theta).  One degree of freedom: on the constraints
``x1' sin(theta) = (l/2) theta'`` (1.88), and the velocity of M2 is ``x1' (cos 2theta, sin 2theta)``.

Painleve's split (1.68)-(1.80).  The friction force accelerates the system along its only
possible velocity: ``rho_1 = m1 mu (1, 0)`` on M1, ``rho_2 = m2 mu (cos 2theta, sin 2theta)``
on M2 (1.79)-(1.80), ``R_tau = (m1 + m2) mu`` (the friction force on M1).  The constraint
multipliers are those of the smooth system, (1.87) and (1.89), for any masses and any f --
``run`` checks them (evaluation's constraint parts) with and without friction along the motion.
The friction part has no vertical component on M1, so Manglieva & Beknazarov's lambda (line, along +y) is
exactly -N.

Friction law (derived).  Coulomb |R_tau| = f |lambda|, opposite to x1':

    mu = -f sign(x1') |lambda| / (m1 + m2)       (= f lambda/(m1 + m2) for x1' > 0, lambda < 0).

**Misprint (1.82)**: printed ``mu = -f lambda/(m1 + m2)`` for x1' > 0 and ``+f lambda/(m1 + m2)``
for x1' < 0 -- the cases are swapped, as in (1.22)-(1.23) (with lambda < 0 the printed law
accelerates M1).  (1.81) ``mu = eps lambda/(m1 + m2)`` drops the factor f.

Equation of motion (derived by the power balance; the ideal constraints do no work, the
friction power is R_tau x1').  With v = x1':

    (m1 + m2) v' = X + m2 g sin(2 theta) + R_tau,     theta' = 2 v sin(theta)/l,         (*)
    R_tau = -f sign(v) |N|,   N = m1 g - m2 g cos(2 theta) + 4 m2 v^2 sin(theta)/l      (= -lambda, (1.89)).

N does not depend on the accelerations: no Painleve paradox for any f.  In theta, (*) is the
Manglieva & Beknazarov's (1.98) with ``eps = sign(x1')`` (not the eps of (1.82)):

    (m1 + m2) l/4 (theta''/s^2 - c theta'^2/s^3) = m2 g c + X/(2 s) + f eps lambda/(2 s).    (1.98)

**Misprint (1.90)-(1.91)** (Painleve's own, unweighted split, not the library's): with the
friction rho_1 = mu (1, 0) on M1 and rho_2 = mu (cos 2theta, sin 2theta) on M2 the derivation gives
lambda_1 = (1.87) + (m2 - m1) cos(theta) mu/(m1 + m2) and lambda_2 = (1.87) + (m2 - m1) sin(theta)
mu/(m1 + m2); printed ``-(q - 1) sin(theta) mu`` and ``+(q - 1) mu`` (q = m1/m2), which no scaling of mu
reconciles.  The conclusion stands: with that split the multipliers depend on friction unless
m1 = m2 (with the mass-weighted split they never do, tested).

**Misprints (1.95)-(1.96), (1.99)**: the generalized friction force is that of the whole
R_tau = (m1 + m2) mu (the friction components on M1 and M2 do the work (m1 + m2) mu delta x1),
not ``m1 mu l/(2 sin(theta))``; (1.98) is consistent with the correct one.  The first equation
of (1.99) reads correctly ``(m1 + m2) x1'' = X + (m1 + m2) mu + m2 g sin(2 theta)``.

Static friction (1.100), checked.  At rest (x1' = theta' = 0) the guide must supply
``R_tau = -(X + m2 g sin 2theta)`` with ``N = m1 g - m2 g cos 2theta``, so M1 stays put iff

    |X + m2 g sin(2 theta)| <= f |(m1 + m2) g - 2 m2 g cos^2(theta)|,                       (1.100)

as printed; otherwise it starts in the direction of ``X + m2 g sin 2theta`` with
``v'(0) = (X + m2 g sin 2theta - f sign(.) |N|)/(m1 + m2)`` and ``theta''(0) = 2 v'(0) sin(theta)/l``.
The sign rule after (1.100) ("eps opposite to the sign of lambda_1 c + lambda_2 s + m2 mu - X")
is right.  ``run`` starts at rest just below and just above both thresholds
``X = -m2 g sin 2theta0 +- f |N0|`` and compares the decision and the initial acceleration
with these formulas, and the library's sticking force with -(X + m2 g sin 2theta0).

Motion (default X = 15 N > X* = 6.0013 N at theta0 = 1.5, from rest): M1 slides to the right,
the rod turns past the vertical (theta = 1.9708 at the stop), gravity brakes and M1 sticks at
t = 0.61743137318: the library's event vs the hand-written equation (*) integrated with SciPy
(relative error ~1e-14); (1.100) holds at the stop state, so M1 stays put for ever.  Also: the
integral tan(theta/2) exp(-2 x1/l) (kinematic, holds with friction), the energy balance
``T + V - (T + V)(0) = X (x1 - x10) + W_friction``, friction power <= 0, all forms (sliding:
``compare_forms``; sticking is complete rest here -- 0 degrees of freedom -- so the forms are
compared at random states at rest inside (1.100): q'' = 0 and the same sticking force).
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Constraint, Model
from .painleve_conditional_constraint import MIDPOINT, angle, first_integral, multipliers

NAME = "painleve-conditional-constraint-rough"
ORDER = 34
TITLE = ("Two points on a rod whose midpoint moves along the rod, rough guide: sliding and "
         "sticking friction (Manglieva & Beknazarov 2022, (1.98), (1.100))")
FILE = "painleve_conditional_constraint_rough.toml"

KEYS = ("m1", "m2", "l", "g", "X", "f", "theta0", "thetad0")


def build(m1: float = 1.0, m2: float = 2.0, l: float = 0.8, g: float = 9.81, X: float = 15.0,
          f: float = 0.3, theta0: float = 1.5, thetad0: float = 0.0, t_end: float = 1.5) -> Model:
    """The system in (x1, y1, x2, y2) with the Python API (same as the model file by default)."""
    v1 = "l*thetad0/(2*sin(theta0))"
    return Model(
        name="Two points on a rod, midpoint velocity along the rod, rough guide",
        coordinates=["x1", "y1", "x2", "y2"],
        parameters={"m1": m1, "m2": m2, "l": l, "g": g, "X": X, "f": f, "theta0": theta0,
                    "thetad0": thetad0},
        bodies=[Particle("M1", "m1", ["x1", "y1"]), Particle("M2", "m2", ["x2", "y2"])],
        gravity=["0", "g"],
        forces={"x1": "X"},
        constraints=[Constraint.holonomic("rod", "sqrt((x2 - x1)^2 + (y2 - y1)^2) - l"),
                     Constraint.nonholonomic("midpoint", MIDPOINT)],
        contacts=[Contact("line", "-y1", ("x1'",), Coulomb("f"), bilateral=True)],
        initial={"x1": 0.0, "y1": 0.0, "x2": "l*cos(theta0)", "y2": "l*sin(theta0)",
                 "x1'": v1, "y1'": 0.0, "x2'": f"{v1} - l*sin(theta0)*thetad0",
                 "y2'": "l*cos(theta0)*thetad0"},
        simulation={"t_end": t_end},
    )


# ------------------------------------------------------------------ closed forms (derived)

def normal_force(theta, v, p):
    """N = -lambda = m1 g - m2 g cos(2 theta) + 4 m2 v^2 sin(theta)/l (upward)."""
    return p["m1"] * p["g"] - p["m2"] * p["g"] * np.cos(2 * theta) + 4 * p["m2"] * v * v * np.sin(theta) / p["l"]


def driving_force(theta, p):
    """X + m2 g sin(2 theta): the force along x1 that friction must balance at rest."""
    return p["X"] + p["m2"] * p["g"] * np.sin(2 * theta)


def sticks_at_rest(theta, p) -> bool:
    """(1.100)."""
    return bool(abs(driving_force(theta, p)) <= p["f"] * abs(normal_force(theta, 0.0, p)))


def thresholds(theta, p):
    """The forces X at which (1.100) becomes an equality: ``(X_low, X_high)``."""
    fn = p["f"] * abs(normal_force(theta, 0.0, p))
    base = -p["m2"] * p["g"] * np.sin(2 * theta)
    return base - fn, base + fn


def acceleration(theta, v, sigma, p):
    """v' = x1'' of (*) while sliding with sigma = sign(v)."""
    R = -p["f"] * sigma * abs(normal_force(theta, v, p))
    return (driving_force(theta, p) + R) / (p["m1"] + p["m2"])


def friction_law_mu(lam, sigma, p):
    """Manglieva & Beknazarov's mu from lambda (derived): ``-f sigma |lambda| / (m1 + m2)``."""
    return -p["f"] * sigma * np.abs(lam) / (p["m1"] + p["m2"])


def printed_mu(lam, sigma, p):
    """(1.82) as printed: ``-f lambda/(m1 + m2)`` for x1' > 0, ``+f lambda/(m1 + m2)`` for x1' < 0."""
    return -sigma * p["f"] * lam / (p["m1"] + p["m2"])


def residual_1_98(theta, thetad, thetadd, lam, eps, p):
    """(1.98) with the line multiplier lambda (along +y) and eps."""
    s, c = np.sin(theta), np.cos(theta)
    lhs = 0.25 * (p["m1"] + p["m2"]) * p["l"] * (thetadd / s ** 2 - c * thetad ** 2 / s ** 3)
    return lhs - (p["m2"] * p["g"] * c + p["X"] / (2 * s) + p["f"] * eps * lam / (2 * s))


def reference_motion(p: dict, theta0: float, v0: float, t_end: float) -> list:
    """Events of the hand-written equation (*) (SciPy DOP853, rtol 1e-13), independent of the
    library: ``[(t, mode, theta, x1), ...]``; at every stop (1.100) decides stick or reversal."""
    from scipy.integrate import solve_ivp

    def start(theta, v):
        if v != 0.0:
            return float(np.sign(v))
        if sticks_at_rest(theta, p):
            return 0.0
        return float(np.sign(driving_force(theta, p)))

    t, z = 0.0, np.array([0.0, theta0, v0])                 # x1, theta, v
    sigma = start(theta0, v0)
    events = []
    while sigma != 0.0 and t < t_end:
        def rhs(_, y, s_=sigma):
            return [y[2], 2 * y[2] * np.sin(y[1]) / p["l"], acceleration(y[1], y[2], s_, p)]

        def stop(_, y):
            return y[2]
        stop.terminal, stop.direction = True, -sigma
        sol = solve_ivp(rhs, (t, t_end), z, events=stop, method="DOP853", rtol=1e-13, atol=1e-13)
        if not sol.t_events[0].size:
            break
        t, z = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
        z[2] = 0.0
        sigma = start(z[1], 0.0)
        events.append((t, {1.0: "slide+", -1.0: "slide-", 0.0: "stick"}[sigma], float(z[1]), float(z[0])))
    return events


# ------------------------------------------------------------------ checks

def split_at(model: Model, q, qd):
    """Evaluation at a state: ``(evaluation, lambda_1, lambda_2, lambda, mu, friction part)``
    with lambda_1, lambda_2, lambda the constraint parts (Manglieva & Beknazarov's multipliers) and mu the
    friction part of M1 / m1."""
    from ..analysis.evaluation import evaluate

    at = {c: q[i] for i, c in enumerate(model.coordinates)}
    at.update({c + "'": qd[i] for i, c in enumerate(model.coordinates)})
    ev = evaluate(model, at=at)
    th = np.arctan2(q[3] - q[1], q[2] - q[0])
    s, c = np.sin(th), np.cos(th)
    rod = np.array(ev.reactions["rod"]["constraint_part"])
    mid = np.array(ev.reactions["midpoint"]["constraint_part"])
    lam1 = float(rod[2:] @ [c, s])
    lam2 = float(mid[2:] @ [-s, c])
    lam = float(ev.reactions["line"]["constraint_part"][1])
    fp = sum(np.array(r["friction_part"]) for r in ev.reactions.values())
    return ev, lam1, lam2, lam, fp[0] / model.parameter_values["m1"], fp


def at_rest(p: dict, X: float, t_end: float = 0.2) -> dict:
    """Start at rest at theta0 with the force X: the library's decision and initial
    accelerations (evaluation) and a short simulation vs (1.100) and (*)."""
    from ..analysis.evaluation import evaluate
    from ..simulation.hybrid import simulate

    q = {**p, "X": X}
    model = build(**{k: q[k] for k in KEYS})
    ev = evaluate(model)
    tr = simulate(model, t_end=t_end)
    th = p["theta0"]
    stick = sticks_at_rest(th, q)
    out = {"X": X, "sticks_(1.100)": stick, "mode": ev.contacts["line"]["mode"],
           "mode_simulated": tr.contacts["line"]["mode"][0], "x1_end": float(tr.q[-1, 0])}
    if stick:   # stays put: no event, x1 constant, the guide holds with -(X + m2 g sin 2theta0)
        out["friction"] = ev.contacts["line"]["friction"][0]
        out["friction_closed_form"] = -driving_force(th, q)
        out["error"] = abs(out["friction"] - out["friction_closed_form"])
        out["ok"] = (out["mode"] == out["mode_simulated"] == "stick" and out["error"] < 1e-10
                     and np.max(np.abs(ev.qdd)) < 1e-12 and not tr.events
                     and float(np.max(np.abs(tr.q[:, 0]))) < 1e-12)
    else:       # starts with v'(0) of (*); over t_end, x1 ~ v'(0) t^2/2
        sigma = float(np.sign(driving_force(th, q)))
        a = acceleration(th, 0.0, sigma, q)
        out["x1dd"] = float(ev.qdd[0])
        out["x1dd_closed_form"] = float(a)
        thdd = (ev.qdd[3] * np.cos(th) - (ev.qdd[2] - ev.qdd[0]) * np.sin(th)) / p["l"]
        out["error"] = max(abs(ev.qdd[0] - a), abs(thdd - 2 * a * np.sin(th) / p["l"]),
                           abs(tr.qdd[0, 0] - a))
        label = "slide+" if sigma > 0 else "slide-"
        out["ok"] = (out["mode"] == out["mode_simulated"] == label and out["error"] < 1e-10
                     and np.sign(tr.q[-1, 0]) == sigma)
    return out


def rest_forms(p: dict, count: int = 20, seed: int = 0) -> dict:
    """Every form at *count* random states at rest with (1.100) satisfied (theta random, X random
    inside the sticking interval): the accelerations must vanish and the sticking force be
    -(X + m2 g sin 2theta).  Returns the worst absolute acceleration and relative force error
    per form.  (``compare_forms(contact_state="stick")`` measures these zero accelerations
    against a fixed floor of 1e-9 and reports round-off of 5e-15 as a 5e-6 disagreement.)"""
    from ..analysis.evaluation import evaluate
    from ..equations.formalisms import FORMS

    rng = np.random.default_rng(seed)
    out = {f: [0.0, 0.0] for f in list(FORMS) + ["gauss"]}
    for _ in range(count):
        th = rng.uniform(0.2, np.pi - 0.2)
        lo, hi = thresholds(th, p)
        X = rng.uniform(lo + 0.05 * (hi - lo), hi - 0.05 * (hi - lo))
        model = build(**{**{k: p[k] for k in KEYS}, "X": X, "theta0": th})
        need = -driving_force(th, {**p, "X": X})
        for f in out:
            ev = evaluate(model, form=f)
            if ev.contacts["line"]["mode"] != "stick":   # pragma: no cover - reported as a failure
                out[f] = [np.inf, np.inf]
                continue
            out[f][0] = max(out[f][0], float(np.max(np.abs(ev.qdd))))
            out[f][1] = max(out[f][1], abs(ev.contacts["line"]["friction"][0] - need) / abs(need))
    return {f: tuple(v) for f, v in out.items()}


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    th0 = p["theta0"]
    # (a) static friction at rest: both sides of both thresholds
    lo, hi = thresholds(th0, p)
    rest = [at_rest(p, X) for X in (lo - 0.01, lo + 0.01, hi - 0.01, hi + 0.01)]
    # (b) the motion: start, stop, stick
    traj = simulate(model, times=np.linspace(0.0, model.simulation.t_end, 601))
    ref = reference_motion(p, th0, 0.0, model.simulation.t_end)
    lib = [(e["t"], e["mode"].split(":")[1]) for e in traj.events]
    same = [m for _, m in lib] == [r[1] for r in ref]
    err_t = max((abs(a[0] / b[0] - 1) for a, b in zip(lib, ref)), default=0.0) if same else np.inf
    th, thd = angle(traj.q, traj.qd)
    x1, v = traj.coordinate("x1"), traj.velocity("x1")
    t_stop = lib[0][0] if lib else np.inf
    sliding = (traj.t > 1e-9) & (traj.t < t_stop - 1e-9)
    after = traj.t > t_stop + 1e-9
    stays = float(np.ptp(x1[after]) + np.ptp(th[after])) if after.any() else np.inf
    stop_holds = sticks_at_rest(th[-1], p)
    # (c) along the sliding part: split, friction law, (1.98), (1.99), N
    errs = {"(1.87)": 0.0, "(1.89)": 0.0, "law": 0.0, "(1.98)": 0.0, "N": 0.0, "rho": 0.0}
    bad = {"(1.82) printed": np.inf, "(1.98) eps of (1.82)": np.inf, "(1.99) printed": np.inf}
    idx = np.flatnonzero(sliding)[::max(1, int(sliding.sum()) // 25)]
    for k in idx:
        ev, lam1, lam2, lam, mu, fp = split_at(model, traj.q[k], traj.qd[k])
        a1, a2, a0 = multipliers(th[k], thd[k], v[k], p["m1"], p["m2"], p["l"], p["g"], p["X"])
        scale = abs(a0)
        errs["(1.87)"] = max(errs["(1.87)"], abs(lam1 - a1) / scale, abs(lam2 - a2) / scale)
        errs["(1.89)"] = max(errs["(1.89)"], abs(lam - a0) / scale)
        sig = np.sign(v[k])
        errs["law"] = max(errs["law"], abs(mu / friction_law_mu(lam, sig, p) - 1))
        bad["(1.82) printed"] = min(bad["(1.82) printed"], abs(mu - printed_mu(lam, sig, p)))
        c2, s2 = np.cos(2 * th[k]), np.sin(2 * th[k])
        errs["rho"] = max(errs["rho"], float(np.max(np.abs(fp - mu * np.array(
            [p["m1"], 0.0, p["m2"] * c2, p["m2"] * s2])))) / abs(mu))
        thdd = (traj.qdd[k, 3] * np.cos(th[k]) - (traj.qdd[k, 2] - traj.qdd[k, 0]) * np.sin(th[k])) / p["l"]
        errs["(1.98)"] = max(errs["(1.98)"], abs(residual_1_98(th[k], thd[k], thdd, lam, sig, p)) / scale)
        bad["(1.98) eps of (1.82)"] = min(bad["(1.98) eps of (1.82)"],
                                          abs(residual_1_98(th[k], thd[k], thdd, lam, -sig, p)))
        errs["N"] = max(errs["N"], abs(ev.contacts["line"]["normal"] - normal_force(th[k], v[k], p)) / scale)
        R = (p["m1"] + p["m2"]) * mu
        printed99 = p["X"] + p["m1"] * mu + p["m2"] * p["l"] * p["g"] * np.cos(th[k])
        bad["(1.99) printed"] = min(bad["(1.99) printed"], abs((p["m1"] + p["m2"]) * traj.qdd[k, 0] - printed99))
        errs["(1.98)"] = max(errs["(1.98)"], abs((p["m1"] + p["m2"]) * traj.qdd[k, 0] - driving_force(th[k], p) - R)
                             / scale)
    # the kinematic integral and the energy
    I = first_integral(th, x1, p["l"])
    err_int = float(np.max(np.abs(I - I[0])) / I[0])
    E, W, WX = traj.energy["energy"], traj.energy["friction_work"], traj.energy["active_work"]
    err_WX = float(np.max(np.abs(WX - p["X"] * (x1 - x1[0]))))
    err_E = float(np.max(np.abs((E - E[0]) - WX - W)))
    forms = {"slide": compare_forms(model, contact_state="slide").worst(),
             "stick (multipliers)": max(compare_forms(model, contact_state="stick").multipliers.values())}
    at_rest_forms = rest_forms(p)
    worst_rest = max(max(v) for v in at_rest_forms.values())
    d = traj.diagnostics
    checks = [all(r["ok"] for r in rest), [r["sticks_(1.100)"] for r in rest] == [False, True, True, False],
              same, err_t < 1e-8, stays < 1e-12, stop_holds, max(errs.values()) < 1e-9,
              min(bad.values()) > 1e-2, err_int < 1e-8, err_WX < 1e-8, err_E < 1e-8,
              float(np.max(np.diff(W))) <= 1e-12, d["energy_balance_relative"] < 1e-8,
              d["constraint_residual_max"] < 1e-8, max(forms.values()) < 1e-10, worst_rest < 1e-12]
    result = {"ok": bool(all(checks)), "thresholds_X": (float(lo), float(hi)), "at_rest": rest,
              "events": lib, "reference_events": ref, "event_times_relative_error": float(err_t),
              "theta_at_stop": float(th[-1]), "x1_at_stop": float(x1[-1]), "spread_after_stop": stays,
              "errors_along_sliding": errs, "printed_formulas_min_error": bad,
              "samples": int(len(idx)), "first_integral_drift": err_int,
              "friction_work": float(W[-1]), "work_of_X": float(WX[-1]), "energy_change": float(E[-1] - E[0]),
              "energy_error": err_E, "energy_balance_relative": d["energy_balance_relative"],
              "constraint_residual_max": d["constraint_residual_max"], "forms": forms,
              "forms_at_rest_(|qdd|, friction)": at_rest_forms}
    if verbose:
        print(TITLE)
        print(f"m1 = {p['m1']}, m2 = {p['m2']}, l = {p['l']}, f = {p['f']}, theta0 = {th0}, at rest")
        print(f"(a) (1.100): M1 stays put iff {lo:.10f} <= X <= {hi:.10f}")
        for r in rest:
            tail = (f"friction {r['friction']:.10f} = -(X + m2 g sin 2theta0) {r['friction_closed_form']:.10f}"
                    if r["sticks_(1.100)"] else
                    f"x1'' = {r['x1dd']:.10f}, closed form {r['x1dd_closed_form']:.10f}")
            print(f"    X = {r['X']:+.4f}: (1.100) says {'stick' if r['sticks_(1.100)'] else 'slip '}, library "
                  f"{r['mode']:7} {tail} (error {r['error']:.1e}); x1(0.2 s) = {r['x1_end']:+.3e}")
        print(f"(b) X = {p['X']}: events {[(round(t, 12), m) for t, m in lib]}")
        print(f"    reference (equation (*) by hand, SciPy): {[(round(r[0], 12), r[1]) for r in ref]}; "
              f"max relative error {err_t:.1e}")
        print(f"    stops at theta = {th[-1]:.10f}, x1 = {x1[-1]:.10f}; (1.100) holds there: {stop_holds}; "
              f"then at rest (spread {stays:.1e})")
        print(f"(c) along the sliding ({len(idx)} samples), max relative errors: " +
              ", ".join(f"{k} {v_:.1e}" for k, v_ in errs.items()))
        print("    printed formulas, min error: " + ", ".join(f"{k} {v_:.3f}" for k, v_ in bad.items()))
        print(f"    tan(theta/2) exp(-2 x1/l) drift {err_int:.1e}")
        print(f"    energy change {E[-1] - E[0]:.10f} = work of X {WX[-1]:.10f} + friction {W[-1]:.10f} "
              f"(error {err_E:.1e}); balance {d['energy_balance_relative']:.1e}, residual "
              f"{d['constraint_residual_max']:.1e}")
        print("all forms vs Lagrange I: " + ", ".join(f"{k} {v_:.1e}" for k, v_ in forms.items()))
        print("all forms at 20 random states at rest inside (1.100): max |q''|, friction error: " +
              ", ".join(f"{k} {a:.0e}/{b:.0e}" for k, (a, b) in at_rest_forms.items()))
        print("ok" if result["ok"] else "FAILED")
    return result
