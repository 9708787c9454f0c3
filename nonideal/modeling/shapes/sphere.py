"""A sphere of radius r about its ``center``: the support point is ``-r n_b``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .base import Shape, positive

__all__ = ["Sphere"]


@dataclass(frozen=True)
class Sphere(Shape):
    """``{type = "sphere", radius}``.

    Examples
    --------
    >>> Sphere(2).support(sp.Matrix([0, 0, 1])).T
    Matrix([[0, 0, -2]])
    """

    TYPE = "sphere"
    SIZES = {"radius": 1}
    radius: Any
    center: tuple[Any, ...] | None = None

    def depth(self, n_b):
        return -sp.sympify(self.radius)

    def support_in(self, n, R):
        return self.offset_in(R) - sp.sympify(self.radius) * n

    def support(self, n_b):
        return -sp.sympify(self.radius) * n_b

    def check(self, values, where):
        return positive(values, self.radius, where, "radius")
