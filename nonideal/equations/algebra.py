"""Small helpers of the symbolic stage: the vector product of component lists and the
operation count of SymEngine expressions (the size guard)."""

from __future__ import annotations

import symengine as se

__all__ = ["cross", "count_ops"]


def cross(a, b) -> list:
    """``a x b`` of two 3-component sequences."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def count_ops(exprs) -> int:
    """Total operation count of SymEngine expressions (used by the size guard)."""
    total = 0
    for e in exprs:
        total += se.count_ops(e) if hasattr(se, "count_ops") else len(str(e))
    return total
