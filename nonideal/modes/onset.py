"""The directions in which a two-component contact can start to slide (the onset of slip).

At a sticking contact whose friction reaches the cone, or at a contact that touches with no
slip, sliding in the unit direction ``s`` is a consistent continuation when the slip
acceleration of that sliding mode is ``U' = kappa s`` with ``kappa >= 0``: friction
opposing the slip that it starts.  These directions are the roots of the cross product
``U'(s) x s`` on the unit circle.

**The slip acceleration is a linear-fractional function of the direction.**  ``s`` enters
the saddle-point system of the sliding mode through one column only, the contact's friction
column ``G_n^T - sigma mu W^T s``, which is affine in ``s``; by the Sherman-Morrison formula
the solution, and with it ``U'(s)``, is ``(P0 + s_1 P1 + s_2 P2) / (1 + b . s)``.  Four
solves (``s = +-e1, +-e2``) fix its eight coefficients, a fifth checks them; the roots of the
numerator's cross product with ``s`` (a trigonometric polynomial of degree two: at most four)
are bracketed on a fine grid of the model, and each is polished on the solves themselves.
Where the check fails (a law whose friction is not affine in the direction) or a solve is
singular, the directions are found by scanning the solves on a grid of 72 directions.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..errors import MechanicsError, SingularSystem
from ..numeric.kernel import SingularMatrix, max_abs
from .types import SLIDE, ContactState, Mode

__all__ = ["onset_directions"]

_FAILED = (SingularSystem, SingularMatrix, MechanicsError)
_FIT = (0.0, 0.5 * math.pi, math.pi, -0.5 * math.pi)  # s = e1, e2, -e1, -e2
_CHECK = 1.0  # a fifth direction, away from the four
_MODEL_GRID = 1441
_POLISH = 1e-7  # half-width (rad) of the bracket of a root of the model on the solves


def onset_directions(solver, t: float, q: np.ndarray, qd: np.ndarray, mode: Mode, c: int) -> list[tuple]:
    """Directions ``s`` (unit, two components) at which contact *c* of *mode* can start to
    slide: ``U'(s) = kappa s`` with ``kappa >= 0`` -- to the tolerance of the sign tests of
    :func:`~nonideal.modes.switching.select_mode` (``1e-9 (1 + max |q''|)``): where the
    sticking friction reaches the cone (a located slip event) the onset is marginal, ``kappa =
    0`` up to rounding, and it is that onset that follows (not the sticking that the event
    ended, resumed until the rounding turns)."""
    name = solver.ck.names[c]
    sigma = mode.contacts[c][1].sigma
    y = np.concatenate((q, qd))

    def udot(phi):
        s = (math.cos(phi), math.sin(phi))
        motion = solver.motion(t, y, mode.with_contact(name, ContactState(SLIDE, s, sigma)))
        return motion.slip_acc(c), np.array(s), motion

    def cross(phi):
        ud, s, _ = udot(phi)
        return float(ud[0] * s[1] - ud[1] * s[0])

    roots = _model_roots(udot, cross)
    if roots is None:
        roots = _scanned_roots(cross)
    out = []
    for phi in roots:
        ud, s, motion = udot(phi)
        if ud @ s >= -1e-9 * (1.0 + max_abs(motion.qdd)):
            out.append(tuple(s))
    return out


def _scanned_roots(cross) -> list[float]:
    """The roots of *cross* bracketed on a grid of 72 directions (the general way)."""
    grid = np.linspace(-np.pi, np.pi, 73)
    vals = []
    for phi in grid:
        try:
            vals.append(cross(phi))
        except _FAILED:
            vals.append(np.nan)
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if not (np.isfinite(fa) and np.isfinite(fb)):
            continue
        if fa == 0 or fa * fb < 0:
            roots.append(a if fa == 0 else brentq(cross, a, b, xtol=1e-14))
    return roots


def _model_roots(udot, cross) -> list[float] | None:
    """The roots of *cross* from the linear-fractional model of ``U'(s)`` (module docstring),
    each polished on the solves; None where the model does not hold."""
    try:
        samples = [udot(phi)[:2] for phi in _FIT]
        ud_check, s_check, _ = udot(_CHECK)
    except _FAILED:
        return None
    coef = _fit(samples)
    if coef is None:
        return None
    P0, P1, P2, b = coef
    scale = 1.0 + max(max_abs(ud) for ud, _ in samples)
    predicted = (P0 + s_check[0] * P1 + s_check[1] * P2) / (1.0 + b @ s_check)
    if not np.all(np.abs(predicted - ud_check) <= 1e-9 * scale):
        return None
    # the numerator's cross product with s: a trigonometric polynomial of degree two
    phi = np.linspace(-np.pi, np.pi, _MODEL_GRID)
    cs, sn = np.cos(phi), np.sin(phi)
    num_x = P0[0] + cs * P1[0] + sn * P2[0]
    num_y = P0[1] + cs * P1[1] + sn * P2[1]
    values = num_x * sn - num_y * cs
    small = np.abs(values) <= 1e-13 * scale * (1.0 + np.abs(b).sum())
    if np.any(small[:-1] & small[1:]):
        return None  # the model vanishes over an interval: no isolated roots to bracket
    fa, fb = values[:-1], values[1:]
    roots = []
    for i in np.flatnonzero((fa == 0) | (fa * fb < 0)).tolist():
        root = _polish(cross, _model_root(P0, P1, P2, phi[i], phi[i + 1]) if fa[i] != 0 else phi[i])
        if root is None:
            return None
        roots.append(root)
    return roots


def _fit(samples) -> tuple | None:
    """``(P0, P1, P2, b)`` with ``U'(s) (1 + b . s) = P0 + s_1 P1 + s_2 P2`` at the four
    samples ``(U'(s), s)``."""
    A = np.zeros((8, 8))
    r = np.zeros(8)
    for i, (ud, s) in enumerate(samples):
        for k in range(2):  # unknowns: P0 (0, 1), P1 (2, 3), P2 (4, 5), b (6, 7)
            row = 2 * i + k
            A[row, k], A[row, 2 + k], A[row, 4 + k] = -1.0, -s[0], -s[1]
            A[row, 6], A[row, 7] = ud[k] * s[0], ud[k] * s[1]
            r[row] = -ud[k]
    try:
        x = np.linalg.solve(A, r)
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(x)):
        return None
    return x[0:2], x[2:4], x[4:6], x[6:8]


def _model_root(P0, P1, P2, a: float, b: float) -> float:
    def f(phi):
        cs, sn = math.cos(phi), math.sin(phi)
        return (P0[0] + cs * P1[0] + sn * P2[0]) * sn - (P0[1] + cs * P1[1] + sn * P2[1]) * cs
    return brentq(f, a, b, xtol=1e-15)


def _polish(cross, phi: float) -> float | None:
    """The root of *cross* (the solves) within :data:`_POLISH` of the model's root *phi*, or
    None when the solves show no sign change there."""
    try:
        lo, hi = phi - _POLISH, phi + _POLISH
        flo, fhi = cross(lo), cross(hi)
        if flo == 0:
            return lo
        if fhi == 0:
            return hi
        if flo * fhi > 0:
            return None
        return brentq(cross, lo, hi, xtol=1e-14)
    except _FAILED:
        return None
