"""Exact rewriting that keeps the quasi-velocity forms readable: trigonometric powers folded
to a canonical form (``sin^2 -> 1 - cos^2`` or the reverse, the shorter kept) and polynomials
in Euler parameters reduced modulo their unit norm.  Identities only (the second on the unit
sphere, which the motion keeps): the folded equations are the derived ones."""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops

__all__ = ["fold_trig", "norm_reducer", "fold_matrix", "foldable", "ADJUGATE_MAX", "FOLD_OPS_MAX"]

#: systems of at most this many coordinates have their equations folded (and small speed
#: matrices inverted by the adjugate); larger ones are left as derived
ADJUGATE_MAX = 6
#: the size (operations) up to which the matrices of a system over ADJUGATE_MAX coordinates are folded
FOLD_OPS_MAX = 50000


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
    (``|e|^2 -> 1`` where it divides, ``e0^k -> e0^(k mod 2) (1 - e1^2 - e2^2 - e3^2)^(k // 2)``,
    expanded: a canonical form on the unit sphere, which the motion keeps and where the
    equations are read), or None when the model has no frame
    given by Euler parameters.  The rates of unit Euler parameters then read ``2 G(e) e'``."""
    quads = [tuple(se.Symbol(str(c)) for c in f.quaternion) for f in getattr(model, "frames", ()) or ()
             if getattr(f, "quaternion", None)]
    if not quads:
        return None
    heads = {q[0]: q[1:] for q in quads}
    unit = {}
    for q in quads:   # |e|^2 (the rotation of e/|e| divides by it) and its powers, expanded or not
        n2 = sum((x * x for x in q), se.Integer(0))
        unit.update({n2: se.Integer(1), se.expand(n2**2): se.Integer(1), se.expand(n2**3): se.Integer(1)})

    def reduce(expr):
        expr = se.sympify(expr)
        if not (expr.free_symbols & set(heads)):
            return expr
        expr = expr.subs(unit)
        if count_ops([expr]) > 20000:
            return expr
        e = se.expand(expr).subs(unit)
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


def foldable(M, n: int, reduce=None) -> bool:
    """Whether the entries of *M* are folded for reading: always for systems of at most
    :data:`ADJUGATE_MAX` coordinates (*n*); a larger one only when it has Euler parameters to
    reduce (*reduce*, from :func:`norm_reducer`) and its entries are small (at most
    :data:`FOLD_OPS_MAX` operations: a top on a plane in body speeds).  Anything else is left as
    derived (a bicycle: walking its expression trees costs minutes, counting them too)."""
    if n <= ADJUGATE_MAX:
        return True
    if reduce is None:
        return False
    total = 0
    for i in range(M.rows):
        for j in range(M.cols):
            total += count_ops([M[i, j]])
            if total > FOLD_OPS_MAX:
                return False
    return True


def fold_matrix(M, reduce=None, n: int = 0):
    """:func:`fold_trig` (and the Euler-parameter reduction *reduce*) on every entry when
    :func:`foldable`, else *M* as derived."""
    if not foldable(M, n, reduce):
        return M
    out = se.zeros(M.rows, M.cols)
    for i in range(M.rows):
        for j in range(M.cols):
            x = M[i, j]
            if x != 0:
                x = fold_trig(reduce(x) if reduce is not None else x)
            out[i, j] = x
    return out
