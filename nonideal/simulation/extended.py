"""The motion of a model with constraints of order three and more, read back from its extended
model (:mod:`nonideal.equations.high_order`): the auxiliary coordinates (the impulses of the
forces that realize the constraints and of the forces' derivatives) are dropped, their
velocities become the forces and their derivatives, and the energy terms are those of the model
itself."""

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
    force is ``B lambda``) and ``Lambda`` for an ideal one of order n (``D^(n-2) R = Lambda
    (d f/d q^(n))^T``); ``controls[name]`` holds the force (``force``: lambda, or ``|R|`` with
    the components ``u_1 .. u_n`` of R when ideal), its derivatives up to order ``n - 3``
    (``force'``, ``force''``, ...; ideal: ``u_1'``, ..., the components of the covariant
    derivatives ``D^k R`` in the metric of the mass matrix, the plain ones where M is constant), its power ``R . q'``, its work and
    ``order`` n.  The work is integrated with the motion where the model has no other active
    forces than the potential's (else Simpson's rule over the samples).  The energy is the model's: the auxiliary kinetic energy ``sum |z_k'|^2/2``
    and the equal works on the ``z_k`` (the chain's, in ``active_work``, and the constraint's,
    in ``reaction_work``) are removed, and the work of the realizing forces is moved from
    ``active_work`` to ``reaction_work`` (the balance is unchanged by it)."""
    model = ext.original
    n = model.n_q
    coords = list(traj.coordinates)
    mult = {k: v for k, v in traj.multipliers.items()}
    own = {s.name for s in ext.constraints}
    ext_controls = traj.controls
    controls = {k: v for k, v in ext_controls.items() if k not in own}
    energy = dict(traj.energy)
    N = len(traj.t)
    aux_energy = np.zeros(N)
    control_work = np.zeros(N)      # of the realizing forces on q
    mu_work = np.zeros(N)           # of the extended constraints' forces on the last level
    for spec in ext.constraints:
        levels = [traj.qd[:, [coords.index(a) for a in level]] for level in spec.aux]
        for W in levels:
            aux_energy += 0.5 * np.einsum("ki,ki->k", W, W)
        W = levels[0]
        if spec.ideal:
            R = W
            entry = {"force": np.sqrt(np.einsum("ki,ki->k", R, R))}
            entry.update({f"u_{k + 1}": R[:, k].copy() for k in range(n)})
            for d, Wd in enumerate(levels[1:], start=1):
                entry.update({f"u_{k + 1}" + "'" * d: Wd[:, k].copy() for k in range(n)})
        else:
            R = _direction(ext, spec, traj, n, parameters) * W[:, :1]
            entry = {"force": W[:, 0].copy()}
            entry.update({"force" + "'" * d: Wd[:, 0].copy() for d, Wd in enumerate(levels[1:], start=1)})
            mult[spec.name] = W[:, 0].copy()          # lambda; the extended row's is lambda^(n-2)
        power = np.einsum("ki,ki->k", R, traj.qd[:, :n])
        work = _integral(power, traj.t)
        control_work += work
        if len(levels) == 1:   # order 3: no chain, the aux energy's change is mu's work
            mu_work += sum(0.5 * np.einsum("ki,ki->k", W, W) for W in levels)
            mu_work -= mu_work[0] if N else 0.0
        else:                  # the extended program's control work (integrated with the motion)
            mu_work += ext_controls[spec.name]["work"]
        entry.update(power=power, work=work, order=spec.order)
        controls[spec.name] = entry
    if N:
        chain_work = (aux_energy - aux_energy[0]) - mu_work   # the aux energy's change is both works'
        if not any(f != 0 for f in model.forces):
            # no other active forces: the realizing forces' work is the extended model's active
            # work less the chain's, integrated with the motion (exact, not a quadrature)
            exact = energy["active_work"] - chain_work
            if len(ext.constraints) == 1:
                controls[ext.constraints[0].name]["work"] = exact.copy()
            control_work = exact
        energy["kinetic"] = energy["kinetic"] - aux_energy
        energy["energy"] = energy["energy"] - aux_energy
        # the realizing forces and the chain act as active forces of the extended model: the
        # forces' work moves from active_work to reaction_work and the chain's leaves it; the
        # work of mu on the last level leaves reaction_work
        energy["active_work"] = energy["active_work"] - control_work - chain_work
        energy["reaction_work"] = energy["reaction_work"] + control_work - mu_work
    diagnostics = dict(traj.diagnostics)
    diagnostics["third_order"] = {s.name: (f"ideal: R{_primes(s.order - 2)} = Lambda (d f/d q{_primes(s.order)})^T"
                                           if s.ideal else "along reaction: R = B lambda")
                                  for s in ext.constraints}
    q, qd = traj.q[:, :n].copy(), traj.qd[:, :n].copy()
    speeds, outputs = _speeds_and_outputs(model, parameters, traj.t, q, qd, mult)
    return replace(traj, coordinates=tuple(model.coordinates), q=q, qd=qd, qdd=traj.qdd[:, :n].copy(),
                   multipliers=mult, energy=energy, controls=controls, diagnostics=diagnostics,
                   speeds=speeds, outputs=outputs)


def _speeds_and_outputs(model, parameters, t, q, qd, mult):
    """The model's own speeds and outputs at the samples: its ``T`` (without the auxiliary
    energy) and its multipliers (lambda, not the extended program's lambda^(n-2))."""
    speeds, outputs = {}, {}
    if not (model.speeds or model.outputs):
        return speeds, outputs
    from ..numeric.speeds import output_kernel_of, speed_kernel_of

    pv = parameter_vector(model, parameters)
    N = len(t)
    if model.speeds:
        sk = speed_kernel_of(model)
        values = np.array([sk.values(t[k], q[k], qd[k], pv) for k in range(N)]).reshape(N, len(sk.names))
        speeds = {name: values[:, j].copy() for j, name in enumerate(sk.names)}
    if model.outputs:
        ok = output_kernel_of(model)
        values = np.array([ok(t[k], q[k], qd[k], pv, {m: v[k] for m, v in mult.items()})
                           for k in range(N)]).reshape(N, len(ok.names))
        outputs = {name: values[:, j].copy() for j, name in enumerate(ok.names)}
    return speeds, outputs


def _primes(k: int) -> str:
    return "'" * k if k <= 3 else f"^({k})"
