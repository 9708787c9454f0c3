"""Events of the hybrid simulation, as objects.

An event has a scalar ``value(ctx)`` whose sign change (from positive to non-positive) marks
the switch, a ``kind`` and the name of the constraint or contact it concerns.  The driver
locates the root on the integrator's dense output (Brent's method) and then asks the mode
selection what happens next.  Nothing is patched onto functions.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Event", "Release", "Touch", "EventContext"]


@dataclass
class EventContext:
    """What an event may look at: the state, the motion in the current mode, observables."""

    t: float
    q: object
    qd: object
    solution: object
    observables: dict


@dataclass(frozen=True)
class Event:
    kind: str
    name: str
    row: int

    def value(self, ctx: EventContext) -> float:
        raise NotImplementedError

    def record(self, t: float) -> dict:
        return {"t": t, "type": self.kind, "constraint": self.name}


@dataclass(frozen=True)
class Release(Event):
    """A held unilateral constraint's multiplier reaches zero (it would pull)."""

    def value(self, ctx: EventContext) -> float:
        return ctx.solution.multiplier(self.row)


@dataclass(frozen=True)
class Touch(Event):
    """A released unilateral constraint closes (``f`` reaches zero)."""

    def value(self, ctx: EventContext) -> float:
        return float(ctx.observables["pos"][self.row])
