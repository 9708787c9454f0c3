"""The elliptic paraboloid z = x^2/(2a) + y^2/(2b) of the body's axes, vertex at ``center``,
the body on its +z side (the bottom of a rattleback: ``a``, ``b`` are the radii of curvature
at the vertex).

The outward normal of the body at (x, y, z(x, y)) is along ``(x/a, y/b, -1)``.  The support
point is where it equals ``-n_b``: ``(x/a, y/b, -1) = -k n_b`` with ``k > 0`` gives
``k = 1/n3`` and

    x = -a n1/n3,      y = -b n2/n3,      z = (a n1^2 + b n2^2) / (2 n3^2),

valid only for ``n3 > 0`` (the plane's normal has a component along the body's +z axis: the
body stands on its curved face).  At ``n3 <= 0`` the paraboloid touches no plane of that
orientation from its valid side.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .base import Shape, positive

__all__ = ["Paraboloid"]


@dataclass(frozen=True)
class Paraboloid(Shape):
    """``{type = "paraboloid", curvature_radii = [a, b]}``.

    Examples
    --------
    >>> Paraboloid((1, 2)).support(sp.Matrix([0, 0, 1])).T
    Matrix([[0, 0, 0]])
    """

    TYPE = "paraboloid"
    SIZES = {"curvature_radii": 2}
    curvature_radii: tuple[Any, ...]
    center: tuple[Any, ...] | None = None

    def depth(self, n_b):
        a, b = (sp.sympify(r) for r in self.curvature_radii)
        return -(a * n_b[0] ** 2 + b * n_b[1] ** 2) / (2 * n_b[2])

    def support(self, n_b):
        a, b = (sp.sympify(r) for r in self.curvature_radii)
        n1, n2, n3 = n_b
        return sp.Matrix([-a * n1 / n3, -b * n2 / n3, (a * n1 ** 2 + b * n2 ** 2) / (2 * n3 ** 2)])

    def validity(self, n_b):
        return (n_b[2], "the plane's normal has no component along the paraboloid's +z axis "
                "(body axes): the body does not stand on its curved face; start with the vertex "
                "down (the body's z axis along the plane's normal)")

    def check(self, values, where):
        return [p for i, s in enumerate(self.curvature_radii)
                for p in positive(values, s, where, f"curvature_radii[{i}]")]
