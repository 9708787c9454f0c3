"""An ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 in the body's axes about its ``center``.

The support point along ``-n_b``: minimizing ``n_b . x`` on the ellipsoid (Lagrange
multiplier, ``x = -D^2 n_b / lambda``) gives

    x = -D^2 n_b / sqrt(n_b^T D^2 n_b),        D = diag(a, b, c),

unique for every orientation (a strictly convex surface).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .base import Shape, positive

__all__ = ["Ellipsoid"]


@dataclass(frozen=True)
class Ellipsoid(Shape):
    """``{type = "ellipsoid", semi_axes = [a, b, c]}``.

    Examples
    --------
    >>> Ellipsoid((1, 2, 3)).support(sp.Matrix([0, 0, 1])).T
    Matrix([[0, 0, -3]])
    """

    TYPE = "ellipsoid"
    SIZES = {"semi_axes": 3}
    semi_axes: tuple[Any, ...]
    center: tuple[Any, ...] | None = None

    def depth(self, n_b):
        return -sp.sqrt(sum(sp.sympify(s) ** 2 * n_b[i] ** 2 for i, s in enumerate(self.semi_axes)))

    def support(self, n_b):
        d2 = [sp.sympify(s) ** 2 for s in self.semi_axes]
        scaled = sp.Matrix([d2[i] * n_b[i] for i in range(3)])
        return -scaled / sp.sqrt(sum(d2[i] * n_b[i] ** 2 for i in range(3)))

    def check(self, values, where):
        return [p for i, s in enumerate(self.semi_axes)
                for p in positive(values, s, where, f"semi_axes[{i}]")]
