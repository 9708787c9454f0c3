"""Painleve's two points on a smooth line in the coordinates (x, y, theta): Lagrange II.

Source: Manglieva & Beknazarov (2022), sec. 1.1, eqs. (1.32)-(1.39), with f = 0.  The same
system as ``painleve-two-points`` (see that docstring for the figure's conventions: Oy points
DOWN, gravity +g along y); here the rod is built into the geometry by the "principle of
release from constraints": M at (x, y), M1 at (x + l cos(theta), y + l sin(theta)), and only
the line remains as a constraint

    line: y = 0,     multiplier lambda_line = force of the line on M along +y (downwards)
                     = Manglieva & Beknazarov's lambda (1.28) = R_y of (1.39).

Lagrange II eliminates y (independent coordinates x, theta: ``[forms] independent``).  With
mu = 0 the equations are Manglieva & Beknazarov's (1.35) and (1.37):

    (m + m1) x'' - m1 l theta'' sin(theta) - m1 l theta'^2 cos(theta) = 0,           (1.35)
    l theta'' - x'' sin(theta) = g cos(theta),                                      (1.37)

and the second equation of (1.39) gives the normal force
``R_y = m1 l (theta'' cos(theta) - theta'^2 sin(theta)) - (m + m1) g``, which must equal
(1.28) ``lambda = -m g - (l theta'^2 + g sin(theta)) m m1 sin(theta)/(m + m1 cos^2(theta))``.
``run`` checks both equations with the simulated accelerations, the multiplier against
(1.28) and against (1.39), and the motion against the redundant-coordinate model.

Misprints (besides those listed in ``painleve-two-points``): the second equation of (1.29) is
printed with ``-g cos(theta)``; (1.37) has the right sign ``+g cos(theta)`` -- with the printed
(1.29) the residual at a simulated state is ``2 g cos(theta)``, as ``run`` shows.  (1.38),
second line: the term ``l theta'^2 sin(theta)`` inside ``m1 l (...)`` has a spurious factor l.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.model import Constraint, Model
from .painleve_two_points import MASSES, form_agreement, multipliers, random_states

NAME = "painleve-two-points-xtheta"
ORDER = 31
TITLE = ("Painleve's two points on a rod, smooth line, in coordinates (x, y, theta): Lagrange's "
         "equations of the second kind (Manglieva & Beknazarov 2022, (1.35)-(1.39))")
FILE = "painleve_two_points_xtheta.toml"


def build(m: float = 1.0, m1: float = 2.0, l: float = 0.5, g: float = 9.81, theta0: float = 0.3,
          thetad0: float = 1.0, v0: float = 0.5, t_end: float = 4.0) -> Model:
    """The system in (x, y, theta) with the Python API (same as the model file by default)."""
    return Model(
        name="Painleve: two points joined by a rod, one on a smooth line (x, y, theta)",
        coordinates=["x", "y", "theta"],
        parameters={"m": m, "m1": m1, "l": l, "g": g, "theta0": theta0, "thetad0": thetad0, "v0": v0},
        bodies=[Particle("M", "m", ["x", "y"]),
                Particle("M1", "m1", ["x + l*cos(theta)", "y + l*sin(theta)"])],
        gravity=["0", "g"],
        constraints=[Constraint.holonomic("line", "y")],
        independent=["x", "theta"],
        initial={"x": 0.0, "y": 0.0, "theta": "theta0", "x'": "v0", "y'": 0.0, "theta'": "thetad0"},
        simulation={"t_end": t_end},
    )


def residuals(theta, thetad, xdd, thetadd, m, m1, l, g):
    """Residuals of (1.35) and (1.37) (mu = 0) at states with accelerations."""
    r35 = (m + m1) * xdd - m1 * l * thetadd * np.sin(theta) - m1 * l * thetad ** 2 * np.cos(theta)
    r37 = l * thetadd - xdd * np.sin(theta) - g * np.cos(theta)
    return r35, r37


def normal_force_1_39(theta, thetad, thetadd, m, m1, l, g):
    """R_y from the second equation of (1.39) (with the spurious l removed)."""
    return m1 * l * (thetadd * np.cos(theta) - thetad ** 2 * np.sin(theta)) - (m + m1) * g


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.evaluation import evaluate
    from ..simulation.hybrid import simulate
    from .painleve_two_points import build as build_redundant

    model = gallery.load(NAME)
    p = model.parameter_values
    m, m1, l, g = p["m"], p["m1"], p["l"], p["g"]
    times = np.linspace(0.0, model.simulation.t_end, 401)
    traj = simulate(model, times=times)
    th, thd = traj.coordinate("theta"), traj.velocity("theta")
    xdd, thdd = traj.qdd[:, 0], traj.qdd[:, 2]
    r35, r37 = residuals(th, thd, xdd, thdd, m, m1, l, g)
    err_eq = float(max(np.max(np.abs(r35)), np.max(np.abs(r37))))
    misprint_129 = float(np.max(np.abs(l * thdd - xdd * np.sin(th) + g * np.cos(th))))
    _, lam = multipliers(th, thd, m, m1, l, g)
    err_128 = float(np.max(np.abs(traj.multipliers["line"] - lam)))
    err_139 = float(np.max(np.abs(traj.multipliers["line"] - normal_force_1_39(th, thd, thdd, m, m1, l, g))))

    red = simulate(build_redundant(**{k: p[k] for k in ("m", "m1", "l", "g", "theta0", "thetad0", "v0")}),
                   times=times)
    th_red = np.arctan2(red.coordinate("y1") - red.coordinate("y"), red.coordinate("x1") - red.coordinate("x"))
    err_red = float(max(np.max(np.abs(traj.coordinate("x") - red.coordinate("x"))),
                        np.max(np.abs(th - np.unwrap(th_red)))))

    err_masses = 0.0
    for mm, mm1 in MASSES:
        mod = build(m=mm, m1=mm1)
        for theta, thetad, xd in random_states():
            ev = evaluate(mod, at={"x": 0.0, "y": 0.0, "theta": theta, "x'": xd, "y'": 0.0, "theta'": thetad})
            _, a = multipliers(theta, thetad, mm, mm1, l, g)
            r35_, r37_ = residuals(theta, thetad, ev.qdd[0], ev.qdd[2], mm, mm1, l, g)
            err_masses = max(err_masses, abs(ev.multipliers["line"] - a) / abs(a),
                             abs(r35_) / (mm + mm1), abs(r37_))

    forms = form_agreement(model)
    worst_form = max([v for v in forms.values() if isinstance(v, float)] + [0.0])
    d = traj.diagnostics
    result = {
        "ok": err_eq < 1e-9 and err_128 < 1e-8 and err_139 < 1e-8 and err_red < 1e-8
        and err_masses < 1e-12 and misprint_129 > 1.0 and worst_form < 1e-10
        and d["energy_balance_relative"] < 1e-8 and d["constraint_residual_max"] < 1e-8,
        "max_residual_(1.35)_(1.37)": err_eq,
        "max_residual_(1.29)_as_printed": misprint_129,
        "max_error_lambda_line_(1.28)": err_128, "max_error_lambda_line_(1.39)": err_139,
        "max_error_vs_redundant_model": err_red,
        "max_relative_error_several_masses": err_masses,
        "energy_balance_relative": d["energy_balance_relative"],
        "constraint_residual_max": d["constraint_residual_max"],
        "forms": forms,
    }
    if verbose:
        print(TITLE)
        print(f"m = {m}, m1 = {m1}, l = {l}; t in [0, {times[-1]:g}]")
        print(f"  max residual of (1.35), (1.37)            = {err_eq:.2e}")
        print(f"  max residual of (1.29) as printed (-g cos) = {misprint_129:.4f}  (misprint)")
        print(f"  max |lambda_line - (1.28)|                 = {err_128:.2e}")
        print(f"  max |lambda_line - R_y of (1.39)|          = {err_139:.2e}")
        print(f"  max |(x, theta) - redundant model|         = {err_red:.2e}")
        print(f"  masses {MASSES}: max error at random states = {err_masses:.2e}")
        print(f"  energy balance (relative)                  = {d['energy_balance_relative']:.2e}")
        print(f"  constraint residual                        = {d['constraint_residual_max']:.2e}")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v if isinstance(v, str) else f'{v:.2e}'}")
        print("ok" if result["ok"] else "FAILED")
    return result
