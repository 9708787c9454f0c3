"""The contact of a shape fixed in a rigid body with a plane: support point, gap, slip and
the angular velocities a friction torque reads.

With the body's rotation ``R`` (body -> N), its centre ``r_G`` (N), the plane's unit normal
``n`` and point ``p0``, and the support point ``P`` of the shape along ``-n``:

* gap ``g = n . (P - p0) = n . (r_G - p0) + n_b . c + depth(n_b)`` with ``n_b = R^T n`` and
  ``c`` the shape's ``center`` (body axes): the signed normal distance, so that the multiplier
  of ``g >= 0`` is the normal force;
* slip ``U_k = t_k . (v_G + omega x (P - r_G) - v_s(P))`` for ``k = 1, 2``: the velocity of
  the body's MATERIAL point at P (rigid-body formula, not the time derivative of the support
  point's position, which moves over the body as it rolls) minus the surface's material
  velocity there;
* ``omega`` from ``R``: the skew matrix ``Rdot R^T`` (N axes), ``omega_rel = omega -
  omega_s``; :func:`spin_and_rolling` splits it into the spin about the normal and the
  rolling angular velocity in the tangent plane (what spin and rolling friction read).

Everything is a SymPy expression in the coordinates, velocities, time and parameters, built
without ``simplify`` (the numeric stage compiles it with common subexpressions eliminated).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from .base import Shape
from .surface import Plane

__all__ = ["ContactGeometry", "contact_geometry", "angular_velocity", "spin_and_rolling", "fold"]


@dataclass(frozen=True)
class ContactGeometry:
    """What a shape contact derives (every vector a 3x1 SymPy matrix in N axes).

    Attributes
    ----------
    normal : the plane's unit normal n (into the body's side)
    tangents : (t1, t2), the axes of the two slip components
    support : the support point P (position in N)
    support_body : P - r_G in body axes (moves over the body as it rolls)
    gap : n . (P - p0)
    slip : (U1, U2), linear in the velocities
    omega : the body's angular velocity (N axes)
    omega_relative : omega minus the surface's angular velocity
    validity : (expression, explanation) or None -- the support point is unique where the
        expression is positive
    """

    normal: sp.Matrix
    tangents: tuple[sp.Matrix, sp.Matrix]
    support: sp.Matrix
    support_body: sp.Matrix
    gap: sp.Expr
    slip: tuple[sp.Expr, sp.Expr]
    omega: sp.Matrix
    omega_relative: sp.Matrix
    validity: tuple[sp.Expr, str] | None


def _dt(expr: sp.Expr, q: Sequence[sp.Symbol], qd: Sequence[sp.Symbol], t: sp.Symbol) -> sp.Expr:
    """Total time derivative of an expression of (q, t)."""
    out = sp.diff(expr, t)
    for qi, vi in zip(q, qd):
        if qi in expr.free_symbols:
            out += sp.diff(expr, qi) * vi
    return out


def angular_velocity(R: sp.Matrix, q, qd, t) -> sp.Matrix:
    """The angular velocity in N axes of a frame whose rotation (frame -> N) is *R*: the axial
    vector of ``Rdot R^T``.

    Examples
    --------
    >>> a = sp.Symbol("a"); ad = sp.Symbol("a'"); t = sp.Symbol("t")
    >>> Rz = sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])
    >>> angular_velocity(Rz, [a], [ad], t).applyfunc(sp.trigsimp).T
    Matrix([[0, 0, a']])
    """
    Rdot = R.applyfunc(lambda x: _dt(x, q, qd, t))
    W = Rdot * R.T
    return sp.Matrix([fold(W[2, 1]), fold(W[0, 2]), fold(W[1, 0])])


def fold(expr: sp.Expr) -> sp.Expr:
    """*expr* expanded with every ``sin(u)^k`` (k >= 2) written ``sin(u)^(k mod 2) (1 -
    cos(u)^2)^(k div 2)``: a normal form of polynomials in sines and cosines modulo ``sin^2 +
    cos^2 = 1``, so the identity's terms cancel (``Rdot R^T`` of Euler angles shrinks from ~100
    operations to ~5) -- cheap, unlike ``trigsimp``.

    Examples
    --------
    >>> a, b = sp.symbols("a b")
    >>> fold(b*sp.sin(a)**2 + b*sp.cos(a)**2)
    b
    """
    expr = sp.expand(expr)
    powers = {p: sp.sin(p.base.args[0]) ** (p.exp % 2) * (1 - sp.cos(p.base.args[0]) ** 2) ** (p.exp // 2)
              for p in expr.atoms(sp.Pow)
              if isinstance(p.base, sp.sin) and p.exp.is_Integer and p.exp >= 2}
    return sp.expand(expr.xreplace(powers)) if powers else expr


def contact_geometry(shape: Shape, surface: Plane, rotation, position, q, qd, t,
                     omega=None) -> ContactGeometry:
    """Gap, slip and angular velocities of *shape* (fixed in the body with *rotation* R, body
    -> N, 3x3, and centre *position*, 3 expressions) touching *surface*; *omega* (N axes) is the
    body's angular velocity when known (a frame in Euler parameters), else derived from R.

    Examples
    --------
    A sphere of radius r whose centre is at height z rolls on z = 0 while x' = r b':

    >>> from nonideal.modeling.shapes import Sphere, Plane
    >>> x, z, b = sp.symbols("x z b"); xd, zd, bd = sp.symbols("x' z' b'"); t, r = sp.symbols("t r")
    >>> Ry = sp.Matrix([[sp.cos(b), 0, sp.sin(b)], [0, 1, 0], [-sp.sin(b), 0, sp.cos(b)]])
    >>> g = contact_geometry(Sphere(r), Plane(), Ry, (x, 0, z), [x, z, b], [xd, zd, bd], t)
    >>> g.gap, [sp.trigsimp(u) for u in g.slip]
    (-r + z, [-b'*r + x', 0])
    """
    R = sp.Matrix(rotation)
    rG = sp.Matrix(list(position))
    n = surface.unit_normal
    t1, t2 = surface.tangents()
    p0 = sp.Matrix([sp.sympify(c) for c in surface.point])
    n_b = R.T * n
    offset = shape.offset
    gap = (n.T * (rG - p0))[0] + (n_b.T * offset)[0] + shape.depth(n_b)
    rel = shape.support_in(n, R)
    P = rG + rel
    vG = rG.applyfunc(lambda x: _dt(x, q, qd, t))
    omega = angular_velocity(R, q, qd, t) if omega is None else sp.Matrix(omega).applyfunc(fold)
    v = vG + omega.cross(rel) - surface.material_velocity(P)
    slip = (fold((t1.T * v)[0]), fold((t2.T * v)[0]))
    validity = shape.validity(n_b)
    return ContactGeometry(n, (t1, t2), P, offset + shape.support(n_b), gap, slip, omega,
                           omega - surface.angular_velocity, validity)


def spin_and_rolling(geometry: ContactGeometry) -> tuple[sp.Expr, sp.Matrix]:
    """The spin (pivoting) angular velocity ``omega_rel . n`` and the rolling angular velocity
    ``omega_rel - (omega_rel . n) n`` (in the tangent plane, N axes) of a shape contact: what
    spin and rolling friction torques oppose.

    Examples
    --------
    >>> from nonideal.modeling.shapes import Sphere, Plane
    >>> a = sp.Symbol("a"); ad = sp.Symbol("a'"); t = sp.Symbol("t")
    >>> Rz = sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])
    >>> g = contact_geometry(Sphere(1), Plane(), Rz, (0, 0, a), [a], [ad], t)
    >>> spin, rolling = spin_and_rolling(g)
    >>> sp.trigsimp(spin), rolling.applyfunc(sp.trigsimp).T
    (a', Matrix([[0, 0, 0]]))
    """
    n, w = geometry.normal, geometry.omega_relative
    spin = (w.T * n)[0]
    return spin, w - spin * n
