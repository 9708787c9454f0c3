"""Event guards that a long step cannot skip.

The hybrid loop watches each event function ``g`` (a gap, a slip velocity, a normal force, the
margin of the friction cone: :mod:`nonideal.simulation.events`) for a change of sign from positive to
non-positive.  Comparing ``g`` at the two ends of an accepted step misses every event whose
function goes through zero and back within the step: a slip that stops and restarts within one
step (the stiff stick-slip oscillator, where sticking lasts microseconds), a ball that leaves
the floor and lands again within a step (the integrator takes one step over a whole parabola
of free flight, which it integrates exactly).  A :class:`StepScan` reads the integrator's
dense output inside the step instead:

1. the event functions are sampled at :data:`PROBES` interior points of the step and just
   inside its ends (one :class:`~nonideal.modes.motion.Motion` per point, shared by all the
   events) -- always the kinematic ones (gaps, slips: no solve), the forces (normal force,
   friction cone margin, multiplier: a solve of the mode each) when the step brings them
   within :data:`PROBE_NEAR` times their change across it of zero;
2. an event that starts the step unarmed (``g <= tol``, e.g. a gap just closed by an impact)
   is armed at the first sample where ``g > tol``; when none is, but ``g`` rises from the start,
   its maximum in the first interval is located (bounded Brent) and arms it when above ``tol``;
3. a sign change between consecutive samples is bracketed; an interior local minimum of the
   samples that stays positive is minimized (bounded Brent on the dense output) and bracketed
   when its minimum is not positive -- the double roots a sampled sign test misses;
4. the root is located with Brent's method; the earliest event of the step wins.

The cost is ``PROBES`` evaluations of the watched quantities per step (kinematic quantities for
gaps and slips, one solve of the mode for forces), plus a few dozen for each local minimum.

Samples only find what the step resolves.  The integrator's error control resolves the state,
hence the kinematic functions of the state; it does not see a force guard that varies faster
than the state: a block held by static friction under a force ``F(t)`` oscillating at 1000
rad/s has a constant state (its sticking mode is integrated exactly by any step), while the
margin of its friction cone ``mu_s N - |F(t)|`` dips below zero for a fraction of every period.
A :class:`GuardRates` therefore bounds the variation of the force guards over the next step:

5. at the end of every accepted step (and at the start of a phase) the rate and the curvature
   of each force guard along the motion, ``g'`` and ``g''``, are the central differences of
   ``g`` a short way (:data:`RATE_STEP` of the step) along the trajectory's tangent
   ``(q', q'')`` -- two more solves of the mode, shared by the force guards.  The tangent
   gives ``g'`` to second order (all of ``dg/dt = g_t + g_y y'``); ``g''`` lacks the term
   ``g_y y''`` of the trajectory's own curvature, which the integrator resolves;
6. the next step is limited to the largest ``h`` with ``|g'| h + |g''| h^2 / 2 <= RESOLVE G``
   (:func:`step_limit`), ``G`` the guard's scale (the forces of the model at the state, the
   radius of the friction cone when larger): a
   step covers at most a fraction of the time in which the guard can change by its own size,
   so that the guard's dips are sampled by the probes of step 1 (a limit on the resolution,
   not on the distance to zero: steps do not shrink geometrically as a guard approaches its
   root, they bracket it);
7. the rates at the ends of a step decide, like the kinematic slopes, whether the force guards
   are probed inside it (a guard that falls and rises again within the step shows a slope at
   its ends).

The guard derivative is all that a compiled loop needs to reproduce: ``g`` and its first two
time derivatives along the motion at the step's end (here by differences, compiled they can be
exact), the closed-form limit of step 6, and the probes of steps 1-4.
"""

from __future__ import annotations

import math

from collections.abc import Callable, Sequence

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..errors import NonidealError
from ..modes.motion import Motion
from ..numeric.kernel import SingularMatrix
from .events import SlipStop

__all__ = ["PROBES", "RESOLVE", "RATE_STEP", "ARREST_STEPS", "ARREST_REACH", "StepScan", "Step", "GuardRates",
           "step_limit", "with_step_limit", "event_hits", "arrest"]

PROBES = 3
"""Interior samples of the event functions per accepted step."""
PROBE_NEAR = 2.0
"""Functions that need a solve are probed when their smaller end value is within this many
times their change across the step of zero."""
SLOPE_STEP = 1e-6
"""The slopes of the kinematic event functions at the ends of a step are their differences over
this fraction of the step along the trajectory's tangent."""
NEAR_END = 1e-3
"""Two more samples this fraction of an interval inside the ends of the step (the slopes)."""
RESOLVE = 0.25
"""A step may change a force guard, by its local quadratic model, by at most this fraction of
its scale (:func:`step_limit`); with the :data:`PROBES` samples, a dip of the guard is sampled
about 20 times per time in which the guard changes by its own size."""
RATE_STEP = 1e-3
"""The force guards' rates are differences over this fraction of the last step along the
trajectory's tangent (their rounding, ``~ eps G / e^2`` in the curvature, is taken off)."""


def step_limit(rate: float, curvature: float, scale: float) -> float:
    """The largest step ``h`` with ``|rate| h + |curvature| h^2 / 2 <= RESOLVE scale``.

    Examples
    --------
    >>> step_limit(0.0, 0.0, 1.0)
    inf
    >>> round(step_limit(2.0, 0.0, 1.0), 12)  # a linear guard: RESOLVE scale / |rate|
    0.125
    >>> round(step_limit(0.0, 8.0, 1.0), 12)  # at a turning point: sqrt(2 RESOLVE scale / |g''|)
    0.25
    """
    r, c, budget = abs(float(rate)), abs(float(curvature)), RESOLVE * float(scale)
    if r == 0.0 and c == 0.0:
        return math.inf
    return 2.0 * budget / (r + math.sqrt(r * r + 2.0 * c * budget))


class StepScan:
    """The event functions of one mode over one accepted step ``[a, b]``.

    Parameters
    ----------
    value : callable
        ``value(k, s)``: event *k*'s function at time *s* of the step (reads the dense output).
    a, b : float
        The step.
    ends : sequence of (float, float)
        ``(g(a), g(b))`` of each event (known from the loop).
    """

    def __init__(self, value: Callable[[int, float], float], a: float, b: float,
                 ends: Sequence[tuple[float, float]], cheap: Sequence[bool] | None = None,
                 slopes: Callable[[int], tuple[float, float] | None] | None = None):
        self.value, self.a, self.b = value, a, b
        self.cheap = cheap
        self.ends = ends
        self.slopes = slopes
        self._s = None

    @property
    def s(self) -> np.ndarray:
        """The sample times: the ends, :data:`PROBES` interior points and, just inside the
        ends, two more (a minimum near an end shows as a local minimum there)."""
        if self._s is None:
            a, b = self.a, self.b
            h = (b - a) / (PROBES + 1)
            inner = [a + h * i for i in range(1, PROBES + 1)]
            self._s = np.array([a, a + NEAR_END * h] + inner + [b - NEAR_END * h, b])
        return self._s

    def _samples(self, k: int) -> list[float]:
        ga, gb = self.ends[k]
        return [ga] + [self.value(k, s) for s in self.s[1:-1]] + [gb]

    def first_root(self, k: int, armed: bool, tol: float) -> tuple[float | None, bool]:
        """The earliest time in the step where event *k* goes from positive (after being
        armed) to non-positive, or None; and whether the event is armed at the end of the step.

        An event that is not armed at the start (its function within *tol* of zero or below)
        is armed where its function first exceeds *tol*.
        """
        ga, gb = self.ends[k]
        if armed and not self.worth_probing(k, ga, gb):
            return (self._root(k, self.a, self.b) if ga > 0 >= gb else None), True
        s = self.s
        g = self._samples(k)
        start = 0
        if not armed:
            above = [i for i, v in enumerate(g) if v > tol]
            if above:
                start = above[0]
            else:
                # a peak inside the first interval (a bounce shorter than a fifth of the step),
                # or before the first sample when the function rises from the start
                peak = self._maximum(k, s[0], s[2]) if g[1] > g[0] else \
                    self._maximum(k, s[0], s[1]) if self._rises(k) else None
                if peak is None or peak[1] <= tol:
                    return None, False
                return self._after(k, peak[0], peak[1]), True
        te = self._scan(k, s[start:], g[start:])
        return te, True

    def _rises(self, k: int) -> bool:
        """Whether function *k* rises at the start of the step (its slope there, when known)."""
        slopes = self.slopes(k) if self.slopes is not None else None
        return slopes is not None and slopes[0] > 0

    def worth_probing(self, k: int, ga: float, gb: float) -> bool:
        """Whether the step could bring function *k* to zero inside: when it comes within
        :data:`PROBE_NEAR` times its change across the step of zero, or crosses.  The change is
        ``|g(b) - g(a)|`` and, for the cheap (kinematic: gaps, slips) functions whose slopes at
        the ends are known, ``h |g'|`` at either end: a dip to zero and back within the step
        shows in the slopes (a slip that stops and restarts, a flight landing within the step).
        A cheap function without slopes is always probed; a force guard's slopes are its
        rates (:class:`GuardRates`) when known."""
        change = abs(gb - ga)
        slopes = self.slopes(k) if self.slopes is not None else None
        if slopes is None and (self.cheap is None or self.cheap[k]):
            return True
        if slopes is not None:
            change = max(change, (self.b - self.a) * max(abs(slopes[0]), abs(slopes[1])))
        return min(ga, gb) <= PROBE_NEAR * change

    def _after(self, k: int, x: float, gx: float) -> float | None:
        """First root after an interior point *x* (``g(x) = gx > 0``) of the step."""
        s = np.concatenate(([x], self.s[self.s > x]))
        g = [gx] + [self.value(k, v) for v in s[1:-1]] + [self.ends[k][1]]
        return self._scan(k, s, g)

    def _scan(self, k: int, s, g) -> float | None:
        for i in range(1, len(s)):
            if i < len(s) - 1 and 0 < g[i] < g[i - 1] and g[i] < g[i + 1] \
                    and (g[i] < max(g[i - 1], g[i + 1]) - g[i]  # a dip as deep as its height
                         or _vertex(s[i - 1:i + 2], g[i - 1:i + 2]) <= 0):  # or its parabola's
                low = self._minimum(k, s[i - 1], s[i + 1])
                if low is not None and low[1] <= 0:
                    return self._root(k, s[i - 1], low[0])
            if g[i - 1] > 0 >= g[i]:
                return self._root(k, s[i - 1], s[i])
        return None

    def _root(self, k: int, lo: float, hi: float) -> float:
        return brentq(lambda x: self.value(k, x), lo, hi,
                      xtol=1e-15 * max(1.0, abs(hi)), rtol=8.9e-16, maxiter=200)

    def _minimum(self, k: int, lo: float, hi: float):
        return self._extremum(lambda x: self.value(k, x), lo, hi)

    def _maximum(self, k: int, lo: float, hi: float):
        found = self._extremum(lambda x: -self.value(k, x), lo, hi)
        return None if found is None else (found[0], -found[1])

    @staticmethod
    def _extremum(f, lo: float, hi: float):
        if not hi > lo:
            return None
        res = minimize_scalar(f, bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-12 * max(1.0, abs(hi)) + 1e-9 * (hi - lo)})
        return float(res.x), float(res.fun)


def _vertex(s, g) -> float:
    """The lowest value of the parabola through three samples ``(s_j, g_j)`` whose middle one
    is the lowest (a dip whose minimum lies close to one of its neighbours)."""
    d01 = (g[1] - g[0]) / (s[1] - s[0])
    curvature = ((g[2] - g[1]) / (s[2] - s[1]) - d01) / (s[2] - s[0])
    slope = d01 + curvature * (s[1] - s[0])
    return g[1] - slope * slope / (4.0 * curvature)


class Step:
    """One accepted step of the integrator, read lazily: the dense output and the
    :class:`~nonideal.modes.motion.Motion` at any time of the step (cached, shared by the
    event guards and the regularity guard)."""

    def __init__(self, solver, mode, ode, motion):
        self.solver, self.mode, self.ode = solver, mode, ode
        self.a, self.b = ode.t_old, ode.t
        self._dense = None
        self._motions = {self.b: motion}
        self._tangents = None

    def tangents(self):
        """The motions a short way along the trajectory's tangent from both ends, ``(t_a + e,
        y_a + e f_a)`` and ``(t_b - e, y_b - e f_b)`` with ``e = SLOPE_STEP h``, for the slopes
        of the kinematic event functions, from the derivatives an explicit Runge-Kutta method
        holds at the ends of its step (no evaluation of the right-hand side, no dense output);
        None for the other integrators."""
        if self._tangents is None:
            ode = self.ode
            K, f, y_old = (getattr(ode, key, None) for key in ("K", "f", "y_old"))
            if K is None or f is None or y_old is None:
                self._tangents = False
            else:
                e = SLOPE_STEP * (self.b - self.a)
                self._tangents = (e, Motion(self.solver, self.mode, self.a + e, y_old + e * K[0]),
                                  Motion(self.solver, self.mode, self.b - e, ode.y - e * f))
        return self._tangents or None

    @property
    def dense(self):
        if self._dense is None:
            self._dense = self.ode.dense_output()
        return self._dense

    def state(self, s: float) -> np.ndarray:
        return self.dense(s)

    def motion(self, s: float) -> Motion:
        m = self._motions.get(s)
        if m is None:
            m = self._motions[s] = Motion(self.solver, self.mode, s, self.dense(s))
        return m


class GuardRates:
    """The rates of a mode's force guards (steps 5-7 of the module docstring).

    Parameters
    ----------
    events : sequence of Event
        The mode's events; those that are not kinematic are watched.
    """

    def __init__(self, events):
        self.events = events
        self.watched = [k for k, ev in enumerate(events) if not ev.kinematic]

    def at(self, motion: Motion, span: float) -> dict[int, tuple[float, float]] | None:
        """``{event: (g', g'')}`` at *motion*, differences over ``RATE_STEP span`` along the
        tangent ``(q', q'')``; None without force guards (or when the mode cannot be solved
        a short way off the state)."""
        if not self.watched or not span > 0.0:
            return None
        n, t, y = motion.n, motion.t, motion.y
        e = RATE_STEP * span
        tangent = np.zeros_like(y)
        try:
            tangent[:n], tangent[n:2 * n] = motion.qd, motion.qdd
            ahead = Motion(motion.solver, motion.mode, t + e, y + e * tangent)
            behind = Motion(motion.solver, motion.mode, t - e, y - e * tangent)
            out = {}
            for k in self.watched:
                ev = self.events[k]
                g, gp, gm = ev.value(motion), ev.value(ahead), ev.value(behind)
                if not np.isfinite(g + gp + gm):
                    continue
                noise = 16 * np.finfo(float).eps * ev.scale(motion) / (e * e)
                curvature = (gp - 2.0 * g + gm) / (e * e)
                out[k] = ((gp - gm) / (2.0 * e), np.sign(curvature) * max(abs(curvature) - noise, 0.0))
        except (ArithmeticError, ValueError, np.linalg.LinAlgError, SingularMatrix, NonidealError):
            return None  # no limit: the probes and the ends still guard the step
        return out

    def limit(self, rates, motion: Motion) -> float:
        """The longest next step that the force guards allow (:func:`step_limit`, each with
        its own scale, :meth:`Event.scale <nonideal.simulation.events.Event.scale>`)."""
        if not rates:
            return np.inf
        return min(step_limit(r, c, self.events[k].scale(motion)) for k, (r, c) in rates.items())


def event_hits(step: Step, events, armed: list[bool], tols, g_prev, g_new,
               rates=(None, None)) -> list[tuple[float, int]]:
    """``(time, index)`` of every event that fires in *step* (:class:`StepScan`); *armed* is
    updated for the events armed inside the step.  An unarmed event whose function left zero
    on the wrong side (a force that was zero at the switch) fires where it passes ``-tol/2``.
    *rates* are the force guards' rates at the two ends of the step (:meth:`GuardRates.at`)."""
    if not events:
        return []

    def value(k, s):
        return events[k].value(step.motion(s))

    def slopes(k):
        if not events[k].kinematic:
            if rates[0] is None or rates[1] is None or k not in rates[0] or k not in rates[1]:
                return None
            return rates[0][k][0], rates[1][k][0]
        tangents = step.tangents()
        if tangents is None:
            return None
        e, at_a, at_b = tangents
        return (events[k].value(at_a) - g_prev[k]) / e, (g_new[k] - events[k].value(at_b)) / e
    scan = StepScan(value, step.a, step.b, list(zip(g_prev, g_new)), [ev.kinematic for ev in events],
                    slopes)
    hits = []
    for k in range(len(events)):
        te, now_armed = scan.first_root(k, armed[k], tols[k])
        if te is None and not now_armed and g_new[k] < -tols[k]:
            shift = tols[k] / 2
            if value(k, step.a) + shift <= 0:
                te = step.a
            else:
                te = brentq(lambda s, k=k: value(k, s) + shift, step.a, step.b,
                            xtol=1e-15 * max(1.0, abs(step.b)), rtol=8.9e-16, maxiter=200)
        if te is not None:
            hits.append((te, k))
        elif now_armed:
            armed[k] = True
    return hits


ARREST_STEPS = 20
"""Accepted steps in a row shorter than 1e-9 of the run's span (or of 1) after which a slip
about to stop is located by :func:`arrest`."""
ARREST_REACH = 8.0
""":func:`arrest` takes a slip's zero that its linear extrapolation puts within this many of
the last step's lengths past the step."""


def arrest(step: Step, events, armed: list[bool], g_new, level: float) -> list[tuple[float, int]]:
    """``(time, index)`` of the slip-stop events whose slip, positive and falling at the end of
    *step*, reaches zero within :data:`ARREST_REACH` step lengths by its linear
    extrapolation, at that zero; or, below *level* (the slip that counts as vanishing), at the
    end of *step*.

    The finite-time arrest of a two-component Coulomb slip: as the slip vanishes its direction
    may turn ever faster (the friction force follows it), the solution's higher derivatives
    grow like inverse powers of the time left, and the integrator's accepted steps shrink with
    that time -- each step a fraction of the way, never across the instant.  Called after
    :data:`ARREST_STEPS` such steps in a row: the time left is then below ~1e-8 of the span,
    the slip ``g ~ |g'| (t* - t)``, and its zero ``t* = t + g / |g'|`` is located to the second
    order in that time (the slope from the step's tangent, as the scan's).  A slip that hovers
    below *level* instead (at the slip floor the friction turns from the slip's direction to
    its reference and back, step after step) has stopped to that level: the stop is taken
    where the steps are, and the mode selected there decides stick or a new slip."""
    tangents = step.tangents()
    if tangents is None:
        return []
    e, _, at_b = tangents
    reach = ARREST_REACH * (step.b - step.a)
    hits = []
    for k, ev in enumerate(events):
        if isinstance(ev, SlipStop) and armed[k] and g_new[k] > 0:
            slope = (g_new[k] - ev.value(at_b)) / e
            if slope < 0 and g_new[k] <= -slope * reach:
                hits.append((step.b + g_new[k] / -slope, k))
            elif g_new[k] <= level:
                hits.append((step.b, k))
    return hits


def with_step_limit(ode, restart):
    """The integrator that honours the step limit just set as ``ode.max_step``.

    SciPy's explicit Runge-Kutta methods and Radau/BDF read ``max_step`` at every step; LSODA
    hands it to ODEPACK once, when it starts, and ignores a smaller one set afterwards -- so the
    limit of the force guards (:func:`step_limit`) did not bind it within a phase, and a guard
    that dips faster later in the phase than at its start was stepped over (a block under
    ``F = a t^2 sin(w t)``: 3 of 7 stick/slip switches found).  For LSODA whose limit at its
    start is larger than the one set now (or more than :data:`LSODA_REGROW` times smaller,
    so that a transient limit does not slow the rest of the phase), the integration restarts
    from the current state with the new limit: ``restart(t, y, max_step=..., first_step=...)``
    returns the new integrator.  Any other integrator is returned as it is.

    Parameters
    ----------
    ode : scipy.integrate.OdeSolver
        After an accepted step, with ``ode.max_step`` set to the limit.
    restart : callable
    """
    solver = getattr(ode, "_lsoda_solver", None)
    if solver is None or ode.status != "running":
        return ode
    try:
        built = float(solver._integrator.rwork[5])   # ODEPACK's HMAX (0: none)
    except (AttributeError, IndexError, TypeError):  # pragma: no cover - another SciPy layout
        built = 0.0
    built = np.inf if built == 0.0 else built
    limit = float(ode.max_step)
    if not (built > limit * (1 + 1e-12) or (np.isfinite(limit) and limit > LSODA_REGROW * built)):
        return ode
    span = ode.t_bound - ode.t
    if not span > 0:
        return ode
    last = ode.step_size if ode.step_size else span
    new = restart(ode.t, ode.y, max_step=limit, first_step=min(last, limit, span))
    new.max_step = limit
    return new


LSODA_REGROW = 8.0
"""LSODA restarts when the guards' step limit has grown this many times beyond the one it
started with (:func:`with_step_limit`)."""
