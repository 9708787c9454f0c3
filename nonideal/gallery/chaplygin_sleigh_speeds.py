"""The Chaplygin sleigh written in generalized speeds.

Source: Yushkov 1999, appendix A, sec. 2 (free motion of the Chaplygin sleigh); the speeds as
in Kane & Levinson 1985, ch. 2.  Same system and closed form as ``chaplygin-sleigh``
(:mod:`nonideal.gallery.chaplygin_sleigh`), described by its speeds instead of its geometry:

    v = x' cos(theta) + y' sin(theta)      (velocity of the knife edge C along the axis),
    w = theta'                             (angular velocity),
    s = -x' sin(theta) + y' cos(theta)     (velocity of C across the axis: the knife edge makes it 0).

The kinetic energy in the speeds (G at distance a ahead of C) is
``T = m (v^2 + (s + a w)^2)/2 + I w^2/2`` and the constraint is ``s = 0``.  Kane's equations
(and Boltzmann--Hamel's, Poincaré--Chetaev's) print the equations of Yushkov's appendix,

    m (v' - a w^2) = 0,        (I + m a^2) w' + m a v w = 0,

whose solution is ``v = V tanh(k t + c0)``, ``w = w0 cosh(c0) / cosh(k t + c0)``, ``V =
sqrt(2E/m)``, ``k = m a V / J`` -- and the reaction of the knife edge, given as an output,
``lambda = m I v w / J``.  The initial state is given in speeds (v, w).
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model
from .chaplygin_sleigh import closed_form

NAME = "chaplygin-sleigh-speeds"
ORDER = 10.5
TITLE = "Chaplygin sleigh in speeds v, w: Kane's equations, v = V tanh(kt + c0) (Yushkov 1999, app. A)"
FILE = "chaplygin_sleigh_speeds.toml"


def build(m: float = 2.0, I: float = 0.3, a: float = 0.4, v0: float = 1.0, w0: float = 1.5,
          t_end: float = 5.0) -> Model:
    """The model with the Python API (the model file for the default values)."""
    return Model(
        name="Chaplygin sleigh in speeds, free motion",
        coordinates=["x", "y", "theta"],
        parameters={"m": m, "I": I, "a": a},
        speeds={"v": "x'*cos(theta) + y'*sin(theta)", "w": "theta'",
                "s": "-x'*sin(theta) + y'*cos(theta)"},
        kinetic="m/2*(v^2 + (s + a*w)^2) + I/2*w^2",
        constraints=[Constraint.nonholonomic("knife", "s")],
        outputs={"E": "T", "reaction": "lambda_knife", "predicted_reaction": "m*I*v*w/(I + m*a^2)"},
        initial={"x": 0.0, "y": 0.0, "theta": 0.0, "v": v0, "w": w0},
        simulation={"t_end": t_end},
    )


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..equations.formalisms import derive
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    m, I, a = p["m"], p["I"], p["a"]
    times = np.linspace(0.0, model.simulation.t_end, 11)
    v_cf, w_cf, th_cf = closed_form(times, m, I, a, 1.0, 1.5)
    errors = {}
    for form in ("lagrange1", "kane", "boltzmann_hamel", "poincare_chetaev", "chaplygin"):
        traj = simulate(model, times=times, form=form)
        errors[form] = max(float(np.max(np.abs(traj.speeds["v"] - v_cf))),
                           float(np.max(np.abs(traj.speeds["w"] - w_cf))),
                           float(np.max(np.abs(traj.coordinate("theta") - th_cf))),
                           float(np.max(np.abs(traj.outputs["reaction"] - traj.outputs["predicted_reaction"]))))
    kane = derive(model, "kane")
    result = {
        "ok": max(errors.values()) < 1e-8, "max_error": errors,
        "kane_equations": kane.readable(),
    }
    if verbose:
        print(TITLE)
        print(kane.as_text())
        for form, err in errors.items():
            print(f"  {form:>16}: max |v, w, theta, lambda - closed form| = {err:.2e}")
        print("ok" if result["ok"] else "FAILED")
    return result
