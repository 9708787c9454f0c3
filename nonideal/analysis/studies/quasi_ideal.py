"""Quasi-ideal constraints as a design tool (Briskin et al. 2021).

A quasi-ideal constraint ``f(q, t) = 0`` has reactions ``R`` with ``A R = lambda grad f``
(Briskin et al. 2021, (2.1)): ``R = A^-1 grad f lambda``, formed as ``R = adj(A) grad f mu``
with ``lambda = det(A) mu`` so that it stays finite where ``det A = 0``.  The motion stays on
the constraint for any ``A`` with ``G M^-1 adj(A) G^T != 0``, while the direction of ``R`` -- the
control -- depends on ``A``.  Splitting ``R`` as Painleve's split does (the part ``G^T lambda*``
that does no work on the possible displacements, the *ideal part*, and the rest ``M V mu``,
which does: the *control part*) shows what the transform adds to the ideal reaction.

This module measures a design:

* :func:`actuator_heat` -- the heat lost in the drives that produce the reactions,
  ``W = int sum_j mu_j R_j^2 dt`` (Briskin et al. 2021, (3.7)), with the loss coefficients
  ``mu_j`` of each constraint (model file: ``losses = [...]``, one per coordinate);
* :func:`design_measures` -- the work of the reactions ``A`` (the simulation's
  ``reaction_work``), the heat ``W`` and the criterion ``I = |A| + chi W`` (3.10) of one
  motion;
* :func:`nonideal.analysis.studies.design.minimize_criterion` -- the minimum of ``I`` over some
  parameters (the transform's ``alpha, beta``), on top of the sweep.
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ...errors import ModelError

__all__ = ["actuator_heat", "design_measures", "criterion", "HEAT_SAMPLES"]

#: samples of the dense run on which the heat is integrated (Simpson's rule)
HEAT_SAMPLES = 201


def _loss_functions(model):
    """``{constraint: f(params) -> ndarray (n_q,)}`` for the constraints with ``losses``."""
    import sympy as sp

    symbols = [sp.Symbol(n) for n in model.parameters]
    out = {}
    for c in model.constraints:
        losses = getattr(c, "losses", None)
        if losses is not None:
            out[c.name] = sp.lambdify(symbols, list(losses), "numpy")
    return out


def actuator_heat(model, traj, parameters: Mapping[str, float] | None = None) -> dict[str, Any]:
    """The heat lost in the drives along a trajectory (Briskin et al. 2021, (3.7)).

    ``W_c(t) = int_0^t sum_j mu_j R_{c,j}^2 dt`` for every constraint ``c`` with loss
    coefficients, ``R_c = B_c lambda_c`` its generalized reaction.  The integral is taken over
    the trajectory's samples (Simpson's rule between events): sample it densely (``times=``)
    for an accurate number -- :func:`design_measures` does.

    Parameters
    ----------
    model : Model
    traj : Trajectory
        A simulation of *model*.
    parameters : mapping, optional
        The parameter values the simulation used (default: the model's).

    Returns
    -------
    dict
        ``"rate"``: ``{c: ndarray (N,)}``, ``"heat"``: ``{c: ndarray (N,)}`` (cumulative),
        ``"total"``: ``ndarray (N,)``.
    """
    from scipy.integrate import cumulative_simpson

    from ...numeric.kernel import kernel_of, parameter_vector

    losses = _loss_functions(model)
    if not losses:
        raise ModelError("actuator heat: no constraint has loss coefficients; give "
                         "losses = [\"mu_x\", \"mu_y\", ...] (one per coordinate) in its "
                         "[[constraints]] table", None if model.source == "<api>" else model.source)
    kernel = kernel_of(model)
    params = parameter_vector(model, parameters)
    values = dict(model.parameter_values)
    values.update(parameters or {})
    t = np.asarray(traj.t, dtype=float)
    rate = {c: np.zeros(len(t)) for c in losses}
    for k in range(len(t)):
        B = kernel.dense(kernel.dynamics(kernel.state_input(t[k], traj.q[k], traj.qd[k], params)), "B")
        for c, fn in losses.items():
            mu = np.asarray(fn(*values.values()), dtype=float)
            R = np.asarray(B)[:, kernel.row_index[c]] * float(traj.multipliers[c][k])
            rate[c][k] = float(mu @ (R * R))
    heat = {}
    for c, r in rate.items():
        heat[c] = np.zeros(len(t))
        if len(t) > 1:
            # Simpson between events (the rate jumps there), the trapezoid on a two-sample piece
            breaks = [0] + [k for k in range(1, len(t)) if t[k] == t[k - 1]] + [len(t)]
            offset = 0.0
            for a, b in zip(breaks, breaks[1:]):
                seg_t, seg_r = t[a:b], r[a:b]
                if len(seg_t) >= 3:
                    part = cumulative_simpson(seg_r, x=seg_t, initial=0.0)
                elif len(seg_t) == 2:
                    part = np.array([0.0, 0.5 * (seg_r[0] + seg_r[1]) * (seg_t[1] - seg_t[0])])
                else:
                    part = np.zeros(len(seg_t))
                heat[c][a:b] = offset + part
                offset = heat[c][b - 1]
    total = sum(heat.values()) if heat else np.zeros(len(t))
    return {"rate": rate, "heat": heat, "total": total}


def criterion(work: float, heat: float, chi: float = 1.0) -> float:
    """Briskin et al. 2021, (3.10): ``I = |A| + chi W``."""
    return abs(float(work)) + float(chi) * float(heat)


def design_measures(model, t_end: float | None = None, parameters: Mapping[str, float] | None = None,
                    initial: Mapping[str, float] | None = None, chi: float = 1.0,
                    samples: int = HEAT_SAMPLES) -> dict[str, float]:
    """Work of the reactions, actuator heat and the criterion of one motion.

    Simulates *model* on ``samples`` uniform times up to ``t_end`` (dense output) and returns
    ``{"work": A, "heat": W, "criterion": |A| + chi W, "t_end": ...}`` (Briskin et al. 2021,
    (3.7), (3.8), (3.10); ``A`` is the simulation's ``reaction_work``, checked there by the
    energy balance).
    """
    from ...simulation.hybrid import simulate

    t_end = float(t_end if t_end is not None else model.simulation.t_end)
    times = np.linspace(model.t0, t_end, samples)
    traj = simulate(model, times=times, parameters=parameters, initial=initial)
    heat = float(actuator_heat(model, traj, parameters)["total"][-1])
    work = float(traj.energy["reaction_work"][-1])
    return {"work": work, "heat": heat, "criterion": criterion(work, heat, chi), "t_end": t_end}
