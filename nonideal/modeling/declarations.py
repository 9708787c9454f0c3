"""The parts of a model declaration: :class:`Parameter`, :class:`Constraint` (with its kind,
reaction direction and order) and :class:`SimulationSettings`, and the names they reserve."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any


from ..errors import did_you_mean
from .expressions import CONSTANTS, FUNCTIONS

__all__ = ["Parameter", "Constraint", "Control", "SimulationSettings", "RESERVED_NAMES",
           "CONSTRAINT_TYPES", "METHODS", "SPLIT_RULES", "split_problems"]

RESERVED_NAMES = frozenset({"t"} | set(FUNCTIONS) | set(CONSTANTS))

CONSTRAINT_TYPES = ("holonomic", "nonholonomic", "servo")
ROOT_RULES = ("largest", "smallest")
METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
#: how the reactions of a statically indeterminate contact set are split (the motion does not
#: depend on it): see :mod:`nonideal.modes.indeterminate`
SPLIT_RULES = ("widest-margin", "least-norm")


@dataclass(frozen=True)
class Parameter:
    """A named constant: value in the model's base units (SI unless ``[units]`` says
    otherwise), optional unit and description.

    ``definition`` is the expression (text) a derived parameter was given by, in the other
    parameters (``A = "m*r^2/4"``), ``""`` for a number; ``value`` is its value.  Analyses in
    symbolic parameters substitute it (``stability --symbolic r`` carries ``A`` as ``m*r^2/4``).
    ``given`` is the quantity as written when it was converted (``"30 deg"`` for the value
    ``0.5236`` rad).
    """

    name: str
    value: float
    unit: str = ""
    description: str = ""
    definition: str = ""
    given: str = ""


@dataclass(frozen=True)
class Constraint:
    """A constraint ``expr = 0`` (or ``expr >= 0`` if ``unilateral``) with its reaction.

    Parameters
    ----------
    name : str
    expr : str or sympy.Expr
        Holonomic constraints depend on coordinates and time; nonholonomic ones also on
        velocities (linear or not: Chetaev's rule gives the reaction direction); a
        second-order constraint may contain accelerations (``x''``), one of order n >= 3 the
        n-th derivatives (``x'''``, ``x''''``, ...), linearly or not (then with ``reaction``).
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
        2021, (3.7); :func:`nonideal.analysis.studies.quasi_ideal.actuator_heat`).
    root : {"largest", "smallest"}, optional
        A second-order constraint nonlinear in the accelerations (with ``reaction``): which
        root of its multiplier (default ``"largest"``).
    controls : sequence of j direction vectors (n_q expressions each), optional
        Several control directions for one program (Béghin 1922: r < j, indeterminate); the
        controls are the least-cost ones, ``min u^T cost u`` (least norm by default).
    cost : j x j nested sequence of numbers / parameter expressions, optional
        The symmetric positive-definite quadratic cost of the controls.
    initial : number, expression, or sequence of them, optional
        A constraint of order n >= 3 (``x'''``, ``x''''``, ... in ``expr``): its force and the
        force's derivatives up to order ``n - 3`` at ``t0``, which the state (q, q') does not
        determine.  With ``reaction``: the multiplier ``lambda(t0)`` (order 3), or the sequence
        ``(lambda, lambda', ...)`` of ``n - 2`` numbers.  Without (ideal: ``R^(n-2) = Lambda
        (d expr/d q^(n))^T``, the generalized Gauss principle of order n): the generalized
        reaction ``R(t0)`` (n_q components; order 3), or ``n - 2`` such sequences
        ``(R, R', ...)``.  In a model file: ``[initial] lambda_<name>``, ``"lambda_<name>'"``, ...
    """

    name: str
    expr: Any
    kind: str = "auto"
    unilateral: bool = False
    reaction: tuple[Any, ...] | None = None
    transform: tuple[tuple[Any, ...], ...] | None = None
    restitution: float = 0.0
    order: int = -1  # filled by the Model: 0 holonomic, 1 first order, 2 second, n: order n
    losses: tuple[Any, ...] | None = None
    root: str | None = None  # "largest" | "smallest": a constraint nonlinear in q''
    controls: tuple[tuple[Any, ...], ...] | None = None  # j control directions (Beghin: r < j)
    cost: tuple[tuple[Any, ...], ...] | None = None      # j x j quadratic cost of the controls
    initial: Any = None  # order n >= 3: the force and its derivatives at t0 (normalized: n - 2 levels)
    shared: bool = False  # a servo program realized by the model's shared controls (set by the Model)

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
        if self.reaction is not None or self.controls is not None or self.shared:
            return "servo"
        if self.transform is not None:
            return "quasi-ideal"
        return "ideal"


@dataclass(frozen=True)
class Control:
    """A control shared by the servo-constraints of a model (Béghin 1922: r programs realized by
    one set of j controls; ``[[controls]]`` in a model file).

    Parameters
    ----------
    name : str
    direction : sequence of n_q expressions
        The generalized direction ``d`` of its force ``d u`` (may contain velocities).
    weight : number or expression in the parameters, > 0
        Its weight in the rule that chooses the controls when they are more than the programs
        (r < j): the least ``sum_k weight_k u_k^2`` (default 1: the least-norm controls).
    description : str
    """

    name: str
    direction: tuple[Any, ...]
    weight: Any = 1
    description: str = ""


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
    #: the rule that splits statically indeterminate reactions (one of :data:`SPLIT_RULES`)
    split: str = "widest-margin"
    #: the relative compliance of each row in the ``least-norm`` rule, by constraint or contact
    #: name: ``(c,)`` for every component, ``(c_normal, c_tangential)`` for a contact; 1 if absent
    split_weights: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    #: the output: a uniform grid of this many times and each event's state (None: the
    #: default, 1001), or every accepted step
    grid: int | None = None
    every_step: bool = False

    def __post_init__(self):
        if isinstance(self.split_weights, Mapping):   # a number for every component, or a list
            object.__setattr__(self, "split_weights", {
                k: tuple(v) if isinstance(v, (list, tuple)) else (v,) for k, v in self.split_weights.items()})

    def __hash__(self) -> int:
        return hash((self.t_end, self.rtol, self.atol, self.method, self.max_step, self.singular,
                     self.grid, self.every_step, self.split, tuple(sorted(self.split_weights.items()))))


def split_problems(settings: SimulationSettings, constraints: Iterable[str],
                   contacts: Iterable[str]) -> list[str]:
    """What is wrong with ``[simulation] split`` and ``split_weights`` (empty when nothing)."""
    out = []
    if settings.split not in SPLIT_RULES:
        out.append(f"[simulation] split: '{settings.split}' unknown{did_you_mean(str(settings.split), SPLIT_RULES)}; "
                   f"choose one of {', '.join(SPLIT_RULES)}")
    weights = settings.split_weights
    if not isinstance(weights, Mapping):
        return out + [f"[simulation] split_weights: must be a table name = weight (got {weights!r})"]
    rows, touching = set(constraints), set(contacts)
    for name, w in weights.items():
        if name not in rows | touching:
            out.append(f"[simulation] split_weights: '{name}' is not a constraint or contact"
                       f"{did_you_mean(str(name), sorted(rows | touching))}")
            continue
        size = (1, 2) if name in touching else (1,)
        if not (isinstance(w, tuple) and len(w) in size
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) and 0 < v < float("inf") for v in w)):
            form = "a number > 0, or [normal, tangential] numbers > 0" if name in touching else "a number > 0"
            out.append(f"[simulation] split_weights: {name} must be {form} (got {w!r})")
    if weights and settings.split != "least-norm" and settings.split in SPLIT_RULES:
        out.append("[simulation] split_weights: used by split = \"least-norm\" only (split is "
                   f"\"{settings.split}\"); set split = \"least-norm\" or remove the weights")
    return out
