"""Rotation matrices of the gallery's rigid bodies: successive rotations about body axes (the
matrix maps body components to N components), built with SymPy rather than typed out."""

from __future__ import annotations

import sympy as sp

__all__ = ["body_rotation"]


def _axis(axis: str, angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return {"x": sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def body_rotation(axes: str, angles) -> list[list[sp.Expr]]:
    """``R = R_axes[0](angles[0]) R_axes[1](angles[1]) ...`` (body-fixed sequence) as a nested
    list, e.g. ``body_rotation("zxz", ("psi", "theta", "phi"))`` for Euler's angles.

    Examples
    --------
    >>> body_rotation("z", ("c",))[0]
    [cos(c), -sin(c), 0]
    """
    R = sp.eye(3)
    for axis, angle in zip(axes, angles):
        R = R * _axis(axis, sp.Symbol(angle) if isinstance(angle, str) else angle)
    return R.tolist()
