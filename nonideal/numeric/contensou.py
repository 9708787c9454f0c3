"""Coulomb's friction integrated over a circular contact patch: Contensou's coupling of sliding
and pivoting (Contensou 1963; Zhuravlev 1998, the same integrals in closed form).

A patch of radius rho under uniform pressure ``p = N/(pi rho^2)`` slides at ``v`` and pivots at
``omega`` about its normal.  Its points move about the instantaneous centre ``r_c``, at distance
``d rho`` from the patch's centre (``d = |v|/(rho |omega|)``); on the circle of radius ``s``
about ``r_c`` the part inside the patch is the arc ``|phi| <= alpha(s)`` about the direction to
the centre, ``cos alpha = (s^2 + d^2 - 1)/(2 s d)`` (rho = 1).  The Coulomb tractions, tangent
to these circles, sum to

    f(d) = (1/pi) int 2 s sin(alpha) ds,
    m(d) = (2/3) max(0, 1 - d)^3 + (1/pi) int (2 alpha s^2 - 2 d s sin(alpha)) ds,

over ``|1 - d| <= s <= 1 + d`` (the first term of m: the whole circles inside the patch) --
the force ``-mu N f(d) v/|v|`` and the torque ``-mu N rho m(d) omega/|omega|``.  The integrands
have square-root ends; ``s = c - h cos(t)`` makes them smooth and Gauss-Legendre in ``t``
converges exponentially: 32 nodes give the integrals to ~1e-15 (f(1) = 8/(3 pi)).  Below
d = 1e-3 and above d = 100 the series f = d (1 - d^2/8 - d^4/64), m = 2/3 - d^2/2 + 3 d^4/32 and
f = 1 - 1/(8 d^2) - 1/(64 d^4), m = (1 + 1/(12 d^2) + 3/(128 d^4))/(4 d) replace the quadrature
(whose terms cancel there); both agree with the integrals evaluated to 40 digits to 1e-12.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["contensou", "contensou_shape"]

_X, _W = np.polynomial.legendre.leggauss(32)
_T = (_X + 1.0) * (math.pi / 2)
_WT = _W * (math.pi / 2)
_COS, _SIN = np.cos(_T), np.sin(_T)


def contensou(d: float) -> tuple[float, float]:
    """``(f(d), m(d))``: the friction force and the pivoting torque of a patch of unit radius
    sliding at ``d`` times its rim's pivoting speed, per unit ``mu N`` (module docstring).

    Examples
    --------
    >>> [round(x, 12) for x in contensou(0.0)], round(contensou(1.0)[0] * 3 * math.pi / 8, 12)
    ([0.0, 0.666666666667], 1.0)
    """
    if d < 1e-3:                       # mostly pivoting: the series to O(d^6)
        d2 = d * d
        return d * (1.0 - d2 / 8.0 - d2 * d2 / 64.0), 2.0 / 3.0 - d2 / 2.0 + 3.0 * d2 * d2 / 32.0
    if d > 100.0:                      # mostly sliding: the series to O(1/d^6)
        e2 = 1.0 / (d * d)
        return 1.0 - e2 / 8.0 - e2 * e2 / 64.0, 0.25 / d * (1.0 + e2 / 12.0 + 3.0 * e2 * e2 / 128.0)
    lo, hi = abs(1.0 - d), 1.0 + d
    c, h = 0.5 * (lo + hi), 0.5 * (hi - lo)
    s = c - h * _COS
    ds = h * _SIN * _WT
    # sin(alpha) without cancellation: 4 s^2 d^2 sin^2 = ((s + d)^2 - 1)(1 - (s - d)^2)
    sa = np.sqrt(np.maximum(((s + d) ** 2 - 1.0) * (1.0 - (s - d) ** 2), 0.0)) / (2.0 * s * d)
    a = np.arctan2(sa, (s * s + d * d - 1.0) / (2.0 * s * d))
    f = float(np.dot(2.0 * s * sa, ds)) / math.pi
    m = (2.0 / 3.0) * max(0.0, 1.0 - d) ** 3 + float(np.dot(2.0 * a * s * s - 2.0 * d * s * sa, ds)) / math.pi
    return f, m


def contensou_shape(U) -> np.ndarray:
    """The friction "shape" ``s`` of a Coulomb-Contensou contact (``F = -mu N s``) from its slip
    ``U = (U1, U2, rho omega_n)``: ``f(d) U12/|U12|`` and ``m(d) sign(omega_n)``; None where the
    slip and the pivoting both vanish (the law is set-valued there)."""
    u = math.hypot(U[0], U[1])
    w = abs(U[2])
    if w == 0.0:
        if u == 0.0:
            return None
        return np.array([U[0] / u, U[1] / u, 0.0])
    f, m = contensou(u / w)
    scale = f / u if u > 0.0 else 1.0 / w      # f(d)/u -> 1/w as u -> 0
    return np.array([U[0] * scale, U[1] * scale, math.copysign(m, U[2])])
