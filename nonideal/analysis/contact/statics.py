"""Equilibrium under servo-constraints (Béghin 1922; Appell 1911, servo-constraints).

D'Alembert's principle gives the conditions of equilibrium when the inertia terms are dropped:
Béghin's equations (10) with ``P = 0``,

    Q(q, t) + sum_k B_k lambda_k = 0,

where the columns ``B_k`` are the ideal reactions of the constraints and the control directions
of the servo-constraints, together with those of the servo relations that are finite (a
program on the positions must hold at the configuration; a program on the velocities must
admit rest).  At a configuration this is a linear system for the multipliers and controls:
solved in the least-squares sense, the configuration is an equilibrium when the residual
vanishes, and the controls that hold it are reported.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...modeling.model import Model
from ...numeric.kernel import kernel_of, parameter_vector

__all__ = ["ServoEquilibrium", "servo_equilibrium"]

TOL = 1e-9


@dataclass
class ServoEquilibrium:
    """Whether a configuration, at rest, is an equilibrium under the servo-constraints.

    Attributes
    ----------
    equilibrium : bool
    residual : float
        ``|Q + B x|`` at the least-squares x, relative to ``|Q|`` (plus the violation of the
        programs at rest, relative to the coordinates).
    controls, multipliers : dict name -> float
        The controls (servo-constraints) and the ideal multipliers that hold it.
    reasons : list of str
        What prevents the equilibrium, when it is not one.
    """

    equilibrium: bool
    residual: float
    controls: dict[str, float] = field(default_factory=dict)
    multipliers: dict[str, float] = field(default_factory=dict)
    reasons: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"equilibrium": self.equilibrium, "residual": self.residual,
                "controls": self.controls, "multipliers": self.multipliers, "reasons": self.reasons}

    def note(self) -> str:
        if self.equilibrium:
            held = ", ".join(f"{k} = {v:.10g}" for k, v in self.controls.items())
            return ("at rest the initial configuration is an equilibrium under the servo-constraints "
                    f"(Béghin's equations with the inertia terms dropped), held by the controls {held}")
        return ("at rest the initial configuration is not an equilibrium under the servo-constraints: "
                + "; ".join(self.reasons))


def servo_equilibrium(model: Model, q=None, t: float | None = None) -> ServoEquilibrium:
    """Béghin's conditions of equilibrium at the configuration *q* (default: the initial one,
    completed from the constraints), at rest.

    Examples
    --------
    A pendulum held at ``theta0`` by a torque: the torque is ``m g l sin(theta0)``.
    """
    from ...numeric.consistency import complete_state

    kernel = kernel_of(model)
    params = parameter_vector(model)
    t = model.t0 if t is None else t
    if q is None:
        q, _, _ = complete_state(kernel, model.numeric_initial(), params, t)
    q = np.asarray(q, dtype=float)
    qd = np.zeros_like(q)
    x = kernel.state_input(t, q, qd, params)
    out = kernel.dynamics(x)
    obs = kernel.observables(x)
    rows = [i for i, r in enumerate(kernel.rows) if not r.unilateral]
    F = np.asarray(out["F"], dtype=float)
    B = kernel.dense(out, "B")[:, rows] if rows else np.zeros((len(q), 0))
    reasons = []
    scale_q = 1.0 + float(np.max(np.abs(q)))
    for i in rows:
        r = kernel.rows[i]
        if r.position is not None and abs(obs["pos"][i]) > TOL * scale_q:
            reasons.append(f"constraint '{r.name}' does not hold at this configuration "
                           f"(residual {obs['pos'][i]:.3g})")
        elif r.velocity is not None and abs(obs["vel"][i]) > TOL * scale_q:
            reasons.append(f"constraint '{r.name}' does not admit rest (its value at zero "
                           f"velocities is {obs['vel'][i]:.6g})")
    if kernel.conditions is not None:           # programs kept through the dynamics
        compiled, names, _ = kernel.conditions
        cout = compiled(x)
        for k, name in enumerate(names):
            value = float(np.atleast_1d(cout["pos"])[k]) or float(np.atleast_1d(cout["vel"])[k])
            if abs(value) > TOL * scale_q:
                reasons.append(f"the program '{name}' does not admit rest (residual {value:.6g})")
    sol = np.linalg.lstsq(B, -F, rcond=None)[0] if rows else np.zeros(0)
    residual = float(np.linalg.norm(F + B @ sol) / max(np.linalg.norm(F), 1e-300)) if rows or np.any(F) else 0.0
    if residual > TOL:
        reasons.append(f"the reactions and controls cannot balance the forces (residual "
                       f"{residual:.3g} of |Q|): no choice of the controls holds the system at rest")
    controls, multipliers = {}, {}
    shared, _, C = kernel.dyn.shared_rows
    for k, i in enumerate(rows):
        r = kernel.rows[i]
        # a program realized by the shared controls: its multiplier is no control force
        into = controls if r.reaction_kind == "servo" and r.name not in shared else multipliers
        into[r.name] = float(sol[k])
    if shared:      # the shared controls u = C mu (Béghin 1922), under their own names
        from ...numeric.kernel import Compiled

        coef = Compiled(kernel.symbols, {"c": [c for row in C for c in row]})
        Cn = np.asarray(coef.batch(x[None, :]), dtype=float).reshape(len(model.controls), len(shared))
        mu = np.array([multipliers[name] for name in shared])
        for a, ctl in enumerate(model.controls):
            controls[ctl.name] = float(Cn[a] @ mu)
    return ServoEquilibrium(not reasons, residual, controls, multipliers, reasons)
