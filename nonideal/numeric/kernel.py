"""Compiled numerics: symbolic matrices -> fast callables, and the linear solves.

The symbolic equations are compiled once with SymEngine's ``Lambdify`` (common-subexpression
elimination, LLVM backend when available) into one callable per purpose, taking the flat
input ``[t, q, q', parameters, (auxiliaries)]``.  The linear system of the motion,

    [[A, -B], [G, 0]] [a; mu] = [b; -gamma],

is solved numerically at each evaluation with LAPACK (Cholesky when there are no multipliers,
LU otherwise); nothing is inverted symbolically, so operating points where a symbolic LU
would have a removable singularity are harmless.

* :class:`Compiled` -- one Lambdify over named outputs (scalars, vectors, matrices).  With
  the LLVM backend it compiles first without optimization (4-5x faster to build, ~1.2-2x
  slower to evaluate) and recompiles with full optimization after :data:`TIER_UP_CALLS`
  evaluations, when the faster evaluation has paid for it; both give bit-identical results
  (no fast-math).
* :class:`Kernel` -- the model-level functions (``M, F`` and every constraint row; energies,
  residuals) shared by the simulation, the reactions and the checks.
* :class:`FormSystem` -- the compiled equations of one :class:`~nonideal.equations.eom.EquationsOfMotion`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se
from scipy.linalg import lapack
from scipy.sparse import csr_matrix, issparse

from . import compact
from .compact import SparsePattern

from ..equations.dynamics import ConstraintRow, Dynamics, dynamics_of
from ..equations.eom import EquationsOfMotion
from ..errors import MechanicsError, ModelError, did_you_mean
from ..modeling.model import Model

__all__ = ["Compiled", "Sparse", "Kernel", "FormSystem", "solve_saddle", "SingularMatrix", "kernel_of", "max_abs"]


class SingularMatrix(Exception):
    """Raised by :func:`solve_saddle`; callers turn it into a named, actionable error."""


@dataclass(frozen=True)
class Sparse:
    """A matrix output given by its nonzero entries: ``shape (rows, cols)`` and
    ``entries {(i, j): expression}``; the others are structurally zero.  :class:`Compiled`
    compiles only the entries and writes them into the dense (row-major) layout, so a
    block-diagonal mass matrix of n_q coordinates costs O(n_q) compiled outputs, not n_q^2."""

    shape: tuple[int, int]
    entries: Mapping[tuple[int, int], object]


def _flatten(value):
    if isinstance(value, Sparse):
        cols = value.shape[1]
        items = {i * cols + j: e for (i, j), e in value.entries.items()}
        return items, value.shape
    if isinstance(value, se.DenseMatrix):
        return list(value), value.shape
    if isinstance(value, (list, tuple)):
        if value and isinstance(value[0], (list, tuple)):
            rows, cols = len(value), len(value[0])
            return [x for row in value for x in row], (rows, cols)
        return list(value), (len(value),)
    return [value], ()


TIER_UP_CALLS = 100_000
"""Evaluations after which a :class:`Compiled` is recompiled with full LLVM optimization.

Measured on the benchmark systems (``benchmarks/RESULTS.md``): full optimization costs
30-250 ms more to build for 100-1000 outputs and saves 0.2-2 us per evaluation, so it pays
off after roughly 10^5 evaluations -- far more than a typical simulation needs."""

_LLVM = bool(getattr(se, "have_llvm", False))


CSE_MAX_SYMBOLS = 10_000
"""Above this many occurrences of symbols in the compiled outputs (summed over the outputs'
sets of free symbols) SymEngine's common-subexpression elimination is skipped: its cost grows
faster than linearly with the size (1000 particles on springs: the 3000 forces compile in 15 s
with it, 3.2 s without; their potential 6.7 s and 2.2 s), while the outputs of such large
systems (many bodies, each entry of its own few coordinates) share little.  Smaller kernels --
every model of the gallery, the 20-link pendulum -- keep it."""


def _lambdify(inputs, exprs, optimize: bool):
    """SymEngine Lambdify with CSE (up to :data:`CSE_MAX_SYMBOLS`); LLVM without
    optimization unless *optimize*.

    The inputs are renamed first: SymEngine's common-subexpression elimination names its
    temporaries ``x0, x1, ...`` and avoids only the names that occur in the expressions, so an
    input called ``x1`` that no output uses would be overwritten.  Each expression is renamed
    through a map of its own symbols only (a map of every input costs O(inputs) per
    expression: 6.5 s for the 3000 forces of 1000 particles on springs, O(n^2)).
    """
    safe = [se.Symbol(f"__in{i}__") for i in range(len(inputs))]
    rename = dict(zip(inputs, safe))
    exprs = [se.sympify(e) for e in exprs]
    size, renamed = 0, []
    for e in exprs:
        free = e.free_symbols
        size += len(free)
        renamed.append(e.xreplace({s: rename[s] for s in free if s in rename}) if free else e)
    exprs, inputs = renamed, safe
    cse = size <= CSE_MAX_SYMBOLS
    if len(exprs) * len(inputs) > compact.CHUNK_MIN_WORK:
        return compact.Chunked(inputs, exprs, optimize, _lambdify)
    if _LLVM and not optimize:
        try:
            return se.Lambdify(inputs, exprs, cse=cse, backend="llvm", opt_level=0)
        except (TypeError, ValueError, RuntimeError):  # pragma: no cover - older SymEngine
            pass
    return se.Lambdify(inputs, exprs, cse=cse)


class Compiled:
    """A single Lambdify over named outputs.

    Parameters
    ----------
    inputs : list of se.Symbol
    outputs : mapping name -> expression, list, nested list, se.DenseMatrix or :class:`Sparse`
    optimize : bool, optional
        Compile with full optimization at once (default: only after
        :data:`TIER_UP_CALLS` evaluations, see the module docstring).
    sparse : bool, optional
        Compile only the outputs that are not identically zero (default); the others are
        zeros of the flat layout.  ``False`` compiles every output (the dense path: the same
        numbers, tested).

    Calling it with a flat float array returns a dict of NumPy views: scalars as 0-d values,
    vectors with shape (n,), matrices with shape (rows, cols).

    Attributes
    ----------
    size : int
        Length of the flat output (every entry of every output).
    compiled : int
        How many of them are compiled (the nonzero ones with ``sparse``).
    """

    def __init__(self, inputs: Sequence, outputs: Mapping[str, object], optimize: bool = False,
                 sparse: bool = True):
        self.inputs = list(inputs)
        self.slices: dict[str, tuple[slice, tuple]] = {}
        exprs: list = []
        where: list[int] = []
        size = 0
        for name, value in outputs.items():
            items, shape = _flatten(value)
            length = math.prod(shape) if shape else 1
            self.slices[name] = (slice(size, size + length), shape)
            pairs = sorted(items.items()) if isinstance(items, dict) else enumerate(items)
            for k, e in pairs:
                e = se.sympify(e)
                if sparse and e == 0:
                    continue
                where.append(size + k)
                exprs.append(e)
            size += length
        self.size = size
        self.compiled = len(exprs)
        self._exprs = exprs
        #: positions of the compiled outputs in the flat layout (None: all of them, in order)
        self._where = None if len(exprs) == size else np.array(where, dtype=np.intp)
        self._part = np.zeros(len(exprs)) if self._where is not None else None
        # tiering only matters for the LLVM backend
        self._calls = 0 if (_LLVM and not optimize) else -1
        self.fn = _lambdify(self.inputs, self._exprs, optimize or not _LLVM) if exprs else None
        if self.fn is None:
            self._calls = -1
        self.out = np.zeros(self.size)
        self._clean = self.out  # the last buffer whose uncompiled entries are known to be zero
        self._views = self.views(self.out)
        self._scalars = [(name, sl.start) for name, (sl, shape) in self.slices.items() if not shape]

    def entries(self, name: str) -> np.ndarray:
        """Offsets, within output *name*, of its compiled entries (row-major for a matrix):
        every entry but those that are identically zero (all of them without ``sparse``)."""
        sl, _ = self.slices[name]
        if self._where is None:
            return np.arange(sl.stop - sl.start, dtype=np.intp)
        w = self._where
        return w[(w >= sl.start) & (w < sl.stop)] - sl.start

    def _tier_up(self) -> None:
        self.fn = _lambdify(self.inputs, self._exprs, True)
        self._calls = -1

    def raw(self, x: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """The flat output array: written into *out* (contiguous, shape ``(size,)``) when
        given, else into a reused buffer (copy it to keep it).  With uncompiled (zero)
        entries, a buffer other than the last one given is zeroed first; the caller must not
        write into the zero entries of a buffer it passes again."""
        if out is None:
            out = self.out
        if self._where is not None:
            if out is not self._clean:
                out.fill(0.0)
                self._clean = out
            if self.fn is not None:
                self.fn.unsafe_real(x, self._part)
                out[self._where] = self._part
        elif self.fn is not None:
            self.fn.unsafe_real(x, out)
        if self.fn is not None:
            if self._calls >= 0:
                self._calls += 1
                if self._calls >= TIER_UP_CALLS:
                    self._tier_up()
        return out

    def batch(self, X: np.ndarray) -> np.ndarray:
        """Evaluate at every row of *X* (shape ``(N, inputs)``) in one call: shape ``(N, size)``."""
        if self.fn is None or len(X) == 0:
            return np.zeros((len(X), self.size))
        values = np.asarray(self.fn(np.ascontiguousarray(X, dtype=float)), dtype=float).reshape(len(X), -1)
        if self._where is None:
            return values
        out = np.zeros((len(X), self.size))
        out[:, self._where] = values
        return out

    def __call__(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Evaluate; returns views into a reused buffer (valid until the next call)."""
        flat = self.raw(x)
        out = self._views.copy()
        for name, i in self._scalars:
            out[name] = float(flat[i])
        return out

    def views(self, flat: np.ndarray) -> dict[str, np.ndarray]:
        """Named views into a flat output array (*flat* of shape ``(size,)``, or ``(N, size)``
        from :meth:`batch`: then every view has the leading dimension N); scalars are
        ``None`` in a single output (see :meth:`__call__`)."""
        lead = flat.shape[:-1]
        return {name: flat[..., sl].reshape(lead + shape) if (shape or lead) else None
                for name, (sl, shape) in self.slices.items()}


def max_abs(v: np.ndarray) -> float:
    """``max |v_i|`` of a small finite vector (0 when empty): in Python, 2-4x faster than the
    NumPy reductions at the sizes of a mechanical state (the scales of tolerances)."""
    return max(map(abs, v.tolist()), default=0.0)


_dposv, _dgesv = lapack.dposv, lapack.dgesv


def solve_saddle(A: np.ndarray, b: np.ndarray, B: np.ndarray | None = None,
                 G: np.ndarray | None = None, gamma: np.ndarray | None = None):
    """Solve ``A a - B mu = b``, ``G a = -gamma`` for ``(a, mu)``.

    Without rows: Cholesky (LAPACK ``dposv``), LU if ``A`` is not positive definite.  With
    rows: LU of the saddle-point matrix ``[[A, B], [G, 0]]`` for ``(a, -mu)`` (``dgesv``,
    in place on a Fortran-ordered work array).  Returns fresh arrays.

    Raises
    ------
    SingularMatrix
        When the system has no unique solution.
    """
    k = A.shape[0]
    if G is None or G.shape[0] == 0:
        _, x, info = _dposv(A, b)
        if info == 0:
            return x, np.empty(0)
        _, _, x, info = _dgesv(A, b)
        if info != 0:
            raise SingularMatrix("mass matrix")
        return x, np.empty(0)
    m = G.shape[0]
    s = k + m
    # [[A, B], [G, 0]] [a; -mu] = [b; -gamma]: B enters unnegated (one operation less)
    K = np.zeros((s, s), order="F")
    K[:k, :k] = A
    K[:k, k:] = B
    K[k:, :k] = G
    rhs = np.empty(s)
    rhs[:k] = b
    np.negative(gamma, out=rhs[k:])
    _, _, x, info = _dgesv(K, rhs, overwrite_a=1, overwrite_b=1)
    # x . x is finite iff every entry is (barring overflow, which the exact check catches)
    if info != 0 or not (math.isfinite(x @ x) or np.all(np.isfinite(x))):
        raise SingularMatrix("saddle-point system")
    # a badly conditioned system is as bad as a singular one for the user
    mu = x[k:]
    np.negative(mu, out=mu)
    return x[:k], mu


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
    mode by index.  ``observables(x)`` returns ``T, T0, V``, ``T2 = q' M q'/2``, the power of
    the non-potential forces ``P_nc``, the explicit-time power ``P_t = dV/dt - dT/dt`` and the
    position/velocity residuals of every row.
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
        F = list(dyn.F)
        gamma = [r.gamma for r in self.rows]
        #: whether ``M``, ``G`` and ``B`` are compiled as the vectors of their nonzero entries
        #: (many coordinates: :data:`~nonideal.numeric.compact.SPARSE_MIN_N`); read them with :meth:`mass`,
        #: :meth:`gradients`, :meth:`reactions`
        self.compact = n >= compact.SPARSE_MIN_N
        self.patterns: dict[str, SparsePattern] = {}
        if self.compact:
            mass = sorted(dyn.mass_entries.items())
            self.patterns["M"] = SparsePattern((n, n), [ij for ij, _ in mass])
            outputs = {"M": [e for _, e in mass], "F": F}
            if m:
                # nonzero entries by row (O(nnz) symbolic tests: the zeros are the Integer 0
                # the rows are built with, found by identity first)
                zero = se.Integer(0)
                G = [((i, j), e) for i, r in enumerate(self.rows) for j, e in enumerate(r.G)
                     if e is not zero and e != 0]
                B = sorted(((j, i), e) for i, r in enumerate(self.rows) for j, e in enumerate(r.B)
                           if e is not zero and e != 0)
                self.patterns["G"] = SparsePattern((m, n), [ij for ij, _ in G])
                self.patterns["B"] = SparsePattern((n, m), [ij for ij, _ in B])
                outputs.update(G=[e for _, e in G], gamma=gamma, B=[e for _, e in B])
        else:
            G = [[r.G[j] for j in range(n)] for r in self.rows]
            B = [[r.B[j] for r in self.rows] for j in range(n)] if m else []
            # the mass matrix by its nonzero entries (O(n) of them for many bodies), dense at evaluation
            outputs = {"M": Sparse((n, n), dyn.mass_entries), "F": F}
            if m:
                outputs.update(G=G, gamma=gamma, B=B)
        self.has_nc_forces = any(se.sympify(q) != 0 for q in dyn.Q_nc)
        P_t = se.diff(dyn.V, dyn.t) - se.diff(dyn.T, dyn.t)
        self.explicit_time = P_t != 0
        #: ``[P_nc, P_t]``: powers of the non-potential forces and of the explicit time
        #: dependence (None when both vanish identically)
        self.powers = None
        if self.has_nc_forces or self.explicit_time:
            self.powers = [sum((a * b for a, b in zip(dyn.Q_nc, dyn.qd)), se.Integer(0)), P_t]
            outputs["P"] = self.powers
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
            # T2 = q'.M.q'/2 from the nonzero entries (a trajectory's energy without n x n
            # matrices per sample)
            T2 = se.Add(*[e * qd[i] * qd[j] for (i, j), e in dyn.mass_entries.items()]) / 2
            outputs = {"T": dyn.T, "T0": dyn.T0, "T2": T2, "V": dyn.V, "P_nc": P_nc, "P_t": P_t}
            if self.rows:
                outputs.update(pos=pos, vel=vel)
            self._obs = Compiled(self.symbols, outputs)
        return self._obs

    @property
    def root_discriminants(self):
        """``(Compiled with output "disc", names)`` for the constraints nonlinear in the
        accelerations (their discriminants must stay >= 0), or None."""
        if "_roots" not in self.__dict__:
            roots = {name: disc for name, (_, disc, _) in self.dyn.root_rows.items() if disc is not None}
            self.__dict__["_roots"] = (Compiled(self.symbols, {"disc": list(roots.values())}), list(roots)) \
                if roots else None
        return self.__dict__["_roots"]

    @property
    def conditions(self) -> Compiled | None:
        """The conditions that hold along the motion besides the rows -- programs whose control
        acts through the dynamics and their intermediate conditions of dynamics
        (``Dynamics.servo_conditions``): ``G (k, n)`` (d vel / d q'), ``pos (k,)``, ``vel (k,)``;
        None when there are none."""
        if "_conditions" not in self.__dict__:
            conds = self.dyn.servo_conditions()
            self.__dict__["_conditions"] = None
            if conds:
                zero = se.Integer(0)
                G = []
                for c in conds:
                    if c.position is not None:
                        G.append([se.diff(c.position, qk) for qk in self.dyn.q])
                    else:
                        G.append([se.diff(c.velocity, v) for v in self.dyn.qd])
                outputs = {"G": G,
                           "pos": [c.position if c.position is not None else zero for c in conds],
                           "vel": [c.velocity if c.velocity is not None else zero for c in conds]}
                self.__dict__["_conditions"] = (Compiled(self.symbols, outputs),
                                                [c.name for c in conds],
                                                [c.position is not None for c in conds])
        return self.__dict__["_conditions"]

    def mass(self, out) -> np.ndarray | csr_matrix:
        """``M`` from the outputs *out* of :attr:`dynamics` (a dict of views, or the flat
        array): a dense array, or with :attr:`compact` a ``scipy.sparse.csr_matrix`` (a copy)."""
        return self._matrix(out, "M")

    def gradients(self, out) -> np.ndarray | csr_matrix:
        """``G`` (shape (m, n)) from the outputs *out*, like :meth:`mass`."""
        return self._matrix(out, "G") if self.m else np.zeros((0, self.n))

    def reactions(self, out) -> np.ndarray | csr_matrix:
        """``B`` (shape (n, m)) from the outputs *out*, like :meth:`mass`."""
        return self._matrix(out, "B") if self.m else np.zeros((self.n, 0))

    def dense(self, out, name: str) -> np.ndarray:
        """Output matrix *name* (``M``, ``G``, ``B``) as a dense array -- O(n^2) memory with
        :attr:`compact`: for the diagnoses of small systems and the paths that need it."""
        if isinstance(out, np.ndarray):
            out = self.dynamics.views(out)
        values = np.asarray(out[name], dtype=float)
        if self.compact and values.ndim == 2:   # a batch (dynamics.batch): one row per state
            pattern = self.patterns[name]
            dense = np.zeros((len(values),) + pattern.shape)
            dense[:, pattern.rows, pattern.cols] = values
            return dense
        value = self._matrix(out, name)
        return value.toarray() if issparse(value) else np.array(value, dtype=float)

    def _matrix(self, out, name: str):
        if isinstance(out, np.ndarray):
            out = self.dynamics.views(out)
        if not self.compact:
            return out[name]
        return self.patterns[name].matrix(out[name])

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


def kernel_of(model: Model) -> Kernel:
    """The (cached) compiled kernel of *model*."""
    return model.cached("kernel", lambda: Kernel(model))


class FormSystem:
    """The compiled equations of one :class:`EquationsOfMotion`.

    ``solve(x)`` returns ``(a, mu, qdd)``: the form's unknowns, its multipliers, and the
    accelerations of all coordinates.  :attr:`last` holds the compiled outputs of the last
    call (views, valid until the next): ``A, b, R, r`` and, with multipliers, ``B, G,
    gamma``, and the *extra_outputs*.

    Parameters
    ----------
    eom : EquationsOfMotion
    extra : sequence of str
        Names of further inputs, after the parameters (e.g. slip directions).
    extra_outputs : mapping name -> expressions, optional
        Further expressions of the inputs compiled with the equations (e.g. the chart test
        of Lagrange II, :func:`nonideal.modes.charts.chart_outputs`); their names are kept in the
        attribute of that name.
    """

    def __init__(self, eom: EquationsOfMotion, extra: Sequence = (),
                 extra_outputs: Mapping[str, object] | None = None):
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
        self.aux_names = [(f"K{i}", f"Y{i}") for i in range(len(eom.auxiliaries))]
        b = eom.Qf_ - eom.c_
        outputs = {"A": eom.A_, "b": list(b), "R": eom.R_, "r": list(eom.r_)}
        self.m = len(eom.multipliers)
        if self.m:
            outputs.update(B=eom.B_, G=eom.G_, gamma=list(eom.gamma_))
        self.extra_outputs = tuple(extra_outputs or ())
        outputs.update(extra_outputs or {})
        self.k = eom.k
        self.main = Compiled(base + aux_syms, outputs)
        self.x = np.zeros(len(base) + len(aux_syms))
        self.last: dict[str, np.ndarray] = {}

    def solve(self, x_base: np.ndarray):
        x = self.x
        x[:self.n_base] = x_base
        if self.stage1 is not None:
            s1 = self.stage1(x_base)
            off = self.n_base
            for kname, yname in self.aux_names:
                # LAPACK directly: np.linalg.solve costs ~4 us more per call on small blocks
                _, _, X, info = _dgesv(s1[kname], s1[yname])
                if info != 0:
                    raise SingularMatrix("dependent-velocity block")
                x[off:off + X.size] = X.ravel()
                off += X.size
        out = self.last = self.main(x)
        if self.k == 0 and self.m == 0:  # no freedom left: the motion is the program itself
            return np.empty(0), np.empty(0), np.array(out["r"], dtype=float)
        if self.m:
            a, mu = solve_saddle(out["A"], out["b"], out["B"], out["G"], out["gamma"])
        else:
            a, mu = solve_saddle(out["A"], out["b"])
        qdd = out["R"] @ a + out["r"]
        return a, mu, qdd


def root_failure(kernel, t: float, q, qd, params) -> MechanicsError | None:
    """A root rule that selects nothing at a state: the discriminant of a constraint nonlinear
    in the accelerations is negative (its two branches have met and no real multiplier keeps
    the constraint).  Returns the error to raise (exit code 3, with the state), or None."""
    compiled = kernel.root_discriminants
    if compiled is None:
        return None
    fn, names = compiled
    values = np.atleast_1d(np.asarray(fn(kernel.state_input(t, q, qd, params))["disc"], dtype=float))
    bad = [(nm, v) for nm, v in zip(names, values) if not v >= 0]
    if not bad:
        return None
    coords = kernel.model.coordinates
    state = {c: float(v) for c, v in zip(coords, q)}
    state.update({c + "'": float(v) for c, v in zip(coords, qd)})
    name, value = bad[0]
    rule = kernel.model.constraint(name).root
    return MechanicsError(
        f"constraint '{name}': the root rule root = \"{rule}\" selects nothing: no real multiplier "
        f"keeps the constraint at this state (the discriminant of its quadratic in the multiplier "
        f"is {value:.6g} < 0: its two roots have met and left the real line); the force along the "
        "given reaction direction cannot realize the constraint here -- change the direction, the "
        "program or the initial state", t, state, details={"constraint": name, "discriminant": value})
