"""The modes of a hybrid mechanical system and the motion in a mode, as data.

A :class:`Mode` says which unilateral constraints are held and, for every contact, its
:class:`ContactState`: separated, sticking (rolling), sliding in a direction, or "smooth" -- the
one touching state of a contact without a sticking mode.  :class:`RowSpec` names a row of a
mode's linear system, :class:`Solution` is the motion at a state (accelerations, multipliers,
contact forces) -- the one result every solve route of :mod:`nonideal.modes.solver` returns.

This module imports nothing above :mod:`nonideal.modeling`: the machinery that computes these
objects imports them, never the other way round.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

__all__ = ["Mode", "ContactState", "RowSpec", "Solution", "ContactForce",
           "SEPARATED", "STICK", "SLIDE", "SMOOTH"]

SEPARATED, STICK, SLIDE, SMOOTH = "separated", "stick", "slide", "smooth"


@dataclass(frozen=True)
class ContactState:
    """State of one contact.

    Attributes
    ----------
    state : {"separated", "stick", "slide", "smooth"}
        "smooth": touching, for a regularized law or a frictionless contact (no direction).
    direction : tuple of float
        Sliding: ``(+1,)`` or ``(-1,)`` for one slip component (the sign of ``U``); for two
        components the unit direction used only while ``|U| ~ 0`` at the onset of sliding
        (afterwards ``s = U/|U|``).
    sigma : int
        Sign of the normal force (bilateral contacts; +1 for unilateral ones).
    """

    state: str = SEPARATED
    direction: tuple[float, ...] = ()
    sigma: int = 1

    def label(self) -> str:
        return self._label

    @cached_property
    def _label(self) -> str:
        if self.state == SLIDE and len(self.direction) == 1:
            out = "slide+" if self.direction[0] > 0 else "slide-"
        else:
            out = self.state
        return out + ("(N<0)" if self.sigma < 0 else "")

    @property
    def structure(self) -> tuple:
        """What the symbolic equations depend on (directions enter as numbers)."""
        return (self.state, self.sigma)


@dataclass(frozen=True)
class Mode:
    """Held unilateral constraints and the state of every contact (model order)."""

    held: frozenset[str] = frozenset()
    contacts: tuple[tuple[str, ContactState], ...] = ()

    def contact(self, name: str) -> ContactState:
        for n, cs in self.contacts:
            if n == name:
                return cs
        return ContactState()

    def label(self) -> str:
        return self._label

    @cached_property
    def _label(self) -> str:
        parts = sorted(self.held)
        parts += [f"{n}:{cs.label()}" for n, cs in self.contacts]
        return ", ".join(parts) if parts else "free"

    @cached_property
    def structure(self) -> tuple:
        """What the equations depend on (directions enter as numbers)."""
        return (self.held, tuple((n, cs.structure) for n, cs in self.contacts))

    def with_contact(self, name: str, cs: ContactState) -> "Mode":
        return Mode(self.held, tuple((n, cs if n == name else c) for n, c in self.contacts))


@dataclass(frozen=True)
class RowSpec:
    """One row of a mode: ``kind`` is "constraint" (kernel row ``index``), "normal" (contact
    ``index``) or "tangent" (component ``k`` of contact ``index``)."""

    kind: str
    index: int
    k: int = 0
    name: str = ""


@dataclass
class ContactForce:
    """Contact quantities at a state: normal force, friction force, slip, gap."""

    state: str
    N: float = 0.0
    F: np.ndarray = field(default_factory=lambda: np.zeros(0))
    U: np.ndarray = field(default_factory=lambda: np.zeros(0))
    Udot: np.ndarray = field(default_factory=lambda: np.zeros(0))
    gap: float = 0.0
    gap_rate: float = 0.0
    gap_acc: float = 0.0
    mu: float = 0.0
    mu_s: float = 0.0

    def to_dict(self) -> dict:
        return {"mode": self.state, "normal": float(self.N), "friction": [float(v) for v in self.F],
                "slip": [float(v) for v in self.U], "gap": float(self.gap)}


@dataclass
class Solution:
    """The motion at one state in one mode.

    Attributes
    ----------
    qdd : ndarray, shape (n_q,)
    rows : list of int -- active kernel constraint rows
    multipliers : ndarray -- multipliers of ``rows`` (same order)
    layout : list of RowSpec -- every row of the mode; ``values`` their multipliers
    M, F : ndarray -- mass matrix and forcing
    G, gamma, B : ndarray -- every constraint row of the kernel (active or not)
    Gm, gammam, Bm : ndarray -- the assembled rows of the mode
    contacts : dict name -> ContactForce
    friction : ndarray, shape (n_q,) -- generalized friction force ``sum_k W_k^T F_k``
    direct : dict name -> float -- the multipliers the form computes itself
    particular : bool -- the rows are dependent and ``values`` is the minimum-norm solution
        (``ModeSolver.solve(..., distribute=False)``), not the reported distribution
    shown : Solution or None -- the same motion with the multipliers split by another rule
        than the widest margin (``[simulation] split``); None when they are these

    For a mode with dependent rows (statically indeterminate reactions) ``values`` is the
    admissible distribution with the widest margins (:mod:`nonideal.modes.indeterminate`): the
    one the mode's consistency and its events read.  What is reported is :attr:`reported`.
    """

    qdd: np.ndarray
    rows: list[int]
    multipliers: np.ndarray
    layout: list[RowSpec]
    values: np.ndarray
    M: np.ndarray
    F: np.ndarray
    G: np.ndarray
    gamma: np.ndarray
    B: np.ndarray
    Gm: np.ndarray
    gammam: np.ndarray
    Bm: np.ndarray
    contacts: dict[str, ContactForce] = field(default_factory=dict)
    friction: np.ndarray | None = None
    direct: dict[str, float] = field(default_factory=dict)
    particular: bool = False
    shown: "Solution | None" = None

    @property
    def reported(self) -> "Solution":
        """The motion with the multipliers of the model's split rule (itself when the
        reactions are unique or the rule is the widest margin)."""
        return self.shown if self.shown is not None else self

    def multiplier(self, row: int) -> float:
        return float(self.multipliers[self.rows.index(row)]) if row in self.rows else 0.0
