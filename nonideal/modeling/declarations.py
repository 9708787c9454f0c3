"""The parts of a model declaration: :class:`Parameter`, :class:`Constraint` (with its kind,
reaction direction and order) and :class:`SimulationSettings`, and the names they reserve."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any


from .expressions import CONSTANTS, FUNCTIONS

__all__ = ["Parameter", "Constraint", "SimulationSettings", "RESERVED_NAMES", "CONSTRAINT_TYPES",
           "METHODS"]

RESERVED_NAMES = frozenset({"t"} | set(FUNCTIONS) | set(CONSTANTS))

CONSTRAINT_TYPES = ("holonomic", "nonholonomic", "servo")
ROOT_RULES = ("largest", "smallest")
METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")


@dataclass(frozen=True)
class Parameter:
    """A named constant: value in SI units, optional unit and description."""

    name: str
    value: float
    unit: str = ""
    description: str = ""


@dataclass(frozen=True)
class Constraint:
    """A constraint ``expr = 0`` (or ``expr >= 0`` if ``unilateral``) with its reaction.

    Parameters
    ----------
    name : str
    expr : str or sympy.Expr
        Holonomic constraints depend on coordinates and time; nonholonomic ones also on
        velocities (linear or not: Chetaev's rule gives the reaction direction); a
        second-order constraint may contain accelerations linearly.
    kind : {"auto", "holonomic", "nonholonomic", "servo"}
        ``"auto"`` infers holonomic/nonholonomic from the derivatives present.  ``"servo"``
        requires ``reaction``.
    unilateral : bool
        ``expr >= 0`` with a multiplier ``>= 0``, released when it would become negative
        (holonomic constraints only).
    restitution : float
        Impact law when a released unilateral constraint closes again: 0 (default) plastic,
        ``e > 0`` Newton's law.
    reaction : sequence of n_q expressions, optional
        Generalized reaction direction (servo-constraint realized by a control force of
        prescribed direction).  Default: ideal (the gradient of ``expr`` by the highest
        derivative present).
    transform : n_q x n_q nested sequence, optional
        Quasi-ideal constraint: the reaction ``R`` satisfies ``A R = (df/dq)^T lambda``.
    losses : sequence of n_q expressions in the parameters, optional
        Heat loss coefficients ``mu_j`` of the drives that produce the generalized reaction
        components ``R_j``: they lose ``sum_j mu_j R_j^2`` per unit time (Briskin et al.
        2021, (3.7); :func:`nonideal.analysis.quasi_ideal.actuator_heat`).
    root : {"largest", "smallest"}, optional
        A second-order constraint nonlinear in the accelerations (with ``reaction``): which
        root of its multiplier (default ``"largest"``).
    controls : sequence of j direction vectors (n_q expressions each), optional
        Several control directions for one program (Béghin 1922: r < j, indeterminate); the
        controls are the least-cost ones, ``min u^T cost u`` (least norm by default).
    cost : j x j nested sequence of numbers / parameter expressions, optional
        The symmetric positive-definite quadratic cost of the controls.
    """

    name: str
    expr: Any
    kind: str = "auto"
    unilateral: bool = False
    reaction: tuple[Any, ...] | None = None
    transform: tuple[tuple[Any, ...], ...] | None = None
    restitution: float = 0.0
    order: int = -1  # filled by the Model: 0 holonomic, 1 first order, 2 second order
    losses: tuple[Any, ...] | None = None
    root: str | None = None  # "largest" | "smallest": a constraint nonlinear in q''
    controls: tuple[tuple[Any, ...], ...] | None = None  # j control directions (Beghin: r < j)
    cost: tuple[tuple[Any, ...], ...] | None = None      # j x j quadratic cost of the controls

    @classmethod
    def holonomic(cls, name: str, expr: Any, unilateral: bool = False, **kw) -> "Constraint":
        return cls(name, expr, "holonomic", unilateral, **kw)

    @classmethod
    def nonholonomic(cls, name: str, expr: Any, **kw) -> "Constraint":
        return cls(name, expr, "nonholonomic", **kw)

    @classmethod
    def servo(cls, name: str, expr: Any, reaction: Iterable[Any], **kw) -> "Constraint":
        return cls(name, expr, "servo", reaction=tuple(reaction), **kw)

    @property
    def reaction_kind(self) -> str:
        """``"ideal"``, ``"servo"`` or ``"quasi-ideal"``."""
        if self.reaction is not None or self.controls is not None:
            return "servo"
        if self.transform is not None:
            return "quasi-ideal"
        return "ideal"


@dataclass(frozen=True)
class SimulationSettings:
    """Integrator settings: end time, tolerances, SciPy method, optional max step, and what a
    run does where the constraints become singular (``"smooth"``: go on on the smooth branch;
    ``"stop"``)."""

    t_end: float | None = None
    rtol: float = 1e-10
    atol: float = 1e-12
    method: str = "DOP853"
    max_step: float | None = None
    singular: str = "smooth"
