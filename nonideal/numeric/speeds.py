"""Compiled generalized speeds and outputs of a model.

:func:`speed_kernel_of` compiles, once per model, the speeds ``u = W(q, t) q' + w0(q, t)``
(values, the matrix ``W`` and ``w0``) and their time derivatives ``u' = W q'' + W' q' + w0'``;
:func:`velocities_from_speeds` turns speeds given at a state into the velocities they determine
(with the velocity-level constraints).  :func:`output_kernel_of` compiles the ``[outputs]``
(with ``T``, ``V`` and the multipliers ``lambda_<constraint>`` as arguments).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import symengine as se

from ..errors import InconsistentInitialConditions
from ..modeling.symbols import to_se

__all__ = ["SpeedKernel", "speed_kernel_of", "velocities_from_speeds", "OutputKernel", "output_kernel_of"]


class SpeedKernel:
    """The model's speeds compiled: :meth:`values`, :meth:`matrix`, :meth:`rates`.

    Every method takes ``t`` and arrays ``q, qd`` (and ``qdd``) of shape (n_q,) and the
    parameter vector in the model's order.
    """

    def __init__(self, model):
        from ..equations.dynamics import dynamics_of

        dyn = dynamics_of(model)
        self.names = tuple(model.speeds)
        exprs = [to_se(e) for e in model.speeds.values()]
        args = dyn.q + dyn.qd + dyn.qdd + [dyn.t] + dyn.params
        self.n = dyn.n
        W = [se.diff(e, v) for e in exprs for v in dyn.qd]
        w0 = [e.subs({v: 0 for v in dyn.qd}) for e in exprs]
        rates = [dyn.dt(e) for e in exprs]
        self._values = se.Lambdify(args, exprs or [se.Integer(0)], cse=True)
        self._matrix = se.Lambdify(args, (W + w0) or [se.Integer(0)], cse=True)
        self._rates = se.Lambdify(args, rates or [se.Integer(0)], cse=True)

    def _x(self, t, q, qd, qdd, params):
        qdd = np.zeros(self.n) if qdd is None else qdd
        return np.concatenate([q, qd, qdd, [t], params]).astype(float)

    def values(self, t, q, qd, params) -> np.ndarray:
        """``u``, shape (n_u,)."""
        if not self.names:
            return np.zeros(0)
        return np.asarray(self._values(self._x(t, q, qd, None, params)), dtype=float).ravel()

    def matrix(self, t, q, params) -> tuple[np.ndarray, np.ndarray]:
        """``(W, w0)``, shapes (n_u, n_q) and (n_u,)."""
        k = len(self.names)
        out = np.asarray(self._matrix(self._x(t, q, np.zeros(self.n), None, params)), dtype=float).ravel()
        return out[:k * self.n].reshape(k, self.n), out[k * self.n:]

    def rates(self, t, q, qd, qdd, params) -> np.ndarray:
        """``u'``, shape (n_u,)."""
        if not self.names:
            return np.zeros(0)
        return np.asarray(self._rates(self._x(t, q, qd, qdd, params)), dtype=float).ravel()


def speed_kernel_of(model) -> SpeedKernel:
    return model.cached("speed_kernel", lambda: SpeedKernel(model))


def velocities_from_speeds(model, speeds: Mapping[str, float], params, t, q, qd, unknown: list[int],
                           constraint_rows=None, source=None) -> tuple[np.ndarray, list[int]]:
    """The velocities that the given *speeds* determine, with the velocity-level constraint
    rows ``(G, residual)`` given by *constraint_rows* (a callable of ``qd``) held.

    Returns the velocities and the indices of the unknown velocities still undetermined.
    Raises :class:`InconsistentInitialConditions` when the speeds contradict the velocities
    given with them (or each other through the constraints), naming the speeds and residuals.
    """
    sk = speed_kernel_of(model)
    idx = [sk.names.index(k) for k in speeds]
    target = np.array([speeds[k] for k in speeds], dtype=float)
    W, w0 = sk.matrix(t, q, params)
    W, w0 = W[idx], w0[idx]
    qd = np.array(qd, dtype=float)
    for _ in range(20):
        res = W @ qd + w0 - target
        J = W[:, unknown]
        if constraint_rows is not None:
            G, vres = constraint_rows(qd)
            res = np.concatenate([res, vres])
            J = np.vstack([J, G[:, unknown]])
        if not unknown or np.max(np.abs(res), initial=0.0) < 1e-14 * (1 + np.abs(qd).max(initial=0.0)):
            break
        step, *_ = np.linalg.lstsq(J, -res, rcond=None)
        qd[unknown] += step
    res = W @ qd + w0 - target
    scale = 1.0 + float(np.max(np.abs(np.concatenate([qd, target]))))
    bad = [(k, r) for k, r in zip(speeds, res) if abs(r) > 1e-9 * scale]
    if bad:
        given = ", ".join(f"{model.coordinates[j]}' = {qd[j]:.6g}" for j in range(len(qd)) if j not in unknown)
        raise InconsistentInitialConditions(
            [f"[initial]: speed '{k}' = {speeds[k]:.6g} contradicts the velocities "
             f"{'given with it (' + given + ')' if given else 'the other speeds and the constraints determine'}: "
             f"residual {r:.3e}; give each velocity either directly or through the speeds, consistently"
             for k, r in bad], source)
    still = list(unknown)
    if unknown:
        J = W[:, unknown]
        if constraint_rows is not None:
            J = np.vstack([J, constraint_rows(qd)[0][:, unknown]])
        null = np.linalg.svd(J)[2][np.linalg.matrix_rank(J):] if J.size else np.eye(len(unknown))
        still = [j for c, j in enumerate(unknown) if null.size and np.abs(null[:, c]).max() > 1e-9]
    return qd, still


class OutputKernel:
    """The ``[outputs]`` compiled: :meth:`__call__` at one state with ``T``, ``V`` and the
    multipliers given."""

    def __init__(self, model):
        from ..equations.dynamics import dynamics_of

        dyn = dynamics_of(model)
        self.names = tuple(model.outputs)
        self.multipliers = tuple(f"lambda_{c.name}" for c in model.constraints)
        T, V = se.Symbol("T"), se.Symbol("V")
        lam = [se.Symbol(m) for m in self.multipliers]
        exprs = [to_se(e) for e in model.outputs.values()]
        exprs = [e.subs({T: dyn.T, V: dyn.V}) for e in exprs]
        self.n = dyn.n
        self._fn = se.Lambdify(dyn.q + dyn.qd + [dyn.t] + dyn.params + lam, exprs or [se.Integer(0)], cse=True)

    def __call__(self, t, q, qd, params, multipliers: Mapping[str, float]) -> np.ndarray:
        if not self.names:
            return np.zeros(0)
        lam = [float(multipliers.get(m[len("lambda_"):], 0.0)) for m in self.multipliers]
        x = np.concatenate([q, qd, [t], params, lam]).astype(float)
        return np.asarray(self._fn(x), dtype=float).ravel()


def output_kernel_of(model) -> OutputKernel:
    return model.cached("output_kernel", lambda: OutputKernel(model))
