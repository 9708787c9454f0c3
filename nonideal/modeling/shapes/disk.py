"""The rim of a thin disk: the circle of radius r about ``center`` normal to ``axis``.

The point of the rim farthest along ``-n_b``: with ``a`` the unit axis, the projection of
``n_b`` on the disk's plane is ``w = n_b - (n_b . a) a`` and

    x = -r w / |w|,        |w|^2 = 1 - (n_b . a)^2,

singular when the disk lies flat (``n_b`` along the axis: every rim point touches).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .base import Shape, positive

__all__ = ["Disk"]


@dataclass(frozen=True)
class Disk(Shape):
    """``{type = "disk", radius, axis = [..]}`` (the axis in body axes, any length).

    Examples
    --------
    >>> Disk(1, (0, 1, 0)).support(sp.Matrix([0, 0, 1])).T
    Matrix([[0, 0, -1]])
    """

    TYPE = "disk"
    SIZES = {"radius": 1, "axis": 3}
    radius: Any
    axis: tuple[Any, ...]
    center: tuple[Any, ...] | None = None

    def unit_axis(self) -> sp.Matrix:
        a = sp.Matrix([sp.sympify(c) for c in self.axis])
        norm = sp.sqrt(sum(c ** 2 for c in a))
        return a if norm == 1 else a / norm

    def depth(self, n_b):
        na = (n_b.T * self.unit_axis())[0]
        return -sp.sympify(self.radius) * sp.sqrt(1 - na ** 2)

    def support(self, n_b):
        a = self.unit_axis()
        na = (n_b.T * a)[0]
        w = n_b - na * a
        return -sp.sympify(self.radius) * w / sp.sqrt(1 - na ** 2)

    def validity(self, n_b):
        na = (n_b.T * self.unit_axis())[0]
        return (1 - na ** 2, "the disk lies flat on the plane (its axis along the plane's normal): "
                "every point of the rim touches; tilt it or describe the flat contact otherwise")

    def check(self, values, where):
        out = positive(values, self.radius, where, "radius")
        try:
            norm = sum(float(sp.sympify(c).xreplace(values)) ** 2 for c in self.axis)
        except (TypeError, ValueError):
            return out + [f"{where}: axis must be numbers or parameters"]
        if not norm > 0:
            out.append(f"{where}: axis = {list(self.axis)} is the zero vector; give the direction "
                       "of the disk's axis in body axes")
        return out
