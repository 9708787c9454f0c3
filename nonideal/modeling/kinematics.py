"""Kinematics of the declared frames and points, derived once and cached.

:class:`Kinematics` holds, for every frame, its rotation ``R`` to N (columns: the frame's unit
vectors in N), its angular velocity in N and in its own axes (composed along the parent chain
from each frame's relative rate, ``w_B = w_P + R_P w_rel``: never ``R' R^T`` of a product of
rotations), its angular acceleration; for every point its position, velocity and acceleration
in N by the two-point and one-point theorems (Kane & Levinson 1985, ch. 2):

    v_P = v_Q + R p' + w x (R p),
    a_P = a_Q + R p'' + 2 w x (R p') + alpha x (R p) + w x (w x (R p)),

``p`` the components of the position in the axes of the frame (rotation ``R``, angular
velocity ``w``, acceleration ``alpha``).  Expressions are SymPy, in the model's symbols
``x``, ``x'``, ``x''`` and ``t``; each quantity is computed on first use and kept.

Euler parameters (a frame given by ``quaternion``) keep their norm at one with no constraint.
The frame turns by the rotation of ``e/|e|`` (``R(e)/|e|^2``, angular velocity
``2 (e0 e' - e0' e +- e x e')/|e|^2``), so every position, angular velocity and load is
invariant under ``e -> k e`` and blind to the radial rate ``e . e'``: their generalized forces
have no component along ``e``.  The kinetic energy gains ``c/2 (e . e')^2``, whose Lagrange
derivative along ``e`` is ``c |e|^2 (e . e')'``: the equation of motion along ``e`` is
``(e . e')' = 0``, so ``e . e'`` -- zero at t0, the initial rates are projected on the
sphere -- stays zero and ``|e|`` stays one; the term itself vanishes on that motion, and it
makes the mass matrix positive definite.  No multiplier is solved for: the motion is
integrated like that of independent coordinates (faster than Euler angles on the heavy top:
benchmarks/bench_euler_parameters.py), and a drift of ``|e|`` at the integrator's tolerance
changes no physical quantity.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import sympy as sp

from ..errors import did_you_mean
from .frames import FIXED, ORIGIN, matmul, relative
from .vectors import AXES, Unknown, Vector, add, as_basic, cross, zero

__all__ = ["Kinematics", "RESERVED_KINEMATIC_NAMES"]

#: names a frame or point cannot take
RESERVED_KINEMATIC_NAMES = frozenset({FIXED, ORIGIN, "t", "T", "V"})


class Kinematics:
    """Frames and points of a model, normalized; derived quantities computed once.

    Parameters
    ----------
    frames : mapping name -> (parent, kind, data)
        ``kind`` and ``data`` as :func:`nonideal.modeling.frames.relative` takes them.
    points : mapping name -> (origin, frame, position)
        ``position``: 3 SymPy expressions in the axes of ``frame``.
    q, qd, qdd : sequences of sympy.Symbol
        The coordinates, velocities and accelerations of the model.
    t : sympy.Symbol
    """

    def __init__(self, frames: Mapping[str, tuple], points: Mapping[str, tuple],
                 q: Sequence[sp.Symbol], qd: Sequence[sp.Symbol], qdd: Sequence[sp.Symbol],
                 t: sp.Symbol):
        self.frames = dict(frames)
        self.points = dict(points)
        self.t = t
        self._next = {s: d for s, d in zip(q, qd)}
        self._next.update({s: d for s, d in zip(qd, qdd)})
        self._cache: dict = {}
        self.bodies: dict[str, object] = {}   # normalized bodies by name (momentum, ...)
        self.points_ready = True   # False while the points' own positions are read

    # ---------------------------------------------------------------- calculus
    def dt(self, expr) -> sp.Expr:
        """The total time derivative of an expression in q, q', t (q'' where q' occurs)."""
        expr = as_basic(expr)
        free = expr.free_symbols
        out = [sp.diff(expr, self.t)] if self.t in free else []
        for s in sorted(free, key=lambda s: s.name):
            d = self._next.get(s)
            if d is not None:
                out.append(sp.diff(expr, s) * d)
        return sp.Add(*out)

    def _memo(self, key, build: Callable):
        try:
            return self._cache[key]
        except KeyError:
            value = self._cache[key] = build()
            return value

    # ---------------------------------------------------------------- frames
    def _relative(self, name: str):
        parent, kind, data = self.frames[name]
        return self._memo(("rel", name), lambda: relative(kind, data, self.dt))

    def rotation(self, name: str) -> sp.Matrix:
        """``R`` of frame *name* to N: N components = R @ frame components."""
        if name == FIXED:
            return sp.eye(3)

        def build():
            R = self._relative(name)[0]
            parent = self.frames[name][0]
            return R if parent == FIXED else matmul(self.rotation(parent), R)
        return self._memo(("R", name), build)

    def omega(self, name: str) -> Vector:
        """Angular velocity of frame *name* in N (components in N)."""
        if name == FIXED:
            return zero()

        def build():
            parent = self.frames[name][0]
            w = self._relative(name)[1]
            if parent == FIXED:
                v = Vector(list(w))
            else:
                v = self.omega(parent) + Vector(list(matmul(self.rotation(parent), w)))
            return Vector(v.components, (name, list(self.omega_own(name))))
        return self._memo(("w", name), build)

    def omega_own(self, name: str) -> sp.Matrix:
        """Angular velocity of frame *name* in N, components in the frame's own axes."""
        if name == FIXED:
            return sp.zeros(3, 1)

        def build():
            parent = self.frames[name][0]
            R, _, w = self._relative(name)
            return w if parent == FIXED else matmul(R.T, self.omega_own(parent)) + w
        return self._memo(("w_own", name), build)

    def alpha(self, name: str) -> Vector:
        """Angular acceleration of frame *name* in N (contains accelerations)."""
        return self._memo(("alpha", name), lambda: Vector([self.dt(c) for c in self.omega(name)]))

    def unit(self, name: str, axis: int) -> Vector:
        """The unit vector ``name.x`` (axis 0), ``.y`` (1), ``.z`` (2) in N components."""
        local = (name, [sp.Integer(int(k == axis)) for k in range(3)])
        return self._memo(("unit", name, axis), lambda: Vector(list(self.rotation(name)[:, axis]), local))

    # ---------------------------------------------------------------- points
    def _offset(self, name: str, order: int = 0):
        """``R p`` (order 0), ``R p'`` (1) or ``R p''`` (2) of point *name* from its origin, in N
        components: the position and the relative velocity and acceleration in its frame's
        axes, turned into N.  None for orders 1, 2 when the components are constants.  Each
        computed only when asked (a contact point's position is used, rarely its rates)."""
        def build():
            _, frame, p = self.points[name]
            if order == 0:
                comps = p
            elif not any(self._moves(c) for c in p):
                return None
            else:
                below = self._components(name, order - 1)
                comps = [self.dt(c) for c in below]
            self._cache[("comps", name, order)] = comps
            if frame == FIXED:
                return Vector(comps)
            return Vector(list(matmul(self.rotation(frame), sp.Matrix(comps))))
        return self._memo(("offset", name, order), build)

    def _components(self, name: str, order: int):
        """The components (in the frame's axes) of the position's *order*-th derivative."""
        self._offset(name, order)
        return self._cache[("comps", name, order)]

    def _moves(self, expr) -> bool:
        return any(s in self._next or s == self.t for s in as_basic(expr).free_symbols)

    def pos(self, name: str) -> Vector:
        """Position of point *name* from O, in N."""
        if name == ORIGIN:
            return zero()

        def build():
            origin = self.points[name][0]
            r = self._offset(name)
            return r if origin == ORIGIN else self.pos(origin) + r
        return self._memo(("pos", name), build)

    def vel(self, name: str) -> Vector:
        """Velocity of point *name* in N: ``v_Q + R p' + w x (R p)``."""
        if name == ORIGIN:
            return zero()

        def build():
            origin, frame, _ = self.points[name]
            r, rd = self._offset(name), self._offset(name, 1)
            parts = [] if origin == ORIGIN else [self.vel(origin)]
            if rd is not None:
                parts.append(rd)
            if frame != FIXED:
                parts.append(cross(self.omega(frame), r))
            return add(parts) if parts else zero()
        return self._memo(("vel", name), build)

    def acc(self, name: str) -> Vector:
        """Acceleration of point *name* in N (the one-point theorem)."""
        if name == ORIGIN:
            return zero()

        def build():
            origin, frame, _ = self.points[name]
            r, rd = self._offset(name), self._offset(name, 1)
            rdd = self._offset(name, 2) if rd is not None else None
            parts = [] if origin == ORIGIN else [self.acc(origin)]
            if rd is not None:
                parts.append(rdd)
            if frame != FIXED:
                w, a = self.omega(frame), self.alpha(frame)
                parts += [cross(a, r), cross(w, cross(w, r))]
                if rd is not None:
                    parts.append(cross(w, rd).scaled(2))
            return add(parts) if parts else zero()
        return self._memo(("acc", name), build)

    # ---------------------------------------------------------------- bodies
    def _body_velocity(self, body) -> Vector:
        r = list(body.position) + [sp.Integer(0)] * (3 - len(body.position))
        center = getattr(body, "center", None)
        return self.vel(center) if center is not None else Vector([self.dt(c) for c in r])

    def momentum(self, name: str) -> Vector:
        """Linear momentum ``m v_G`` of body *name* (absolute velocity)."""
        body = self.bodies[name]
        return self._body_velocity(body).scaled(body.mass)

    def angular_momentum(self, name: str, point: str) -> Vector:
        """Angular momentum of body *name* about point *point*:
        ``H_G + (r_G - r_P) x m v_G`` (absolute velocities)."""
        body = self.bodies[name]
        r = Vector(list(body.position) + [sp.Integer(0)] * (3 - len(body.position)))
        own = self._spin(body)
        return own + cross(r - self.pos(point), self.momentum(name))

    def _spin(self, body) -> Vector:
        """``H_G``: ``R I Omega`` of a rigid body, ``I angle'`` about z of a planar one."""
        if hasattr(body, "rotation") and body.rotation is not None and hasattr(body, "inertia") \
                and isinstance(body.inertia, tuple):
            R = sp.Matrix(body.rotation)
            if getattr(body, "omega", None) is not None:
                Om = sp.Matrix(body.omega)
            else:
                Rd = R.applyfunc(self.dt)
                W = R.T * Rd
                Om = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
            return Vector(list(R * (sp.Matrix(body.inertia) * Om)))
        if hasattr(body, "angle"):
            return Vector((0, 0, body.inertia * self.dt(body.angle)))
        return zero()

    # ---------------------------------------------------------------- the parser's hook
    def names_of(self, kind: str) -> list[str]:
        if kind == "frame":
            return [FIXED, *self.frames]
        if kind == "point":
            return [ORIGIN, *self.points]
        return list(self.bodies)

    def check(self, kind: str, name: str) -> None:
        """Raise :class:`Unknown` if *name* is not a declared frame / point / body."""
        known = self.names_of(kind)
        if kind == "point" and not self.points_ready:
            raise Unknown("a point's position may use the frames' unit vectors (B.x, dot(N.z, B.x) "
                          "...) but not the points: place it from another point with 'from'")
        if name not in known:
            declare = {"frame": "[[frames]]", "point": "[[points]]", "body": "[[bodies]]"}[kind]
            plural = "bodies" if kind == "body" else kind + "s"
            raise Unknown(f"unknown {kind} '{name}'{did_you_mean(name, known)}; the {plural} are "
                          f"{', '.join(known) or 'none'} (declare it in {declare})")

    def call(self, fname: str, args: list) -> Vector:
        """The value of the vector function *fname* of names (frames, points, bodies)."""
        if fname in ("omega", "alpha"):
            self.check("frame", args[0])
            return getattr(self, fname)(args[0])
        if fname in ("pos", "vel", "acc"):
            self.check("point", args[0])
            return getattr(self, fname)(args[0])
        self.check("body", args[0])
        if fname == "momentum":
            return self.momentum(args[0])
        self.check("point", args[1])
        return self.angular_momentum(args[0], args[1])

    def axis(self, frame: str, letter: str) -> Vector:
        """``B.x`` and the like (raises :class:`Unknown`)."""
        self.check("frame", frame)
        if letter not in AXES:
            raise Unknown(f"'{frame}.{letter}': a frame's unit vectors are {frame}.x, {frame}.y, "
                          f"{frame}.z")
        return self.unit(frame, AXES[letter])

    # ---------------------------------------------------------------- Euler parameters
    def quaternions(self) -> dict[str, tuple[sp.Symbol, ...]]:
        """``{frame: (e0, e1, e2, e3)}`` of the frames given by Euler parameters."""
        return {n: tuple(data["e"]) for n, (_, kind, data) in self.frames.items() if kind == "quaternion"}

    def regularization(self, bodies: Sequence) -> sp.Expr:
        """``sum c/2 (e . e')^2`` over the frames given by Euler parameters, ``c`` four
        times the mean principal moment of the rigid bodies attached to the frame (1 when
        none is): zero on the unit sphere, it makes the mass matrix positive definite."""
        out = []
        for name, e in self.quaternions().items():
            moments = [sp.Add(*[b.inertia[i][i] for i in range(3)]) / 3 for b in bodies
                       if getattr(b, "frame", None) == name]
            c = 4 * sp.Add(*moments) if moments else sp.Integer(1)
            s = sp.Add(*[x * self._next[x] for x in e])
            out.append(c * s**2 / 2)
        return sp.Add(*out)
