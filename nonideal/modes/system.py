"""The saddle-point system of a mode, as the hybrid loop solves it: :class:`ModeSystem` and
:class:`ModeFunction` (the motion at a state read from them: :mod:`nonideal.modes.motion`).

For Lagrange's equations of the first kind the motion in a mode is the saddle-point system

    [[M, B], [G, 0]] [q''; -lambda] = [F; -gamma]

whose blocks are entries of the compiled kernels (:class:`~nonideal.numeric.kernel.Kernel`: ``M``,
``F`` and every constraint row; :class:`~nonideal.numeric.contact_kernel.ContactKernel`: the contacts'
normal and slip rows).  A :class:`ModeSystem` is built once per mode structure and holds where
every entry of that matrix and of its right-hand side sits in the kernels' flat outputs, so
that one evaluation is two compiled calls writing into one buffer, one gather, one numeric
update of each sliding contact's friction column ``-sigma mu s W`` (``s`` depends on the slip),
and one LAPACK ``dgesv``, whose LU factors are kept: the effective normal compliance of a
sliding contact (Painleve's watch, :class:`~nonideal.simulation.events.Jam`) then costs one more
triangular solve.  It does the same floating-point operations as the general path
(:meth:`ModeSolver.assemble <nonideal.modes.solver.ModeSolver.assemble>` +
:func:`~nonideal.numeric.kernel.solve_saddle`), which stays the reference and handles singular
systems (minimum-norm contact forces, named errors).  Once a mode structure with contacts
has been integrated :data:`SPECIALIZE_CALLS` times, :class:`ModeFunction` compiles its whole
system (friction columns, slip direction and powers included): the NumPy calls around the
compiled code, not the compiled code, were the cost of an evaluation.
"""

from __future__ import annotations

import math

import numpy as np
import symengine as se
from scipy.linalg import lapack
from scipy.sparse import issparse

from ..numeric.contact_kernel import SLIP_FLOOR, contact_kernel_of
from ..modeling.contacts import RegularizedCoulomb
from ..equations.dynamics import dynamics_of
from .types import SEPARATED, SLIDE, SMOOTH, STICK, Mode, RowSpec
from ..numeric.blocks import BLOCKS_MIN_N, BlockSolver, SparseSaddle, blocks_of, dependent_rows
from ..numeric.kernel import Compiled, SingularMatrix

__all__ = ["ModeSystem", "ModeFunction", "system_of", "compliance_of", "SPECIALIZE_CALLS"]

_dgesv, _dgetrs, _dposv = lapack.dgesv, lapack.dgetrs, lapack.dposv


class ModeSystem:
    """The rows of one mode structure and, for Lagrange I, their assembly by index (shared by
    every :class:`~nonideal.modes.solver.ModeSolver` of the model: :func:`system_of`; its only state
    is the count of right-hand-side evaluations and the compiled :class:`ModeFunction`).

    Parameters
    ----------
    kernel : Kernel
    mode : Mode
        Any mode of the structure (sliding directions are read at each evaluation).

    Attributes
    ----------
    layout : list of RowSpec
        The rows of the mode; ``n + j`` is the column of row ``j`` in the saddle-point matrix.
    row_col, normal_col : dict
        Layout position of each active kernel row / of each touching contact's normal row.
    tangent_cols : dict
        Layout positions of a sticking contact's slip rows (their multipliers: the friction).
    dropped : frozenset of int
        Layout positions of the ideal rows that repeat what the others impose, when the rows
        are dependent (:meth:`dependent`); the reduced forms are derived without them.

    Notes
    -----
    Evaluations take the :class:`~nonideal.modes.solver.ModeSolver` whose buffers they use: its input
    ``x``, its output buffer ``z = [kernel outputs | contact outputs]`` and its slip references;
    the solver also remembers the last solve (``solver.last``).
    """

    def __init__(self, kernel, mode: Mode):
        ck = contact_kernel_of(kernel.model)
        rows = [i for i, r in enumerate(kernel.rows) if not r.unilateral or r.name in mode.held]
        layout = [RowSpec("constraint", i, 0, kernel.rows[i].name) for i in rows]
        parents = ck.parents
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state == SEPARATED:
                continue
            if parents[c] is None:  # a friction torque has its contact's normal row
                layout.append(RowSpec("normal", c, 0, name))
            if cs.state == STICK:
                d = ck.dims[c]
                for k in range(d):
                    layout.append(RowSpec("tangent", c, k, f"{name}_t{k + 1}" if d > 1 else f"{name}_t"))
        self.layout = layout
        self.n = n = kernel.n
        self.m = m = len(layout)
        self.s = s = n + m
        self.row_col = {r.index: j for j, r in enumerate(layout) if r.kind == "constraint"}
        self.normal_col = {r.index: j for j, r in enumerate(layout) if r.kind == "normal"}
        #: the layout row of the normal force of every touching contact and friction torque
        self.normal_of = {c: self.normal_col[c if p is None else p] for c, p in enumerate(parents)
                          if (c if p is None else p) in self.normal_col and mode.contacts[c][1].state != SEPARATED}
        self.tangent_cols: dict[int, list[int]] = {}
        for j, r in enumerate(layout):
            if r.kind == "tangent":
                self.tangent_cols.setdefault(r.index, []).append(j)
        self.tangent = [j for cols in self.tangent_cols.values() for j in cols]
        # rows whose reaction column is their gradient: dropping a dependent one keeps the motion
        # (not a normal row that carries a sliding friction torque)
        torque_sliding = {parents[c] for c in ck.torques if mode.contacts[c][1].state in (SLIDE, SMOOTH)}
        self._ideal = [r.kind == "tangent" or (r.kind == "normal" and mode.contacts[r.index][1].state == STICK
                                               and r.index not in torque_sliding)
                       or (r.kind == "constraint" and kernel.rows[r.index].reaction_kind == "ideal")
                       for r in layout]
        self._dependent = None if m else False
        self.dropped: frozenset[int] = frozenset()
        self.contact_rows = m > len(self.row_col)
        #: active kernel rows with a position level / a velocity level (the drift check)
        self.drift_rows = kernel.kinematic_level(rows)
        kd = kernel.dynamics
        ksl = {name: sl.start for name, (sl, _) in kd.slices.items()}
        c0 = kd.size  # the contact outputs follow the kernel's in z
        cat = {name: c0 + start for name, start in ck.at.items()}
        m_all = kernel.m
        # K (Fortran order: entry (i, k) at i + k s) and r = [F; -gamma], gathered from z: the
        # compiled (nonzero) entries of M only, the others stay zero; with a compact kernel
        # (many coordinates) K is sparse: the same entries by (row, column) (SparseSaddle)
        compact = kernel.compact
        self.M_at = ksl["M"]
        #: the pattern of M's entries in a compact kernel
        self.mass_pattern = kernel.patterns.get("M")
        if compact:
            pM = kernel.patterns["M"]
            nz = pM.rows * n + pM.cols   # only for the blocks below
            trip = [(pM.rows, pM.cols, ksl["M"] + np.arange(len(pM.rows)))]
            if m_all:
                pG, pB = kernel.patterns["G"], kernel.patterns["B"]
                b_order = np.argsort(pB.cols, kind="stable")
                b_ptr = np.concatenate(([0], np.cumsum(np.bincount(pB.cols, minlength=m_all))))
        else:
            nz = kd.entries("M")
            trip = [(nz // n, nz % n, ksl["M"] + nz)]
        #: M q'' = F by blocks when M has independent blocks (many bodies; None: dense LAPACK)
        self.blocks = None
        if not m and n >= BLOCKS_MIN_N:
            if compact:
                self.blocks = BlockSolver.of_pattern(n, pM.rows, pM.cols)
            else:
                groups = blocks_of(n, zip((nz // n).tolist(), (nz % n).tolist()))
                self.blocks = BlockSolver(n, groups) if len(groups) > 1 else None
        every = np.arange(n)
        rsrc = list(range(ksl["F"], ksl["F"] + n))
        self.sliding = []
        self.tangent_slip: dict[int, int] = {}  # layout row of a sticking slip -> its U in z
        for j, r in enumerate(layout):
            col = n + j
            if r.kind == "constraint":
                if compact:
                    lo, hi = pG.indptr[r.index], pG.indptr[r.index + 1]
                    g_cols, g_src = pG.cols[lo:hi], ksl["G"] + np.arange(lo, hi)
                    at = b_order[b_ptr[r.index]:b_ptr[r.index + 1]]
                    b_rows, b_src = pB.rows[at], ksl["B"] + at
                else:
                    g_cols = b_rows = every
                    g_src, b_src = ksl["G"] + r.index * n + every, ksl["B"] + every * m_all + r.index
                rsrc.append(ksl["gamma"] + r.index)
            elif r.kind == "normal":
                c = r.index
                g_cols = b_rows = every
                g_src = b_src = cat["Gn"] + c * n + every
                rsrc.append(cat["gamma_n"] + c)
                if mode.contacts[c][1].state in (SLIDE, SMOOTH):
                    o, d = ck.offsets[c], ck.dims[c]
                    # (row, contact, U in z, W in z, W's shape, mu in z, the column in K)
                    self.sliding.append((j, c, slice(cat["U"] + o, cat["U"] + o + d),
                                         slice(cat["W"] + o * n, cat["W"] + (o + d) * n), (d, n), cat["mu"] + c,
                                         col))
            else:
                row = ck.offsets[r.index] + r.k
                self.tangent_slip[j] = cat["U"] + row
                g_cols = b_rows = every
                g_src = b_src = cat["W"] + row * n + every
                rsrc.append(cat["gamma_U"] + row)
            trip.append((np.full(len(g_cols), col), g_cols, g_src))
            trip.append((b_rows, np.full(len(b_rows), col), b_src))
        for c in sorted(ck.torques):   # a sliding friction torque: in its contact's normal column
            if mode.contacts[c][1].state in (SLIDE, SMOOTH):
                j = self.normal_of[c]
                o, d = ck.offsets[c], ck.dims[c]
                self.sliding.append((j, c, slice(cat["U"] + o, cat["U"] + o + d),
                                     slice(cat["W"] + o * n, cat["W"] + (o + d) * n), (d, n), cat["mu"] + c, n + j))
        rows_K, cols_K, src = (np.concatenate(v).astype(np.intp) for v in zip(*trip))
        #: the sparse saddle-point matrix of a compact kernel with rows (None: dense K)
        self.sparse = SparseSaddle(s, rows_K, cols_K, src) if compact and m else None
        if self.sparse is not None:   # a sliding column: the data of K's column (its n rows of B)
            ptr = self.sparse.indptr
            self.sliding = [(*e[:-1], slice(ptr[e[-1]], ptr[e[-1]] + n)) for e in self.sliding]
        else:
            self.sliding = [(*e[:-1], slice(e[-1] * s, e[-1] * s + n)) for e in self.sliding]
        self.src, self.dst = src, rows_K + cols_K * s
        self.rsrc = np.array(rsrc, dtype=np.intp)
        self.power = slice(ksl["P"], ksl["P"] + 2) if "P" in ksl else None
        #: the compiled :class:`ModeFunction` once the structure has been hot in a run (False:
        #: not compilable); a run uses it once it is hot in that run (``ModeSolver.hot``)
        self.function = None

    # ------------------------------------------------------------------ evaluation
    def assemble(self, solver, t: float, y: np.ndarray, mode: Mode, powers: bool = False):
        """``K`` (shape (s, s), Fortran order, friction columns included) and ``r`` at the state
        ``y = [q, q', ...]``; with *powers* also, per unit normal force, the power of each
        sliding contact's friction on its slip, ``F . U`` (``fcol . q'`` less the part a moving
        support supplies: ``U = W q' + U_0``).  Without rows ``K`` is ``M``,
        a view of the solver's buffer (the factorization copies it)."""
        n = self.n
        x, z = solver.x, solver.z
        x[0] = t
        x[1:1 + 2 * n] = y[:2 * n]
        solver.kernel.dynamics.raw(x, solver.kz)
        if not self.m:  # no rows: M q'' = F, read in place (M is symmetric: no transpose)
            if solver.kernel.compact:  # the vector of M's entries
                return z[self.M_at:self.M_at + len(self.src)], z[self.rsrc], []
            return z[self.M_at:self.M_at + n * n].reshape(n, n), z[self.rsrc], []
        if self.contact_rows:
            solver.ck.fn.raw(x, solver.cz)
        if self.sparse is not None:
            K = self.sparse.data(z)
        else:
            K = np.zeros(self.s * self.s)
            K[self.dst] = z[self.src]
        r = z[self.rsrc]
        np.negative(r[n:], out=r[n:])
        fq = []
        if self.sliding:
            qd = y[n:2 * n]
            for j, c, u, w, shape, mu, col in self.sliding:
                cs = mode.contacts[c][1]
                direction = solver.friction_shape(c, cs, z[u], qd)
                fcol = cs.sigma * z[mu] * (direction @ z[w].reshape(shape))
                K[col] -= fcol
                if powers:
                    fq.append(cs.sigma * z[mu] * float(direction @ z[u]))
        if self.sparse is not None:
            K = self.sparse.matrix(K)
            if self._dependent is None:
                self.dependent(K[n:, :n])
            return K, r, fq
        K = K.reshape((self.s, self.s), order="F")
        if self._dependent is None:
            self.dependent(K[n:, :n])
        return K, r, fq

    def dependent(self, G: np.ndarray) -> bool:
        """Whether the rows of the mode are dependent, so that the multipliers are statically
        indeterminate (a ladder sticking at a rough wall and a rough floor: four rows on three
        coordinates; a table on three legs sticking: nine on six) -- decided once, from the rows
        *G* (shape (m, n)) of the first state that asks (the rank of a mode's rows is the same
        at its admissible states but for singular configurations).  Also sets
        :attr:`dropped`.  A dependent system is never factored: :meth:`factor` raises
        :class:`~nonideal.numeric.SingularMatrix`, and the general path
        (:meth:`ModeSolver.accelerations <nonideal.modes.solver.ModeSolver.accelerations>`) solves it."""
        if self._dependent is None and issparse(G):
            # many rows: rank tests component by component (rows sharing no coordinate are
            # independent of each other); the rows kept are the earlier ones
            order = [j for j in range(self.m) if not self._ideal[j]] + [j for j in range(self.m) if self._ideal[j]]
            tol = DEPENDENT_RTOL * max(1.0, float(abs(G).max()) if G.nnz else 0.0)
            repeated = {order[k] for k in dependent_rows(G[order], tol)}
            self._dependent = bool(repeated)
            self.dropped = frozenset(j for j in repeated if self._ideal[j])
        if self._dependent is None:
            # keep the non-ideal rows first, then every ideal row that adds to the rank
            order = [j for j in range(self.m) if not self._ideal[j]] + [j for j in range(self.m) if self._ideal[j]]
            tol = DEPENDENT_RTOL * max(1.0, float(np.max(np.abs(G))))
            keep: list[int] = []
            for j in order:
                if np.linalg.matrix_rank(G[keep + [j]], tol=tol) == len(keep) + 1:
                    keep.append(j)
            self._dependent = len(keep) < self.m
            self.dropped = frozenset(j for j in range(self.m) if j not in keep and self._ideal[j])
        return self._dependent

    @property
    def dependence(self) -> bool | None:
        """Whether the rows are dependent (:meth:`dependent`); None until a state decided it."""
        return self._dependent

    def factor(self, K: np.ndarray, r: np.ndarray):
        """``[q''; -lambda]`` and the LU factors (``None`` without rows: Cholesky of M).

        Raises
        ------
        SingularMatrix
            A singular system, or one with dependent rows (:meth:`dependent`), whose LU
            factorization would give arbitrary multipliers."""
        if self._dependent:
            raise SingularMatrix("dependent rows: statically indeterminate multipliers")
        if self.sparse is not None:
            found = SparseSaddle.factor(K, r)
            if found is None:
                raise SingularMatrix("saddle-point system")
            return found[0], found[1], None
        if self.m == 0:
            if K.ndim == 1:   # a compact kernel: K holds the entries of M
                sol = self.blocks.solve_entries(K, r) if self.blocks is not None else None
                if sol is None:
                    found = SparseSaddle.factor(self.mass_pattern.matrix(K).tocsc(), r)
                    if found is None:
                        raise SingularMatrix("mass matrix")
                    sol = found[0]
                return sol, None, None
            if self.blocks is not None:
                sol = self.blocks.solve(K, r)
                if sol is not None:
                    return sol, None, None
            _, sol, info = _dposv(K, r)
            if info == 0:
                return sol, None, None
            lu, piv, sol, info = _dgesv(K, r)
        else:
            lu, piv, sol, info = _dgesv(K, r, overwrite_a=1, overwrite_b=1)
        # sol . sol is finite iff every entry is (barring overflow, which the exact check catches)
        if info != 0 or not (math.isfinite(sol @ sol) or np.all(np.isfinite(sol))):
            raise SingularMatrix("saddle-point system")
        return sol, lu, piv

    def solve(self, solver, t: float, y: np.ndarray, mode: Mode) -> np.ndarray:
        """``[q''; -lambda]`` at the state ``y = [q, q', ...]`` (remembered as ``solver.last``).

        Raises
        ------
        SingularMatrix
            The general path (:meth:`ModeSolver.accelerations`) then explains or resolves it.
        """
        K, r, _ = self.assemble(solver, t, y, mode)
        sol, lu, piv = self.factor(K, r)
        solver.last = (t, y, mode, sol, lu, piv)
        return sol

    def solve_with_powers(self, solver, t: float, y: np.ndarray, mode: Mode):
        """:meth:`solve` and the powers: ``(sol, P_reactions, P_friction, P)``, ``P_reactions``
        of the ideal and servo reactions, ``P_friction`` of the friction forces (both
        ``sum_j lambda_j B_j . q'`` over the rows concerned), ``P = [P_nc, P_t]`` of the forces
        and the explicit time dependence (None when the model has none).  The right-hand side
        of the simulation: it counts towards :data:`SPECIALIZE_CALLS` (in *solver*'s run)."""
        solver.calls[self] = solver.calls.get(self, 0) + 1
        K, r, fq = self.assemble(solver, t, y, mode, powers=True)
        n = self.n
        if self.sparse is not None:
            Bqd = K[:n, n:].T @ y[n:2 * n]
        else:
            Bqd = y[n:2 * n] @ K[:n, n:] if self.m else np.empty(0)  # before the factorization overwrites K
        sol, lu, piv = self.factor(K, r)
        solver.last = (t, y, mode, sol, lu, piv)
        lam = sol[n:]  # -lambda
        solver.column_powers = -lam * Bqd   # lambda_j B_j . q' of each column (the controls' powers)
        total = -float(lam @ Bqd)
        friction = 0.0
        for (j, *_), p in zip(self.sliding, fq):
            friction += float(lam[j]) * p  # the column's friction part is -fcol
        for j in self.tangent:  # sticking: the friction's power on the (vanishing) slip
            friction -= float(lam[j] * solver.z[self.tangent_slip[j]])
        return sol, total - friction, friction, (solver.kz[self.power] if self.power else None)

    def specialized(self, kernel, mode: Mode, solver):
        """The :class:`ModeFunction` of this structure once *solver*'s run has evaluated it
        :data:`SPECIALIZE_CALLS` times by :meth:`solve_with_powers` (compiled then, once per
        process), or None (before that, without contact rows, or for a law it does not
        compile).  From then on the run's motions read it too (``solver.hot``)."""
        if solver.calls.get(self, 0) < SPECIALIZE_CALLS:
            return None
        if self.function is None and self.contact_rows and not self._dependent and self.sparse is None \
                and not contact_kernel_of(kernel.model).torques:   # friction torques: the index path
            self.function = ModeFunction.of(kernel, self, mode)
        if self.function:
            solver.hot.add(self)
        return self.function or None

    def compliance(self, lu: np.ndarray, piv: np.ndarray, c: int) -> float:
        """Effective normal compliance ``b = dg''/dN`` of touching contact ``c`` from the LU
        factors of ``K``: the lower-right block of ``K^-1`` is ``-(G M^-1 B)^-1``, so
        ``b = -1/(K^-1)_{n+j, n+j}``."""
        i = self.n + self.normal_col[c]
        e = np.zeros(self.s)
        e[i] = 1.0
        inv = lu.solve(e)[i] if piv is None else _dgetrs(lu, piv, e)[0][i]
        return -1.0 / inv if inv != 0 else math.inf


DEPENDENT_RTOL = 1e-7
"""Rows whose singular values fall below this (relative to the largest entry) are dependent:
well above the rounding of rows that are exactly dependent at admissible states, well below
the conditioning of a well-posed mode."""

SPECIALIZE_CALLS = 400
"""Right-hand-side evaluations of a mode structure in one run after which :class:`ModeFunction`
compiles it (once per process): 3-6 ms of compilation for a small system (LLVM, unoptimized),
~10 us saved per evaluation (measured on the sphere benchmark: 19 -> 8 us), so it pays for
itself after a few hundred evaluations.  Short runs keep the index path.  Until then the
phases of that mode run on the index path; the switch happens at the start of a phase, and
the two paths agree to rounding (tested to 1e-13), not bit for bit -- which is why the count
is the run's own: a run takes the same path whatever ran before it in the process."""


class ModeFunction:
    """The saddle-point system of one mode structure with contact rows, compiled as a whole.

    One Lambdify (:class:`~nonideal.numeric.kernel.Compiled`) evaluates ``K`` in Fortran order with
    the sliding contacts' friction columns ``dg/dq - sigma mu s W`` built in (``s`` the slip
    direction: an input ``+-1`` for one component; ``rho U/|U|`` for two, ``rho = sign(U .
    s_ref)`` with the slip reference an input; ``U/sqrt(|U|^2 + eps^2)`` for the smooth law),
    ``[F; -gamma]``, ``B^T q'``, the friction part of it, the powers ``[P_nc, P_t]`` and, for
    two slip components, the guards ``|U| - 2 SLIP_FLOOR (1 + |q'|)`` and ``U . s_ref``: where a guard
    fails (slip ~ 0, orientation undefined) the caller takes the index path of
    :class:`ModeSystem`, whose :meth:`~nonideal.modes.solver.ModeSolver.friction_shape` decides.

    Parameters
    ----------
    kernel : Kernel
    system : ModeSystem
    mode : Mode
    """

    def __init__(self, kernel, system: ModeSystem, mode: Mode):
        dyn = dynamics_of(kernel.model)
        n, m, s = system.n, system.m, system.s
        self.n, self.s = n, s
        qd = dyn.qd
        zero = se.Integer(0)
        extra: list = []
        self.directions = []  # (input position, layout row, contact) of one-component slips
        self.references = []  # (input position, contact) of two-component slip references
        guards = []
        columns, rows, gammas, fpow = [], [], [], []
        n_in = len(kernel.symbols)
        for j, r in enumerate(system.layout):
            if r.kind == "constraint":
                row = kernel.rows[r.index]
                g, b, gamma, fp = list(row.G), list(row.B), row.gamma, zero
            elif r.kind == "tangent":
                cd = dyn.contacts[r.index]
                g = b = list(cd.W[r.k])
                gamma = cd.gamma_U[r.k]
                fp = cd.U[r.k]  # the friction's power on the slip, per unit force
            else:
                c = r.index
                cd = dyn.contacts[c]
                cs = mode.contacts[c][1]
                g, gamma = list(cd.Gn), cd.gamma_n
                b, fp = g, zero
                if cs.state in (SLIDE, SMOOTH):
                    U = list(cd.U)
                    law = cd.law
                    if cs.state == SMOOTH and law.exact:
                        shape = [zero] * len(U)  # a frictionless contact
                    elif cs.state == SMOOTH:
                        if not isinstance(law, RegularizedCoulomb):
                            raise _NotCompiled  # the epsilon-linear law is piecewise
                        scale = se.sqrt(sum((u * u for u in U), zero) + law.eps ** 2)
                        shape = [u / scale for u in U]
                    elif len(U) == 1:
                        d = se.Symbol(f"__direction{len(extra)}__")
                        self.directions.append((n_in + len(extra), c))
                        extra.append(d)
                        shape = [d]
                    else:
                        ref = [se.Symbol(f"__reference{len(extra) + k}__") for k in range(len(U))]
                        self.references.append((n_in + len(extra), c))
                        extra += ref
                        norm = se.sqrt(sum((u * u for u in U), zero))
                        dot = sum((u * v for u, v in zip(U, ref)), zero)
                        shape = [u * dot / (se.Abs(dot) * norm) for u in U]
                        speed = se.sqrt(sum((v * v for v in qd), zero))
                        guards += [norm - 2 * SLIP_FLOOR * (1 + speed), dot]
                    fcol = [cs.sigma * cd.mu * sum((sk * w[i] for sk, w in zip(shape, cd.W)), zero)
                            for i in range(n)]
                    b = [gi - fi for gi, fi in zip(g, fcol)]
                    fp = -cs.sigma * cd.mu * sum((sk * u for sk, u in zip(shape, U)), zero)
            columns.append(b)
            rows.append(g)
            gammas.append(gamma)
            fpow.append(fp)
        K = [[dyn.M[i, k] for k in range(n)] + [columns[j][i] for j in range(m)] for i in range(n)]
        K += [rows[j] + [zero] * m for j in range(m)]
        # the powers per unit multiplier: of the whole reaction column (B^T q') and of its
        # friction part, as one (2, m) block
        outputs = {"K": [K[i][k] for k in range(s) for i in range(s)],
                   "r": list(dyn.F) + [-gamma for gamma in gammas],
                   "powers": [[sum((b * v for b, v in zip(col, qd)), zero) for col in columns], fpow]}
        if kernel.powers is not None:
            outputs["P"] = kernel.powers
        if guards:
            outputs["guard"] = guards
        self.fn = Compiled(kernel.symbols + extra, outputs)
        self.n_extra = len(extra)
        sl = {name: sl for name, (sl, _) in self.fn.slices.items()}
        self.K, self.r, self.powers, self.P = sl["K"], sl["r"], sl["powers"], sl.get("P")
        self.m = m
        # (|U| - bound, U . s_ref) of each two-component slip, by position in the outputs
        g0 = sl["guard"].start if guards else 0
        self.guards = [(g0 + k, g0 + k + 1) for k in range(0, len(guards), 2)]

    @classmethod
    def of(cls, kernel, system: ModeSystem, mode: Mode):
        """The compiled function, or False when the mode has a law it does not compile."""
        try:
            return cls(kernel, system, mode)
        except _NotCompiled:
            return False

    def inputs(self, solver, mode: Mode) -> np.ndarray:
        """An input vector for a phase in *mode*: the solver's (parameters) and the sliding
        directions of its one-component contacts."""
        x = np.concatenate((solver.x, np.zeros(self.n_extra)))
        for i, c in self.directions:
            x[i] = mode.contacts[c][1].direction[0]
        return x

    def solve_with_powers(self, solver, x: np.ndarray, t: float, y: np.ndarray, mode: Mode):
        """As :meth:`ModeSystem.solve_with_powers`, with *x* from :meth:`inputs`; None where a
        guard fails (the index path decides there).

        Raises
        ------
        SingularMatrix
        """
        n, s = self.n, self.s
        x[0] = t
        x[1:1 + 2 * n] = y[:2 * n]
        for i, c in self.references:
            ref = solver.reference.get(c)
            if ref is None:
                return None
            x[i:i + len(ref)] = ref
        out = self.fn.raw(x)
        for margin, dot in self.guards:
            if out[margin] <= 0.0 or out[dot] == 0.0:
                return None
        lu, piv, sol, info = _dgesv(out[self.K].reshape((s, s), order="F"), out[self.r])
        if info != 0 or not (math.isfinite(sol @ sol) or np.all(np.isfinite(sol))):
            raise SingularMatrix("saddle-point system")
        solver.last = (t, y, mode, sol, lu, piv)
        weights = out[self.powers].reshape(2, self.m)
        total, friction = weights @ sol[n:]  # sol[n:] = -lambda
        solver.column_powers = -weights[0] * sol[n:]
        return sol, friction - total, -friction, (out[self.P] if self.P else None)


class _NotCompiled(Exception):
    """A mode :class:`ModeFunction` does not compile (the epsilon-linear friction law)."""


def system_of(kernel, mode: Mode) -> ModeSystem:
    """The (cached) :class:`ModeSystem` of *mode*'s structure for *kernel*."""
    return kernel.model.cached(("mode system", mode.structure), lambda: ModeSystem(kernel, mode))


def compliance_of(M: np.ndarray, B: np.ndarray, G: np.ndarray, j: int) -> float:
    """Effective normal compliance ``b = 1/((G M^-1 B)^-1)_jj`` of row *j* of a saddle-point
    system ``M a = F + B lambda``, ``G a + gamma = 0`` (the lower-right block of the inverse of
    ``[[M, -B], [G, 0]]`` is ``(G M^-1 B)^-1``); 0 when that matrix is singular."""
    n, m = M.shape[0], G.shape[0]
    M, B, G = (A.toarray() if issparse(A) else A for A in (M, B, G))   # sparse: many coordinates
    K = np.zeros((n + m, n + m))
    K[:n, :n] = M
    K[:n, n:] = -B
    K[n:, :n] = G
    e = np.zeros(n + m)
    e[n + j] = 1.0
    try:
        inv_jj = np.linalg.solve(K, e)[n + j]
    except np.linalg.LinAlgError:
        return 0.0
    return float(1.0 / inv_jj) if inv_jj != 0 else math.inf
