"""The surface a shape touches: a plane of any orientation, fixed or moving in its own plane.

``{type = "plane", normal = [..], point = [..], velocity = [..], omega = [..]}`` (components
in N).  ``normal`` points from the plane into the side where the body is (default ``[0, 0,
1]``), ``point`` is a point of the plane (default the origin).  The material velocity of the
surface at a point P of the plane is ``velocity + omega x (P - point)``: a conveyor belt
(``velocity``), a turntable (``omega`` along the normal); both default to zero and may depend
on time.  The plane moves in its own plane only: ``velocity . n = 0`` and ``omega x n = 0``.

The tangent axes of the slip components: ``t1`` is the unit projection of N.x on the plane
(of N.y when N.x is normal to it), ``t2 = n x t1``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

__all__ = ["Plane"]


def _unit(v: sp.Matrix) -> sp.Matrix:
    norm = sp.sqrt(sum(c ** 2 for c in v))
    norm = sp.nsimplify(norm) if norm.is_number else norm
    return v if norm == 1 else v / norm


@dataclass(frozen=True)
class Plane:
    """A plane surface (see the module docstring).

    Examples
    --------
    >>> p = Plane()
    >>> p.unit_normal.T, p.tangents()[0].T, p.tangents()[1].T
    (Matrix([[0, 0, 1]]), Matrix([[1, 0, 0]]), Matrix([[0, 1, 0]]))
    """

    TYPE = "plane"
    SIZES = {}
    OPTIONAL = {"normal": 3, "point": 3, "velocity": 3, "omega": 3}
    normal: tuple[Any, ...] = (0, 0, 1)
    point: tuple[Any, ...] = (0, 0, 0)
    velocity: tuple[Any, ...] | None = None
    omega: tuple[Any, ...] | None = None

    @property
    def unit_normal(self) -> sp.Matrix:
        return _unit(sp.Matrix([sp.sympify(c) for c in self.normal]))

    def tangents(self) -> tuple[sp.Matrix, sp.Matrix]:
        """``(t1, t2)``: t1 the unit projection of N.x on the plane (N.y where N.x is normal),
        t2 = n x t1."""
        n = self.unit_normal
        for e in (sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0])):
            p = e - (n.T * e)[0] * n
            if not all(sp.simplify(c) == 0 for c in p):
                t1 = _unit(p.applyfunc(sp.cancel))
                return t1, n.cross(t1)
        raise AssertionError("unreachable: N.x and N.y cannot both be normal to a plane")

    def material_velocity(self, P: sp.Matrix) -> sp.Matrix:
        """Velocity of the surface's material point at P (components in N)."""
        v = sp.zeros(3, 1) if self.velocity is None else sp.Matrix([sp.sympify(c) for c in self.velocity])
        if self.omega is not None:
            w = sp.Matrix([sp.sympify(c) for c in self.omega])
            v = v + w.cross(P - sp.Matrix([sp.sympify(c) for c in self.point]))
        return v

    @property
    def angular_velocity(self) -> sp.Matrix:
        return sp.zeros(3, 1) if self.omega is None else sp.Matrix([sp.sympify(c) for c in self.omega])

    def check(self, values, where) -> list[str]:
        """The normal is not zero; the plane moves in its own plane."""
        out = []
        n = sp.Matrix([sp.sympify(c) for c in self.normal])
        try:
            nn = float(sum(c ** 2 for c in n).xreplace(values))
        except (TypeError, ValueError):
            return [f"{where}: normal must be numbers or parameters (the plane is fixed in "
                    "orientation)"]
        if not nn > 0:
            return [f"{where}: normal = {list(self.normal)} is the zero vector; give the plane's "
                    "normal, e.g. normal = [0, 0, 1]"]
        if self.velocity is not None:
            along = sp.expand((sp.Matrix([sp.sympify(c) for c in self.velocity]).T * n)[0])
            if along.xreplace(values) != 0:
                out.append(f"{where}: velocity = {list(self.velocity)} has a component along the "
                           "normal; a plane moves in its own plane only (velocity . normal = 0)")
        if self.omega is not None:
            w = sp.Matrix([sp.sympify(c) for c in self.omega])
            if any(sp.expand(c).xreplace(values) != 0 for c in w.cross(n)):
                out.append(f"{where}: omega = {list(self.omega)} is not along the normal; a plane "
                           "turns in its own plane only (a turntable: omega = [0, 0, W] for the "
                           "plane z = 0)")
        return out
