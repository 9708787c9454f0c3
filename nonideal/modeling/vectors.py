"""Vectors in model expressions: three SymPy components in the axes of the fixed frame N.

The safe parser (:mod:`nonideal.modeling.expressions`) reads vector-valued subexpressions --
``omega(B)``, ``vel(P)``, ``pos(P)``, ``acc(P)``, ``momentum(b)``, ``angular_momentum(b, P)``,
the unit vectors ``B.x``, ``B.y``, ``B.z`` -- into :class:`Vector` values and combines them
with the whitelisted operations of this module: sums and differences of vectors, products
and quotients by scalars, ``dot``, ``cross`` and ``norm``.  Anything else (a vector where a
scalar is expected, a product of two vectors, a vector in ``sin``) is an error the parser
reports with the column.  Nothing here evaluates text.

Examples
--------
>>> import sympy as sp
>>> a = Vector((sp.Integer(1), sp.Integer(0), sp.Integer(0)))
>>> b = Vector((sp.Integer(0), sp.Integer(2), sp.Integer(0)))
>>> cross(a, b).components, dot(a + b, b), norm(b)
((0, 0, 2), 4, 2)
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

__all__ = ["Vector", "Unknown", "as_basic", "dot", "cross", "norm", "VECTOR_FUNCTIONS", "AXES", "zero"]

#: the unit vectors of a frame by attribute: B.x, B.y, B.z
AXES = {"x": 0, "y": 1, "z": 2}

#: the vector functions of expressions and the kind of each argument: "frame", "point",
#: "body" (a name), "vector" (a vector expression)
VECTOR_FUNCTIONS: dict[str, tuple[str, ...]] = {
    "omega": ("frame",), "alpha": ("frame",),
    "pos": ("point",), "vel": ("point",), "acc": ("point",),
    "dot": ("vector", "vector"), "cross": ("vector", "vector"), "norm": ("vector",),
    "momentum": ("body",), "angular_momentum": ("body", "point"),
}


class Unknown(LookupError):
    """A vector function named a frame, point or body that is not declared (the message names
    the kind, the name and the closest declared one)."""


class Vector:
    """A vector: its three components in the axes of the fixed frame N (SymPy expressions).

    Supports ``u + v``, ``u - v``, ``-u``, ``c * u``, ``u * c`` and ``u / c`` with a scalar
    ``c``; products of vectors are :func:`dot` and :func:`cross`.

    A vector that is naturally expressed in a frame B (``omega(B)``, ``B.x``) also keeps
    ``local = (B, components in B's axes)``; sums, multiples and products of vectors of one
    frame are formed in that frame, as ``sympy.physics.vector`` does, so that
    ``dot(omega(B), B.x)`` is the body component itself and not its N-axes expansion (which
    carries the angles of B's orientation in terms that cancel only by sin^2 + cos^2 = 1).
    """

    __slots__ = ("components", "local")

    def __init__(self, components: Sequence, local: tuple | None = None):
        comps = tuple(as_basic(c) for c in components)
        if len(comps) != 3:
            raise ValueError(f"a vector has 3 components, got {len(comps)}")
        self.components = comps
        self.local = None if local is None else (local[0], tuple(as_basic(c) for c in local[1]))

    def _same_frame(self, other: "Vector"):
        if self.local is not None and other.local is not None and self.local[0] == other.local[0]:
            return self.local[0]
        return None

    def __add__(self, other: "Vector") -> "Vector":
        f = self._same_frame(other)
        return Vector([a + b for a, b in zip(self.components, other.components)],
                      None if f is None else (f, [a + b for a, b in zip(self.local[1], other.local[1])]))

    def __sub__(self, other: "Vector") -> "Vector":
        f = self._same_frame(other)
        return Vector([a - b for a, b in zip(self.components, other.components)],
                      None if f is None else (f, [a - b for a, b in zip(self.local[1], other.local[1])]))

    def __neg__(self) -> "Vector":
        return Vector([-a for a in self.components],
                      None if self.local is None else (self.local[0], [-a for a in self.local[1]]))

    def scaled(self, c) -> "Vector":
        return Vector([c * a for a in self.components],
                      None if self.local is None else (self.local[0], [c * a for a in self.local[1]]))

    def __iter__(self):
        return iter(self.components)

    def __getitem__(self, i):
        return self.components[i]

    def __eq__(self, other) -> bool:
        return isinstance(other, Vector) and self.components == other.components

    def __hash__(self) -> int:
        return hash(self.components)

    def __repr__(self) -> str:
        return f"Vector({list(self.components)})"

    def has(self, *patterns) -> bool:
        return any(c.has(*patterns) for c in self.components)

    @property
    def free_symbols(self) -> set:
        return set().union(*(c.free_symbols for c in self.components))


def as_basic(c) -> sp.Basic:
    """A SymPy object of an internal value (a SymPy expression or a Python number; never text:
    no ``sympify`` runs here)."""
    if isinstance(c, sp.Basic):
        return c
    if isinstance(c, int):
        return sp.Integer(c)
    if isinstance(c, float):
        return sp.Float(c)
    raise TypeError(f"a vector component must be a SymPy expression or a number, got {type(c).__name__}")


def zero() -> Vector:
    return Vector((sp.Integer(0),) * 3)


def add(vectors: Sequence[Vector]) -> Vector:
    """The sum of several vectors in one step (no quadratic re-flattening)."""
    frames = {v.local[0] if v.local is not None else None for v in vectors}
    local = None
    if len(frames) == 1 and None not in frames:
        local = (frames.pop(), [sp.Add(*[v.local[1][i] for v in vectors]) for i in range(3)])
    return Vector([sp.Add(*[v.components[i] for v in vectors]) for i in range(3)], local)


def _mul(x, y):
    """``x * y`` with the zero and unit factors of unit vectors skipped: SymPy's ``0 * e``
    asks whether ``e`` is infinite, which walks a large ``e`` through the assumptions."""
    if x == 0 or y == 0:
        return sp.Integer(0)
    if x == 1:
        return y
    if y == 1:
        return x
    return x * y


def _sum(terms):
    terms = [t for t in terms if t != 0]
    return sp.Add(*terms) if terms else sp.Integer(0)


def dot(a: Vector, b: Vector) -> sp.Expr:
    """The scalar product (formed in the frame both vectors are expressed in, when they share one)."""
    if a._same_frame(b) is not None:
        return _sum([_mul(x, y) for x, y in zip(a.local[1], b.local[1])])
    return _sum([_mul(x, y) for x, y in zip(a.components, b.components)])


def _cross3(a, b):
    (a1, a2, a3), (b1, b2, b3) = a, b
    return (_sum([_mul(a2, b3), -_mul(a3, b2)]), _sum([_mul(a3, b1), -_mul(a1, b3)]),
            _sum([_mul(a1, b2), -_mul(a2, b1)]))


def cross(a: Vector, b: Vector) -> Vector:
    """The vector product (right-handed axes; also in the frame both share, when they do)."""
    f = a._same_frame(b)
    return Vector(_cross3(a.components, b.components),
                  None if f is None else (f, _cross3(a.local[1], b.local[1])))


def norm(a: Vector) -> sp.Expr:
    """The length ``sqrt(dot(a, a))``."""
    return sp.sqrt(dot(a, a))
