"""Suslov's problem: a rigid body about a fixed point with a constraint on its angular velocity.

Source: G. K. Suslov, *Theoretical Mechanics* (1902; 3rd ed. 1946), the motion of a rigid body
about a fixed point with the nonholonomic constraint ``omega . e = 0``, ``e`` fixed in the body;
also Borisov, Kilin & Mamaev, Regul. Chaotic Dyn. 16 (2011).  The closed form below is derived
here and checked against the simulation and every form of the equations.

Model.  Body axes 1, 2, 3 with ``e`` = axis 3; the inertia tensor in these axes is

    J = [[J1, 0, a], [0, J2, 0], [a, 0, J3]]

(axes 1, 2 turned about ``e`` so that ``J12 = 0``; here also ``J23 = 0``).  The speeds are the
body components of the angular velocity, read from the body's frame B (Euler angles psi,
theta, phi, body ZXZ): ``w1 = dot(omega(B), B.x)`` (= psi' sin(theta) sin(phi) + theta'
cos(phi)), ``w2 = dot(omega(B), B.y)``, ``w3 = dot(omega(B), B.z)``; the constraint is
``w3 = 0`` and no torque acts.

Equations (Kane's form in the speeds w1, w2: Euler's equations with the reaction torque
``lambda e`` about axis 3, whose row is eliminated)

    J1 w1' + a w1 w2 = 0,        J2 w2' - a w1^2 = 0,        (a w1' + (J2 - J1) w1 w2 = lambda).

Closed form (derived).  The energy ``T = (J1 w1^2 + J2 w2^2)/2`` is conserved; with
``s = sqrt(2T/J2)``, ``k = a s / J1`` and ``c0 = artanh(w2(0)/s)``

    w2(t) = s tanh(k t + c0),          w1(t) = w1(0) cosh(c0) / cosh(k t + c0),

so the body ends up spinning about axis 2 at the rate ``s`` (towards ``-s`` when ``a < 0``),
and the reaction torque is ``lambda = w1 w2 (J2 - J1 - a^2/J1)`` (from the third row).
"""

from __future__ import annotations

import numpy as np

from ..modeling.frames import Frame
from ..modeling.model import Constraint, Model

NAME = "suslov-problem"
ORDER = 11
TITLE = "Suslov's problem: rigid body with omega . e = 0, closed form w2 = s tanh(k t + c0) (Suslov 1902)"
FILE = "suslov_problem.toml"

#: the speeds: the body components of the body's angular velocity, read from its frame
SPEEDS = {"w1": "dot(omega(B), B.x)", "w2": "dot(omega(B), B.y)", "w3": "dot(omega(B), B.z)"}


def build(J1: float = 2.0, J2: float = 3.0, J3: float = 4.0, a: float = 0.5, w10: float = 1.0,
          w20: float = 0.2, t_end: float = 10.0) -> Model:
    """The model with the Python API (the model file for the default values)."""
    return Model(
        name="Suslov's problem: rigid body with omega . e3 = 0",
        coordinates=["psi", "theta", "phi"],
        parameters={"J1": J1, "J2": J2, "J3": J3, "a": a},
        frames=[Frame("B", rotation="body ZXZ", angles=["psi", "theta", "phi"])],
        speeds=SPEEDS,
        kinetic="(J1*w1^2 + J2*w2^2 + J3*w3^2)/2 + a*w1*w3",
        constraints=[Constraint.nonholonomic("suslov", "w3")],
        outputs={"E": "T", "limit_w2": "sqrt(2*T/J2)", "torque": "lambda_suslov"},
        initial={"psi": 0.0, "theta": 1.2, "phi": 0.3, "w1": w10, "w2": w20, "w3": 0.0},
        simulation={"t_end": t_end, "rtol": 1e-12, "atol": 1e-13},
    )


def closed_form(t, J1, J2, a, w10, w20):
    """``w1(t), w2(t), lambda(t)`` (see the module docstring)."""
    t = np.asarray(t, dtype=float)
    s = np.sqrt((J1 * w10 ** 2 + J2 * w20 ** 2) / J2)
    k = a * s / J1
    c0 = np.arctanh(w20 / s)
    w2 = s * np.tanh(k * t + c0)
    w1 = w10 * np.cosh(c0) / np.cosh(k * t + c0)
    lam = w1 * w2 * (J2 - J1 - a * a / J1)
    return w1, w2, lam


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..equations.formalisms import derive
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    J1, J2, a = p["J1"], p["J2"], p["a"]
    times = np.linspace(0.0, model.simulation.t_end, 21)
    w1c, w2c, lamc = closed_form(times, J1, J2, a, 1.0, 0.2)
    errors = {}
    for form in ("lagrange1", "kane", "poincare_chetaev"):
        traj = simulate(model, times=times, form=form)
        errors[form] = max(float(np.max(np.abs(traj.speeds["w1"] - w1c))),
                           float(np.max(np.abs(traj.speeds["w2"] - w2c))),
                           float(np.max(np.abs(traj.multipliers["suslov"] - lamc))))
    traj = simulate(model, times=times)
    kane = derive(model, "kane")
    result = {
        "ok": max(errors.values()) < 1e-8 and traj.diagnostics["constraint_residual_max"] < 1e-9,
        "max_error": errors, "w2_end": float(traj.speeds["w2"][-1]),
        "limit_s": float(traj.outputs["limit_w2"][-1]),
        "energy_drift": float(np.ptp(traj.outputs["E"])),
        "theta_range": [float(traj.coordinate("theta").min()), float(traj.coordinate("theta").max())],
        "constraint_residual_max": traj.diagnostics["constraint_residual_max"],
        "kane_equations": kane.readable(),
    }
    if verbose:
        print(TITLE)
        print(kane.as_text())
        for form, err in errors.items():
            print(f"  {form:>16}: max |w1, w2, lambda - closed form| over t in [0, {times[-1]:g}] = {err:.2e}")
        print(f"  w2(t_end) = {result['w2_end']:.12f} -> s = {result['limit_s']:.12f}; "
              f"energy drift {result['energy_drift']:.1e}")
        print("ok" if result["ok"] else "FAILED")
    return result
