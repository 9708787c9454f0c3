"""Events of the hybrid simulation, as objects.

An event has a scalar ``value(motion)`` whose sign change (from positive to non-positive) marks
the switch, a ``kind`` and the name of the constraint or contact it concerns.  It reads the
:class:`~nonideal.modes.motion.Motion` at a state, which computes only what is asked: a slip
stop or a touch needs the kinematics, not the accelerations.  The driver locates the root on
the integrator's dense output (Brent's method) and then asks the mode selection what happens
next.  Nothing is patched onto functions.

======================  ======================================  =============================
event                   value                                   in mode
======================  ======================================  =============================
:class:`Release`        multiplier of a unilateral constraint   held
:class:`Touch`          the constraint function ``f``           released
:class:`ContactTouch`   the gap ``g``                           contact separated
:class:`Lift`           the normal force ``sigma N``            contact touching
:class:`SlipStart`      ``mu_s |N| - |F|``                      contact sticking
:class:`SlipStop`       ``s . U`` (one component),              contact sliding
                        ``U . s_ref`` (two; ``s_ref`` the
                                                                slip direction at step start)
:class:`Jam`            effective normal compliance ``b``       contact sliding (Painleve)
======================  ======================================  =============================

``row`` is the kernel row of a constraint event and the index of the contact of a contact event.

The ``kind`` of an event is what it watches; the ``type`` it is recorded with says what happened
to its contact, read from the states before and after the switch (:func:`transition`):

============  =====================================================================
type          what happened
============  =====================================================================
touch         a separated contact closed (whatever the impact left: the record has
              the mode after it)
lift-off      a touching contact separated
slip          a sticking contact started sliding
stick         a sliding contact started sticking (rolling)
reverse       a sliding contact's slip changed direction without sticking (one
              component: its sign; two: it passed through or near zero)
normal-sign   a bilateral contact's normal force changed sign (and so its friction)
============  =====================================================================

When the contact's state did not change (another contact's did), the record keeps the
event's kind.  Constraint events are recorded with their kind (``release``, ``contact``).  When
a switch changes other contacts too (the legs of a table starting to slip together), the record
lists every change, ``changes = {contact: type}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..modes.types import SEPARATED, SLIDE, SMOOTH, STICK, ContactState

__all__ = ["Event", "Release", "Touch", "ContactTouch", "Lift", "SlipStart", "SlipStop", "Jam",
           "transition", "mode_events"]


def transition(before: ContactState, after: ContactState) -> str | None:
    """What happened to a contact whose state went from *before* to *after* (the types of the
    module docstring), or ``None`` when its state did not change.

    Examples
    --------
    >>> transition(ContactState(SLIDE, (1.0,)), ContactState(SLIDE, (-1.0,)))
    'reverse'
    >>> transition(ContactState(SLIDE, (1.0,)), ContactState(STICK))
    'stick'
    """
    if before.state == SEPARATED:
        return None if after.state == SEPARATED else "touch"
    if after.state == SEPARATED:
        return "lift-off"
    if after.state == STICK:
        return None if before.state == STICK else "stick"
    if before.state == STICK:
        return "slip"
    if before.state == SLIDE == after.state and before.direction != after.direction:
        return "reverse"
    if before.sigma != after.sigma:
        return "normal-sign"
    return None


@dataclass(frozen=True)
class Event:
    kind: str
    name: str
    row: int
    #: whether the mode that the event ends must be excluded from the next selection
    excludes_current = False
    #: whether its value is kinematic (no solve of the mode: cheap to probe inside a step)
    kinematic = False

    def value(self, motion) -> float:
        raise NotImplementedError

    def scale(self, motion) -> float:
        """The size of the value's terms: a step may change a force guard by a fraction of it
        (:func:`~nonideal.simulation.guards.step_limit`)."""
        return motion.force_scale()

    def record(self, t: float) -> dict:
        return {"t": t, "type": self.kind, "constraint": self.name}

    def outcome(self, before, after) -> str:
        """The type to record for a switch from mode *before* to mode *after*."""
        return self.kind


@dataclass(frozen=True)
class Release(Event):
    """A held unilateral constraint's multiplier reaches zero (it would pull)."""

    excludes_current = True

    def value(self, motion) -> float:
        return motion.multiplier(self.row)


@dataclass(frozen=True)
class Touch(Event):
    """A released unilateral constraint closes (``f`` reaches zero)."""

    kinematic = True

    def value(self, motion) -> float:
        return float(motion.observables["pos"][self.row])


@dataclass(frozen=True)
class ContactEvent(Event):
    def record(self, t: float) -> dict:
        return {"t": t, "type": self.kind, "contact": self.name}

    def outcome(self, before, after) -> str:
        """What happened to the event's contact (:func:`transition`), else the event's kind."""
        return transition(before.contact(self.name), after.contact(self.name)) or self.kind


@dataclass(frozen=True)
class ContactTouch(ContactEvent):
    """A separated contact closes: the gap reaches zero."""

    kinematic = True

    def value(self, motion) -> float:
        return motion.gap(self.row)


@dataclass(frozen=True)
class Lift(ContactEvent):
    """The normal force of a touching contact reaches zero (separation; for a bilateral
    contact, a change of sign of N, hence of the friction direction)."""

    sigma: int = 1
    excludes_current = True

    def value(self, motion) -> float:
        return self.sigma * motion.normal(self.row)


@dataclass(frozen=True)
class SlipStart(ContactEvent):
    """A sticking contact needs more friction than static friction can give."""

    excludes_current = True

    def value(self, motion) -> float:
        mu_s = motion.mu_s(self.row)
        if mu_s == math.inf:  # ideal rolling: an unbounded cone never lets it slip
            return math.inf
        F = motion.friction(self.row)
        return mu_s * abs(motion.normal(self.row)) - math.sqrt(F @ F)

    def scale(self, motion) -> float:
        """The cone's radius ``mu_s |N|`` or the model's forces, the larger."""
        mu_s = motion.mu_s(self.row)
        cone = mu_s * abs(motion.normal(self.row)) if mu_s != math.inf else 0.0
        return max(motion.force_scale(), cone)


@dataclass(frozen=True)
class SlipStop(ContactEvent):
    """A sliding contact's slip velocity reaches zero: ``s . U`` changes sign, with ``s`` the
    sliding direction (one component) or the slip direction at the start of the step (two)."""

    direction: float = 1.0
    kinematic = True

    def outcome(self, before, after) -> str:
        """``stick``, or ``reverse`` when the contact goes on sliding (with two components the
        sliding states need not carry a direction to compare), or what else happened."""
        if after.contact(self.name).state == SLIDE:
            return "reverse"
        return super().outcome(before, after)

    def value(self, motion) -> float:
        U = motion.slip(self.row)
        if len(U) == 1:
            return self.direction * float(U[0])
        ref = motion.solver.reference.get(self.row)
        return float(U @ ref) if ref is not None else math.sqrt(U @ U)


@dataclass(frozen=True)
class Jam(ContactEvent):
    """The effective normal compliance of a sliding contact reaches zero: beyond it sliding
    has no consistent (or no unique) continuation -- Painleve's paradox."""

    def value(self, motion) -> float:
        return motion.compliance(self.row)


def mode_events(solver, mode, detect_jam: bool = True) -> list[Event]:
    """The events that end a phase in *mode* (a :class:`~nonideal.modes.solver.ModeSolver`'s
    model): per closed unilateral constraint its release or touch, per contact its touch,
    lift-off (or the sign of a bilateral one's normal force), slip or stop, and while it slides
    Painleve's watch (*detect_jam*)."""
    out: list[Event] = []
    for i in solver.unilateral:
        name = solver.kernel.rows[i].name
        out.append(Release("release", name, i) if name in mode.held else Touch("contact", name, i))
    for c, (name, cs) in enumerate(mode.contacts):
        bilateral = solver.ck.data[c].bilateral
        torque = c in solver.ck.torques  # touches and lifts with its contact: stick, slip only
        if cs.state == SEPARATED:
            out += [] if torque else [ContactTouch("touch", name, c)]
            continue
        if not bilateral and not torque:
            out.append(Lift("lift-off", name, c))
        elif cs.state in (SLIDE, SMOOTH):
            out.append(Lift("normal-sign", name, c, sigma=cs.sigma))
        if cs.state == STICK:
            out.append(SlipStart("slip", name, c))
        elif cs.state == SLIDE:
            direction = cs.direction[0] if solver.ck.dims[c] == 1 else 1.0
            out.append(SlipStop("slip-stop", name, c, direction=direction))
            if detect_jam and not bilateral and not torque:
                out.append(Jam("jam", name, c))
    return out
