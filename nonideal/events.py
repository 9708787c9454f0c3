"""Events of the hybrid simulation, as objects.

An event has a scalar ``value(ctx)`` whose sign change (from positive to non-positive) marks
the switch, a ``kind`` and the name of the constraint or contact it concerns.  The driver
locates the root on the integrator's dense output (Brent's method) and then asks the mode
selection what happens next.  Nothing is patched onto functions.

======================  ====================================  =============================
event                   value                                 in mode
======================  ====================================  =============================
:class:`Release`        multiplier of a unilateral constraint held
:class:`Touch`          the constraint function ``f``         released
:class:`ContactTouch`   the gap ``g``                         contact separated
:class:`Lift`           the normal force ``sigma N``          contact touching
:class:`SlipStart`      ``mu_s |N| - |F|``                    contact sticking
:class:`SlipStop`       ``s . U`` (one component),            contact sliding
                        ``U . s_ref`` (two; ``s_ref`` the
                                                              slip direction at step start)
:class:`Jam`            effective normal compliance ``b``     contact sliding (Painleve)
======================  ====================================  =============================
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Event", "Release", "Touch", "ContactTouch", "Lift", "SlipStart", "SlipStop", "Jam",
           "EventContext"]


@dataclass
class EventContext:
    """What an event may look at: the state, the motion in the current mode, observables."""

    t: float
    q: object
    qd: object
    solution: object
    observables: dict
    solver: object = None
    mode: object = None


@dataclass(frozen=True)
class Event:
    kind: str
    name: str
    row: int
    #: whether the mode that the event ends must be excluded from the next selection
    excludes_current = False

    def value(self, ctx: EventContext) -> float:
        raise NotImplementedError

    def record(self, t: float) -> dict:
        return {"t": t, "type": self.kind, "constraint": self.name}


@dataclass(frozen=True)
class Release(Event):
    """A held unilateral constraint's multiplier reaches zero (it would pull)."""

    excludes_current = True

    def value(self, ctx: EventContext) -> float:
        return ctx.solution.multiplier(self.row)


@dataclass(frozen=True)
class Touch(Event):
    """A released unilateral constraint closes (``f`` reaches zero)."""

    def value(self, ctx: EventContext) -> float:
        return float(ctx.observables["pos"][self.row])


@dataclass(frozen=True)
class ContactEvent(Event):
    def record(self, t: float) -> dict:
        return {"t": t, "type": self.kind, "contact": self.name}


@dataclass(frozen=True)
class ContactTouch(ContactEvent):
    """A separated contact closes: the gap reaches zero."""

    def value(self, ctx: EventContext) -> float:
        return ctx.solution.contacts[self.name].gap


@dataclass(frozen=True)
class Lift(ContactEvent):
    """The normal force of a touching contact reaches zero (separation; for a bilateral
    contact, a change of sign of N, hence of the friction direction)."""

    sigma: int = 1
    excludes_current = True

    def value(self, ctx: EventContext) -> float:
        return self.sigma * ctx.solution.contacts[self.name].N


@dataclass(frozen=True)
class SlipStart(ContactEvent):
    """A sticking contact needs more friction than static friction can give."""

    excludes_current = True

    def value(self, ctx: EventContext) -> float:
        cf = ctx.solution.contacts[self.name]
        return cf.mu_s * abs(cf.N) - float(np.sqrt(cf.F @ cf.F))


@dataclass(frozen=True)
class SlipStop(ContactEvent):
    """A sliding contact's slip velocity reaches zero: ``s . U`` changes sign, with ``s`` the
    sliding direction (one component) or the slip direction at the start of the step (two)."""

    direction: float = 1.0

    def value(self, ctx: EventContext) -> float:
        U = ctx.solution.contacts[self.name].U
        if len(U) == 1:
            return self.direction * float(U[0])
        ref = ctx.solver.reference.get(self.row)
        return float(U @ ref) if ref is not None else float(np.sqrt(U @ U))


@dataclass(frozen=True)
class Jam(ContactEvent):
    """The effective normal compliance of a sliding contact reaches zero: beyond it sliding
    has no consistent (or no unique) continuation -- Painleve's paradox."""

    def value(self, ctx: EventContext) -> float:
        # b = 1/(K^-1)_jj from the matrices the solution already holds (no kernel calls)
        sol = ctx.solution
        j = next(k for k, r in enumerate(sol.layout) if r.kind == "normal" and r.name == self.name)
        n, m = sol.M.shape[0], len(sol.layout)
        K = np.zeros((n + m, n + m))
        K[:n, :n] = sol.M
        K[:n, n:] = -sol.Bm
        K[n:, :n] = sol.Gm
        e = np.zeros(n + m)
        e[n + j] = 1.0
        try:
            inv_jj = np.linalg.solve(K, e)[n + j]
        except np.linalg.LinAlgError:
            return 0.0
        return float(1.0 / inv_jj) if inv_jj != 0 else float("inf")
