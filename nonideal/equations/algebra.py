"""Small helpers of the symbolic stage: the vector product of component lists, the
operation count of SymEngine expressions (the size guard) and the identity
``sin(u)^2 + cos(u)^2 = 1`` in the squared lengths of a point's Jacobian."""

from __future__ import annotations

import symengine as se

__all__ = ["cross", "count_ops", "pythagorean", "PYTHAGOREAN_OPS_MAX"]

PYTHAGOREAN_OPS_MAX = 400
"""Sums larger than this (operations) are left as they are by :func:`pythagorean`."""


def cross(a, b) -> list:
    """``a x b`` of two 3-component sequences."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def count_ops(exprs) -> int:
    """Total operation count of SymEngine expressions (used by the size guard)."""
    total = 0
    for e in exprs:
        total += se.count_ops(e) if hasattr(se, "count_ops") else len(str(e))
    return total


def pythagorean(e):
    """*e* with every pair of terms ``c sin(u)^2 + c cos(u)^2`` of its expansion replaced by
    ``c`` (again on the result, until none is left): the mass-matrix entry ``m (J_x^2 + J_y^2)`` of a point on a circle, ``m l^2
    (sin^2 q + cos^2 q)``, becomes ``m l^2`` (shorter, and exact in floating point).  Sums over
    :data:`PYTHAGOREAN_OPS_MAX` operations are returned unchanged (no expansion of large
    expressions)."""
    if se.count_ops(e) > PYTHAGOREAN_OPS_MAX:
        return e
    expanded = se.expand(e)
    if not isinstance(expanded, se.Add):
        return e
    terms = list(expanded.args)
    squares: dict = {}  # (sin or cos, u, rest) -> index of the term
    for k, term in enumerate(terms):
        for f in term.args if isinstance(term, se.Mul) else (term,):
            if isinstance(f, se.Pow) and f.args[1] == 2 and isinstance(f.args[0], (se.sin, se.cos)):
                kind = se.sin if isinstance(f.args[0], se.sin) else se.cos
                squares.setdefault((kind, f.args[0].args[0], term / f), k)
    used: set[int] = set()  # a term pairs once (c sin^2 u cos^2 v may pair over u or over v)
    for (kind, u, rest), k in squares.items():
        other = squares.get((se.cos, u, rest)) if kind is se.sin else None
        if other is not None and k not in used and other not in used:
            terms[k], terms[other] = rest, None
            used.update((k, other))
    changed = bool(used)
    return pythagorean(se.Add(*[t for t in terms if t is not None])) if changed else e
