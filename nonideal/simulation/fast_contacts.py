"""Phases of modes with contacts in native code (numba, the optional extra ``fast``).

The hybrid loop (:mod:`nonideal.simulation.hybrid`) steps SciPy's DOP853 and scans every
step for events (:mod:`nonideal.simulation.guards`).  Most steps of a long run with contacts --
a ball rolling, a block sliding, a body sticking -- contain no event, and the scan finds
nothing: all that Python work (the step, the guard values at its ends, their slopes and rates,
the residuals) only proves that.  :class:`FastContacts` hands such a phase to
:func:`nonideal.numeric.contact_integrator.phase`, which takes the same DOP853 steps with the
same right-hand side (the saddle-point system with the friction columns, compiled with the
contacts: :mod:`nonideal.numeric.native_contacts`) and makes the same tests natively (the
guards at the ends of the step, their slopes and rates, the samples inside the step where the
scan takes them, the minimum of a dip the scan would minimize).  In the first step in which a
guard reaches zero the native code locates the event as the scan does (the first zero of each
guard, Brent's method on the dense output) and hands the step over as a :class:`LocatedStep`:
the hybrid loop samples it up to the event and switches there, as after a step of its own.  A
step the native code does not decide (a guard that is not a number, a residual to project,
the mass matrix near singular, :data:`~nonideal.simulation.guards.ARREST_STEPS` - 1 very short
steps in a row) is not taken: the hybrid loop restarts at the state before it with that step
size and takes it with its scan.  After such a hand-back the loop takes :data:`COOLDOWN`
steps (doubled while the native code hands back at once) before it tries again.

Applies to Lagrange I with DOP853, contacts that touch, stick or slide by Coulomb's law
(not the regularized laws, not friction torques), no unilateral constraint rows, no drift-
checked constraint rows, no chart and no watched singular row.  An event not armed (its guard
within its tolerance of zero, as after the switch that started the phase) is watched natively
as the scan watches it: armed at its first sample above the tolerance, or at a peak above it,
and, below minus the tolerance at a step's end, located where it passes half of it -- except
the stop of a two-component slip that has just started: there DOP853 steps at its stability
limit and the slip's component along its reference oscillates about zero by ~1e-9 (measured
on a rough rattleback), so whether a sample of it falls below zero after it first exceeds the
tolerance depends on the step sequence; those steps stay on the Python path, whose event
sequence they then keep (the native loop taking them added spurious slip reversals).  With
``native=None`` (the default) a mode structure goes native after it has taken
:data:`~nonideal.simulation.fast.NATIVE_STEPS` steps in the run; ``native=True`` at once.

**Agreement.**  The native right-hand side is the index path's formulas with another order of
the floating-point operations (LU without LAPACK): the two agree to rounding; the step
sequences agree until DOP853's error estimate, which at tight tolerances is itself at the
level of that rounding, picks a slightly different step; the motions then agree within the
tolerance and the events at the same instants to the accuracy of their location.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from ..modes.types import SEPARATED, SLIDE, STICK, Mode
from .events import ContactTouch, Jam, Lift, SlipStart, SlipStop
from .sample_batch import SampleBatch
from .fast import NATIVE_CHUNK, NATIVE_STEPS, deferred_signals
from .guards import ARREST_STEPS

__all__ = ["FastContacts", "LocatedStep", "NativeStart", "COOLDOWN"]

COOLDOWN = 1
"""Steps the hybrid loop takes after a native phase handed a step back before it tries native
code again (doubled, up to 16, while the native code hands back within two steps)."""

_EPS = np.finfo(float).eps
_KINDS = {ContactTouch: 0, Lift: 1, SlipStart: 2, SlipStop: 3, Jam: 4}


class NativeStart:
    """What the native loop reads of SciPy's solver, for a phase that goes native from its
    first step (no solver is made for it): the state, the step carried over from before the
    switch (``h_abs`` 0 without one), the tolerances (SciPy's: ``rtol`` at least 100 machine
    epsilons, with SciPy's warning) and the largest step.  The loop evaluates the derivative
    (``f`` empty) and, without a step carried over, takes SciPy's first step
    (:func:`~nonideal.numeric.contact_integrator.initial_step`)."""

    def __init__(self, t: float, y: np.ndarray, first_step, t_end: float, rtol: float, atol, max_step: float):
        self.t, self.y = t, y
        self.f = np.zeros(0)
        self.h_abs = min(first_step, t_end - t) if first_step else 0.0
        if rtol < 100 * _EPS:
            warnings.warn("At least one element of `rtol` is too small. "
                          f"Setting `rtol = np.maximum(rtol, {100 * _EPS})`.", stacklevel=3)
            rtol = 100 * _EPS
        self.rtol, self.atol, self.max_step = rtol, atol, max_step


class LocatedStep:
    """The step from ``(a, y)`` of length *h* in which the native code located event *k* at
    *te* (*ye* the state there): what the hybrid loop reads of a step whose event it
    switches, as of a :class:`~nonideal.simulation.guards.Step` -- its ``hits``, its ends, the
    state at a time of it (``dense``: SciPy's ``Dop853DenseOutput`` of the coefficients *F*)."""

    def __init__(self, a: float, h: float, y: np.ndarray, F: np.ndarray, te: float, k: int, ye: np.ndarray):
        self.a, self.b, self.h, self.y, self.F = a, a + h, h, y, F
        self.hits = [(te, k)]
        self._te, self._ye = te, ye

    def dense(self, s):
        """The state at time(s) *s* of the step: shape ``(n_y,)``, or ``(n_y, len(s))``."""
        x = (np.asarray(s, dtype=float) - self.a) / self.h
        y = np.zeros((x.size, self.y.size)) if x.ndim else np.zeros(self.y.size)
        xx = x[:, None] if x.ndim else x
        for i, row in enumerate(self.F[::-1]):
            y += row
            y *= xx if i % 2 == 0 else 1.0 - xx
        y += self.y
        return y.T

    def state(self, s: float) -> np.ndarray:
        return self._ye.copy() if s == self._te else self.dense(s)


class FastContacts:
    """The native path of the modes with contacts of one
    :class:`~nonideal.simulation.hybrid.Simulation` (module docstring).

    Parameters
    ----------
    sim : Simulation
    option : bool or None
        As :class:`~nonideal.simulation.fast.FastPhases`.
    """

    def __init__(self, sim, option: bool | None):
        self.sim = sim
        self.option = option
        self._native = None
        #: processor time spent loading (compiling) the native code, not counted in a run's budget
        self.loading = 0.0
        self._arrays: dict = {}
        self.start()
        if option and sim.contacts:
            self.native  # load now: a compilation is not counted in a run's time budget

    @property
    def native(self):
        """The model's :class:`~nonideal.numeric.native_contacts.NativeContacts` (False: numba
        absent or not writable natively)."""
        if self._native is None:
            if self.option is False or not self.sim.contacts:
                self._native = False
            else:
                from ..numeric.native_contacts import native_contacts_of

                spent = time.thread_time()
                with deferred_signals():
                    self._native = native_contacts_of(self.sim.kernel, self.sim.solver.ck) or False
                self.loading += time.thread_time() - spent
        return self._native

    def start(self) -> None:
        """A run starts."""
        self.loading = 0.0
        self._steps: dict = {}
        self._failed: set = set()
        self._wait = 0
        self._handed = None  # the mode of the last hand-back
        self._cooldown = COOLDOWN
        #: steps taken natively in the run, the hand-backs to the hybrid loop, the events located
        self.native_steps = 0
        self.handbacks = 0
        self.located = 0

    def _eligible(self, mode: Mode, events, drift, watched) -> bool:
        if self.sim.method != "DOP853" or watched or drift[0] or drift[1]:
            return False
        return all(type(ev) in _KINDS for ev in events) and self._solvable(mode)

    def ready(self, mode: Mode, events, armed, drift, watched) -> bool:
        """Whether the next steps of this phase go native (called before each step)."""
        if self.option is False or not self.sim.contacts:
            return False
        key = mode.structure
        if self.option is None:
            count = self._steps[key] = self._steps.get(key, 0) + 1
            if count < NATIVE_STEPS:
                return False
        if self._wait > 0 and mode == self._handed:  # (a switch ends the wait)
            self._wait -= 1
            return False
        if key in self._failed or not self._eligible(mode, events, drift, watched) or any(
                not on and isinstance(ev, SlipStop) and self.sim.solver.ck.dims[ev.row] > 1
                for ev, on in zip(events, armed)):  # (module docstring: a two-component slip's onset)
            return False
        return bool(self.native)

    def sample_motions(self, mode: Mode, T: np.ndarray, Y: np.ndarray):
        """The motions of *mode* at the samples ``(T[k], Y[k])`` solved natively in one call
        (a :class:`~nonideal.simulation.sample_batch.SampleBatch`; its ``ok`` false where the
        system is singular); None when this run took no native step (the Python evaluation
        then, as for a run that never needed native code) or the mode's system is not one the
        native code solves."""
        nat = self._native
        if not (nat and (self.option or self.native_steps)) or not self._solvable(mode):
            return None
        sim = self.sim
        solver = sim.solver
        S = self._with_references(mode)  # (those the Python evaluation reads)
        Z, R = np.zeros((len(T), nat.nz)), np.zeros((len(T), S[3].shape[0]))
        T, Y = np.asarray(T, dtype=float), np.asarray(Y, dtype=float)
        with deferred_signals():
            ok = nat.loop.evaluate(nat.kernel, S, T, Y, Z, R)
        return SampleBatch(solver, mode, solver.system(mode), T, Y, R, Z[:, sim.kernel.dynamics.size:], ok)

    def _solvable(self, mode: Mode) -> bool:
        """Whether the native code solves *mode*'s system (as :meth:`_eligible`, without what
        concerns the steps: events, drift, watched rows)."""
        sim, solver = self.sim, self.sim.solver
        if (not solver.route.saddle_point or solver.charts is not None or sim.control_rows
                or solver.unilateral or solver.ck.torques or not sim.track):
            return False
        if any(cs.state not in (SEPARATED, STICK, SLIDE) for _, cs in mode.contacts):
            return False
        system = solver.system(mode)
        return system.blocks is None and not (system.m and system.dependence is not False)

    # ------------------------------------------------------------------ arrays
    def _with_references(self, mode: Mode):
        """The system arrays of *mode* with the solver's slip references in place."""
        S, contacts = self._system_arrays(mode)
        ref, hasref = S[12], S[13]
        for k, c in enumerate(contacts):
            r = self.sim.solver.reference.get(c)
            hasref[k] = r is not None
            if r is not None:
                ref[k, :len(r)] = r
        return S

    def _system_arrays(self, mode: Mode):
        key = mode
        if key not in self._arrays:
            sim = self.sim
            solver, kernel, nat = sim.solver, sim.kernel, self.native
            system = solver.system(mode)
            ck = solver.ck
            n, m = system.n, system.m
            x = np.array(solver.x, dtype=float)
            z = np.zeros(nat.nz)
            for pos, value in nat.constants.items():
                z[pos] = value
            slide, slidef = [], []
            for j, c, u, w, _shape, mu, _col in system.sliding:
                cs = mode.contacts[c][1]
                d = ck.dims[c]
                direction = list(cs.direction or ())
                slide.append([j, u.start, d, w.start, mu, c])
                fallback = (direction + [0.0, 0.0, 0.0])[:3]
                slidef.append([cs.sigma, direction[0] if d == 1 and direction else 0.0, *fallback,
                               1.0 if direction else 0.0])
            k = len(slide)
            tang = [[j, system.tangent_slip[j]] for j in system.tangent]
            F_at = kernel.dynamics.slices["F"][0].start
            power = system.power.start if system.power is not None else -1
            hdr = np.array([n, m, power, system.M_at, F_at], dtype=np.int64)
            S = (x, z, np.zeros((n + m) ** 2), np.zeros(n + m), np.zeros(n + m, dtype=np.int64),
                 np.zeros(m), np.zeros(k), system.src.astype(np.int64), system.dst.astype(np.int64),
                 system.rsrc.astype(np.int64),
                 np.array(slide, dtype=np.int64).reshape(k, 6)[:, :5].copy(),
                 np.array(slidef, dtype=float).reshape(k, 6), np.zeros((k, 3)), np.zeros(k, dtype=np.bool_),
                 np.array(tang, dtype=np.int64).reshape(len(tang), 2), hdr)
            contacts = [row[5] for row in slide]
            self._arrays[key] = (S, contacts)
        return self._arrays[key]

    def _event_arrays(self, mode: Mode, events, tols, contacts, armed):
        sim = self.sim
        system, ck = sim.solver.system(mode), sim.solver.ck
        base = sim.kernel.dynamics.size
        at = {name: base + start for name, start in ck.at.items()}
        ev, evf = [], []
        for event, tol, on in zip(events, tols, armed):
            c = event.row
            j = system.normal_col.get(c, -1)
            d = ck.dims[c]
            row = [_KINDS[type(event)], j, -1, d, -1, -1, -1]
            value = 1.0
            if isinstance(event, ContactTouch):
                row[5] = at["gap"] + c
            elif isinstance(event, Lift):
                value = float(event.sigma)
            elif isinstance(event, SlipStart):
                cols = system.tangent_cols[c]
                if cols != list(range(cols[0], cols[0] + d)):
                    return None
                row[2], row[6] = cols[0], at["mu_s"] + c
            elif isinstance(event, SlipStop):
                row[4] = contacts.index(c)
                row[5] = at["U"] + ck.offsets[c]
                value = float(event.direction)
            ev.append(row)
            evf.append([value, float(tol), 1.0 if on else 0.0])
        resid = []
        for c, (_, cs) in enumerate(mode.contacts):
            if cs.state != SEPARATED:
                resid.append([at["gap"] + c, at["gap_rate"] + c, at["U"] + ck.offsets[c],
                              ck.dims[c] if cs.state == STICK else 0])
        return (np.array(ev, dtype=np.int64).reshape(len(ev), 7), np.array(evf, dtype=float).reshape(len(evf), 3),
                np.array(resid, dtype=np.int64).reshape(len(resid), 4))

    # ------------------------------------------------------------------ run
    def run(self, mode: Mode, ode, events, tols, armed, t_end: float, h_last, times, next_time: int, emit,
            budget, residual_max, floor: float, tiny_run: int = 0):
        """Integrate natively from the SciPy solver's state (module docstring).  Returns
        ``(t, y, h, next_time, tiny_run, located)``: where the hybrid loop goes on, with the step
        to take next, and its count of steps in a row shorter than 1e-9 of the span (*tiny_run*
        before): the native code takes such steps, a slip's onset, and hands back when they are
        :data:`~nonideal.simulation.guards.ARREST_STEPS` - 1 in a row (the next may locate a
        slip's arrest).  *located*: the :class:`LocatedStep` from ``(t, y)`` in which the
        native code located an event, or None (the hybrid loop takes the next step itself)."""
        budget.start += self.loading  # a compilation is no part of the run's time
        self.loading = 0.0
        S, contacts = self._system_arrays(mode)
        E = self._event_arrays(mode, events, tols, contacts, armed)
        if E is None:
            self._failed.add(mode.structure)
            return float(ode.t), ode.y, float(ode.h_abs) or h_last, next_time, tiny_run, None
        self._with_references(mode)
        nat = self.native
        t, y, f, h_abs = float(ode.t), np.array(ode.y, dtype=float), np.array(ode.f, dtype=float), float(ode.h_abs)
        atol = np.asarray(ode.atol, dtype=float)
        atol = atol.copy() if atol.shape == y.shape else np.full(y.shape, float(atol))
        grid = np.asarray(times if times is not None else np.zeros(0), dtype=float)
        nt = next_time if times is not None else 0
        tiny = 1e-9 * min(t_end - budget.t0, 1.0)
        step_max = float(min(ode.max_step, self.sim.max_step))
        span = float(h_last) if h_last else h_abs
        taken = 0
        while True:
            # the loop's first call in a process compiles it (or loads numba's cache): no part
            # of the run's time, as the loading above
            first = not nat.loop.phase.overloads  # (its signatures: a list built at each read, 10 us)
            spent = time.thread_time()
            with deferred_signals():
                (status, t, y, f, h_abs, step_max, T, Y, count, nt, steps, res_p, res_v, tiny_run,
                 te, ke, ye, Fe) = nat.loop.phase(
                    nat.kernel, S, E, t, y, f, h_abs, span, float(t_end), float(ode.rtol), atol,
                    float(self.sim.max_step), step_max, float(floor), grid, nt, NATIVE_CHUNK,
                    tiny + 4e-16 * abs(t_end), tiny_run, ARREST_STEPS - 1)
            if first:
                budget.start += time.thread_time() - spent
            emit.rows(T[:count], Y[:count], mode, times is None)
            taken += steps
            budget.advance(t, steps)
            residual_max["position"] = max(residual_max["position"], res_p)
            residual_max["velocity"] = max(residual_max["velocity"], res_v)
            if status != 1:
                break
        self.native_steps += taken
        if status == 6:
            self.located += 1
            return t, y, h_abs, (nt if times is not None else next_time), tiny_run, LocatedStep(t, h_abs, y, Fe, te,
                                                                                                 int(ke), ye)
        if status in (4, 5):  # a step that may hold an event, or steps that collapsed (the hybrid
            # loop locates an arrest, or watches the collapse and names its cause): back for a while
            self.handbacks += 1
            self._cooldown = min(16, 2 * self._cooldown) if taken < 2 else COOLDOWN
            self._wait = self._cooldown
            self._handed = mode
        elif status != 0:
            self._failed.add(mode.structure)
        return t, y, h_abs or h_last, (nt if times is not None else next_time), tiny_run, None
