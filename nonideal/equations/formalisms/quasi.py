"""Generalized speeds as the unknowns: the basis shared by ``kane``, ``boltzmann_hamel`` and
``poincare_chetaev``.

The speeds are ``u = W_u(q, t) q' + w_u(q, t)`` (the model's ``[speeds]``; without them the
velocities of the independent coordinates, chosen as for Maggi's form).  The ideal constraints,
linear in the velocities (holonomic ones at velocity level), are ``G q' + g = 0``; their
left-hand sides are taken as further speeds ``sigma`` that vanish on the motion.  Of the
declared speeds, ``k = n - m`` independent ones ``p`` are kept -- in the declared order, each
one that is independent of the constraints and of the speeds kept before it -- so that

    W = [W_p; G],  w = [w_p; g]:       [p; sigma] = W q' + w,      W invertible,
    q' = Phi [p; sigma] + phi0,        Phi = W^-1,  phi0 = -W^-1 w,

and on the motion (``sigma = 0``) ``q' = Phi_p p + phi0``, ``q'' = Phi_p p' + r`` with
``r = -Phi [dW_p/dt q' + dw_p/dt; gamma]`` (``gamma`` the constraints' acceleration terms).
``Phi_p`` (the first ``k`` columns) holds the partial velocities of Kane & Levinson 1985
(ch. 3, the coefficients of the speeds in the velocities).  The results are written in the
speeds: ``q'`` is replaced by ``Phi_p p + phi0`` and the speeds are auxiliary symbols
evaluated from the state (``p = W_p q' + w_p``).

Euler parameters: the frame turns by the rotation of ``e/|e|`` (:mod:`nonideal.modeling.kinematics`),
so declared speeds (three angular ones) are blind to the radial rate ``e . e'``.  When the
declared speeds leave it undetermined, the radial rate of each such frame is taken as one more
combination ``sigma`` (:func:`radial_rows`: ``e . e' = 0`` with ``(e . e')' = 0``, the equation
the regularized kinetic energy gives the other forms): its reaction has no part along the
partial velocities, and ``q'' = Phi_p p' + r`` keeps ``|e|`` constant.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import symengine as se

from ..dynamics import count_ops
from ..eom import Auxiliary, EquationsOfMotion
from ...errors import FormNotApplicable, SingularSystem
from .base import numeric_instances, partition, project_rows, split_rows, symbolic_solve
from .blocksolve import adjugate_solve, block_solve
from .folding import ADJUGATE_MAX, fold_matrix, fold_trig, foldable, norm_reducer

__all__ = ["SpeedBasis", "speed_basis", "velocity_rows", "Reduced", "radial_rows", "PartialVelocities",
           "partial_velocities", "quasi_equations", "ADJUGATE_MAX", "fold_matrix", "fold_trig", "norm_reducer"]


@dataclass(frozen=True)
class Reduced:
    """``q'' = V p' + w`` for :func:`~nonideal.equations.formalisms.base.project_rows`."""

    V: object
    w: object

    @property
    def independent(self) -> range:
        return range(self.V.shape[1])


def velocity_rows(dyn, rows, form: str) -> tuple[list[list], list]:
    """``(G, g)``: the ideal rows at velocity level, ``G q' + g = 0`` (linear required)."""
    G, g = [], []
    zero = {v: se.Integer(0) for v in dyn.qd}
    for r in rows:
        if r.order not in (0, 1) or r.velocity is None:
            raise FormNotApplicable(
                f"the {form} form is written for constraints of the first order; constraint "
                f"'{r.name}' is of order {r.order}: use maggi or appell")
        vel = se.sympify(r.velocity)
        row = [se.diff(vel, v) for v in dyn.qd]
        if any(dyn.depends(x, 1) for x in row):
            raise FormNotApplicable(
                f"the {form} form needs constraints linear in the velocities; constraint "
                f"'{r.name}' is not linear in the velocities: use maggi or appell")
        G.append(row)
        g.append(vel.subs(zero))
    return G, g


@dataclass(frozen=True)
class SpeedBasis:
    """The speeds of a quasi-velocity form (see the module docstring).

    Attributes
    ----------
    names : tuple of str
        The independent speeds ``p`` (``k`` of them).
    symbols : list of se.Symbol
        Their symbols (the velocity symbols themselves when no speeds are declared).
    definitions : list
        ``p`` in ``q, q', t``.
    sigma : list of se.Symbol
        Symbols of the constraint speeds (zero on the motion).
    W, w : se.DenseMatrix
        ``[W_p; G]`` (n x n) and ``[w_p; g]`` (n x 1).
    declared : bool
        Whether the model declares ``[speeds]``.
    dropped : tuple of str
        Declared speeds not kept (fixed by the constraints and the kept ones).
    rows : tuple of ConstraintRow
        The rows of ``G`` (the ideal constraints, then the radial rows of Euler parameters the
        declared speeds leave undetermined); their ``gamma`` enter ``r``.
    """

    names: tuple[str, ...]
    symbols: list
    definitions: list
    sigma: list
    W: object
    w: object
    declared: bool
    dropped: tuple[str, ...]
    rows: tuple = ()

    @property
    def k(self) -> int:
        return len(self.names)

    @property
    def unknowns(self) -> tuple[str, ...]:
        return tuple(n + "'" for n in self.names)

    def accelerations(self) -> list:
        """Symbols of the unknown speed derivatives ``p'``."""
        return [se.Symbol(n) for n in self.unknowns]

    def auxiliaries(self) -> tuple[Auxiliary, ...]:
        """The declared speeds as auxiliary symbols evaluated from the state (none when the
        speeds are the independent velocities themselves)."""
        if not self.declared or not self.k:
            return ()
        return (Auxiliary(se.Matrix([[s] for s in self.symbols]), se.eye(self.k),
                          se.Matrix([[d] for d in self.definitions]),
                          "speeds " + ", ".join(f"{n} = {d}" for n, d in zip(self.names, self.definitions))
                          + " (evaluated from the state)"),)

    @property
    def radial(self) -> tuple:
        """The radial rows of Euler parameters among :attr:`rows` (see :func:`radial_rows`)."""
        return tuple(r for r in self.rows if r.reaction_kind == RADIAL)

    def note(self) -> str:
        if not self.declared:
            return ("no [speeds] declared: the speeds are the independent velocities "
                    + ", ".join(self.names))
        out = "speeds " + ", ".join(self.names)
        if self.dropped:
            out += " (" + ", ".join(self.dropped) + " fixed by the constraints)"
        for r in self.radial:
            out += f"; the radial rate of frame {r.name[:-len('_norm')]}'s Euler parameters held at zero"
        return out


RADIAL = "radial"   # the reaction kind of the radial rows of Euler parameters


def radial_rows(dyn) -> list:
    """``e . e' = 0`` at velocity level, ``e . e'' + e' . e' = 0`` at acceleration level, for
    every frame given by Euler parameters: rows named ``<frame>_norm`` (not constraints of the
    model: the radial rate the declared speeds do not determine, held at zero)."""
    from ..dynamics import ConstraintRow

    out = []
    index = {s: j for j, s in enumerate(dyn.q)}
    for f in getattr(dyn.model, "frames", ()) or ():
        if not getattr(f, "quaternion", None):
            continue
        e = [se.Symbol(str(c)) for c in f.quaternion]
        if not all(x in index for x in e):
            continue
        G = [se.Integer(0)] * dyn.n
        for x in e:
            G[index[x]] = x
        ed = [dyn.qd[index[x]] for x in e]
        out.append(ConstraintRow(f"{f.name}_norm", tuple(G), sum((v * v for v in ed), se.Integer(0)), tuple(G),
                                 sum((x * x for x in e), se.Integer(0)) / 2,
                                 sum((x * v for x, v in zip(e, ed)), se.Integer(0)), 0, False, RADIAL))
    return out


def speed_basis(dyn, rows, independent, form: str, order: tuple[str, ...] | None = None) -> SpeedBasis:
    """Choose the independent speeds for the ideal *rows* (see the module docstring): the
    declared speeds named in *order* (``[forms] independent``) first, in that order, then the
    others in the declared order; a listed speed that cannot be kept is refused (exit 2)."""
    model = dyn.model
    n = dyn.n
    rows = list(rows)
    if model.speeds:   # the radial rates of Euler parameters the declared speeds leave free
        rows += _undetermined(dyn, rows, radial_rows(dyn))
    G, g = velocity_rows(dyn, rows, form)
    m = len(G)
    zero = {v: se.Integer(0) for v in dyn.qd}
    if model.speeds:
        from ...modeling.symbols import to_se

        cand = [(name, to_se(e)) for name, e in model.speeds.items()]
        if order:
            cand = sorted(cand, key=lambda c: order.index(c[0]) if c[0] in order else len(order))
        declared = True
    else:
        _, ind = partition(dyn, rows, independent)
        cand = [(model.coordinates[j] + "'", dyn.qd[j]) for j in ind]
        declared = False
    # the speeds' coefficients with the trigonometric identities folded (a body component of an
    # angular velocity written through the frames carries terms of the other angles that cancel)
    reduce = norm_reducer(model) or (lambda x: x)
    cand = [(name, fold_trig(reduce(e))) for name, e in cand]
    Wc = [[fold_trig(se.diff(e, v)) for v in dyn.qd] for _, e in cand]
    flat = [x for row in G + Wc for x in row]
    inst = [x.reshape(m + len(cand), n) for x in numeric_instances(dyn, flat, count=2)]
    inst = [x for x in inst if np.all(np.isfinite(x))] or inst

    def rank(sel):
        return min(np.linalg.matrix_rank(x[sel], tol=1e-9 * (1 + np.abs(x[sel]).max(initial=0))) if sel
                   else 0 for x in inst)

    base = list(range(m))
    if rank(base) < m:
        raise SingularSystem(
            "the constraints " + ", ".join(f"'{r.name}'" for r in rows) + " are dependent (their "
            "velocity-level gradients are linearly dependent); remove redundant constraints")
    chosen = []
    for c in range(len(cand)):
        if rank(base + chosen + [m + c]) == m + len(chosen) + 1:
            chosen.append(m + c)
    if m + len(chosen) < n:
        raise FormNotApplicable(
            f"the {form} form: the speeds {', '.join(n_ for n_, _ in cand)} with the constraints "
            f"determine only {m + len(chosen)} of the {n} velocities; declare speeds that "
            "determine every velocity")
    sel = [c - m for c in chosen]
    names = tuple(cand[c][0] for c in sel)
    lost = [nm for nm in (order or ()) if nm not in names]
    if declared and lost:
        fixed = [r.name for r in rows if r.reaction_kind != RADIAL]
        by = (f"the constraints {', '.join(fixed)} and " if fixed else "")
        raise FormNotApplicable(
            f"[forms] independent = {list(order)}: the speed '{lost[0]}' is fixed by {by}the speeds "
            f"listed before it, so it cannot be independent; list {len(names)} speeds that the "
            f"constraints leave free (e.g. {', '.join(names)})")
    defs = [cand[c][1] for c in sel]
    W = se.Matrix([Wc[c] for c in sel] + G) if n else se.zeros(0, 0)
    w = se.Matrix([[d.subs(zero)] for d in defs] + [[x] for x in g]) if n else se.zeros(0, 1)
    symbols = [se.Symbol(nm) for nm in names] if declared else [dyn.qd[model.coordinates.index(nm[:-1])] for nm in names]
    sigma = [se.Symbol(f"sigma[{r.name}]") for r in rows]
    return SpeedBasis(names, symbols, defs, sigma, W, w, declared,
                      tuple(cand[c][0] for c in range(len(cand)) if c not in sel) if declared else (),
                      tuple(rows))


def _undetermined(dyn, rows, radial) -> list:
    """The radial rows not determined by the declared speeds and the ideal *rows* (judged at
    generic states; the speeds are blind to the radial rates when they are written through the
    frames, so each radial row is then needed)."""
    if not radial:
        return []
    from ...modeling.symbols import to_se

    exprs = [to_se(e) for e in dyn.model.speeds.values()]
    base = [[se.diff(e, v) for v in dyn.qd] for e in exprs] + [list(r.G) for r in rows]
    extra = [list(r.G) for r in radial]
    flat = [x for row in base + extra for x in row]
    inst = [x.reshape(len(base) + len(extra), dyn.n) for x in numeric_instances(dyn, flat, count=2)]
    inst = [x for x in inst if np.all(np.isfinite(x))] or inst
    out = []
    for k, r in enumerate(radial):
        sel = list(range(len(base))) + [len(base) + j for j in range(k)]
        with_r = sel + [len(base) + k]
        if all(np.linalg.matrix_rank(x[with_r], tol=1e-9 * (1 + np.abs(x).max()))
               > np.linalg.matrix_rank(x[sel], tol=1e-9 * (1 + np.abs(x).max())) for x in inst):
            out.append(r)
    return out


def invert(basis: SpeedBasis, dyn, form: str, columns: list | None = None, factor: int = 4,
           floor: int = 4000, on_sphere: bool = False):
    """Solve ``W X = Y`` symbolically for ``Y = [I | -w]`` (default) or the given *columns*;
    None when the explicit solution exceeds the size budget.

    A small ``W`` (at most :data:`ADJUGATE_MAX` rows) is inverted as ``adj(W) / det(W)`` with
    the determinant simplified by SymPy (``cos^2 + sin^2`` in a denominator would otherwise
    stay); a larger one block by block when its rows fall into groups (a body's rotation and
    translation: :func:`~nonideal.equations.formalisms.blocksolve.block_solve`), else by sparse
    Gaussian elimination (:func:`symbolic_solve`)."""
    n = dyn.n
    Wl = [[basis.W[i, j] for j in range(n)] for i in range(n)]
    if columns is None:
        columns = [[se.Integer(1 if i == j else 0) for i in range(n)] for j in range(n)]
        columns.append([-basis.w[i, 0] for i in range(n)])
    Y = [[col[i] for col in columns] for i in range(n)]
    size = count_ops([x for row in Wl for x in row] + [x for row in Y for x in row])
    reduce = norm_reducer(dyn.model) or (lambda x: x)
    if n <= ADJUGATE_MAX and count_ops([x for row in Wl for x in row]) <= 400:
        X = adjugate_solve(Wl, Y, reduce)
        if X is not None and count_ops([x for row in X for x in row]) <= max(floor, factor * size):
            return X
    if n > ADJUGATE_MAX and norm_reducer(dyn.model) is not None:
        # a body in Euler parameters: its rotation and translation solved group by group; reduced
        # on |e| = 1 when *on_sphere* (the partial velocities, read there), else exact at any |e|
        # (Boltzmann-Hamel and Poincare-Chetaev differentiate the inverse)
        X = block_solve(Wl, Y, reduce if on_sphere else (lambda x: x), max(floor, factor * size))
        if X is not None:
            return X
    return symbolic_solve(Wl, Y, max(floor, factor * size))


@dataclass(frozen=True)
class PartialVelocities:
    """``q' = Phi p + phi0`` and ``q'' = Phi p' + r`` on the constraints (:func:`partial_velocities`).

    Attributes
    ----------
    basis : SpeedBasis
    Phi, r : se.DenseMatrix
        n x k and n x 1: written explicitly, or auxiliary symbols ``Phi[q,p]``, ``r[q]``.
    subs : dict
        ``q' -> Phi p + phi0`` (the velocities in the speeds) when explicit, else empty.
    auxiliaries : tuple of Auxiliary
        The linear system of ``Phi`` and ``r`` when they are not explicit.
    """

    basis: SpeedBasis
    Phi: object
    r: object
    subs: dict
    auxiliaries: tuple


def partial_velocities(dyn, ideal, independent, form: str, order=None) -> PartialVelocities:
    """The speeds of *form* for the ideal rows, their partial velocities ``Phi`` (Kane &
    Levinson 1985, sec. 4.4) and the acceleration terms ``r``: solved symbolically when small
    (:func:`invert`), else as auxiliary symbols solved numerically at each evaluation."""
    basis = speed_basis(dyn, ideal, independent, form, order)
    n, k = dyn.n, basis.k
    b = [dyn.dt(d, with_acceleration=False) for d in basis.definitions] + [r.gamma for r in basis.rows]
    cols = [[se.Integer(1 if i == c else 0) for i in range(n)] for c in range(k)]
    cols.append([-basis.w[i, 0] for i in range(n)])
    cols.append([-x for x in b])
    X = invert(basis, dyn, form, cols, on_sphere=True)
    coords = dyn.model.coordinates
    if X is None:   # too large to write: partial velocities solved numerically
        syms = [[se.Symbol(f"Phi[{coords[i]},{basis.names[c]}]") for c in range(k)]
                + [se.Symbol(f"r[{coords[i]}]")] for i in range(n)]
        Y = se.Matrix([[cols[c][i] for c in range(k)] + [cols[k + 1][i]] for i in range(n)])
        aux = (Auxiliary(se.Matrix(syms), basis.W, Y,
                         "partial velocities Phi[q,p] and r[q] solve W [Phi | r] = [E_p | -(W' q' + w')]"),)
        return PartialVelocities(basis, se.Matrix([row[:k] for row in syms]),
                                 se.Matrix([[row[k]] for row in syms]), {}, aux)
    Phi = se.Matrix([[X[i][c] for c in range(k)] for i in range(n)])
    r = se.Matrix([[X[i][k + 1]] for i in range(n)])
    subs = {dyn.qd[i]: sum((X[i][c] * basis.symbols[c] for c in range(k)), se.Integer(0)) + X[i][k]
            for i in range(n)}
    return PartialVelocities(basis, Phi, r, subs, ())


def to_speeds(expr, subs: dict):
    """An expression in ``q, q', t`` written in the speeds (``q' -> Phi_p p + phi0``)."""
    return se.sympify(expr).subs(subs) if subs else se.sympify(expr)


@dataclass(frozen=True)
class QuasiLagrangian:
    """``T*(q, u, t) = T(q, Phi u + phi0, t)`` over the full set ``u = [p; sigma]`` and what the
    Boltzmann--Hamel and Poincaré--Chetaev forms share (:func:`quasi_lagrangian`).

    Attributes
    ----------
    Phi, phi0 : se.DenseMatrix
        ``q' = Phi u + phi0`` (n x n, n x 1), in ``q, t``.
    u : list
        The full set of speed symbols, independent ones first.
    qdot : list
        ``q'`` in the speeds on the motion (``sigma = 0``).
    Tstar : expression
    dT : list
        ``dT*/du_k`` for every speed of the full set.
    Pi : se.DenseMatrix
        ``Phi_p^T Q`` (k x 1) in the speeds: the generalized forces of the independent speeds.
    R, r : se.DenseMatrix
        ``q'' = R p' + r`` in the speeds.
    """

    basis: SpeedBasis
    Phi: object
    phi0: object
    u: list
    qdot: list
    Tstar: object
    dT: list
    Pi: object
    R: object
    r: object
    on_motion: dict

    def ddt(self, dyn, expr):
        """Total time derivative of ``f(q, u, t)`` along the motion: ``q' -> qdot``, ``p' ->``
        the unknown symbols, ``sigma' = 0``."""
        expr = se.sympify(expr)
        free = expr.free_symbols
        out = se.diff(expr, dyn.t) if dyn.t in free else se.Integer(0)
        for j, qj in enumerate(dyn.q):
            if qj in free:
                out += se.diff(expr, qj) * self.qdot[j]
        for s, a in zip(self.basis.symbols, self.basis.accelerations()):
            if s in free:
                out += se.diff(expr, s) * a
        return out


def quasi_lagrangian(dyn, basis: SpeedBasis, ideal, form: str) -> QuasiLagrangian:
    """Invert ``W`` explicitly and write ``T`` in the speeds (FormNotApplicable when the
    explicit inverse would be too large: then ``kane``, which needs no derivative of ``Phi``)."""
    n, k = dyn.n, basis.k
    X = invert(basis, dyn, form)
    if X is None:
        raise FormNotApplicable(
            f"the {form} form needs the velocities written explicitly in the speeds, and the "
            f"inverse of the {n} x {n} speed matrix is too large to write; use kane (its partial "
            "velocities are solved numerically) or maggi")
    Phi = se.Matrix([[X[i][c] for c in range(n)] for i in range(n)])
    phi0 = se.Matrix([[X[i][n]] for i in range(n)])
    u = list(basis.symbols) + list(basis.sigma)
    full = [sum((Phi[i, c] * u[c] for c in range(n) if Phi[i, c] != 0), se.Integer(0)) + phi0[i, 0]
            for i in range(n)]
    if basis.declared:
        subs = {dyn.qd[i]: full[i] for i in range(n)}
    else:   # the speeds are velocity symbols: substitute the dependent ones only
        own = {s: None for s in basis.symbols}
        subs = {dyn.qd[i]: full[i] for i in range(n) if dyn.qd[i] not in own}
    zero_sigma = {s: se.Integer(0) for s in basis.sigma}
    Tstar = se.sympify(dyn.T).subs(subs)
    dT = [se.diff(Tstar, s) for s in u]
    qdot = [se.sympify(f).subs(zero_sigma) for f in full]
    on_motion = {dyn.qd[i]: qdot[i] for i in range(n)}
    if not basis.declared:
        on_motion = {q: v for q, v in on_motion.items() if q not in set(basis.symbols)}
    Pi = se.zeros(k, 1)
    for r_ in range(k):
        Pi[r_, 0] = sum((Phi[j, r_] * se.sympify(dyn.Q[j]) for j in range(n) if Phi[j, r_] != 0 and dyn.Q[j] != 0),
                        se.Integer(0)).subs(on_motion)
    b = [dyn.dt(d, with_acceleration=False) for d in basis.definitions] + [r_.gamma for r_ in basis.rows]
    R = se.Matrix([[Phi[i, c] for c in range(k)] for i in range(n)])
    r = se.Matrix([[-sum((Phi[i, c] * b[c] for c in range(n) if Phi[i, c] != 0 and b[c] != 0), se.Integer(0))]
                   for i in range(n)]).subs(on_motion)
    Pi, R, r = (fold_matrix(M_, norm_reducer(dyn.model), n) for M_ in (Pi, R, r))
    return QuasiLagrangian(basis, Phi, phi0, u, qdot, Tstar, dT, Pi, R, r, on_motion)


def assemble(dyn, ql: QuasiLagrangian, lhs: list):
    """``A``, ``c`` of the equations ``lhs_r = Pi_r`` (``lhs`` linear in the unknown ``p'``),
    with ``sigma = 0`` and the trigonometric powers folded."""
    k = ql.basis.k
    acc = ql.basis.accelerations()
    zero_sigma = {s: se.Integer(0) for s in ql.basis.sigma}
    zero_acc = {a: se.Integer(0) for a in acc}
    reducer = norm_reducer(dyn.model)
    reduce, fold = reducer or (lambda x: x), fold_trig
    if dyn.n > ADJUGATE_MAX:   # large: left as derived unless small with Euler parameters (see foldable)
        if foldable(se.Matrix([[se.sympify(x) for x in lhs]]), dyn.n, reducer):
            reduce = lambda x: reducer(se.expand(x))   # noqa: E731 -- |e|^2 powers cancel term by term
        else:
            reduce, fold = (lambda x: x), (lambda x: x)
    A = se.zeros(k, k)
    c = se.zeros(k, 1)
    for r_ in range(k):
        e = se.sympify(lhs[r_]).subs(zero_sigma)
        for s in range(k):
            A[r_, s] = fold(reduce(se.diff(e, acc[s])))
        c[r_, 0] = fold(reduce(e.subs(zero_acc)))
    return A, c


def quasi_equations(form, dyn, rows, independent, coefficients, term, describe) -> EquationsOfMotion:
    """The derivation the Lagrangian quasi-velocity forms share (Boltzmann--Hamel,
    Poincaré--Chetaev): for every independent speed ``r``

        d/dt dT*/du_r - sum_j Phi_jr dT*/dq_j + term(r) = Pi_r,

    on the motion, with the ideal rows eliminated and the non-ideal ones kept as in Maggi's form.

    Parameters
    ----------
    form : Formalism
        Its ``name``, ``title`` and ``citation``.
    coefficients : callable ``(dyn, ql) -> dict``
        The form's coefficients (Hamel's, or the structure coefficients).
    term : callable ``(ql, coefficients, r) -> expression``
        The form's own terms of equation ``r``.
    describe : callable ``(ql, coefficients, labels) -> (extras, notes)``
        What the form shows; ``labels`` name the speeds, then the constraints' combinations.
    """
    ideal, kept = split_rows(rows)
    basis = speed_basis(dyn, ideal, independent, form.name, form.speed_order)
    ql = quasi_lagrangian(dyn, basis, ideal, form.name)
    n, k = dyn.n, basis.k
    coeff = coefficients(dyn, ql)
    lhs = []
    for r in range(k):
        e = ql.ddt(dyn, ql.dT[r])
        e -= sum((ql.Phi[j, r] * se.diff(ql.Tstar, dyn.q[j]) for j in range(n) if ql.Phi[j, r] != 0),
                 se.Integer(0))
        e += term(ql, coeff, r)
        lhs.append(e.subs(ql.on_motion))
    A, c = assemble(dyn, ql, lhs)
    G, gam, B = project_rows(kept, Reduced(ql.R, ql.r), n)
    reducer = norm_reducer(dyn.model)
    G, gam, B = (fold_matrix(M_.applyfunc(se.expand) if n > ADJUGATE_MAX and foldable(M_, n, reducer) else M_,
                             reducer, n) for M_ in (G, gam, B))
    labels = list(basis.names) + [f"sigma[{r_.name}]" for r_ in basis.rows]
    extras, notes = describe(ql, coeff, labels)
    return EquationsOfMotion(
        form=form.name, title=form.title, citation=form.citation, model=dyn.model,
        unknowns=basis.unknowns, multipliers=tuple(f"lambda_{r_.name}" for r_ in kept),
        constraint_names=tuple(r_.name for r_ in kept), rows=tuple(rows), independent=basis.names,
        A_=A, c_=c, Qf_=ql.Pi, B_=B, G_=G, gamma_=gam, R_=ql.R, r_=ql.r,
        auxiliaries=basis.auxiliaries(), extras_=extras, notes=(basis.note(), *notes),
        eliminated=tuple(r_.name for r_ in ideal), speeds=basis.names if basis.declared else (),
    )
