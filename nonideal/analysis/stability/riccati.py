"""The Riccati equation ``omega' = A omega^2 + B`` and its regimes.

A point kept on a circle of radius ``r0`` by a quasi-ideal constraint (Briskin et al. 2021,
sec. 3.2) turns with the angular velocity ``omega`` of a Riccati equation with constant
coefficients, (3.13)-(3.14):

    d omega / dt - A omega^2 = B,      A = beta / r0,
    B = F cos(gamma) / (m r0) - beta F sin(gamma) / (m r0^2)

(the force F pushes the point forward along the circle at the angle gamma to the tangent,
inwards; the printed (3.14) has ``+ beta F sin(gamma)``, which contradicts the paper's own
Table 1, ``B = (1 - A)/sqrt(2)`` for m = 1, F = 2, r0 = 2, gamma = pi/4).

:func:`riccati_regime` says which of the four cases of the paper, (3.15)-(3.17) and the
special case A = 0, a given ``(A, B, omega0)`` falls in, and what the motion does: a finite
blow-up time (the "regime with sharpening", energy pumped in by the reactions), a limit
angular velocity, linear growth, or rest.  The closed form ``omega(t)`` is exact in every case
(:meth:`RiccatiRegime.omega`), derived for any signs of A and B: the printed (3.15) and (3.17)
hold for ``A > 0`` only (for ``A < 0`` the argument of tan/tanh is ``A c t``, not ``|A| c t``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RiccatiRegime", "riccati_regime"]

BLOW_UP, LIMIT, LINEAR, CONSTANT = "blow-up", "limit", "linear growth", "constant"


@dataclass(frozen=True)
class RiccatiRegime:
    """The solution of ``omega' = A omega^2 + B``, ``omega(0) = omega0``, classified.

    Attributes
    ----------
    A, B, omega0 : float
    case : int
        The case of Briskin et al. 2021: 1 (``B/A > 0``, (3.15), tan), 2 (``B = 0``, (3.16)),
        3 (``B/A < 0``, (3.17), tanh), 4 (``A = 0``, the special case).
    behaviour : {"blow-up", "limit", "linear growth", "constant"}
    limit : float or None
        ``lim omega`` as ``t -> inf`` when the motion has one.
    blowup_time : float or None
        The time at which ``|omega|`` becomes infinite (``behaviour == "blow-up"``).
    """

    A: float
    B: float
    omega0: float
    case: int
    behaviour: str
    limit: float | None
    blowup_time: float | None

    def omega(self, t):
        """The exact ``omega(t)`` (``t`` before the blow-up time), ``ndarray`` like ``t``."""
        t = np.asarray(t, dtype=float)
        A, B, w0 = self.A, self.B, self.omega0
        if self.case == 4:
            return w0 + B * t
        if self.case == 2:
            return w0 / (1.0 - A * w0 * t)
        if self.case == 1:
            c = math.sqrt(B / A)
            s = math.copysign(1.0, A)
            return s * c * np.tan(A * s * c * t + math.atan(s * w0 / c))
        c = math.sqrt(-B / A)
        if abs(w0) < c:
            return -c * np.tanh(A * c * t - math.atanh(w0 / c))
        if abs(w0) == c:
            return np.full_like(t, w0)
        return -c / np.tanh(A * c * t - _acoth(w0 / c))

    def to_dict(self) -> dict:
        return {"A": self.A, "B": self.B, "omega0": self.omega0, "case": self.case,
                "behaviour": self.behaviour, "limit": self.limit,
                "blowup_time": self.blowup_time}

    def as_text(self) -> str:
        head = (f"omega' = A omega^2 + B with A = {self.A:.6g}, B = {self.B:.6g}, "
                f"omega(0) = {self.omega0:.6g}: case {self.case} (Briskin et al. 2021, "
                f"{_EQUATION[self.case]})")
        if self.behaviour == BLOW_UP:
            return f"{head}; omega blows up at t = {self.blowup_time:.6g}"
        if self.behaviour == LIMIT:
            return f"{head}; omega tends to {self.limit:.6g}"
        if self.behaviour == LINEAR:
            return f"{head}; omega grows linearly, omega = {self.omega0:.6g} + {self.B:.6g} t"
        return f"{head}; omega stays {self.omega0:.6g}"


_EQUATION = {1: "(3.15)", 2: "(3.16)", 3: "(3.17)", 4: "sec. 3.2, case 4"}


def _acoth(x: float) -> float:
    return 0.5 * math.log((x + 1.0) / (x - 1.0))


def riccati_regime(A: float, B: float, omega0: float = 0.0, tol: float = 1e-12) -> RiccatiRegime:
    """Classify the motion of ``omega' = A omega^2 + B`` from ``omega(0) = omega0``.

    Parameters
    ----------
    A, B : float
        The coefficients (Briskin et al. 2021, (3.14)).
    omega0 : float
        The initial angular velocity.
    tol : float
        ``|A|`` or ``|B|`` below ``tol`` (relative to the scale of the other) count as zero.

    Returns
    -------
    RiccatiRegime

    Examples
    --------
    >>> riccati_regime(0.5, 0.5 / 2 ** 0.5).behaviour      # beta = 1 of Table 1
    'blow-up'
    >>> round(riccati_regime(-0.5, 1.5 / 2 ** 0.5).limit, 6)   # beta = -1
    1.456475
    """
    A, B, w0 = float(A), float(B), float(omega0)
    scale = max(abs(A), abs(B), 1.0)
    if abs(A) <= tol * scale:
        if abs(B) <= tol * scale:
            return RiccatiRegime(0.0, 0.0, w0, 4, CONSTANT, w0, None)
        return RiccatiRegime(0.0, B, w0, 4, LINEAR, None, None)
    if abs(B) <= tol * scale:
        # omega = w0 / (1 - A w0 t): blows up when A w0 > 0, else decays to 0
        if A * w0 > 0:
            return RiccatiRegime(A, 0.0, w0, 2, BLOW_UP, None, 1.0 / (A * w0))
        if w0 == 0.0:
            return RiccatiRegime(A, 0.0, w0, 2, CONSTANT, 0.0, None)
        return RiccatiRegime(A, 0.0, w0, 2, LIMIT, 0.0, None)
    if A * B > 0:
        c = math.sqrt(B / A)
        s = math.copysign(1.0, A)
        t_star = (math.pi / 2 - math.atan(s * w0 / c)) / math.sqrt(A * B)
        return RiccatiRegime(A, B, w0, 1, BLOW_UP, None, t_star)
    c = math.sqrt(-B / A)
    s = math.copysign(1.0, A)
    stable, unstable = -s * c, s * c
    if w0 == unstable:
        return RiccatiRegime(A, B, w0, 3, CONSTANT, w0, None)
    if s * (w0 - unstable) > 0:
        # beyond the unstable equilibrium: -c coth(A c t - acoth(w0/c)) reaches infinity
        t_star = _acoth(w0 / c) / (A * c)
        return RiccatiRegime(A, B, w0, 3, BLOW_UP, None, t_star)
    return RiccatiRegime(A, B, w0, 3, LIMIT, stable, None)
