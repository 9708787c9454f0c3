"""A point fixed in the body (its ``center``): the support point is the point itself."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .base import Shape

__all__ = ["Point"]


@dataclass(frozen=True)
class Point(Shape):
    """``{type = "point", center = [..]}`` (default: the body's centre).

    Examples
    --------
    >>> Point().support(sp.Matrix([0, 0, 1])).T
    Matrix([[0, 0, 0]])
    """

    TYPE = "point"
    SIZES = {}
    center: tuple[Any, ...] | None = None

    def depth(self, n_b):
        return sp.Integer(0)

    def support(self, n_b):
        return sp.zeros(3, 1)
