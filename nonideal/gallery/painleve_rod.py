"""Painleve's rod: a uniform rod with one end on a rough floor -- the classic paradox.

Source: P. Painleve, *Lecons sur le frottement* (1895); the modern statement and the
(angle, mu) diagram follow Lotstedt (1981), Genot & Brogliato (1999), Stewart (2000, SIAM
Review "Rigid-body dynamics with friction and impact").  Derived here for the library's
conventions.

Model.  A uniform rod, mass m, length 2 l, central moment of inertia I = m l^2 / 3; centre
(x, y), angle theta with the floor.  End A = (x - l cos(theta), y - l sin(theta)) (the lower
end for 0 < theta < pi/2), end B = (x + l cos(theta), y + l sin(theta)).  Two contacts with
Coulomb friction mu (static = kinetic):

    A:  gap  y - l sin(theta),   slip  U_A = x' + l sin(theta) theta'  (horizontal velocity of A)
    B:  gap  y + l sin(theta),   slip  U_B = x' - l sin(theta) theta'

B only matters when the rod falls flat (it keeps the rod from falling through the floor).

Effective normal compliance.  While A slides with s = sign(U_A), the forces on the rod at A
are N (up) and F = -mu s N (horizontal):

    m x'' = F,    m y'' = N - m g,    I theta'' = (A - C) x (F, N) = -l cos(theta) N + l sin(theta) F,

and the gap acceleration g_A'' = y'' - l cos(theta) theta'' + l sin(theta) theta'^2 is

    g_A'' = g_free'' + b N,     g_free'' = -g + l sin(theta) theta'^2,
    b(theta, mu) = (1/m) (1 + 3 cos^2(theta) + 3 mu s sin(theta) cos(theta)).

(``nonideal.modes.switching.effective_compliance`` is this Schur complement of ``G M^-1 B``.)  With
b > 0 sliding gives ``N = -g_free''/b`` (>= 0 exactly when separation would penetrate): a
unique consistent answer.  b < 0 needs s = -1 -- the end A slides AWAY from the rod (towards
-x, with the rod leaning towards +x) -- and

    mu > mu_c(theta) = (1 + 3 cos^2(theta)) / (3 sin(theta) cos(theta)) = (tan^2(theta) + 4) / (3 tan(theta)),

minimum 4/3 at tan(theta) = 2 (theta = 63.43 deg).  In that region:

* g_free'' < 0 (e.g. the rod at rest in angle, sliding): sliding needs N < 0 and separation
  penetrates -- no consistent continuation (**inconsistency**);
* g_free'' > 0 (fast rotation, ``l sin(theta) theta'^2 > g``): separation (N = 0) and sliding
  with ``N = -g_free''/b > 0`` are both consistent (**indeterminacy**).

The library stops with :class:`~nonideal.errors.PainleveParadox` (CLI exit code 3) in both
cases, naming the contact, the compliance b and the critical coefficient, and
``nonideal.modes.switching.critical_friction`` reproduces mu_c(theta) (for s = +1 it returns None:
no paradox).

Normal case (mu = 0.5 < 4/3, theta0 = 1.1, x' = -1): A slides (s = -1) with
``N = m (g - l sin(theta) theta'^2) / (1 + 3 cos^2(theta) - 3 mu sin(theta) cos(theta))``; it
stops (event "stick") and the rod pivots about A like a physical pendulum,
``theta'' = -(3 g / (4 l)) cos(theta)``, needing ``F = m x_C''``, ``N = m (y_C'' + g)`` with
``x_C'' = -l sin(theta) theta'' - l cos(theta) theta'^2``, ``y_C'' = l cos(theta) theta'' -
l sin(theta) theta'^2``; when ``|F| = mu N`` it slips again (now s = +1) and the rod falls flat:
B touches down (plastic impact; both ends then stick) and the rod lies at rest.  Checks: N of
the sliding phases and (F, N) of the sticking phase against these formulas, ``|F| = mu N`` at
the slip event, the energy balance including the impact loss, friction power <= 0, constraint
residuals.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..modeling.bodies import PlanarBody
from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "painleve-rod"
ORDER = 42
TITLE = ("Painleve's rod on a rough floor: paradox for mu > (1 + 3cos^2 theta)/(3 sin theta cos "
         "theta) (Painleve 1895; at least 4/3)")
FILE = "painleve_rod.toml"

#: angles at which run() prints the critical coefficient
ANGLES = (np.pi / 12, np.pi / 6, np.pi / 4, float(np.arctan(2.0)), 5 * np.pi / 12, 17 * np.pi / 36)


def build(m: float = 1.0, l: float = 0.5, g: float = 9.81, mu: float = 0.5, theta0: float = 1.1,
          xd0: float = -1.0, thetad0: float = 0.0, t_end: float = 1.5, upper_end: bool = True) -> Model:
    """The rod with the Python API (same as the model file for the default values).

    ``upper_end=False``: only the contact A (the rod may then fall through the floor; used for
    the cross-check of the forms on the tilted rod).
    """
    contacts = [Contact("A", "y - l*sin(theta)", ("x' + l*sin(theta)*theta'",), Coulomb("mu"))]
    if upper_end:
        contacts.append(Contact("B", "y + l*sin(theta)", ("x' - l*sin(theta)*theta'",), Coulomb("mu")))
    return Model(
        name="Painleve rod on a rough floor",
        coordinates=["x", "y", "theta"],
        parameters={"m": m, "l": l, "g": g, "mu": mu, "theta0": theta0},
        bodies=[PlanarBody("rod", "m", "m*l^2/3", ["x", "y"], "theta")],
        gravity=["0", "-g"],
        contacts=contacts,
        initial={"x": 0.0, "theta": "theta0", "x'": xd0, "theta'": thetad0},
        simulation={"t_end": t_end},
    )


def compliance(theta, mu, s, m=1.0):
    """``b = dg''/dN`` of end A sliding with ``s = sign(U_A)``."""
    c, sn = np.cos(theta), np.sin(theta)
    return (1 + 3 * c * c + 3 * mu * s * sn * c) / m


def critical_mu(theta):
    """``mu_c(theta) = (1 + 3 cos^2 theta) / (3 sin theta cos theta)`` (for s = -1)."""
    c, sn = np.cos(theta), np.sin(theta)
    return (1 + 3 * c * c) / (3 * sn * c)


def free_gap_acceleration(theta, thetad, p):
    """``g_free'' = -g + l sin(theta) theta'^2`` (no contact force)."""
    return -p["g"] + p["l"] * np.sin(theta) * thetad ** 2


def sliding_normal_force(theta, thetad, s, p):
    """N of end A while it slides (B separated): ``-g_free'' / b``."""
    return -free_gap_acceleration(theta, thetad, p) / compliance(theta, p["mu"], s, p["m"])


def pivot_forces(theta, thetad, p):
    """``(theta'', F, N)`` while A sticks (the rod pivots about A)."""
    m, l, g = p["m"], p["l"], p["g"]
    thdd = -3 * g / (4 * l) * np.cos(theta)
    xc = -l * np.sin(theta) * thdd - l * np.cos(theta) * thetad ** 2
    yc = l * np.cos(theta) * thdd - l * np.sin(theta) * thetad ** 2
    return thdd, m * xc, m * (yc + g)


def reference_events(p: dict, theta0: float = 1.1, xd0: float = -1.0) -> dict:
    """Event times of the normal case from the hand-derived reduced equations, integrated
    independently of the library (SciPy, tolerance 1e-13): A sliding (s = -1) until U_A = 0,
    pivoting about A until ``|F| = mu N``, sliding (s = +1) until theta = 0 (B touches)."""
    from scipy.integrate import solve_ivp

    m, l, mu = p["m"], p["l"], p["mu"]
    I = m * l * l / 3

    def sliding(s):
        def f(t, z):
            x, th, xd, thd = z
            N = sliding_normal_force(th, thd, s, p)
            F = -mu * s * N
            return [xd, thd, F / m, (-l * np.cos(th) * N + l * np.sin(th) * F) / I]
        return f

    opts = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-13}

    def stop(t, z):          # U_A = x' + l sin(theta) theta'
        return z[2] + l * np.sin(z[1]) * z[3]
    stop.terminal, stop.direction = True, 1
    a = solve_ivp(sliding(-1.0), (0, 5), [0.0, theta0, xd0, 0.0], events=stop, **opts)
    t1, (x1, th1, _, thd1) = a.t_events[0][0], a.y_events[0][0]

    def pivot(t, z):
        return [z[1], pivot_forces(z[0], z[1], p)[0]]

    def slip(t, z):
        _, F, N = pivot_forces(z[0], z[1], p)
        return mu * N - abs(F)
    slip.terminal, slip.direction = True, -1
    b = solve_ivp(pivot, (t1, t1 + 5), [th1, thd1], events=slip, **opts)
    t2, (th2, thd2) = b.t_events[0][0], b.y_events[0][0]
    xA = x1 - l * np.cos(th1)
    x2, xd2 = xA + l * np.cos(th2), -l * np.sin(th2) * thd2

    def flat(t, z):
        return z[1]
    flat.terminal, flat.direction = True, -1
    c = solve_ivp(sliding(1.0), (t2, t2 + 5), [x2, th2, xd2, thd2], events=flat, **opts)
    t3, (_, _, xd3, thd3) = c.t_events[0][0], c.y_events[0][0]
    # just before B touches (theta = 0): y' = l cos(theta) theta' (A on the floor)
    ke = 0.5 * m * (xd3 ** 2 + (l * thd3) ** 2) + 0.5 * I * thd3 ** 2
    return {"stick": t1, "slip": t2, "touch": t3, "kinetic_energy_at_touch": ke}


def library_critical_mu(model: Model, theta: float, s: float = -1.0):
    """``critical_friction`` and ``effective_compliance`` of the library for A sliding in the
    direction s at angle theta (rod touching at A, at rest otherwise)."""
    from ..modes.types import SEPARATED, SLIDE, ContactState, Mode
    from ..modes.solver import ModeSolver
    from ..numeric.kernel import kernel_of, parameter_vector
    from ..modes.switching import critical_friction, effective_compliance

    p = model.parameter_values
    solver = ModeSolver(kernel_of(model), parameter_vector(model))
    q = np.array([0.0, p["l"] * np.sin(theta), theta])
    qd = np.array([s, 0.0, 0.0])
    mode = Mode(frozenset(), (("A", ContactState(SLIDE, (s,))), ("B", ContactState(SEPARATED))))
    return (critical_friction(solver, 0.0, q, qd, mode, "A"),
            effective_compliance(solver, 0.0, q, qd, mode, "A"))


def region_plot(path, points=()) -> Path:
    """PNG of the paradox region in the (theta, mu) plane; *points* = ((theta, mu, label), ...)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    th = np.linspace(0.02, np.pi / 2 - 0.02, 400)
    mc = critical_mu(th)
    top = 4.0
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.fill_between(np.degrees(th), np.minimum(mc, top), top, color="tab:red", alpha=0.25,
                    label="paradox (b < 0 when A slides away from the rod)")
    ax.plot(np.degrees(th), mc, "k", lw=1.5, label=r"$\mu_c = (1+3\cos^2\theta)/(3\sin\theta\cos\theta)$")
    ts = np.degrees(np.arctan(2.0))
    ax.plot([ts], [4 / 3], "ko")
    ax.annotate(r"min $4/3$ at $\tan\theta = 2$", (ts, 4 / 3), (ts - 25, 0.6),
                arrowprops={"arrowstyle": "->"})
    for theta, mu, label in points:
        ax.plot([np.degrees(theta)], [mu], "s", ms=7)
        ax.annotate(label, (np.degrees(theta), mu), (4, 6), textcoords="offset points", fontsize=8)
    ax.set_xlim(0, 90)
    ax.set_ylim(0, top)
    ax.set_xlabel(r"angle of the rod with the floor $\theta$ (deg)")
    ax.set_ylabel(r"friction coefficient $\mu$")
    ax.set_title("Painleve's rod: inconsistent if $g''_{free} < 0$, indeterminate if $> 0$")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def paradox(model: Model):
    """Simulate *model*; return the PainleveParadox raised (or None)."""
    from ..errors import PainleveParadox
    from ..simulation.hybrid import simulate

    try:
        simulate(model)
    except PainleveParadox as exc:
        return exc
    return None


def normal_case(model: Model) -> dict:
    """Simulate the consistent case and compare with the closed forms of the docstring."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    full = simulate(model)
    ev = full.events
    times = np.linspace(0.0, model.simulation.t_end, 301)
    tr = simulate(model, times=times)
    th, thd = tr.coordinate("theta"), tr.velocity("theta")
    A, B = tr.contacts["A"], tr.contacts["B"]
    modeA = np.array(A["mode"])
    NA = np.array(A["normal"])
    FA = np.array(A["friction"])[:, 0]
    UA = np.array(A["slip"])[:, 0]
    before = times < (ev[-1]["t"] if ev else np.inf)   # before the rod falls flat
    slide = before & np.char.startswith(modeA, "slide")
    stick = before & (modeA == "stick")
    s = np.sign(UA[slide])
    err_N_slide = float(np.max(np.abs(NA[slide] - sliding_normal_force(th[slide], thd[slide], s, p))))
    thdd, F_piv, N_piv = pivot_forces(th[stick], thd[stick], p)
    err_stick = float(max(np.max(np.abs(FA[stick] - F_piv)), np.max(np.abs(NA[stick] - N_piv)),
                          np.max(np.abs(tr.qdd[stick, 2] - thdd))))
    slip = next((e for e in ev if e["type"] == "slip"), None)
    if slip is not None:   # at the slip event |F| = mu N (pivot formulas at the event state)
        k = int(np.searchsorted(full.t, slip["t"]))
        _, F_e, N_e = pivot_forces(full.coordinate("theta")[k], full.velocity("theta")[k], p)
        slip_ratio = abs(F_e) / N_e
    else:
        slip_ratio = np.nan
    E = full.energy
    ref = reference_events(p, p["theta0"], full.qd[0, 0])
    err_t = max((abs(e["t"] / ref[e["type"]] - 1) for e in ev if e["type"] in ref), default=np.inf)
    return {
        "events": [(e["t"], e["type"], e["contact"], e["mode"]) for e in ev],
        "reference_events": {k: float(v) for k, v in ref.items()},
        "event_times_relative_error": float(err_t),
        "initial_energy": float(E["energy"][0]),
        "max_error_N_sliding": err_N_slide, "max_error_sticking": err_stick,
        "samples_sliding": int(slide.sum()), "samples_sticking": int(stick.sum()),
        "slip_ratio_F_over_N": float(slip_ratio),
        "impact_energy_change": float(E["impact_work"][-1]),
        "friction_work": float(E["friction_work"][-1]),
        "friction_power_max": float(np.max(np.diff(E["friction_work"]))),
        "min_compliance": float(np.min(compliance(th[slide], p["mu"], s, p["m"]))) if slide.any() else np.nan,
        "final_state": {"theta": full.at("theta"), "y": full.at("y"), "x'": full.at("x'"),
                        "theta'": full.at("theta'")},
        "final_mode": full.modes[-1],
        "energy_balance_relative": full.diagnostics["energy_balance_relative"],
        "constraint_residual_max": full.diagnostics["constraint_residual_max"],
    }


def run(verbose: bool = True, png: str | Path | None = None) -> dict:
    """Region plot (to *png*, only when given), critical
    coefficients, the two paradoxes, the normal case, all forms."""
    from .. import gallery
    from ..analysis.crosscheck import compare_forms

    model = gallery.load(NAME)
    p = model.parameter_values
    # (a) the region and the critical coefficient
    crit = []
    for theta in ANGLES:
        lib, b = library_critical_mu(model, theta)
        crit.append((theta, critical_mu(theta), lib, b, compliance(theta, p["mu"], -1.0, p["m"])))
    err_crit = max(abs(lib / cf - 1) for _, cf, lib, _, _ in crit)
    err_b = max(abs(b / bc - 1) for *_, b, bc in crit)
    no_paradox_forward = library_critical_mu(model, 1.1, s=+1.0)[0] is None
    # (b) the paradoxes, mu = 2 > mu_c(1.1) = 1.3335
    inconsistent = build(mu=2.0)
    indeterminate = build(mu=2.0, xd0=-5.0, thetad0=6.0)
    if png is not None:   # nothing is written unless asked for
        png = Path(png)
        region_plot(png, [(1.1, 2.0, "paradox states (b)"), (1.1, p["mu"], "normal case (c)")])
    exc = {"inconsistent": paradox(inconsistent), "indeterminate": paradox(indeterminate)}
    mu_c = critical_mu(1.1)
    g_free = {"inconsistent": free_gap_acceleration(1.1, 0.0, p),
              "indeterminate": free_gap_acceleration(1.1, 6.0, p)}
    word = {"inconsistent": "inconsistency", "indeterminate": "indeterminacy"}
    paradox_ok = all(e is not None and f"Painleve paradox ({word[k]}) at contact(s) A" in str(e)
                     and f"critical friction coefficient: {mu_c:.6g}" in str(e) for k, e in exc.items())
    # (c) the normal case
    nc = normal_case(model)
    kinds = [(e[1], e[2]) for e in nc["events"]]
    normal_ok = (kinds == [("stick", "A"), ("slip", "A"), ("touch", "B")]
                 and nc["event_times_relative_error"] < 1e-9
                 and abs(nc["impact_energy_change"] + nc["reference_events"]["kinetic_energy_at_touch"]) < 1e-8
                 and abs(nc["friction_work"] + nc["impact_energy_change"] + nc["initial_energy"]) < 1e-8
                 and max(nc["max_error_N_sliding"], nc["max_error_sticking"]) < 1e-8
                 and abs(nc["slip_ratio_F_over_N"] - p["mu"]) < 1e-8 and nc["friction_power_max"] <= 1e-10
                 and nc["energy_balance_relative"] < 1e-8 and nc["constraint_residual_max"] < 1e-9
                 and nc["final_mode"] == "A:stick, B:stick")
    # the forms: compare_forms closes every contact, which with both ends lays the rod flat
    # (sliding: fine; sticking: the two no-slip rows coincide, x' = 0 twice -- redundant), so
    # the tilted rod is cross-checked with the end A alone, sliding and sticking
    single = build(upper_end=False)
    cross = {"flat, slide": compare_forms(model, contact_state="slide").worst(),
             "tilted, slide": compare_forms(single, contact_state="slide").worst(),
             "tilted, stick": compare_forms(single, contact_state="stick").worst()}
    ok = (err_crit < 1e-10 and err_b < 1e-10 and no_paradox_forward and paradox_ok and normal_ok
          and max(cross.values()) < 1e-10 and g_free["inconsistent"] < 0 < g_free["indeterminate"])
    out = {"ok": bool(ok), "png": str(png) if png is not None else None,
           "critical_mu": [(float(t), float(cf), float(lib)) for t, cf, lib, _, _ in crit],
           "critical_mu_relative_error": err_crit, "compliance_relative_error": err_b,
           "paradox_messages": {k: str(e) if e else None for k, e in exc.items()},
           "free_gap_acceleration": g_free, "normal_case": nc, "forms_disagreement": cross}
    if verbose:
        print(TITLE)
        print("(a) critical friction coefficient mu_c(theta) = (1 + 3cos^2)/(3 sin cos), end A sliding away:")
        for theta, cf, lib, b, _ in crit:
            print(f"    theta = {np.degrees(theta):7.3f} deg: closed form {cf:.12f}, "
                  f"critical_friction {lib:.12f}; b(mu = {p['mu']}) = {b:.6f}")
        print(f"    relative errors: mu_c {err_crit:.1e}, b {err_b:.1e}; sliding towards the rod "
              f"(s = +1): no critical mu = {no_paradox_forward}")
        print(f"    region plot: {png}" if png is not None else
              "    region plot: not drawn (painleve_rod.run(png=PATH) draws it)")
        for k, e in exc.items():
            print(f"(b) mu = 2 at theta = 1.1 ({k}, g_free'' = {g_free[k]:+.4f}):")
            print("    " + (str(e).replace("\n", "\n    ") if e else "NO PARADOX RAISED"))
        print(f"(c) normal case mu = {p['mu']}: events "
              f"{[(round(e[0], 9), e[1], e[2], e[3]) for e in nc['events']]}")
        r = nc["reference_events"]
        print(f"    reference (reduced equations by hand, SciPy): stick {r['stick']:.12f}, slip "
              f"{r['slip']:.12f}, touch {r['touch']:.12f}; max rel. error "
              f"{nc['event_times_relative_error']:.1e}")
        print(f"    N while sliding vs -g_free''/b: {nc['max_error_N_sliding']:.1e} "
              f"({nc['samples_sliding']} samples); pivot phase F, N, theta'': {nc['max_error_sticking']:.1e}")
        print(f"    |F|/N at the slip event = {nc['slip_ratio_F_over_N']:.12f} (mu = {p['mu']}); impact "
              f"energy change {nc['impact_energy_change']:.9f} J (= -T before the touch, "
              f"{-r['kinetic_energy_at_touch']:.9f}: the rod stops dead)")
        print(f"    friction work {nc['friction_work']:.9f} J + impact {nc['impact_energy_change']:.9f} J = "
              f"-(initial energy {nc['initial_energy']:.9f} J): it ends at rest, flat")
        print(f"    energy balance {nc['energy_balance_relative']:.1e}; constraint residual "
              f"{nc['constraint_residual_max']:.1e}; final mode {nc['final_mode']}")
        print("all forms vs Lagrange I: " + ", ".join(f"{k} {v:.1e}" for k, v in cross.items()))
        print("ok" if ok else "FAILED")
    return out
