"""Reference frames: the declaration (:class:`Frame`) and its rotation relative to its parent.

A frame is rotated from its parent (default the fixed frame ``N``) in one of four ways, with
the meaning of ``sympy.physics.vector.ReferenceFrame``'s ``orient_*`` methods:

* ``rotation = "body ZXZ"`` with ``angles``: successive rotations about the frame's own axes
  as they turn (``orient_body_fixed``), ``R = R1(a1) R2(a2) R3(a3)``;
  ``rotation = "space XYZ"``: about the parent's fixed axes (``orient_space_fixed``),
  ``R = R3(a3) R2(a2) R1(a1)``; one to three axes (``X``, ``Y``, ``Z`` or ``1``, ``2``, ``3``);
* ``axis`` (in the parent's axes) and ``angle`` (``orient_axis``);
* ``quaternion = [e0, e1, e2, e3]``: Euler parameters, scalar first (``orient_quaternion``);
  the rotation is that of e/|e| and the library keeps |e| = 1 (see
  :mod:`nonideal.modeling.kinematics`);
* ``matrix``: the 3x3 matrix itself.

Every rotation ``R`` maps the frame's components to its parent's: its columns are the frame's
unit vectors in the parent's axes.  :func:`relative` returns ``R`` and the angular velocity of
the frame relative to its parent both in the parent's and in the frame's own axes, each from
the declaration's own structure (composed elementary rates, never ``R' R^T`` where it can be
avoided): the expressions stay short.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from ..errors import did_you_mean

__all__ = ["Frame", "FIXED", "ORIGIN", "parse_sequence", "relative", "elementary",
           "quaternion_matrix", "matmul"]

FIXED = "N"      #: the fixed (inertial) frame
ORIGIN = "O"     #: its origin

_AXIS = {"X": 0, "Y": 1, "Z": 2, "1": 0, "2": 1, "3": 2}


@dataclass(frozen=True)
class Frame:
    """A reference frame rotated from ``parent``.

    Give exactly one of ``rotation`` + ``angles``, ``axis`` + ``angle``, ``quaternion`` or
    ``matrix``.

    Parameters
    ----------
    name : str
    parent : str
        Default ``"N"``, the fixed frame.
    rotation : str
        ``"body ZXZ"`` or ``"space XYZ"`` (one to three axes).
    angles : sequence of expressions
        One angle per axis of ``rotation``.
    axis : sequence of 3 expressions
        The rotation axis in the parent's axes (normalized by the library).
    angle : expression
        The angle about ``axis`` (right-handed).
    quaternion : sequence of 4 coordinate names
        Euler parameters ``e0`` (scalar), ``e1, e2, e3``, coordinates of the model.
    matrix : 3x3 nested sequence of expressions
        Columns: the frame's unit vectors in the parent's axes.

    Examples
    --------
    >>> Frame("B", rotation="body ZXZ", angles=("psi", "theta", "phi")).kind
    'body'
    """

    name: str
    parent: str = FIXED
    rotation: str | None = None
    angles: tuple[Any, ...] | None = None
    axis: tuple[Any, ...] | None = None
    angle: Any = None
    quaternion: tuple[Any, ...] | None = None
    matrix: tuple[tuple[Any, ...], ...] | None = None

    def __post_init__(self):
        for key in ("angles", "axis", "quaternion"):
            value = getattr(self, key)
            if isinstance(value, (list, tuple)):
                object.__setattr__(self, key, tuple(value))
        if isinstance(self.matrix, (list, tuple)):
            object.__setattr__(self, "matrix", tuple(tuple(r) if isinstance(r, (list, tuple)) else r
                                                     for r in self.matrix))

    @property
    def kind(self) -> str | None:
        """``"body"``, ``"space"``, ``"axis"``, ``"quaternion"``, ``"matrix"`` or None (none or
        several given: see :meth:`problems`)."""
        given = self.given()
        if len(given) != 1:
            return None
        if given[0] == "rotation":
            word = str(self.rotation).split()[0].lower() if str(self.rotation).split() else ""
            return word if word in ("body", "space") else None
        return given[0]

    def given(self) -> list[str]:
        """The ways of rotating the frame that the declaration gives."""
        out = []
        if self.rotation is not None or self.angles is not None:
            out.append("rotation")
        if self.axis is not None or self.angle is not None:
            out.append("axis")
        if self.quaternion is not None:
            out.append("quaternion")
        if self.matrix is not None:
            out.append("matrix")
        return out


def parse_sequence(text: Any, where: str) -> tuple[str | None, tuple[int, ...], str | None]:
    """``"body ZXZ"`` -> ``("body", (2, 0, 2), None)``; on a problem ``(None, (), message)``."""
    example = "write rotation = \"body ZXZ\" or \"space XYZ\" (one to three axes X, Y, Z)"
    if not isinstance(text, str) or len(text.split()) != 2:
        return None, (), f"{where}: rotation {text!r} is not a sequence; {example}"
    kind, axes = text.split()
    if kind.lower() not in ("body", "space"):
        return None, (), (f"{where}: rotation '{text}': '{kind}' unknown"
                          f"{did_you_mean(kind.lower(), ('body', 'space'))}; {example}")
    bad = [a for a in axes if a.upper() not in _AXIS]
    if bad:
        return None, (), (f"{where}: rotation '{text}': unknown axis {', '.join(repr(a) for a in bad)}; "
                          "axes are X, Y, Z (or 1, 2, 3), e.g. \"body ZXZ\"")
    if not 1 <= len(axes) <= 3:
        return None, (), f"{where}: rotation '{text}' has {len(axes)} axes; give one to three, e.g. \"body ZXZ\""
    return kind.lower(), tuple(_AXIS[a.upper()] for a in axes), None


def elementary(axis: int, a: sp.Expr) -> sp.Matrix:
    """The rotation by *a* about the axis ``0 | 1 | 2`` (columns: the turned unit vectors)."""
    c, s = sp.cos(a), sp.sin(a)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def quaternion_matrix(e: Sequence[sp.Expr]) -> sp.Matrix:
    """The rotation of the Euler parameters ``e = (e0, e1, e2, e3)`` (scalar first), in the
    form of ``orient_quaternion`` (a rotation when ``|e| = 1``)."""
    e0, e1, e2, e3 = e
    return sp.Matrix([
        [e0**2 + e1**2 - e2**2 - e3**2, 2 * (e1 * e2 - e0 * e3), 2 * (e0 * e2 + e1 * e3)],
        [2 * (e1 * e2 + e0 * e3), e0**2 - e1**2 + e2**2 - e3**2, 2 * (e2 * e3 - e0 * e1)],
        [2 * (e1 * e3 - e0 * e2), 2 * (e0 * e1 + e2 * e3), e0**2 - e1**2 - e2**2 + e3**2]])


def matmul(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """``A @ B`` entry by entry, zero factors skipped: SymPy's own product converts symbolic
    matrices to a polynomial domain first, ten times slower on rotation chains."""
    rows = [[sp.Add(*[A[i, k] * B[k, j] for k in range(A.cols) if A[i, k] != 0 and B[k, j] != 0])
             for j in range(B.cols)] for i in range(A.rows)]
    return sp.Matrix(rows)


def _vee(W: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])


def relative(kind: str, data: dict, dt: Callable[[sp.Expr], sp.Expr]):
    """The rotation of a frame relative to its parent and its angular velocity.

    Parameters
    ----------
    kind : {"body", "space", "axis", "quaternion", "matrix"}
    data : dict
        The normalized declaration: ``axes`` and ``angles`` (body, space), ``axis`` (unit) and
        ``angle``, ``e`` (quaternion), ``R`` (matrix).
    dt : callable
        The total time derivative of an expression of the model.

    Returns
    -------
    R : sympy.Matrix, 3x3
        Parent components = R @ frame components.
    w_parent, w_own : sympy.Matrix, 3x1
        The angular velocity relative to the parent in the parent's and in the frame's axes.
    """
    if kind in ("body", "space"):
        axes, angles = data["axes"], data["angles"]
        Rs = [elementary(i, a) for i, a in zip(axes, angles)]
        rates = [dt(a) for a in angles]
        n = len(Rs)
        if kind == "space":   # R = R_n ... R_1 about the parent's axes
            R = sp.eye(3)
            for Rk in Rs:
                R = matmul(Rk, R)
            # w_parent = sum_k (R_n ... R_{k+1}) e_k a_k'
            w = sp.zeros(3, 1)
            outer = sp.eye(3)
            for k in reversed(range(n)):
                w += outer[:, axes[k]] * rates[k]
                outer = matmul(outer, Rs[k])
            return R, w, matmul(R.T, w)
        # body: R = R_1 ... R_n; w_parent = sum_k (R_1..R_{k-1}) e_k a_k',
        # w_own = sum_k (R_{k+1}..R_n)^T e_k a_k' (row a_k of the suffix product)
        prefix = [sp.eye(3)]
        for Rk in Rs:
            prefix.append(matmul(prefix[-1], Rk))
        suffix = [sp.eye(3)]
        for Rk in reversed(Rs):
            suffix.insert(0, matmul(Rk, suffix[0]))
        w_parent = sp.zeros(3, 1)
        w_own = sp.zeros(3, 1)
        for k in range(n):
            w_parent += prefix[k][:, axes[k]] * rates[k]
            w_own += suffix[k + 1][axes[k], :].T * rates[k]
        return prefix[-1], w_parent, w_own
    if kind == "axis":
        u, a = data["axis"], data["angle"]
        c, s = sp.cos(a), sp.sin(a)
        ux = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
        R = c * sp.eye(3) + s * ux + (1 - c) * (u * u.T)
        if not any(x.free_symbols & data["moving"] for x in u):   # a fixed axis: w = a' u
            w = u * dt(a)
            return R, w, w
        Rd = R.applyfunc(dt)
        return R, _vee(matmul(Rd, R.T)), _vee(matmul(R.T, Rd))
    if kind == "quaternion":
        e = data["e"]
        ed = [dt(x) for x in e]
        s, v, sd, vd = e[0], sp.Matrix(e[1:]), ed[0], sp.Matrix(ed[1:])
        # the rotation and angular velocity of e/|e|: invariant under e -> k e, so that the
        # generalized forces have no component along e (see nonideal.modeling.kinematics)
        n2 = sp.Add(*[x**2 for x in e])
        R = quaternion_matrix(e) / n2
        # w = 2 (e0 e' - e0' e +- e x e')/|e|^2: parent (+) and own (-) axes
        return R, 2 * (s * vd - sd * v + v.cross(vd)) / n2, 2 * (s * vd - sd * v - v.cross(vd)) / n2
    R = data["R"]
    Rd = R.applyfunc(dt)
    return R, _vee(matmul(Rd, R.T)), _vee(matmul(R.T, Rd))
