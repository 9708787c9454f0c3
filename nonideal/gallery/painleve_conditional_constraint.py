"""Two points on a rod whose midpoint moves along the rod (a "conditional" constraint).

Source: Manglieva & Beknazarov (2022), sec. 1.3, problem 1, eqs. (1.66)-(1.99), here with a
smooth line (f = 0; the paper shows that the multipliers do not depend on friction, so these
are also its multipliers with friction).

Model (Manglieva & Beknazarov's conventions, Oy DOWN, gravity +g along y).  M1 (mass m1) at (x1, y1) slides
on the line y1 = 0 pushed by a horizontal force X; M2 (mass m2) at (x2, y2) is joined to M1
by a rigid massless rod of length l, x2 = x1 + l cos(theta), y2 = y1 + l sin(theta).  The
velocity of the rod's midpoint is directed along the rod (1.67).  Constraints:

    line:     y1 = 0,
    rod:      sqrt((x2 - x1)^2 + (y2 - y1)^2) - l = 0,
    midpoint: ((x2 - x1)(y2' + y1') - (y2 - y1)(x2' + x1'))/l = 0       ((1.67) divided by l).

Multipliers and signs.  ``lambda_line`` is the force on M1 along +y (Manglieva & Beknazarov's lambda = Y);
``lambda_rod`` gives the force ``lambda_rod (cos(theta), sin(theta))`` on M2 (the opposite on
M1): Manglieva & Beknazarov's lambda_1 of (1.83); by Chetaev's rule ``lambda_midpoint`` gives the force
``lambda_midpoint (-sin(theta), cos(theta))`` on each point: Manglieva & Beknazarov's lambda_2 of (1.83).
(Manglieva & Beknazarov's own normalizations f2 = ((x2-x1)^2 + (y2-y1)^2 - l^2)/2 and f3 = (1.67) give
lambda_1 = l lambda_f2 and lambda_2 = l lambda_f3.)

Multipliers (derived from (1.83) with mu = 0 and the second derivatives (1.85); with
P = l theta'^2 + g sin(theta), W = 2 x1' theta' - g, s = sin(theta), c = cos(theta)):

    lambda_1 = m2/(m1 + m2) (X c - m2 W c^2 s - (m1 + m2 s^2) P),                    (1.87)
    lambda_2 = m2/(m1 + m2) (X s + W c (m1 + m2 c^2) + m2 P s c),                    (1.87)
    lambda   = -(m1 + m2) g - m2 (l theta'^2 s + 2 x1' theta' c^2 - 2 g c^2)
             = -(m1 + m2) g - m2 (l theta'^2 / s - 2 g c^2)      with (1.88),        (1.89)

all as printed: (1.87) and (1.89) are correct.  ``run`` checks them along the motion.

The constraint is integrable (1.92).  On the manifold of the holonomic constraints the
midpoint velocity is (x1' - (l/2) s theta', (l/2) c theta'), and (1.67) reduces to

    x1' sin(theta) = (l/2) theta'     (1.88)  ==>   tan(theta/2) = tan(theta0/2) exp(2 (x1 - x10)/l).

The paper prints ``tg(theta/2) = e^{x1}``: dimensionally wrong (x1 is a length) and without the
integration constant; it holds only for l = 2 (in the units of x1) with a special origin.
``run`` checks the correct first integral along the simulation and that the printed one is
not constant (l = 0.8 here).

Equation of motion (derived).  Along the constraints |v2| = |v1| = |x1'|, so
``T = (m1 + m2) x1'^2 / 2 = (m1 + m2) l^2 theta'^2 / (8 sin^2(theta))`` (1.93, correct), and with
``dy2/dx1 = l cos(theta) dtheta/dx1 = 2 sin(theta) cos(theta)``:

    (m1 + m2) x1'' = X + m2 g sin(2 theta),                                          (**)
    (m1 + m2) l/4 (theta''/s^2 - c theta'^2/s^3) = m2 g c + X/(2 s)          (1.98, f = 0).

Energy integral: ``(m1 + m2) x1'^2/2 - m2 g l sin(theta) - X x1 = const``.

Misprints found in sec. 1.3, problem 1:

* (1.99) first equation ``(m1 + m2) x1'' = X + m1 mu + m2 l g cos(theta)``: the gravity term is
  ``m2 g sin(2 theta)`` (the printed one is not even a force); the static-friction condition
  (1.100) ``|X + m2 g sin(2 theta)| <= ...`` confirms the correct term.
* (1.99) second equation ``x1' sin(theta) = l theta'`` lacks the factor 1/2 of (1.88)/(1.92).
* (1.92) ``tg(theta/2) = e^{x1}``: see above.
* (1.96): ``d/dt[(m1 + m2) l^2 theta'/(4 sin(theta))]`` should be ``sin^2(theta)`` and the term
  ``-dT/dtheta`` is missing; (1.98) is right (divided by l).
* the virtual work before (1.95) has ``m g l cos(theta)``; it is ``m2 g l cos(theta)``.
* the constraint forces printed after (1.80): ``R'_1x = lambda - ...`` and
  ``R'_1y = -lambda_1 sin(theta) - lambda_2 cos(theta)``, ``R'_2y = lambda_1 cos(theta) + ...``
  disagree with (1.83), which is right (``R'_1 = (-lambda_1 c - lambda_2 s, lambda - lambda_1 s
  + lambda_2 c)``, ``R'_2 = (lambda_1 c - lambda_2 s, lambda_1 s + lambda_2 c)``).
* friction terms (not exercised here, f = 0): the generalized friction force is that of the
  total friction R_tau = (m1 + m2) mu acting at M1 (the friction components on M1 and M2 of
  (1.79)-(1.80) do the work (m1 + m2) mu delta x1, since delta r2 = (cos 2 theta, sin 2 theta)
  delta x1), so (1.95), (1.96) and (1.99) should have (m1 + m2) mu instead of m1 mu; (1.98)
  with mu = eps f lambda/(m1 + m2) is consistent with the correct (m1 + m2) mu.
* at rest (x1' = theta' = 0) the printed lambda_1 has both g terms with the wrong sign; the
  correct ``lambda_1 = m2/(m1 + m2) (X c + m2 g c^2 s - (m1 + m2 s^2) g s)``; the printed
  combination ``lambda_1 c + lambda_2 s = m2/(m1 + m2) (X - m1 g sin(2 theta))`` is right.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.model import Constraint, Model

NAME = "painleve-conditional-constraint"
ORDER = 32
TITLE = ("Two points on a rod whose midpoint moves along the rod, smooth guide: reactions of a "
         "conditional constraint (Manglieva & Beknazarov 2022, (1.87)-(1.92))")
FILE = "painleve_conditional_constraint.toml"

MIDPOINT = "((x2 - x1)*(y2' + y1') - (y2 - y1)*(x2' + x1'))/l"


def _parameters(m1, m2, l, g, X, theta0, thetad0):
    return {"m1": m1, "m2": m2, "l": l, "g": g, "X": X, "theta0": theta0, "thetad0": thetad0}


def build(m1: float = 1.0, m2: float = 2.0, l: float = 0.8, g: float = 9.81, X: float = 1.5,
          theta0: float = 1.0, thetad0: float = 0.5, t_end: float = 5.0) -> Model:
    """The system in (x1, y1, x2, y2) with the Python API (same as the model file by default)."""
    v1 = "l*thetad0/(2*sin(theta0))"
    return Model(
        name="Painleve: two points on a rod, midpoint velocity along the rod, smooth line",
        coordinates=["x1", "y1", "x2", "y2"],
        parameters=_parameters(m1, m2, l, g, X, theta0, thetad0),
        bodies=[Particle("M1", "m1", ["x1", "y1"]), Particle("M2", "m2", ["x2", "y2"])],
        gravity=["0", "g"],
        forces={"x1": "X"},
        constraints=[Constraint.holonomic("line", "y1"),
                     Constraint.holonomic("rod", "sqrt((x2 - x1)^2 + (y2 - y1)^2) - l"),
                     Constraint.nonholonomic("midpoint", MIDPOINT)],
        initial={"x1": 0.0, "y1": 0.0, "x2": "l*cos(theta0)", "y2": "l*sin(theta0)",
                 "x1'": v1, "y1'": 0.0, "x2'": f"{v1} - l*sin(theta0)*thetad0",
                 "y2'": "l*cos(theta0)*thetad0"},
        simulation={"t_end": t_end},
    )


def build_lagrange2(m1: float = 1.0, m2: float = 2.0, l: float = 0.8, g: float = 9.81,
                    X: float = 1.5, theta0: float = 1.0, thetad0: float = 0.5,
                    t_end: float = 5.0) -> Model:
    """Manglieva & Beknazarov's one-coordinate model (1.93)-(1.98) with f = 0: an independent check."""
    return Model(
        name="Two points on a rod, midpoint along the rod: Lagrange II in theta (1.93)",
        coordinates=["theta"],
        parameters=_parameters(m1, m2, l, g, X, theta0, thetad0),
        kinetic="(m1 + m2)*l^2*theta'^2/(8*sin(theta)^2)",
        potential="-m2*g*l*sin(theta)",
        forces={"theta": "X*l/(2*sin(theta))"},
        initial={"theta": "theta0", "theta'": "thetad0"},
        simulation={"t_end": t_end},
    )


def angle(q, qd):
    """``theta, theta'`` of the rod from (x1, y1, x2, y2) states (arrays (N, 4))."""
    dx, dy = q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]
    dxd, dyd = qd[:, 2] - qd[:, 0], qd[:, 3] - qd[:, 1]
    return np.arctan2(dy, dx), (dx * dyd - dy * dxd) / (dx * dx + dy * dy)


def multipliers(theta, thetad, x1d, m1, m2, l, g, X):
    """(1.87) and the first form of (1.89): ``lambda_1 (rod), lambda_2 (midpoint), lambda (line)``."""
    s, c = np.sin(theta), np.cos(theta)
    P = l * thetad ** 2 + g * s
    W = 2 * x1d * thetad - g
    k = m2 / (m1 + m2)
    lam1 = k * (X * c - m2 * W * c * c * s - (m1 + m2 * s * s) * P)
    lam2 = k * (X * s + W * c * (m1 + m2 * c * c) + m2 * P * s * c)
    lam = -(m1 + m2) * g - m2 * (l * thetad ** 2 * s + 2 * x1d * thetad * c * c - 2 * g * c * c)
    return lam1, lam2, lam


def line_force_1_89(theta, thetad, m1, m2, l, g):
    """(1.89): lambda after substituting (1.88)."""
    return -(m1 + m2) * g - m2 * (l * thetad ** 2 / np.sin(theta) - 2 * g * np.cos(theta) ** 2)


def first_integral(theta, x1, l):
    """``tan(theta/2) exp(-2 x1/l)``: constant by (1.88)."""
    return np.tan(theta / 2) * np.exp(-2 * x1 / l)


def printed_integral(theta, x1):
    """Manglieva & Beknazarov's (1.92) as printed, ``tan(theta/2) e^{-x1}`` (should be 1): not constant."""
    return np.tan(theta / 2) * np.exp(-x1)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation.hybrid import simulate
    from .painleve_two_points import form_agreement

    model = gallery.load(NAME)
    p = model.parameter_values
    m1, m2, l, g, X = p["m1"], p["m2"], p["l"], p["g"], p["X"]
    times = np.linspace(0.0, model.simulation.t_end, 501)
    traj = simulate(model, times=times)
    th, thd = angle(traj.q, traj.qd)
    x1, x1d, x1dd = traj.coordinate("x1"), traj.velocity("x1"), traj.qdd[:, 0]
    lam1, lam2, lam = multipliers(th, thd, x1d, m1, m2, l, g, X)
    scale = np.max(np.abs(lam))
    err_87 = float(max(np.max(np.abs(traj.multipliers["rod"] - lam1)),
                       np.max(np.abs(traj.multipliers["midpoint"] - lam2))) / scale)
    err_89 = float(np.max(np.abs(traj.multipliers["line"] - line_force_1_89(th, thd, m1, m2, l, g))) / scale)
    err_88 = float(np.max(np.abs(x1d * np.sin(th) - l * thd / 2)))
    I = first_integral(th, x1, l)
    err_int = float(np.max(np.abs(I - I[0])) / I[0])
    Ip = printed_integral(th, x1)
    spread_printed = float(np.max(Ip) - np.min(Ip))
    err_eom = float(np.max(np.abs((m1 + m2) * x1dd - X - m2 * g * np.sin(2 * th))))
    E = 0.5 * (m1 + m2) * x1d ** 2 - m2 * g * l * np.sin(th) - X * x1
    err_E = float(np.max(np.abs(E - E[0])))
    err_WX = float(np.max(np.abs(traj.energy["active_work"] - X * (x1 - x1[0]))))

    one = simulate(build_lagrange2(**p, t_end=model.simulation.t_end), times=times)
    err_l2 = float(np.max(np.abs(one.coordinate("theta") - th)))

    forms = form_agreement(model)
    worst_form = max([v for v in forms.values() if isinstance(v, float)] + [0.0])
    d = traj.diagnostics
    result = {
        "ok": err_87 < 1e-9 and err_89 < 1e-9 and err_88 < 1e-9 and err_int < 1e-8 and spread_printed > 0.1
        and err_eom < 1e-8 and err_E < 1e-8 and err_WX < 1e-8 and err_l2 < 1e-8 and worst_form < 1e-10
        and d["energy_balance_relative"] < 1e-8 and d["constraint_residual_max"] < 1e-8,
        "max_relative_error_(1.87)": err_87, "max_relative_error_(1.89)": err_89,
        "max_residual_(1.88)": err_88,
        "first_integral_tan(theta/2)exp(-2x1/l)": float(I[0]),
        "max_relative_drift_first_integral": err_int,
        "spread_of_printed_(1.92)": spread_printed,
        "max_residual_equation_of_motion": err_eom,
        "max_error_energy_integral": err_E, "max_error_work_of_X": err_WX,
        "max_error_vs_lagrange2_in_theta": err_l2,
        "theta_range": [float(th.min()), float(th.max())],
        "energy_balance_relative": d["energy_balance_relative"],
        "constraint_residual_max": d["constraint_residual_max"],
        "forms": forms,
    }
    if verbose:
        print(TITLE)
        print(f"m1 = {m1}, m2 = {m2}, l = {l}, X = {X}; t in [0, {times[-1]:g}], "
              f"theta in [{th.min():.4f}, {th.max():.4f}]")
        print(f"  max |lambda_1, lambda_2 - (1.87)| / max|lambda|   = {err_87:.2e}")
        print(f"  max |lambda - (1.89)| / max|lambda|              = {err_89:.2e}")
        print(f"  max |x1' sin(theta) - l theta'/2|  (1.88)        = {err_88:.2e}")
        print(f"  tan(theta/2) exp(-2 x1/l) = {I[0]:.12f}, relative drift {err_int:.2e}")
        print(f"  printed (1.92) tan(theta/2) e^(-x1) varies by {spread_printed:.4f} (misprint)")
        print(f"  max |(m1+m2) x1'' - X - m2 g sin(2 theta)|       = {err_eom:.2e}")
        print(f"  energy integral drift                           = {err_E:.2e}")
        print(f"  work of X vs X (x1 - x10)                       = {err_WX:.2e}")
        print(f"  max |theta - Lagrange II model (1.93)|          = {err_l2:.2e}")
        print(f"  energy balance (relative)                       = {d['energy_balance_relative']:.2e}")
        print(f"  constraint residual                             = {d['constraint_residual_max']:.2e}")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v if isinstance(v, str) else f'{v:.2e}'}")
        print("ok" if result["ok"] else "FAILED")
    return result
