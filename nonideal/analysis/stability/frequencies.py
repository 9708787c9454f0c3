"""Natural frequencies of small oscillations about an equilibrium or a steady motion, from the
first approximation (:func:`~nonideal.analysis.stability.linearize.linearize`).

The linearization ``x' = A x`` on the constraint manifold (dependent coordinates eliminated,
ignorable ones dropped) has, for an undamped stable oscillation, the eigenvalues ``+-i w_k``
(and zeros for rigid-body motions: a free-free member, a cart's position kept); the natural
frequencies are the ``w_k``.  Gyroscopic terms (a rotating hub) are allowed: only the real
parts must vanish.  For a system with elastic members (:mod:`nonideal.modeling.members`) they
are the Rayleigh–Ritz approximations of the member's frequencies, upper bounds that decrease
to the exact ones as the number of shape functions grows (Meirovitch 1967, ch. 5); with the
members coupled through constraints the multipliers are the interaction forces of the parts
(Yushkov 1999, ch. I §5).

API::

    natural_frequencies(model, at=None, about="equilibrium", **linearize_options) -> Frequencies
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import MechanicsError
from ...modeling.model import Model
from .linearize import Linearization, linearize

__all__ = ["Frequencies", "natural_frequencies"]

#: relative size of a real part (of the largest eigenvalue's modulus) taken as zero
TOLERANCE = 1e-7


@dataclass(frozen=True)
class Frequencies:
    """The natural frequencies of a linearization.

    Attributes
    ----------
    model : str
    omega : tuple of float
        The nonzero circular frequencies (rad per time unit), ascending.
    rigid : int
        The number of zero frequencies: rigid-body motions (a coordinate nothing depends on,
        dropped from the linearization as ignorable, counts as one).
    modes : tuple of dict
        For each frequency, the coordinates' amplitudes of its mode (real, the largest 1).
    linearization : Linearization
    """

    model: str
    omega: tuple
    rigid: int
    modes: tuple = ()
    linearization: Any = field(default=None, repr=False)

    @property
    def hertz(self) -> tuple:
        """The frequencies in cycles per time unit, ``omega / (2 pi)``."""
        return tuple(w / (2 * np.pi) for w in self.omega)

    def to_dict(self) -> dict:
        return {"model": self.model, "omega": list(self.omega), "hertz": list(self.hertz),
                "rigid_modes": self.rigid, "modes": [dict(m) for m in self.modes],
                "state": {**self.linearization.q, **{k + "'": v for k, v in self.linearization.qdot.items()}}}

    def as_text(self) -> str:
        lin = self.linearization
        lines = [f"{self.model}: natural frequencies about the {lin.about}"]
        if lin.ignorable:
            lines.append("  ignorable (dropped): " + ", ".join(lin.ignorable))
        if self.rigid:
            lines.append(f"  rigid-body motions (zero frequency): {self.rigid}")
        lines.append("   k   omega (rad/s)        f (Hz)")
        for k, (w, f) in enumerate(zip(self.omega, self.hertz), 1):
            lines.append(f"  {k:2d}   {w:<18.10g} {f:.10g}")
        return "\n".join(lines)


def natural_frequencies(model: Model, at: Any = None, about: str = "equilibrium",
                        **options) -> Frequencies:
    """Natural frequencies about an equilibrium (or a steady motion) of *model*.

    Parameters
    ----------
    model : Model
    at : mapping or str, optional
        The state or a guess (see :func:`linearize`); default the initial state.
    about : {"equilibrium", "steady"}
    **options
        Passed to :func:`linearize` (``keep``, ``exact``, ``independent``).

    Returns
    -------
    Frequencies

    Raises
    ------
    MechanicsError
        The linearization has eigenvalues off the imaginary axis (damping, or an unstable
        equilibrium): there are no natural frequencies of free undamped oscillation.

    Examples
    --------
    >>> from nonideal.modeling.model import Model
    >>> m = Model("spring", ["x"], {"k": 4.0, "m": 1.0}, kinetic="m/2*x'^2", potential="k/2*x^2")
    >>> [round(w, 12) for w in natural_frequencies(m, at={"x": 0}).omega]
    [2.0]
    """
    if about not in ("equilibrium", "steady"):
        raise MechanicsError(f"natural frequencies: about '{about}' -- only about an equilibrium or a "
                             "steady motion (a programmed motion has a time-varying linearization)")
    lin: Linearization = linearize(model, about=about, at=at, **options)
    lam = np.linalg.eigvals(lin.A) if lin.A.size else np.zeros(0, complex)
    scale = max(1.0, float(np.abs(lam).max(initial=0.0)))
    off = [z for z in lam if abs(z.real) > TOLERANCE * scale]
    if off:
        worst = max(off, key=lambda z: abs(z.real))
        kind = "unstable (a growing motion)" if worst.real > 0 else "damped"
        raise MechanicsError(
            f"natural frequencies: the linearization of {model.name} about the {about} has "
            f"eigenvalues off the imaginary axis (largest real part {worst.real:.6g}: {kind}); natural "
            "frequencies are those of undamped stable oscillations -- see `nonideal stability` for "
            "the eigenvalues", state={**lin.q, **{k + "'": v for k, v in lin.qdot.items()}})
    zero = sum(1 for z in lam if abs(z) <= TOLERANCE * scale)
    values, vectors = np.linalg.eig(lin.A) if lam.size else (lam, np.zeros((0, 0)))
    n_q = sum(1 for v in lin.variables if not v.endswith("'"))
    rows = []
    for z, vec in zip(values, vectors.T):
        if z.imag > TOLERANCE * scale:
            shape = vec[:n_q] / vec[np.argmax(np.abs(vec[:n_q]))] if n_q else vec[:0]
            rows.append((float(z.imag), {name: float(np.real(a)) for name, a in
                                         zip(lin.variables[:n_q], shape)}))
    rows.sort(key=lambda r: r[0])
    # a rigid motion is a double zero eigenvalue, or a single one when linearize dropped its
    # coordinate as ignorable (nothing depends on it) and kept its velocity
    dropped = len(lin.ignorable)
    rigid = dropped + max(0, zero - dropped) // 2
    return Frequencies(model.name, tuple(w for w, _ in rows), rigid, tuple(m for _, m in rows), lin)
