"""Two particles whose velocities stay perpendicular: a constraint quadratic in the velocities.

Source: nonlinear nonholonomic constraints of Chetaev type (Yushkov 1999, ch. II sec. 5,
"virtual displacements by Chetaev").  A constraint homogeneous of degree k in
the velocities satisfies Euler's identity ``d(phi)/d(q') . q' = k phi``; with Chetaev's rule
the power of its reaction is ``lambda k phi = 0``, so the energy is conserved.  This is the
simplest such constraint of degree 2 that is not a product of linear ones.

Model.  Particles P1 (mass m1) at r1 = (x1, y1) and P2 (mass m2) at r2 = (x2, y2) in a plane,
P1 pulled to the origin by a spring k1, P2 to the point (d, 0) by a spring k2, with

    phi = x1' x2' + y1' y2' = v1 . v2 = 0.

Chetaev's rule: the reaction on P1 is lambda v2 and on P2 lambda v1.  With the spring forces
F1 = -k1 r1, F2 = -k2 (r2 - d e_x), Newton's equations m1 r1'' = F1 + lambda v2,
m2 r2'' = F2 + lambda v1 and the differentiated constraint r1''.v2 + v1.r2'' = 0 give
(derived)

    lambda = -(F1 . v2 / m1 + F2 . v1 / m2) / (|v2|^2 / m1 + |v1|^2 / m2).

``run`` checks lambda along the simulation, the energy (conserved), the zero work of the
reaction, and the motion against an independent integration of these equations (numpy/SciPy,
no library code).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from ..modeling.bodies import Particle
from ..modeling.model import Constraint, Model

NAME = "perpendicular-velocities"
ORDER = 51
TITLE = ("Two particles with perpendicular velocities x1'x2' + y1'y2' = 0 (degree-2 constraint, "
         "energy conserved)")
FILE = "perpendicular_velocities.toml"

INITIAL = {"x1": 1.0, "y1": 0.0, "x2": 2.5, "y2": 0.3, "x1'": 0.0, "y1'": 1.2, "x2'": 0.8, "y2'": 0.0}


def build(m1: float = 1.0, m2: float = 2.0, k1: float = 3.0, k2: float = 5.0, d: float = 2.0,
          t_end: float = 10.0) -> Model:
    """The two particles with the Python API (same as the model file for the default values)."""
    return Model(
        name="Two particles with perpendicular velocities, on springs",
        coordinates=["x1", "y1", "x2", "y2"],
        parameters={"m1": m1, "m2": m2, "k1": k1, "k2": k2, "d": d},
        bodies=[Particle("P1", "m1", ["x1", "y1"]), Particle("P2", "m2", ["x2", "y2"])],
        potential="k1/2*(x1^2 + y1^2) + k2/2*((x2 - d)^2 + y2^2)",
        constraints=[Constraint.nonholonomic("perpendicular", "x1'*x2' + y1'*y2'")],
        initial=dict(INITIAL),
        simulation={"t_end": t_end},
    )


def multiplier(q, qd, m1, m2, k1, k2, d):
    """The closed-form lambda at states (arrays (N, 4))."""
    q, qd = np.atleast_2d(q), np.atleast_2d(qd)
    r1, r2, v1, v2 = q[:, :2], q[:, 2:], qd[:, :2], qd[:, 2:]
    F1 = -k1 * r1
    F2 = -k2 * (r2 - np.array([d, 0.0]))
    num = np.sum(F1 * v2, axis=1) / m1 + np.sum(F2 * v1, axis=1) / m2
    den = np.sum(v2 * v2, axis=1) / m1 + np.sum(v1 * v1, axis=1) / m2
    return -num / den


def energy(q, qd, m1, m2, k1, k2, d):
    q, qd = np.atleast_2d(q), np.atleast_2d(qd)
    T = 0.5 * m1 * np.sum(qd[:, :2] ** 2, axis=1) + 0.5 * m2 * np.sum(qd[:, 2:] ** 2, axis=1)
    V = 0.5 * k1 * np.sum(q[:, :2] ** 2, axis=1) + 0.5 * k2 * ((q[:, 2] - d) ** 2 + q[:, 3] ** 2)
    return T + V


def reference(times, m1, m2, k1, k2, d, initial=INITIAL):
    """Independent integration of Newton's equations with the closed-form lambda."""
    names = ["x1", "y1", "x2", "y2"]
    y0 = [initial[n] for n in names] + [initial[n + "'"] for n in names]

    def f(t, y):
        q, qd = y[:4], y[4:]
        lam = multiplier(q, qd, m1, m2, k1, k2, d)[0]
        F1 = -k1 * q[:2]
        F2 = -k2 * (q[2:] - np.array([d, 0.0]))
        return np.concatenate((qd, (F1 + lam * qd[2:]) / m1, (F2 + lam * qd[:2]) / m2))
    sol = solve_ivp(f, (times[0], times[-1]), y0, t_eval=times, method="DOP853", rtol=1e-12, atol=1e-13)
    return sol.y[:4].T, sol.y[4:].T


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation.hybrid import simulate
    from .painleve_two_points import form_agreement

    model = gallery.load(NAME)
    p = model.parameter_values
    args = (p["m1"], p["m2"], p["k1"], p["k2"], p["d"])
    times = np.linspace(0.0, model.simulation.t_end, 201)
    traj = simulate(model, times=times)
    lam = multiplier(traj.q, traj.qd, *args)
    err_lam = float(np.max(np.abs(traj.multipliers["perpendicular"] - lam)))
    E = energy(traj.q, traj.qd, *args)
    err_E = float(np.max(np.abs(E - E[0])) / E[0])
    W_R = float(np.max(np.abs(traj.energy["reaction_work"])))
    phi = np.sum(traj.qd[:, :2] * traj.qd[:, 2:], axis=1)
    q_ref, qd_ref = reference(times, *args)
    err_ref = float(max(np.max(np.abs(traj.q - q_ref)), np.max(np.abs(traj.qd - qd_ref))))
    forms = form_agreement(model)
    worst_form = max([v for v in forms.values() if isinstance(v, float)] + [0.0])
    d = traj.diagnostics
    result = {
        "ok": err_lam < 1e-8 and err_E < 1e-9 and W_R < 1e-9 and err_ref < 1e-7 and worst_form < 1e-10
        and d["energy_balance_relative"] < 1e-8 and d["constraint_residual_max"] < 1e-8,
        "lambda_initial": float(traj.multipliers["perpendicular"][0]), "lambda_initial_closed_form": float(lam[0]),
        "lambda_range": [float(lam.min()), float(lam.max())],
        "max_error_lambda": err_lam, "max_relative_energy_drift": err_E,
        "max_abs_reaction_work": W_R, "max_abs_phi": float(np.max(np.abs(phi))),
        "max_error_vs_independent_integration": err_ref,
        "energy_balance_relative": d["energy_balance_relative"],
        "constraint_residual_max": d["constraint_residual_max"],
        "forms": forms,
    }
    if verbose:
        print(TITLE)
        print(f"m1, m2, k1, k2, d = {args}; t in [0, {times[-1]:g}]")
        print(f"  lambda(0) = {traj.multipliers['perpendicular'][0]:.12f}; closed form {lam[0]:.12f}")
        print(f"  max |lambda - closed form| = {err_lam:.2e} (lambda in [{lam.min():.4f}, {lam.max():.4f}])")
        print(f"  relative energy drift      = {err_E:.2e}; max |work of the reaction| = {W_R:.2e}")
        print(f"  max |v1 . v2|              = {result['max_abs_phi']:.2e}")
        print(f"  max |state - independent integration| = {err_ref:.2e}")
        print(f"  energy balance (relative)  = {d['energy_balance_relative']:.2e}")
        print(f"  constraint residual        = {d['constraint_residual_max']:.2e}")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v if isinstance(v, str) else f'{v:.2e}'}")
        print("ok" if result["ok"] else "FAILED")
    return result
