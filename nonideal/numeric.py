"""Compiled numerics: symbolic matrices -> fast callables, and the linear solves.

The symbolic equations are compiled once with SymEngine's ``Lambdify`` (common-subexpression
elimination, LLVM backend when available) into one callable per purpose, taking the flat
input ``[t, q, q', parameters, (auxiliaries)]``.  The linear system of the motion,

    [[A, -B], [G, 0]] [a; mu] = [b; -gamma],

is solved numerically at each evaluation with LAPACK (Cholesky when there are no multipliers,
LU otherwise); nothing is inverted symbolically, so operating points where a symbolic LU
would have a removable singularity are harmless.

* :class:`Compiled` -- one Lambdify over named outputs (scalars, vectors, matrices).
* :class:`Kernel` -- the model-level functions (``M, F`` and every constraint row; energies,
  residuals) shared by the simulation, the reactions and the checks.
* :class:`FormSystem` -- the compiled equations of one :class:`~nonideal.eom.EquationsOfMotion`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se
from scipy.linalg import lapack

from .dynamics import ConstraintRow, Dynamics, dynamics_of
from .eom import EquationsOfMotion
from .errors import ModelError, SingularSystem, did_you_mean
from .model import Model

__all__ = ["Compiled", "Kernel", "FormSystem", "solve_saddle", "SingularMatrix", "kernel_of"]


class SingularMatrix(Exception):
    """Raised by :func:`solve_saddle`; callers turn it into a named, actionable error."""


def _flatten(value):
    if isinstance(value, se.DenseMatrix):
        return list(value), value.shape
    if isinstance(value, (list, tuple)):
        if value and isinstance(value[0], (list, tuple)):
            rows, cols = len(value), len(value[0])
            return [x for row in value for x in row], (rows, cols)
        return list(value), (len(value),)
    return [value], ()


class Compiled:
    """A single Lambdify over named outputs.

    Parameters
    ----------
    inputs : list of se.Symbol
    outputs : mapping name -> expression, list, nested list or se.DenseMatrix

    Calling it with a flat float array returns a dict of NumPy views: scalars as 0-d values,
    vectors with shape (n,), matrices with shape (rows, cols).
    """

    def __init__(self, inputs: Sequence, outputs: Mapping[str, object]):
        self.inputs = list(inputs)
        self.slices: dict[str, tuple[slice, tuple]] = {}
        flat: list = []
        for name, value in outputs.items():
            items, shape = _flatten(value)
            self.slices[name] = (slice(len(flat), len(flat) + len(items)), shape)
            flat.extend(items)
        self.size = len(flat)
        if flat:
            self.fn = se.Lambdify(self.inputs, [se.sympify(x) for x in flat], cse=True)
        else:
            self.fn = None
        self.out = np.zeros(self.size)
        self._views = {name: self.out[sl].reshape(shape) if shape else None
                       for name, (sl, shape) in self.slices.items()}

    def raw(self, x: np.ndarray) -> np.ndarray:
        """The flat output array (reused buffer: copy it to keep it)."""
        if self.fn is not None:
            self.fn.unsafe_real(x, self.out)
        return self.out

    def __call__(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Evaluate; returns views into a reused buffer (valid until the next call)."""
        flat = self.raw(x)
        out = dict(self._views)
        for name, (sl, shape) in self.slices.items():
            if not shape:
                out[name] = float(flat[sl.start])
        return out

    def view(self, flat: np.ndarray, name: str) -> np.ndarray:
        sl, shape = self.slices[name]
        v = flat[sl]
        return v.reshape(shape) if shape else v[0]


def solve_saddle(A: np.ndarray, b: np.ndarray, B: np.ndarray | None = None,
                 G: np.ndarray | None = None, gamma: np.ndarray | None = None):
    """Solve ``A a - B mu = b``, ``G a = -gamma`` for ``(a, mu)``.

    Raises
    ------
    SingularMatrix
        When the system has no unique solution.
    """
    k = A.shape[0]
    if G is None or G.shape[0] == 0:
        _, x, info = lapack.dposv(A, b)
        if info == 0:
            return x, np.zeros(0)
        _, _, x, info = lapack.dgesv(A, b)
        if info != 0:
            raise SingularMatrix("mass matrix")
        return x, np.zeros(0)
    m = G.shape[0]
    K = np.zeros((k + m, k + m))
    K[:k, :k] = A
    K[:k, k:] = -B
    K[k:, :k] = G
    rhs = np.concatenate((b, -gamma))
    _, _, x, info = lapack.dgesv(K, rhs)
    if info != 0 or not np.all(np.isfinite(x)):
        raise SingularMatrix("saddle-point system")
    # a badly conditioned system is as bad as a singular one for the user
    return x[:k], x[k:]


@dataclass
class Inputs:
    """Layout of the flat input vector ``[t, q, q', parameters]``."""

    n: int
    n_p: int

    def make(self, params: np.ndarray, extra: int = 0) -> np.ndarray:
        x = np.zeros(1 + 2 * self.n + self.n_p + extra)
        x[1 + 2 * self.n:1 + 2 * self.n + self.n_p] = params
        return x


def parameter_vector(model: Model, overrides: Mapping[str, float] | None = None) -> np.ndarray:
    values = dict(model.parameter_values)
    for k, v in (overrides or {}).items():
        if k not in values:
            raise ModelError(f"parameter override '{k}': no such parameter{did_you_mean(k, values)}")
        values[k] = float(v)
    return np.array(list(values.values()), dtype=float)


class Kernel:
    """Model-level compiled functions: ``M``, ``F`` and every constraint row; observables.

    Parameters
    ----------
    model : Model

    Notes
    -----
    ``dynamics(x)`` returns ``M (n, n)``, ``F (n,)``, ``G (m, n)``, ``gamma (m,)``, ``B (n, m)``
    for all ``m`` constraint rows of the model; the simulation selects the rows of the current
    mode by index.  ``observables(x)`` returns ``T, T0, V``, the power of the non-potential
    forces ``P_nc``, the explicit-time power ``P_t = dV/dt - dT/dt`` and the position/velocity
    residuals of every row.
    """

    def __init__(self, model: Model):
        self.model = model
        dyn = dynamics_of(model)
        self.dyn = dyn
        self.n = dyn.n
        self.rows: list[ConstraintRow] = dyn.rows()
        self.row_index = {r.name: i for i, r in enumerate(self.rows)}
        self.symbols = [dyn.t] + dyn.q + dyn.qd + dyn.params
        self.layout = Inputs(dyn.n, len(dyn.params))
        n, m = dyn.n, len(self.rows)
        M = dyn.M
        Mu = [M[i, j] for i in range(n) for j in range(n)]
        F = list(dyn.F)
        G = [[r.G[j] for j in range(n)] for r in self.rows]
        gamma = [r.gamma for r in self.rows]
        B = [[r.B[j] for r in self.rows] for j in range(n)] if m else []
        outputs = {"M": [Mu[i * n:(i + 1) * n] for i in range(n)], "F": F}
        if m:
            outputs.update(G=G, gamma=gamma, B=B)
        self.has_nc_forces = any(se.sympify(q) != 0 for q in dyn.Q_nc)
        P_t = se.diff(dyn.V, dyn.t) - se.diff(dyn.T, dyn.t)
        self.explicit_time = P_t != 0
        if self.has_nc_forces or self.explicit_time:
            P_nc = sum((a * b for a, b in zip(dyn.Q_nc, dyn.qd)), se.Integer(0))
            outputs["P"] = [P_nc, P_t]
        self.dynamics = Compiled(self.symbols, outputs)
        self.m = m
        self._obs = None

    @property
    def observables(self) -> Compiled:
        if self._obs is None:
            dyn = self.dyn
            qd = dyn.qd
            P_nc = sum((a * b for a, b in zip(dyn.Q_nc, qd)), se.Integer(0))
            P_t = se.diff(dyn.V, dyn.t) - se.diff(dyn.T, dyn.t)
            pos = [r.position if r.position is not None else se.Integer(0) for r in self.rows]
            vel = [r.velocity if r.velocity is not None else se.Integer(0) for r in self.rows]
            outputs = {"T": dyn.T, "T0": dyn.T0, "V": dyn.V, "P_nc": P_nc, "P_t": P_t}
            if self.rows:
                outputs.update(pos=pos, vel=vel)
            self._obs = Compiled(self.symbols, outputs)
        return self._obs

    def state_input(self, t: float, q, qd, params: np.ndarray) -> np.ndarray:
        x = self.layout.make(params)
        x[0] = t
        x[1:1 + self.n] = q
        x[1 + self.n:1 + 2 * self.n] = qd
        return x

    def kinematic_level(self, rows: Sequence[int]):
        """Indices of rows with a position residual (holonomic) and with a velocity residual."""
        pos = [i for i in rows if self.rows[i].position is not None]
        vel = [i for i in rows if self.rows[i].velocity is not None]
        return pos, vel


_KERNELS: dict[int, tuple[Model, Kernel]] = {}


def kernel_of(model: Model) -> Kernel:
    """The (cached) compiled kernel of *model*."""
    hit = _KERNELS.get(id(model))
    if hit is not None and hit[0] is model:
        return hit[1]
    k = Kernel(model)
    if len(_KERNELS) > 32:
        _KERNELS.clear()
    _KERNELS[id(model)] = (model, k)
    return k


class FormSystem:
    """The compiled equations of one :class:`EquationsOfMotion`.

    ``solve(x)`` returns ``(a, mu, qdd)``: the form's unknowns, its multipliers, and the
    accelerations of all coordinates.
    """

    def __init__(self, eom: EquationsOfMotion, extra: Sequence = ()):
        self.eom = eom
        dyn: Dynamics = dynamics_of(eom.model)
        # extra inputs (e.g. slip directions of sliding contacts) follow the parameters
        base = [dyn.t] + dyn.q + dyn.qd + dyn.params + [se.Symbol(str(s)) for s in extra]
        self.n_base = len(base)
        self.aux_shapes = []
        aux_syms = []
        stage1 = {}
        for i, aux in enumerate(eom.auxiliaries):
            stage1[f"K{i}"] = aux.K
            stage1[f"Y{i}"] = aux.Y
            self.aux_shapes.append(aux.symbols.shape)
            aux_syms.extend(list(aux.symbols))
        self.stage1 = Compiled(base, stage1) if stage1 else None
        b = eom.Qf_ - eom.c_
        outputs = {"A": eom.A_, "b": list(b), "R": eom.R_, "r": list(eom.r_)}
        self.m = len(eom.multipliers)
        if self.m:
            outputs.update(B=eom.B_, G=eom.G_, gamma=list(eom.gamma_))
        self.k = eom.k
        self.main = Compiled(base + aux_syms, outputs)
        self.x = np.zeros(len(base) + len(aux_syms))

    def solve(self, x_base: np.ndarray):
        x = self.x
        x[:self.n_base] = x_base
        if self.stage1 is not None:
            s1 = self.stage1(x_base)
            off = self.n_base
            for i, shape in enumerate(self.aux_shapes):
                K, Y = s1[f"K{i}"], s1[f"Y{i}"]
                try:
                    X = np.linalg.solve(K, Y)
                except np.linalg.LinAlgError:
                    raise SingularMatrix("dependent-velocity block") from None
                x[off:off + X.size] = X.ravel()
                off += X.size
        out = self.main(x)
        if self.m:
            a, mu = solve_saddle(out["A"], out["b"], out["B"], out["G"], out["gamma"])
        else:
            a, mu = solve_saddle(out["A"], out["b"])
        qdd = out["R"] @ a + out["r"]
        return a, mu, qdd
