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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import symengine as se

from ..dynamics import count_ops
from ..eom import Auxiliary
from ...errors import FormNotApplicable, SingularSystem
from .base import numeric_instances, partition, symbolic_solve

__all__ = ["SpeedBasis", "speed_basis", "velocity_rows", "Reduced"]


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
    """

    names: tuple[str, ...]
    symbols: list
    definitions: list
    sigma: list
    W: object
    w: object
    declared: bool
    dropped: tuple[str, ...]

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

    def note(self) -> str:
        if not self.declared:
            return ("no [speeds] declared: the speeds are the independent velocities "
                    + ", ".join(self.names))
        out = "speeds " + ", ".join(self.names)
        if self.dropped:
            out += " (" + ", ".join(self.dropped) + " fixed by the constraints)"
        return out


def speed_basis(dyn, rows, independent, form: str) -> SpeedBasis:
    """Choose the independent speeds for the ideal *rows* (see the module docstring)."""
    model = dyn.model
    n = dyn.n
    G, g = velocity_rows(dyn, rows, form)
    m = len(G)
    zero = {v: se.Integer(0) for v in dyn.qd}
    if model.speeds:
        from ...modeling.symbols import to_se

        cand = [(name, to_se(e)) for name, e in model.speeds.items()]
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
    defs = [cand[c][1] for c in sel]
    W = se.Matrix([Wc[c] for c in sel] + G) if n else se.zeros(0, 0)
    w = se.Matrix([[d.subs(zero)] for d in defs] + [[x] for x in g]) if n else se.zeros(0, 1)
    symbols = [se.Symbol(nm) for nm in names] if declared else [dyn.qd[model.coordinates.index(nm[:-1])] for nm in names]
    sigma = [se.Symbol(f"sigma[{r.name}]") for r in rows]
    return SpeedBasis(names, symbols, defs, sigma, W, w, declared,
                      tuple(cand[c][0] for c in range(len(cand)) if c not in sel) if declared else ())


def _reparse(expr):
    """SymPy's canonical form of *expr* through its text, every name read as a symbol (a
    parameter called ``beta``, ``gamma`` or ``S`` is not SymPy's function or singleton)."""
    import sympy as sp

    names = {str(x): sp.Symbol(str(x)) for x in se.sympify(expr).free_symbols}
    return sp.sympify(str(expr), locals=names)


def invert(basis: SpeedBasis, dyn, form: str, columns: list | None = None, factor: int = 4,
           floor: int = 4000):
    """Solve ``W X = Y`` symbolically for ``Y = [I | -w]`` (default) or the given *columns*;
    None when the explicit solution exceeds the size budget.

    A small ``W`` (at most :data:`ADJUGATE_MAX` rows) is inverted as ``adj(W) / det(W)`` with
    the determinant simplified by SymPy (``cos^2 + sin^2`` in a denominator would otherwise
    stay); larger ones by sparse Gaussian elimination (:func:`symbolic_solve`)."""
    n = dyn.n
    Wl = [[basis.W[i, j] for j in range(n)] for i in range(n)]
    if columns is None:
        columns = [[se.Integer(1 if i == j else 0) for i in range(n)] for j in range(n)]
        columns.append([-basis.w[i, 0] for i in range(n)])
    Y = [[col[i] for col in columns] for i in range(n)]
    size = count_ops([x for row in Wl for x in row] + [x for row in Y for x in row])
    if n <= ADJUGATE_MAX and count_ops([x for row in Wl for x in row]) <= 400:
        import sympy as sp

        Ws = sp.Matrix(n, n, lambda i, j: _reparse(Wl[i][j]) if Wl[i][j].free_symbols else sp.sympify(Wl[i][j]))
        reduce = norm_reducer(dyn.model) or (lambda x: x)
        det = sp.trigsimp(sp.factor(_reparse(reduce(se.sympify(Ws.det(method="berkowitz"))))))
        if det != 0:
            adj = Ws.adjugate(method="berkowitz")
            adj_se = [[reduce(se.sympify(sp.expand(adj[i, j]))) for j in range(n)] for i in range(n)]
            d = se.sympify(det)
            X = [[sum((adj_se[i][l] * Y[l][c] for l in range(n) if adj_se[i][l] != 0 and Y[l][c] != 0),
                      se.Integer(0)) / d for c in range(len(columns))] for i in range(n)]
            if count_ops([x for row in X for x in row]) <= max(floor, factor * size):
                return X
    return symbolic_solve(Wl, Y, max(floor, factor * size))


ADJUGATE_MAX = 6


def to_speeds(expr, subs: dict):
    """An expression in ``q, q', t`` written in the speeds (``q' -> Phi_p p + phi0``)."""
    return se.sympify(expr).subs(subs) if subs else se.sympify(expr)


def _reduce_powers(expr, kind: str):
    """``expr`` expanded with every ``sin(a)^k`` (``kind = "sin"``; or ``cos``), ``k >= 2``,
    written as ``sin(a)^(k mod 2) (1 - cos(a)^2)^(k // 2)`` and expanded again: a canonical
    form of a polynomial in the sines and cosines of one angle."""
    other = se.cos if kind == "sin" else se.sin
    func = se.sin if kind == "sin" else se.cos

    def term(t):
        factors = t.args if isinstance(t, se.Mul) else (t,)
        out, changed = [], False
        for f in factors:
            if isinstance(f, se.Pow) and isinstance(f.args[0], func) \
                    and f.args[1].is_integer and int(f.args[1]) >= 2:
                k = int(f.args[1])
                a = f.args[0].args[0]
                out.append(func(a) ** (k % 2) * (1 - other(a) ** 2) ** (k // 2))
                changed = True
            else:
                out.append(f)
        return se.Mul(*out) if changed else t

    e = se.expand(expr)
    terms = e.args if isinstance(e, se.Add) else (e,)
    return se.expand(se.Add(*[term(t) for t in terms]))


def fold_trig(expr):
    """The shortest of *expr* and its two canonical trigonometric forms (``sin^2 -> 1 - cos^2``
    or ``cos^2 -> 1 - sin^2``, expanded) -- exact identities only; cancels the high powers
    (``cos^8 + 3 cos^4 sin^2 + cos^2 sin^6 + sin^2 = 1``) that pairwise folding misses.  Only
    polynomial parts are rewritten (a quotient is kept as it is)."""
    expr = se.sympify(expr)
    if not any(isinstance(a, (se.sin, se.cos)) for a in expr.atoms(se.Function)):
        return expr
    best, size = expr, count_ops([expr])
    if size > 4000:
        return expr
    for kind in ("sin", "cos"):
        try:
            cand = _reduce_powers(expr, kind)
        except (RuntimeError, TypeError, ValueError):   # pragma: no cover - unusual nodes
            continue
        s = count_ops([cand])
        if s < size:
            best, size = cand, s
    return best


def norm_reducer(model):
    """A function reducing a polynomial in Euler parameters modulo their unit norm
    (``e0^k -> e0^(k mod 2) (1 - e1^2 - e2^2 - e3^2)^(k // 2)``, expanded: a canonical form on
    the constraint manifold, where the equations hold), or None when the model has no frame
    given by Euler parameters.  The rates of unit Euler parameters then read ``2 G(e) e'``."""
    quads = [tuple(se.Symbol(str(c)) for c in f.quaternion) for f in getattr(model, "frames", ()) or ()
             if getattr(f, "quaternion", None)]
    if not quads:
        return None
    heads = {q[0]: q[1:] for q in quads}

    def reduce(expr):
        expr = se.sympify(expr)
        if not (expr.free_symbols & set(heads)) or count_ops([expr]) > 20000:
            return expr
        e = se.expand(expr)
        terms = e.args if isinstance(e, se.Add) else (e,)
        out = []
        for t in terms:
            factors = t.args if isinstance(t, se.Mul) else (t,)
            new = []
            for f in factors:
                if isinstance(f, se.Pow) and f.args[0] in heads and f.args[1].is_integer and int(f.args[1]) >= 2:
                    k = int(f.args[1])
                    rest = sum((x * x for x in heads[f.args[0]]), se.Integer(0))
                    new.append(f.args[0] ** (k % 2) * (1 - rest) ** (k // 2))
                else:
                    new.append(f)
            out.append(se.Mul(*new))
        return se.expand(se.Add(*out))
    return reduce


def fold_matrix(M, reduce=None, n: int = 0):
    """:func:`fold_trig` (and the Euler-parameter reduction *reduce*) on every entry -- for
    systems of at most :data:`ADJUGATE_MAX` coordinates (*n*), whose equations are read; a
    larger one (a bicycle) is left as derived: walking its expression trees costs minutes."""
    if n > ADJUGATE_MAX:
        return M
    out = se.zeros(M.rows, M.cols)
    for i in range(M.rows):
        for j in range(M.cols):
            x = M[i, j]
            if x != 0:
                x = fold_trig(reduce(x) if reduce is not None else x)
            out[i, j] = x
    return out


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
    b = [dyn.dt(d, with_acceleration=False) for d in basis.definitions] + [r_.gamma for r_ in ideal]
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
    reduce = norm_reducer(dyn.model) or (lambda x: x)
    if dyn.n > ADJUGATE_MAX:   # large: left as derived (see fold_matrix)
        reduce, fold = (lambda x: x), (lambda x: x)
    else:
        fold = fold_trig
    A = se.zeros(k, k)
    c = se.zeros(k, 1)
    for r_ in range(k):
        e = se.sympify(lhs[r_]).subs(zero_sigma)
        for s in range(k):
            A[r_, s] = fold(reduce(se.diff(e, acc[s])))
        c[r_, 0] = fold(reduce(e.subs(zero_acc)))
    return A, c
