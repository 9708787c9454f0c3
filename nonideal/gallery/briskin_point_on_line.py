"""A point on a line held by a quasi-ideal constraint: reactions, heat, work, criterion.

Source: Briskin, Pavlovsky, Pavlovsky & Smirnaya 2021, *Shaping the motion of mechanical
systems by controlling the reactions of holonomic quasi-ideal constraints*, sec. 3.1,
(3.1)-(3.10), figs. 2-4.

Model.  A point of mass m in the plane, coordinates x, y, under an active force G downwards
(its weight), kept on the line ``f = y - b + k x = 0`` (3.1).  The constraint is
*quasi-ideal*: its reaction ``R = (R_x, R_y)`` satisfies ``A R = lambda grad f`` (3.3) with
the transform ``A = [[1, alpha], [beta, 1]]`` (3.4) instead of the ideal ``R = lambda grad f``.
The model file's ``transform`` key says exactly this.

Closed form (derived; with ``D = 1 + k^2 - k (alpha + beta)``):

    lambda = G (1 - alpha beta) / D,  R_x = G (k - alpha) / D,  R_y = G (1 - beta k) / D  (3.5)
    x'' = R_x / m,   y'' = -k x'' = G k (alpha - k) / (m D)                               (3.6)

so the reactions are constant, and from rest after the time tau the point has travelled
``l = x'' tau^2 / 2`` along x.  The drives that produce ``R_x`` and ``R_y`` lose the heat
(3.7) ``W = mu_x int R_x^2 dt + mu_y int R_y^2 dt = (mu_x R_x^2 + mu_y R_y^2) tau`` (the
constraint's ``losses = ["mu_x", "mu_y"]``), and the reactions do the work

    A = R_x l + R_y (-k l) = G l (beta k^2 - alpha) / D.

**Misprint.**  The paper prints (3.8) as ``A = l (beta k - alpha) / D``: the force G is
dropped and ``beta k`` should be ``beta k^2``.  Checked three ways: the integral of (3.8)'s
own definition with (3.5) (``R_x l - k l R_y``), the energy balance (the reactions' work is
the kinetic energy gained minus the work of G: ``m x'' (1 + k^2) l - G k l``), and the
simulation's ``reaction_work`` (below).  Both forms vanish for ``alpha = beta = 0`` (the ideal
constraint), which is why the check the paper gives cannot tell them apart.

The split of the reaction.  ``evaluate`` splits ``R`` into its ideal part (along ``grad f``,
no work) and its control part (along the line: the work ``A``).  At ``alpha = beta k^2`` the
control part vanishes: every such transform gives the ideal reaction ``G (k, 1)/(1 + k^2)``.

Criterion (3.10) ``I = |A| + chi W`` over (alpha, beta).  ``R`` depends on (alpha, beta) only
through one number, ``u = R_x`` (``R_y = G - k u`` keeps the point on the line), so ``I`` is a
function of ``u`` alone and its minima over (alpha, beta) are curves, not points: the optimum
is a reaction direction.  :func:`optimum_closed_form` minimizes ``I(u)`` (a quadratic on each
side of the zeros of ``A``); :func:`~nonideal.analysis.studies.quasi_ideal.minimize_criterion`
(a sweep, then Nelder-Mead) must reach the same value.  With ``mu_x = mu_y`` the ideal
reaction is optimal (``A = 0`` and the least heat); with unequal losses it is not.

Singular transforms.  At ``D = 0`` the reaction's direction lies along the line and cannot
hold the point.  At ``alpha beta = 1`` the transform itself is singular: (3.5) still has a
limit there (``lambda = 0`` and ``R`` in the null space of ``A``), but ``R = A^-1 grad f
lambda`` does not exist.  By the definition (1.3), ``A R = lambda grad f``, the motion is still
well posed when ``grad f`` is not in the range of ``A``: the reaction is along
``adj(A) grad f`` with ``lambda = 0`` (at ``alpha = -0.5, beta = -2``: ``R = 0.4 G (1, 2) =
(3.924, 7.848)``).  The library forms every quasi-ideal reaction as ``R = adj(A) grad f mu``
(``mu`` the row's multiplier, ``lambda = det(A) mu``: the same motion wherever ``det A != 0``,
and its continuous limit where ``det A = 0``), so it computes that motion; ``evaluate``
prints ``mu``, ``lambda`` and ``det A``.  Here ``mu = G/D`` and ``lambda = G (1 - alpha beta)/D``.
When ``adj(A) grad f = 0`` as well (``alpha = 0.5, beta = 2``, where also ``D = 0``) the
definition leaves a family of reactions and the library stops with exit code 3 saying so.  On
the grid of figs. 2-4 (``k = 0.5``) these are the two points with ``alpha beta = 1``; the sweep
computes the first and records the second.
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "briskin-point-on-line"
ORDER = 70
TITLE = ("Point on a line, quasi-ideal constraint (Briskin et al. 2021, 3.1): reactions, heat "
         "(3.7), work (3.8 corrected), criterion I = |A| + chi W")
FILE = "briskin_point_on_line.toml"


def build(m: float = 1.0, G: float = 9.81, k: float = 0.5, b: float = 1.0, alpha: float = 0.0,
          beta: float = 0.0, mu_x: float = 1.0, mu_y: float = 1.0, t_end: float = 1.0) -> Model:
    """The point on the line with the Python API (same as the model file)."""
    return Model(
        name="Briskin et al. 2021, 3.1: point on a line with a quasi-ideal constraint",
        coordinates=["x", "y"],
        parameters={"m": m, "G": G, "k": k, "b": b, "alpha": alpha, "beta": beta,
                    "mu_x": mu_x, "mu_y": mu_y},
        kinetic="m/2*(x'^2 + y'^2)", potential="G*y",
        constraints=[Constraint("line", "y - b + k*x", "holonomic",
                                transform=(("1", "alpha"), ("beta", "1")),
                                losses=("mu_x", "mu_y"))],
        initial={"x": 0.0, "x'": 0.0}, simulation={"t_end": t_end})


def closed_form(p: dict, tau: float) -> dict:
    """(3.5)-(3.8) and (3.10) (chi = 1) for parameters *p*, from rest over the time *tau*."""
    G, k, m, al, be = p["G"], p["k"], p["m"], p["alpha"], p["beta"]
    D = 1 + k * k - k * (al + be)
    Rx, Ry = G * (k - al) / D, G * (1 - be * k) / D
    ax = Rx / m
    l = ax * tau * tau / 2
    W = (p["mu_x"] * Rx ** 2 + p["mu_y"] * Ry ** 2) * tau
    A = G * l * (be * k * k - al) / D
    return {"D": D, "lambda": G * (1 - al * be) / D, "mu": G / D, "R_x": Rx, "R_y": Ry, "a_x": ax,
            "a_y": -k * ax, "a": abs(ax) * np.sqrt(1 + k * k), "l": l, "heat": W, "work": A,
            "work_printed": l * (be * k - al) / D, "criterion": abs(A) + W}


def criterion_of_u(u, p: dict, tau: float, chi: float = 1.0):
    """``I`` as a function of ``u = R_x`` alone (``R_y = G - k u``)."""
    G, k, m = p["G"], p["k"], p["m"]
    u = np.asarray(u, dtype=float)
    work = u * tau * tau / (2 * m) * ((1 + k * k) * u - k * G)
    heat = tau * (p["mu_x"] * u * u + p["mu_y"] * (G - k * u) ** 2)
    return np.abs(work) + chi * heat


def optimum_closed_form(p: dict, tau: float, chi: float = 1.0) -> dict:
    """The least ``I(u)``: the vertices of its two quadratics (``A >= 0`` and ``A <= 0``) that
    lie in their region, and the zeros of ``A``."""
    G, k, m = p["G"], p["k"], p["m"]
    c = tau * tau / (2 * m)
    zeros = [0.0, k * G / (1 + k * k)]
    candidates = list(zeros)
    for s in (1.0, -1.0):   # I = s c u ((1+k^2) u - k G) + chi tau (mu_x u^2 + mu_y (G - k u)^2)
        a2 = s * c * (1 + k * k) + chi * tau * (p["mu_x"] + p["mu_y"] * k * k)
        a1 = -s * c * k * G - 2 * chi * tau * p["mu_y"] * k * G
        if a2 > 0:
            u = -a1 / (2 * a2)
            sign_A = u * ((1 + k * k) * u - k * G)
            if s * sign_A >= 0:
                candidates.append(u)
    values = criterion_of_u(candidates, p, tau, chi)
    best = int(np.argmin(values))
    return {"u": float(candidates[best]), "criterion": float(values[best])}


def check(model: Model, tau: float = 1.0) -> dict:
    """Evaluate and simulate *model*; compare with the closed form (relative errors)."""
    from ..analysis.evaluation import evaluate
    from ..analysis.studies.quasi_ideal import design_measures

    p = model.parameter_values
    cf = closed_form(p, tau)
    ev = evaluate(model).to_dict()
    line = ev["reactions"]["line"]
    measures = design_measures(model, t_end=tau)

    def rel(a, b):
        return abs(a - b) / max(abs(b), 1e-300)

    errors = {
        "mu": rel(ev["multipliers"]["line"], cf["mu"]),
        "lambda": abs(line["lambda"] - cf["lambda"]) / max(abs(cf["mu"]), 1e-300),
        "R_x": rel(line["generalized"][0], cf["R_x"]), "R_y": rel(line["generalized"][1], cf["R_y"]),
        "a_x": rel(ev["qddot"]["x"], cf["a_x"]), "a_y": rel(ev["qddot"]["y"], cf["a_y"]),
        "heat": rel(measures["heat"], cf["heat"]),
        "work": abs(measures["work"] - cf["work"]) / max(abs(cf["heat"]), 1.0),
    }
    ideal = np.array([p["k"], 1.0]) * p["G"] / (1 + p["k"] ** 2)
    control = np.array(line["control_part"])
    errors["ideal_part"] = float(np.max(np.abs(np.array(line["ideal_part"]) - ideal))) / p["G"]
    errors["control_along_line"] = abs(control[0] * p["k"] + control[1]) / p["G"]  # (1, -k) only
    return {"parameters": {k: p[k] for k in ("alpha", "beta")}, "closed_form": cf,
            "simulated": measures, "errors": errors}


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.studies.design import minimize_criterion
    from ..analysis.studies.sweep import parse_vary, sweep
    from ..modeling.modelfile import load_model

    path = gallery.model_path(NAME)
    cases = [(0.0, 0.0), (0.3, -0.4), (-1.0, 2.0), (1.5, -2.0), (0.45, 2.0)]
    results = [check(load_model(path, parameters={"alpha": a, "beta": b})) for a, b in cases]
    worst = max(max(r["errors"].values()) for r in results)
    ok = worst < 1e-9
    # figs. 2-4: alpha from -2 to 2 at beta = 2, 0, -2 -- one sweep; D = 0 at alpha = 0.5, beta = 2
    figure = sweep(path, [parse_vary("beta=2,0,-2"), parse_vary("alpha=-2:2:9")], "simulate",
                   workers=1)
    sweep_errors = []
    singular = []
    base = load_model(path).parameter_values
    for row in figure.rows:
        p = {**base, **row["parameters"]}
        if row["exit_code"] != 0:
            singular.append((row["parameters"], row["exit_code"]))
            continue
        cf = closed_form(p, 1.0)
        s = row["summary"]
        sweep_errors.append(max(abs(s["actuator_heat"] / cf["heat"] - 1),
                                abs(s["reaction_work"] - cf["work"]) / cf["heat"]))
    ok &= max(sweep_errors) < 1e-9
    # alpha = 0.5, beta = 2: det A = 0 and adj(A) grad f = 0 (and D = 0), the reaction is not
    # fixed; alpha = -0.5, beta = -2: det A = 0, computed along adj(A) grad f with lambda = 0
    ok &= ([s[0] for s in singular] == [{"beta": 2.0, "alpha": 0.5}]
           and all(code == 3 for _, code in singular))
    # the criterion's minimum with unequal losses: a sweep, then Nelder-Mead
    lossy = {"mu_x": "0.2"}
    best = minimize_criterion(path, [parse_vary("alpha=-1:1:5"), parse_vary("beta=-1:1:5")],
                              settings=lossy)
    exact = optimum_closed_form({**base, "mu_x": 0.2}, 1.0)
    ok &= abs(best.value / exact["criterion"] - 1) < 1e-6
    out = {"ok": bool(ok), "cases": results, "worst_relative_error": worst,
           "sweep_worst_error": max(sweep_errors), "singular_points": singular,
           "minimum": best.to_dict(), "minimum_closed_form": exact}
    if verbose:
        print(TITLE)
        for r in results:
            cf, sim = r["closed_form"], r["simulated"]
            print(f"alpha = {r['parameters']['alpha']:g}, beta = {r['parameters']['beta']:g}: "
                  f"lambda = {cf['lambda']:.10g}, R = ({cf['R_x']:.10g}, {cf['R_y']:.10g}), "
                  f"a = ({cf['a_x']:.10g}, {cf['a_y']:.10g})")
            print(f"  heat W = {sim['heat']:.10g} (3.7: {cf['heat']:.10g}); work A = "
                  f"{sim['work']:.10g} (derived {cf['work']:.10g}; printed (3.8) "
                  f"{cf['work_printed']:.6g}); I = {sim['criterion']:.10g}")
        print(f"worst relative error against the closed form: {worst:.1e}")
        print(f"sweep beta = 2, 0, -2 x alpha = -2..2 (figs. 2-4): worst error "
              f"{max(sweep_errors):.1e}; singular transform (exit 3) at {singular}")
        print(f"min I (mu_x = 0.2): {best.value:.10g} at alpha = {best.x['alpha']:.6g}, beta = "
              f"{best.x['beta']:.6g} (R_x = {exact['u']:.6g} in closed form, I = "
              f"{exact['criterion']:.10g}); the minima form a curve in (alpha, beta)")
        print("ok" if ok else "FAILED")
    return out
