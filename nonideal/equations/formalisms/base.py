"""The :class:`Formalism` base class and the velocity reduction shared by the reduced forms.

Checklist for implementing a formalism (read before adding one):

1. Subclass :class:`Formalism`; set ``name`` (the CLI's ``--form``), ``title`` and ``citation``
   (source and equation numbers; say which code name is which symbol).
2. Implement :meth:`Formalism.derive` taking the kernel :class:`~nonideal.equations.dynamics.Dynamics`,
   the constraint rows to respect and the user's choice of independent coordinates; return an
   :class:`~nonideal.equations.eom.EquationsOfMotion` filled completely: ``A, c, Q_f`` (dynamics),
   ``B, G, gamma`` for the multipliers the form keeps, and ``R, r`` mapping the form's
   unknowns back to all accelerations.
3. Raise :class:`~nonideal.errors.FormNotApplicable` naming the form that applies instead when
   the model is outside the form's domain.  Never return a partial result.
4. Symbolic work stays cheap: no ``simplify``, no symbolic inversion beyond the dependent block
   of the constraints (use :func:`reduce_velocities`, which falls back to auxiliary symbols
   solved numerically when the explicit inverse would blow up).
5. Register the class in :data:`nonideal.equations.formalisms.FORMS` and add the form to the
   cross-form agreement tests (every gallery model, random admissible states).
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import numpy as np
import symengine as se
from scipy.linalg.lapack import zgesv as _zgesv

from ..dynamics import ConstraintRow, Dynamics, count_ops
from ..eom import Auxiliary, EquationsOfMotion
from ...errors import FormNotApplicable, SingularSystem, did_you_mean

__all__ = ["Formalism", "Reduction", "partition", "reduce_velocities", "split_rows", "numeric_instances", "vanishing"]


class Formalism:
    """Base class of a formalism (see the module docstring for the checklist)."""

    name: str = ""
    title: str = ""
    citation: str = ""
    branch: dict[str, float] | None = None   # Lagrange II: where to pick the constraints' roots
    #: the declared speeds ``[forms] independent`` names, in its order (the quasi-velocity forms
    #: keep them first); the other names of that list are the coordinates ``derive`` receives
    speed_order: tuple[str, ...] | None = None

    def derive(self, dyn: Dynamics, rows: list[ConstraintRow],
               independent: tuple[str, ...] | None) -> EquationsOfMotion:
        raise NotImplementedError


def split_rows(rows: list[ConstraintRow]) -> tuple[list[ConstraintRow], list[ConstraintRow]]:
    """Ideal rows (eliminated by the reduced forms) and non-ideal rows (kept with multipliers)."""
    ideal = [r for r in rows if r.reaction_kind == "ideal"]
    other = [r for r in rows if r.reaction_kind != "ideal"]
    return ideal, other


# ----------------------------------------------------------------------------- numerics helpers


def _random_point(rng: random.Random, count: int) -> list[float]:
    return [rng.uniform(0.2, 1.1) * rng.choice((-1, 1)) for _ in range(count)]


def _evaluate(dyn: Dynamics, exprs: list, points: list[list[float]],
              auxiliaries: tuple[Auxiliary, ...] = ()) -> list[np.ndarray]:
    """Complex values of *exprs* at *points* (values of ``q, q', q'', t``; the parameters'
    values are appended), through one compiled function (no per-entry substitution).

    Auxiliary symbols take the values that solve their linear systems at each point.
    """
    syms = dyn.q + dyn.qd + dyn.qdd + [dyn.t]
    pvals = list(dyn.model.parameter_values.values())
    aux_syms = [s for aux in auxiliaries for s in aux.symbols]
    fn = se.Lambdify(syms + dyn.params + aux_syms, [se.sympify(e) for e in exprs], real=False, cse=False)
    systems = []
    for aux in auxiliaries:
        # only the nonzero entries are compiled (block systems are mostly zeros)
        entries = [(i, e) for i, e in enumerate(list(aux.K) + list(aux.Y)) if e != 0]
        fk = se.Lambdify(syms + dyn.params, [e for _, e in entries], real=False, cse=False)
        systems.append((fk, [i for i, _ in entries], aux.K.shape, aux.Y.shape))
    out = []
    for point in points:
        base = np.array(list(point) + pvals, dtype=complex)
        values = [base]
        for fk, where, kshape, yshape in systems:
            ky = np.zeros(kshape[0] * kshape[1] + yshape[0] * yshape[1], dtype=complex)
            ky[where] = np.asarray(fk(base), dtype=complex).ravel()
            K, Y = ky[:kshape[0] * kshape[1]].reshape(kshape), ky[kshape[0] * kshape[1]:].reshape(yshape)
            X, info = _zgesv(K, Y)[2:]
            values.append(X.ravel() if info == 0 else np.full(Y.size, np.nan, dtype=complex))
        out.append(np.asarray(fn(np.concatenate(values)), dtype=complex).ravel())
    return out


def numeric_instances(dyn: Dynamics, exprs: list, count: int = 2, seed: int = 7,
                      with_initial: bool = False) -> list[np.ndarray]:
    """Evaluate expressions at *count* generic points (random q, q', q'', t; parameter values).

    With ``with_initial`` the first point takes the coordinates of the model's initial state
    when they are all given (so that choices made from these values suit the simulation).
    Complex values give their real part, non-finite ones NaN.
    """
    rng = random.Random(seed)
    n = dyn.n
    init = None
    if with_initial:
        values = dyn.model.numeric_initial()
        if all(c in values for c in dyn.model.coordinates):
            init = [values[c] for c in dyn.model.coordinates]
    points = []
    for k in range(count + (1 if init else 0)):
        point = _random_point(rng, 3 * n + 1)
        if k == 0 and init:
            point[:n] = init
            point[3 * n] = dyn.model.t0
        points.append(point)
    out = []
    with np.errstate(all="ignore"):
        for vals in _evaluate(dyn, exprs, points):
            real = vals.real.copy()
            real[~np.isfinite(vals)] = np.nan
            out.append(real)
    return out


# ----------------------------------------------------------------------------- reduction


@dataclass(frozen=True)
class Reduction:
    """Velocity reduction ``q' = V p + v0`` / ``q'' = V p' + w`` on the constraint manifold.

    Attributes
    ----------
    dependent, independent : list of int
        Coordinate indices; ``p`` are the velocities of the independent ones.
    V : se.DenseMatrix, shape (n_q, k)
    w : se.DenseMatrix, shape (n_q, 1)
        Particular acceleration satisfying ``G w + gamma = 0`` with zero independent part.
    auxiliaries : tuple of Auxiliary
        Non-empty when V and w are kept as symbols (explicit inverse too large).
    """

    dependent: list[int]
    independent: list[int]
    V: object
    w: object
    auxiliaries: tuple[Auxiliary, ...]

    @property
    def explicit(self) -> bool:
        return not self.auxiliaries


def _choose_dependent(dyn: Dynamics, G: list[list], names: list[str],
                      independent: tuple[str, ...] | None, row_names: list[str],
                      holonomic: int = 0) -> list[int]:
    """Pick one dependent coordinate per constraint row (Markowitz pivoting, numerically safe).

    *independent* (``[forms] independent``: the coordinates kept independent as far as the
    constraints allow, the same list for every form) decides the choice: exactly ``n - m``
    names are the independent velocities themselves; more (at most ``n - h``, the coordinates
    Lagrange II keeps) keep every unlisted coordinate dependent and take the other dependent
    velocities among the listed ones by pivoting; fewer keep the listed ones independent and
    choose the rest among the unlisted.  *holonomic* is ``h``, the number of holonomic rows."""
    m, n = len(G), dyn.n
    coords = list(dyn.model.coordinates)
    flat = [G[i][j] for i in range(m) for j in range(n)]
    # the initial state guides an automatic choice; a given choice is only checked generically
    inst = [x.reshape(m, n) for x in numeric_instances(dyn, flat, count=2,
                                                         with_initial=independent is None
                                                         or len(independent) != n - m)]
    listed = set()
    if independent is not None:
        ind = [coords.index(c) for c in independent]
        dep = [j for j in range(n) if j not in ind]
        if len(ind) > n - holonomic:
            raise FormNotApplicable(
                f"[forms] independent: {len(ind)} coordinates listed, but the {holonomic} holonomic "
                f"constraint(s) on {n} coordinates leave {n - holonomic} independent coordinates "
                f"(and the {m} velocity-level constraint(s) {', '.join(row_names)} leave "
                f"{n - m} independent velocities); list at most {n - holonomic}: the coordinates "
                "kept by lagrange2 and the linearization, among which the reduced forms choose "
                f"their {n - m} independent velocities -- or exactly {n - m} to choose those yourself"
            )
        if len(dep) == m:
            for Gn in inst:
                if np.linalg.matrix_rank(Gn[:, dep]) < m:
                    raise FormNotApplicable(
                        f"[forms] independent = {list(independent)}: the constraints "
                        f"({', '.join(row_names)}) cannot be solved for the velocities of "
                        f"{[coords[j] for j in dep]}; choose other independent coordinates"
                    )
            return dep
        listed = set(ind)
    pattern = [[G[i][j] != 0 for j in range(n)] for i in range(m)]
    work = [g.copy() for g in inst]
    rows_left, cols_left, dep = list(range(m)), list(range(n)), []
    ops = [[count_ops([G[i][j]]) for j in range(n)] for i in range(m)]
    for _ in range(m):
        best = None
        for i in rows_left:
            rnnz = sum(pattern[i][j] for j in cols_left)
            for j in cols_left:
                if not pattern[i][j]:
                    continue
                mags = [abs(W[i, j]) / (np.abs(W[i, cols_left]).max() + 1e-300) for W in work]
                if min(mags) < 1e-6:
                    continue
                cnnz = sum(pattern[r][j] for r in rows_left)
                key = (j in listed, (rnnz - 1) * (cnnz - 1), -round(mags[0], 3), ops[i][j], -j)
                if best is None or key < best[0]:
                    best = (key, i, j)
        if best is None:
            bad = [row_names[i] for i in rows_left]
            raise SingularSystem(
                f"constraints {', '.join(repr(b) for b in bad)} are dependent on the others "
                "(their velocity-level gradients are linearly dependent); remove redundant "
                "constraints"
            )
        _, pi, pj = best
        for W in work:
            piv = W[pi, pj]
            for r in rows_left:
                if r != pi and W[r, pj] != 0:
                    W[r, :] -= W[r, pj] / piv * W[pi, :]
        for r in rows_left:
            if r != pi and pattern[r][pj]:
                pattern[r] = [a or b for a, b in zip(pattern[r], pattern[pi])]
        rows_left.remove(pi)
        cols_left.remove(pj)
        dep.append(pj)
    if listed:
        unlisted = [j for j in range(n) if j not in listed]
        lost = ([coords[j] for j in unlisted if j not in dep] if len(unlisted) <= m
                else [coords[j] for j in dep if j in listed])
        if lost:
            raise FormNotApplicable(
                f"[forms] independent = {[coords[j] for j in sorted(listed)]}: the constraints "
                f"({', '.join(row_names)}) cannot "
                + (f"be solved for the velocities of {lost}" if len(unlisted) <= m else
                   f"keep the velocities of {lost} independent")
                + "; choose other independent coordinates"
            )
    return sorted(dep)


def symbolic_solve(K: list[list], Y: list[list], budget: int):
    """Solve K X = Y (square K) by Gaussian elimination with sparse-aware pivoting.

    Returns the list-of-lists X, or None when the operation count exceeds *budget*.
    """
    m = len(K)
    p = len(Y[0]) if Y else 0
    aug = [list(K[i]) + list(Y[i]) for i in range(m)]
    order = []
    remaining = list(range(m))
    for col in range(m):
        cands = [r for r in remaining if aug[r][col] != 0]
        if not cands:
            return None
        piv = min(cands, key=lambda r: (sum(1 for c in range(col, m) if aug[r][c] != 0),
                                        count_ops([aug[r][col]])))
        remaining.remove(piv)
        order.append(piv)
        for r in remaining:
            if aug[r][col] != 0:
                f = aug[r][col] / aug[piv][col]
                aug[r] = [aug[r][c] - f * aug[piv][c] if c > col and aug[piv][c] != 0 else
                          (se.Integer(0) if c == col else aug[r][c]) for c in range(m + p)]
        if count_ops([x for row in aug for x in row]) > budget:
            return None
    X = [[se.Integer(0)] * p for _ in range(m)]
    for col in reversed(range(m)):
        r = order[col]
        for c in range(p):
            acc = aug[r][m + c]
            for k in range(col + 1, m):
                if aug[r][k] != 0:
                    acc -= aug[r][k] * X[k][c]
            X[col][c] = acc / aug[r][col]
        if count_ops([x for x in X[col]]) > budget:
            return None
    return X


def partition(dyn: Dynamics, rows: list[ConstraintRow],
              independent: tuple[str, ...] | None) -> tuple[list[int], list[int]]:
    """Dependent and independent coordinate indices for the velocity-level rows ``G`` of *rows*.

    *independent* (coordinate names) is checked; without it a sparse, well-conditioned choice
    is made (:func:`_choose_dependent`).
    """
    coords = list(dyn.model.coordinates)
    if not rows:
        return [], list(range(dyn.n))
    if independent is not None and dyn.model.speeds:   # speed names are the speed forms' choice
        independent = tuple(c for c in independent if c not in dyn.model.speeds) or None
    if independent is not None:
        bad = [c for c in independent if c not in coords]
        if bad:
            raise FormNotApplicable(
                f"[forms] independent: '{bad[0]}' is not a coordinate{did_you_mean(bad[0], coords)}"
            )
    dep = _choose_dependent(dyn, [list(r.G) for r in rows], coords, independent, [r.name for r in rows],
                            sum(1 for r in rows if r.order == 0))
    return dep, [j for j in range(dyn.n) if j not in dep]


def reduce_velocities(dyn: Dynamics, rows: list[ConstraintRow],
                      independent: tuple[str, ...] | None, factor: int = 2,
                      floor: int = 2000) -> Reduction:
    """Eliminate the dependent velocities of *rows*: ``q'' = V p' + w``.

    The dependent block ``G_D`` is solved symbolically when that stays small (a budget of
    ``max(floor, factor * size of the input)`` operations); otherwise the entries of ``V`` and ``w`` become
    auxiliary symbols defined by ``G_D [V_D | w_D] = [-G_I | -gamma]`` and solved numerically.
    """
    n = dyn.n
    coords = list(dyn.model.coordinates)
    m = len(rows)
    dep, ind = partition(dyn, rows, independent)
    if m == 0:
        return Reduction([], ind, se.eye(n), se.zeros(n, 1), ())
    G = [list(r.G) for r in rows]
    gamma = [r.gamma for r in rows]
    k = len(ind)
    K = [[G[i][j] for j in dep] for i in range(m)]
    Y = [[-G[i][j] for j in ind] + [-gamma[i]] for i in range(m)]
    size_in = count_ops([x for row in K for x in row] + [x for row in Y for x in row])
    X = symbolic_solve(K, Y, max(floor, factor * size_in))
    aux: tuple[Auxiliary, ...] = ()
    if X is None:
        syms = [[se.Symbol(f"V[{coords[dep[i]]},{coords[ind[c]]}]") for c in range(k)]
                + [se.Symbol(f"w[{coords[dep[i]]}]")] for i in range(m)]
        aux = (Auxiliary(se.Matrix(syms), se.Matrix(K), se.Matrix(Y),
                         "dependent-velocity coefficients V[d,i] and w[d] solve "
                         "G_D [V_D | w_D] = [-G_I | -gamma] (solved numerically)"),)
        X = syms
    V = se.zeros(n, k)
    w = se.zeros(n, 1)
    for c, j in enumerate(ind):
        V[j, c] = 1
    for i, j in enumerate(dep):
        for c in range(k):
            V[j, c] = X[i][c]
        w[j, 0] = X[i][k]
    return Reduction(dep, ind, V, w, aux)


def project_rows(rows: list[ConstraintRow], red: Reduction, n: int):
    """Kept (non-ideal) rows expressed in the reduced unknowns: ``G V``, ``G w + gamma``, ``V^T B``."""
    k = len(red.independent)
    m = len(rows)
    G = se.zeros(m, k)
    gamma = se.zeros(m, 1)
    B = se.zeros(k, m)
    for i, r in enumerate(rows):
        for c in range(k):
            G[i, c] = sum((r.G[j] * red.V[j, c] for j in range(n) if r.G[j] != 0 and red.V[j, c] != 0),
                          se.Integer(0))
            B[c, i] = sum((red.V[j, c] * r.B[j] for j in range(n) if r.B[j] != 0 and red.V[j, c] != 0),
                          se.Integer(0))
        gamma[i, 0] = r.gamma + sum((r.G[j] * red.w[j, 0] for j in range(n) if r.G[j] != 0 and red.w[j, 0] != 0),
                                    se.Integer(0))
    return G, gamma, B


def quadratic_form(V, M, n: int, k: int):
    """``V^T M V`` exploiting zeros (V is mostly identity/zero)."""
    MV = se.zeros(n, k)
    for i in range(n):
        for c in range(k):
            MV[i, c] = sum((M[i, j] * V[j, c] for j in range(n) if V[j, c] != 0 and M[i, j] != 0), se.Integer(0))
    A = se.zeros(k, k)
    for a in range(k):
        for b in range(a, k):
            A[a, b] = sum((V[i, a] * MV[i, b] for i in range(n) if V[i, a] != 0 and MV[i, b] != 0), se.Integer(0))
            A[b, a] = A[a, b]
    return A, MV


def transpose_times(V, x, n: int, k: int):
    """``V^T x`` for a column ``x``."""
    out = se.zeros(k, 1)
    for c in range(k):
        out[c, 0] = sum((V[i, c] * x[i] for i in range(n) if V[i, c] != 0 and x[i] != 0), se.Integer(0))
    return out


def vanishing(dyn: Dynamics, groups: list[list], count: int = 4, seed: int = 11,
              rtol: float = 1e-9, auxiliaries: tuple[Auxiliary, ...] = ()) -> list[bool]:
    """Which sums vanish identically, judged at *count* generic points.

    Each group lists the terms of one sum.  A sum is taken as zero when, at every generic
    point (random ``q, q', q'', t``; the parameter values; *auxiliaries* solved there) where
    its terms are finite, ``|sum| <= rtol * sum |term|`` -- complex values included (a square
    root of a negative number at a random point is no reason to keep a term; terms that are
    all exactly zero there, e.g. auxiliary symbols whose values vanish, count as zero) -- and
    at least two points gave finite terms.  A group of symbolically zero terms is zero.  Cheap: one
    compiled complex evaluation of all terms, no simplification.
    """
    exprs = [[se.sympify(e) for e in g] for g in groups]
    zero = [all(e == 0 for e in g) for g in exprs]
    flat = [e for g, z in zip(exprs, zero) if not z for e in g]
    if not flat:
        return zero
    rng = random.Random(seed)
    points = [_random_point(rng, 3 * dyn.n + 1) for _ in range(count)]
    with np.errstate(all="ignore"):
        values = _evaluate(dyn, flat, points, auxiliaries)
    # rounding noise of auxiliary values (1e-16 where a coefficient is exactly constant) is
    # judged against the largest sum of the point, not against its own vanishing terms
    scales = []
    for vals in values:
        finite = np.abs(vals[np.isfinite(vals)])
        scales.append(float(finite.max()) if finite.size else 0.0)
    out = []
    pos = 0
    for g, z in zip(exprs, zero):
        if z:
            out.append(True)
            continue
        sl = slice(pos, pos + len(g))
        pos += len(g)
        ok, informative = True, 0
        for vals, scale in zip(values, scales):
            v = vals[sl]
            if not np.all(np.isfinite(v)):
                continue
            mag = max(float(np.sum(np.abs(v))), 1e-6 * scale if auxiliaries else 0.0)
            informative += 1
            if abs(np.sum(v)) > rtol * mag:
                ok = False
                break
        out.append(ok and informative >= 2)
    return out
