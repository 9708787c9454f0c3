"""The motion of a model with third-order constraints, read back from its extended model
(:mod:`nonideal.equations.high_order`): the auxiliary coordinates (the impulses of the forces
that realize the constraints) are dropped, their velocities become the forces, and the energy
terms are those of the model itself."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import symengine as se
from scipy.integrate import cumulative_simpson

from ..modeling.symbols import to_se
from ..numeric.kernel import parameter_vector
from .trajectory import Trajectory

__all__ = ["reduce"]


def _integral(power: np.ndarray, t: np.ndarray) -> np.ndarray:
    if len(t) >= 3 and np.all(np.diff(t) > 0):
        return cumulative_simpson(power, x=t, initial=0.0)
    return np.concatenate(([0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))) \
        if len(t) else np.zeros(0)


def _direction(ext, spec, traj: Trajectory, n: int, parameters=None) -> np.ndarray:
    """``B`` of a constraint realized along a given direction at the samples, shape (N, n)."""
    model = ext.original
    args = [se.Symbol("t")] + [to_se(s) for s in model.q] + [to_se(s) for s in model.qd] \
        + [se.Symbol(p) for p in model.parameters]
    fn = se.Lambdify(args, [to_se(b) for b in spec.B])
    pv = parameter_vector(model, parameters)
    return np.array([np.asarray(fn([t, *q, *qd, *pv]), dtype=float).ravel()
                     for t, q, qd in zip(traj.t, traj.q[:, :n], traj.qd[:, :n])]).reshape(len(traj.t), n)


def reduce(ext, traj: Trajectory, parameters=None) -> Trajectory:
    """The trajectory of ``ext.original`` from *traj*, the extended model's (simulated with the
    parameter values *parameters* overriding the model's, if given).

    ``multipliers[name]`` is ``lambda`` for a constraint realized along ``reaction`` (its
    force is ``B lambda``) and ``Lambda`` for an ideal one (``R' = Lambda (d f/d q''')^T``);
    ``controls[name]`` holds the force (``force``: lambda, or ``|R|`` with the components
    ``u_1 .. u_n`` of R when ideal), its power ``R . q'``, its work and ``order`` 3.  The energy
    is the model's: the auxiliary kinetic energy ``|z'|^2/2`` and the equal work on ``z`` are
    removed, and the work of the realizing forces is counted in ``reaction_work``."""
    model = ext.original
    n = model.n_q
    coords = list(traj.coordinates)
    mult = {k: v for k, v in traj.multipliers.items()}
    controls = {k: v for k, v in traj.controls.items() if k not in {s.name for s in ext.constraints}}
    energy = dict(traj.energy)
    aux_energy = np.zeros(len(traj.t))
    control_work = np.zeros(len(traj.t))
    for spec in ext.constraints:
        cols = [coords.index(a) for a in spec.aux]
        W = traj.qd[:, cols]
        aux_energy += 0.5 * np.einsum("ki,ki->k", W, W)
        if spec.ideal:
            R = W
            entry = {"force": np.sqrt(np.einsum("ki,ki->k", R, R))}
            entry.update({f"u_{k + 1}": R[:, k].copy() for k in range(n)})
        else:
            R = _direction(ext, spec, traj, n, parameters) * W[:, :1]
            entry = {"force": W[:, 0].copy()}
            mult[spec.name] = W[:, 0].copy()          # lambda; the extended row's is lambda'
        power = np.einsum("ki,ki->k", R, traj.qd[:, :n])
        work = _integral(power, traj.t)
        control_work += work
        entry.update(power=power, work=work, order=3)
        controls[spec.name] = entry
    if len(traj.t):
        energy["kinetic"] = energy["kinetic"] - aux_energy
        energy["energy"] = energy["energy"] - aux_energy
        # the realizing forces act as active forces of the extended model: their work moves
        # from active_work to reaction_work (the balance is unchanged), and the work of mu on z
        # (= the change of the auxiliary energy) leaves reaction_work
        energy["active_work"] = energy["active_work"] - control_work
        energy["reaction_work"] = energy["reaction_work"] + control_work - (aux_energy - aux_energy[0])
    diagnostics = dict(traj.diagnostics)
    diagnostics["third_order"] = {s.name: ("ideal: R' = Lambda (d f/d q''')^T" if s.ideal
                                           else "along reaction: R = B lambda") for s in ext.constraints}
    return replace(traj, coordinates=tuple(model.coordinates), q=traj.q[:, :n].copy(),
                   qd=traj.qd[:, :n].copy(), qdd=traj.qdd[:, :n].copy(), multipliers=mult,
                   energy=energy, controls=controls, diagnostics=diagnostics)
