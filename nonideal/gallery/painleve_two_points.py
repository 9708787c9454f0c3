"""Painleve's two points joined by a rod, one sliding on a smooth line (redundant coordinates).

Source: Manglieva & Beknazarov (2022), *On the motion of systems with nonholonomic non-ideal
constraints*, sec. 1.1, eqs. (1.18)-(1.28) -- here with the friction coefficient f = 0 (the
multipliers (1.27)-(1.28) are the same with and without friction: that is the point of the
Manglieva & Beknazarov's "extended method of combining constraints"; with f = 0 they are simply the
multipliers of the smooth system).

Model (Manglieva & Beknazarov's conventions).  The axis Oy points DOWN and gravity is +g along y.  Point M
(mass m) at (x, y) slides on the line y = 0; point M1 (mass m1) at (x1, y1) hangs on a rigid
massless rod of length l, x1 = x + l cos(theta), y1 = y + l sin(theta) (theta = angle of the
rod M M1 with Ox; theta = pi/2 is M1 straight below M).  Two holonomic constraints:

    line:  f_line = y = 0,
    rod:   f_rod  = sqrt((x1 - x)^2 + (y1 - y)^2) - l = 0.

Multipliers and signs (mapping to the paper).  The library's reaction is ``sum lambda grad f``:

* ``lambda_line`` is the force of the line on M along +y (downwards): it is Manglieva & Beknazarov's
  ``lambda = Y`` of (1.18) ``m y'' = lambda - lambda_1 sin(theta) + m g``;
* the rod is normalized by its length, so ``grad_(x1, y1) f_rod = (cos(theta), sin(theta))`` and
  the force on M1 is ``lambda_rod (cos(theta), sin(theta))`` (on M the opposite): exactly the
  Manglieva & Beknazarov's ``R'_1 = lambda_1 (cos(theta), sin(theta))`` of (1.16).  Hence ``lambda_rod`` is the
  Manglieva & Beknazarov's ``lambda_1`` and ``-lambda_rod`` is the rod tension (> 0 while M1 hangs).  (Manglieva & Beknazarov's
  own form ``(x1 - x)^2 + (y1 - y)^2 - l^2`` would give ``lambda_1 = 2 l lambda``.)

Published multipliers (Manglieva & Beknazarov 2022, (1.27), (1.28); derived again here from (1.18) with mu = 0 and the
second derivative of the rod constraint, see (1.26)):

    lambda_1 = -(l theta'^2 + g sin(theta)) m m1 / (m + m1 cos^2(theta)),          (1.27)
    lambda   = -m g + lambda_1 sin(theta).                                          (1.28)

Both agree with the simulation and with evaluation at random states for any masses
(``run`` checks m/m1 = 0.5, 1, 6, 1/25).  Also conserved: the horizontal momentum
``m x' + m1 x1'`` and the energy.

Misprints found in sec. 1.1 of the paper:

* (1.5): for m = m1 the printed ``lambda_1 = -(theta'^2 + g sin(theta))/(1 + cos^2(theta))``
  drops the factor m and the length l (it is not even a force); (1.27) with m = m1 gives
  ``lambda_1 = -m (l theta'^2 + g sin(theta))/(1 + cos^2(theta))`` -- checked in ``run``.
* (1.4): ``m_2`` should be ``m_1`` and ``theta'^2`` should be ``l theta'^2``.
* (1.24): ``y = l sin(theta)`` should read ``y1 = l sin(theta)`` (y = 0 is the line).
* (1.26) is correct (the mu terms cancel as printed); (1.27)-(1.28) are correct.
* (1.29), second equation: ``l theta'' - x'' sin(theta) = -g cos(theta)`` has the wrong sign;
  Manglieva & Beknazarov's own Lagrange-II equation (1.37) ``l theta'' - x'' sin(theta) = g cos(theta)`` is
  right (with Oy down, theta = pi/2 must be the stable equilibrium).  See the example
  ``painleve-two-points-xtheta``.
* before (1.37) the generalized force is printed ``m g l cos(theta)``; it is ``m1 g l cos(theta)``.
* (1.38), second equation: ``m1 l (theta'' cos(theta) - l theta'^2 sin(theta))`` has a spurious
  factor l on theta'^2.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.model import Constraint, Model

NAME = "painleve-two-points"
ORDER = 30
TITLE = ("Painleve's two points on a rod, one on a smooth line: multipliers in redundant "
         "coordinates (Manglieva & Beknazarov 2022, (1.27)-(1.28))")
FILE = "painleve_two_points.toml"


def build(m: float = 1.0, m1: float = 2.0, l: float = 0.5, g: float = 9.81, theta0: float = 0.3,
          thetad0: float = 1.0, v0: float = 0.5, t_end: float = 4.0) -> Model:
    """The system in (x, y, x1, y1) with the Python API (same as the model file by default)."""
    return Model(
        name="Painleve: two points joined by a rod, one on a smooth line",
        coordinates=["x", "y", "x1", "y1"],
        parameters={"m": m, "m1": m1, "l": l, "g": g, "theta0": theta0, "thetad0": thetad0, "v0": v0},
        bodies=[Particle("M", "m", ["x", "y"]), Particle("M1", "m1", ["x1", "y1"])],
        gravity=["0", "g"],
        constraints=[Constraint.holonomic("line", "y"),
                     Constraint.holonomic("rod", "sqrt((x1 - x)^2 + (y1 - y)^2) - l")],
        initial={"x": 0.0, "y": 0.0, "x1": "l*cos(theta0)", "y1": "l*sin(theta0)",
                 "x'": "v0", "y'": 0.0, "x1'": "v0 - l*sin(theta0)*thetad0",
                 "y1'": "l*cos(theta0)*thetad0"},
        simulation={"t_end": t_end},
    )


def multipliers(theta, thetad, m, m1, l, g):
    """Manglieva & Beknazarov 2022, (1.27), (1.28): ``(lambda_1, lambda)`` = (rod, line) multipliers."""
    theta, thetad = np.asarray(theta, float), np.asarray(thetad, float)
    lam1 = -(l * thetad ** 2 + g * np.sin(theta)) * m * m1 / (m + m1 * np.cos(theta) ** 2)
    return lam1, -m * g + lam1 * np.sin(theta)


def printed_1_5(theta, thetad, g):
    """Manglieva & Beknazarov's (1.5) as printed (equal masses): dimensionally wrong, see the docstring."""
    return -(thetad ** 2 + g * np.sin(theta)) / (1 + np.cos(theta) ** 2)


def angle(q, qd):
    """``theta, theta'`` of the rod from (x, y, x1, y1) states (arrays (N, 4))."""
    dx, dy = q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]
    dxd, dyd = qd[:, 2] - qd[:, 0], qd[:, 3] - qd[:, 1]
    return np.arctan2(dy, dx), (dx * dyd - dy * dxd) / (dx * dx + dy * dy)


def state(theta, thetad, xd, l, x=0.0):
    """An admissible (x, y, x1, y1) state, as a dict for ``evaluate(at=...)``."""
    return {"x": x, "y": 0.0, "x1": x + l * np.cos(theta), "y1": l * np.sin(theta),
            "x'": xd, "y'": 0.0, "x1'": xd - l * np.sin(theta) * thetad,
            "y1'": l * np.cos(theta) * thetad}


MASSES = ((1.0, 2.0), (2.0, 2.0), (3.0, 0.5), (0.2, 5.0))


def random_states(count=8, seed=1):
    rng = np.random.default_rng(seed)
    return [(rng.uniform(0.05, 3.0), rng.uniform(-3, 3), rng.uniform(-2, 2)) for _ in range(count)]


def form_agreement(model, count=10):
    """``{form: worst relative disagreement with lagrange1 | 'not applicable: ...'}``."""
    from ..analysis.crosscheck import compare_forms
    from ..errors import FormNotApplicable
    from ..equations.formalisms import FORMS

    out = {}
    for f in list(FORMS) + ["gauss"]:
        if f == "lagrange1":
            continue
        try:
            out[f] = compare_forms(model, forms=[f], count=count).worst()
        except FormNotApplicable as exc:
            out[f] = f"not applicable: {exc}"
    return out


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.evaluation import evaluate
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    m, m1, l, g = p["m"], p["m1"], p["l"], p["g"]
    times = np.linspace(0.0, model.simulation.t_end, 401)
    traj = simulate(model, times=times)
    th, thd = angle(traj.q, traj.qd)
    lam1, lam = multipliers(th, thd, m, m1, l, g)
    # relative to the multipliers' size (|lambda| reaches ~100 when the rod swings fast)
    err_rod = float(np.max(np.abs(traj.multipliers["rod"] - lam1)) / np.max(np.abs(lam1)))
    err_line = float(np.max(np.abs(traj.multipliers["line"] - lam)) / np.max(np.abs(lam)))
    px = m * traj.velocity("x") + m1 * traj.velocity("x1")
    err_px = float(np.max(np.abs(px - px[0])))

    # several masses, random admissible states: (1.27)-(1.28) hold for any m, m1
    err_masses = 0.0
    for mm, mm1 in MASSES:
        mod = build(m=mm, m1=mm1)
        for theta, thetad, xd in random_states():
            ev = evaluate(mod, at=state(theta, thetad, xd, l))
            a1, a = multipliers(theta, thetad, mm, mm1, l, g)
            err_masses = max(err_masses, abs(ev.multipliers["rod"] - a1) / abs(a1),
                             abs(ev.multipliers["line"] - a) / abs(a))
    # (1.5): equal masses m = m1 = 2
    ev = evaluate(build(m=2.0, m1=2.0), at=state(0.7, 1.3, 0.0, l))
    lam1_eq = -2.0 * (l * 1.3 ** 2 + g * np.sin(0.7)) / (1 + np.cos(0.7) ** 2)
    err_eq = abs(ev.multipliers["rod"] - lam1_eq)
    printed = float(printed_1_5(0.7, 1.3, g))

    forms = form_agreement(model)
    worst_form = max([v for v in forms.values() if isinstance(v, float)] + [0.0])
    d = traj.diagnostics
    result = {
        "ok": max(err_rod, err_line) < 1e-9 and err_px < 1e-9 and err_masses < 1e-12 and err_eq < 1e-12
        and abs(printed - lam1_eq) > 1.0 and worst_form < 1e-10
        and d["energy_balance_relative"] < 1e-8 and d["constraint_residual_max"] < 1e-8,
        "max_relative_error_lambda_rod_(1.27)": err_rod, "max_relative_error_lambda_line_(1.28)": err_line,
        "max_relative_error_several_masses": err_masses,
        "lambda1_equal_masses": float(ev.multipliers["rod"]), "lambda1_(1.5)_printed": printed,
        "max_error_horizontal_momentum": err_px,
        "energy_balance_relative": d["energy_balance_relative"],
        "constraint_residual_max": d["constraint_residual_max"],
        "forms": forms,
    }
    if verbose:
        print(TITLE)
        print(f"m = {m}, m1 = {m1}, l = {l}; t in [0, {times[-1]:g}]")
        print(f"  max |lambda_rod  - (1.27)|           = {err_rod:.2e}")
        print(f"  max |lambda_line - (1.28)|           = {err_line:.2e}")
        print(f"  masses {MASSES}: max relative error of (1.27), (1.28) at random states = {err_masses:.2e}")
        print(f"  m = m1 = 2, theta = 0.7, theta' = 1.3: lambda_1 = {ev.multipliers['rod']:.10f}; "
              f"(1.27) = {lam1_eq:.10f}; (1.5) as printed = {printed:.10f} (misprint)")
        print(f"  max |m x' + m1 x1' - const|          = {err_px:.2e}")
        print(f"  energy balance (relative)            = {d['energy_balance_relative']:.2e}")
        print(f"  constraint residual                  = {d['constraint_residual_max']:.2e}")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v if isinstance(v, str) else f'{v:.2e}'}")
        print("ok" if result["ok"] else "FAILED")
    return result
