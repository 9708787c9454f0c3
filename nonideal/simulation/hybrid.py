"""The hybrid simulation: a plain loop around a SciPy ODE solver that restarts at every switch.

Design (as recommended for hybrid systems): integrate one smooth phase with a fixed mode,
stepping the solver by hand; after each accepted step evaluate the event functions of the
mode (:mod:`nonideal.simulation.events`), locate the earliest sign change on the dense output with
Brent's method, apply the switch (impact law, mode selection of :mod:`nonideal.modes.switching`)
and restart the solver from the new state.

State: ``y = [q, q', W]`` -- all coordinates and velocities (whatever formalism evaluates the
accelerations) and, when they are not identically zero, the work integrals of the
non-potential forces, the ideal/servo reactions, the explicit time dependence and friction.
Integrating the works with the motion gives the energy balance to integrator precision.

Constraint drift: the constraints are enforced at acceleration level; after every accepted
step the position and velocity residuals of the active rows are checked and, above ``1e-10``
(relative), the state is projected back (least-norm Newton) and the solver restarted.  We
chose projection over Baumgarte stabilization because it adds no artificial dynamics and no
time-scale parameter; at tight tolerances it is rarely triggered, so it costs little.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, Radau

from ..numeric.consistency import complete_state
from ..errors import IntegrationFailed, ModelError, PainleveParadox
from .events import ContactTouch, Event, Jam, Lift, Release, SlipStart, SlipStop, Touch, mode_events, transition
from ..modeling.model import Model
from ..modeling.shapes.watch import SupportWatch
from ..modes.motion import Motion
from ..modes.types import Mode
from ..modes.solver import ModeSolver
from ..numeric.contact_kernel import SLIP_LEVEL
from ..numeric.kernel import kernel_of, max_abs, parameter_vector
from ..modes.switching import impact, select_mode
from ..modes.validation import validate_state
from .budget import GRID, MAX_SAMPLES, SampleBuffer, StepBudget, check_arguments, emitter, output_times, sample_dense
from .guards import ARREST_STEPS, GuardRates, Step, arrest, event_hits, with_step_limit
from .singular import BRANCHES, JUMP_FROM, MassGuard, Regularity, explain_stall, singular_level
from .extended import reduce
from ..equations.high_order import extension_of
from .rhs import phase_rhs
from .fast import FastPhases
from .fast_contacts import FastContacts, NativeStart
from .projection import project_mode
from .trajectory import Trajectory
from .zeno import Accumulation, ImpactSeries

__all__ = ["simulate", "Simulation"]

SOLVERS = {"DOP853": DOP853, "RK45": RK45, "RK23": RK23, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}
PROJECTION_TOL = 1e-10
N_WORK = 5  # active (non-potential), reactions, explicit time, friction, impacts
WORK_ATOL = 10.0
"""The work integrals in the state only feed the energy balance; at the motion's absolute
tolerance they shortened its steps wherever a power vanishes up to rounding (ideal
reactions, sticking friction: the integrator then resolves noise).  Ten times looser, they
leave the steps to the motion (knife chain n = 6, 5 s at rtol 1e-8: 54 -> 39 steps; looser
still: 37) while every test's bound on the energy balance and on the drift of the
constraints holds (100 times looser breaks the car's: its sticking rows drift more with
longer steps)."""


class Simulation:
    """A configured simulation of one model (immutable inputs; :meth:`run` returns a Trajectory).

    Parameters
    ----------
    model : Model
    form : str
        Formalism evaluating the accelerations (the motion does not depend on it).
    parameters : mapping, optional
        Overrides of parameter values (no recompilation).
    rtol, atol, method, max_step : optional
        Integrator settings; default from the model's ``[simulation]``.
    independent : tuple of str, optional
        Independent coordinates for the reduced forms (Lagrange II: those of the first chart;
        ``diagnostics["chart_changes"]`` counts the changes of chart, :mod:`nonideal.modes.charts`).
    detect_jam : bool
        Watch the effective normal compliance of sliding contacts (Painleve's paradox).
    specialize : bool
        Compile the saddle-point system of a mode with contacts once the run has integrated
        its structure :data:`~nonideal.modes.system.SPECIALIZE_CALLS` times (faster; it agrees
        with the index path to rounding; the count is the run's own, so a run gives the same
        results bit for bit whatever ran before it in the process).  ``False`` keeps the
        index path.
    singular : {"smooth", "stop"}, optional
        Where the constraints become singular along the motion: go on on the smooth branch
        (an event ``singular``) or stop (:class:`~nonideal.errors.SingularMotion`); default
        from the model's ``[simulation] singular`` (:mod:`nonideal.simulation.singular`).
    native : bool or None, optional
        Native code (numba, the extra ``fast``) for the phases it computes
        (:mod:`nonideal.simulation.fast`; the modes with contacts up to each step that may
        hold an event: :mod:`nonideal.simulation.fast_contacts`): None after a mode's first
        :data:`~nonideal.simulation.fast.NATIVE_STEPS` steps, True at once, False never.
    grid, every_step : optional
        The output (when :meth:`run` is given no times): ``grid`` uniform times with each
        event's states (default ``[simulation] grid``, else :data:`~.budget.GRID`), or every
        accepted step (``every_step=True``; ``max_samples`` of them, thinned beyond).
    """

    def __init__(self, model: Model, form: str = "lagrange1",
                 parameters: Mapping[str, float] | None = None, rtol: float | None = None,
                 atol: float | None = None, method: str | None = None,
                 max_step: float | None = None, independent=None, max_events: int = 10_000,
                 detect_jam: bool = True, specialize: bool = True,
                 max_samples: int | None = MAX_SAMPLES, singular: str | None = None,
                 native: bool | None = None, grid: int | None = None, every_step: bool | None = None):
        self.model = model
        self.kernel = kernel_of(model)
        self.params = parameter_vector(model, parameters)
        self.solver = ModeSolver(self.kernel, self.params, form, independent, specialize)
        sim = model.simulation
        self.rtol = rtol if rtol is not None else sim.rtol
        self.atol = atol if atol is not None else sim.atol
        self.method = method or sim.method
        if self.method not in SOLVERS:
            raise ModelError(f"--method: unknown integrator '{self.method}'; choose one of {', '.join(SOLVERS)}")
        self.max_step = max_step if max_step is not None else (sim.max_step or np.inf)
        self.singular = singular or sim.singular
        if self.singular not in BRANCHES:
            raise ModelError(f"singular: must be one of {', '.join(BRANCHES)} (got {self.singular!r})")
        self.max_events = max_events
        self.max_samples = max_samples
        self.grid = grid if grid is not None else (sim.grid or GRID)
        self.every_step = every_step if every_step is not None else (sim.every_step and grid is None)
        self.detect_jam = detect_jam
        k = self.kernel
        self.contacts = bool(self.solver.ck)
        self.track = bool(k.rows) or k.has_nc_forces or k.explicit_time or self.contacts
        self.n = k.n
        #: the servo rows: each control's power is integrated with the motion, after the works
        self.control_rows = [i for i, r in enumerate(k.rows) if r.reaction_kind == "servo"]
        self.fast = FastPhases(self, native)
        self.fast_contacts = FastContacts(self, native)  # the modes with contacts

    # ------------------------------------------------------------------ right-hand side
    def rhs(self, mode: Mode):  # the right-hand side f(t, y) of a phase in *mode* (rhs.phase_rhs)
        return phase_rhs(self, mode)

    # ------------------------------------------------------------------ events
    def events(self, mode: Mode, t: float, y: np.ndarray) -> list[Event]:
        return mode_events(self.solver, mode, self.detect_jam)

    def _tolerance(self, ev: Event, motion: Motion) -> float:
        if isinstance(ev, (Release, Lift, SlipStart)):
            return 1e-9 * motion.force_scale()
        if isinstance(ev, Jam):
            return 1e-12
        if isinstance(ev, SlipStop):
            return 1e-10 * (1.0 + max_abs(motion.qd))
        return 1e-10 * (1.0 + max_abs(motion.q))

    # ------------------------------------------------------------------ switching
    def _switch(self, t: float, y: np.ndarray, mode: Mode, ev: Event):
        n = self.n
        q, qd = y[:n].copy(), y[n:2 * n].copy()
        y = y.copy()
        record = ev.record(t)
        if isinstance(ev, Jam):
            state = dict(zip(self.model.coordinates, q))
            state.update({c + "'": v for c, v in zip(self.model.coordinates, qd)})
            from ..modes.switching import critical_friction
            mu_c = critical_friction(self.solver, t, q, qd, mode, ev.name)
            raise PainleveParadox(
                f"Painleve paradox at contact '{ev.name}': while sliding, its effective normal "
                "compliance b = dg''/dN reached zero -- the normal force grows without bound and "
                "beyond this state sliding has no consistent continuation under rigid-body "
                "Coulomb friction (tangential impact / dynamic jamming)", t, state,
                {"critical friction coefficient": f"{mu_c:.6g}" if mu_c else "none",
                 "mode": mode.label()})
        if isinstance(ev, (Touch, ContactTouch)):
            rest = {i: c.restitution for i, c in self._restitution.items()}
            e_before = self._energy(t, q, qd)
            if isinstance(ev, Touch):
                vel = self.kernel.observables(self.solver.input(t, q, qd))["vel"][ev.row]
                qd, impulses = impact(self.solver, t, q, qd, [ev.row], rest)
            else:
                vel = self.solver.ck(self.solver.input(t, q, qd))["gap_rate"][ev.row]
                qd, impulses = impact(self.solver, t, q, qd, (), rest, contacts_hit=[ev.name])
            loss = self._energy(t, q, qd) - e_before
            record.update(normal_velocity=float(vel), impulses=impulses, energy_change=float(loss))
            if self.track:
                y[2 * n + 4] += loss  # work of the impulsive reactions
            new = select_mode(self.solver, t, q, qd, tol_pos=1e-8, tol_vel=1e-8, previous=mode,
                              concerned=ev.name)
        else:
            same = self._chain[1] if abs(t - self._chain[0]) <= 1e-8 * (1 + abs(t)) else []
            self._chain = (t, same + [mode] if ev.excludes_current else same)
            if len(self._chain[1]) > 20:
                raise IntegrationFailed(t, mode.label(), "the mode switches at this instant do not "
                                        f"settle: {', '.join(m.label() for m in same[-4:])}, ...")
            new = select_mode(self.solver, t, q, qd, tol_pos=1e-8, tol_vel=1e-8,
                              exclude=self._chain[1] or None, previous=mode, concerned=ev.name)
        q, qd = self._project(new, t, q, qd)
        y[:n], y[n:2 * n] = q, qd
        record["type"] = ev.outcome(mode, new)
        changes = {name: kind for (name, a), (_, b) in zip(mode.contacts, new.contacts)
                   if (kind := transition(a, b))}
        if set(changes) - {ev.name}:
            record["changes"] = changes
        record["mode"] = new.label()
        return y, new, record

    def _accumulate(self, limit: Accumulation, y: np.ndarray, mode: Mode, ev: Event):
        """Jump over the rest of a geometric series of impacts (:mod:`nonideal.zeno`) to its
        limit: the impact law applied at the extrapolated state, the mode selected there; the
        energy of the skipped flights and impacts is counted in the impact work."""
        n = self.n
        after = y.copy()
        after[:n], after[n:2 * n] = limit.q, limit.qd
        if self.track:
            after[2 * n + 4] += (self._energy(limit.t, limit.q, limit.qd)
                                 - self._energy(limit.last, y[:n], y[n:2 * n]))
        after, new, record = self._switch(limit.t, after, mode, ev)
        record.update(type="zeno", impacts=limit.impacts, ratio=limit.ratio,
                      last_impact=limit.last, mode=new.label())
        return after, new, record

    def _project(self, mode: Mode, t, q, qd):
        """Project onto the constraint rows of *mode* (:func:`~nonideal.simulation.projection.project_mode`)."""
        return project_mode(self, mode, t, q, qd)

    def work_tolerances(self):
        """Absolute tolerances of the state ``[q, q', W]``: *atol* for the motion and
        :data:`WORK_ATOL` times it for the work integrals (a user's array is kept)."""
        size = 2 * self.n + N_WORK + len(self.control_rows)   # the controls' works last
        atol = np.asarray(self.atol, dtype=float) if np.ndim(self.atol) else np.full(2 * self.n, self.atol)
        return np.concatenate((atol, np.full(max(0, size - atol.size), WORK_ATOL * atol.max())))

    def _energy(self, t, q, qd) -> float:
        """Jacobi's energy ``T2 - T0 + V`` at a state."""
        x = self.solver.input(t, q, qd)
        M = self.kernel.mass(self.kernel.dynamics(x))   # sparse for many coordinates
        obs = self.kernel.observables(x)
        return float(0.5 * qd @ M @ qd - obs["T0"] + obs["V"])

    @property
    def _restitution(self):
        return {self.kernel.row_index[c.name]: c for c in self.model.constraints if c.unilateral}

    # ------------------------------------------------------------------ main loop
    def initial_state(self, initial: Mapping[str, float] | None = None):
        """The initial ``(q, q')``: the model's values with the overrides *initial*, completed
        and checked by :func:`~nonideal.numeric.consistency.complete_state` (a pure function of the
        model, the parameters and the values: memoized)."""
        given = dict(self.model.numeric_initial())
        given.update(initial or {})
        numbers = all(isinstance(v, (int, float, np.number)) for v in given.values())
        key = (tuple(sorted(given.items())), self.params.tobytes()) if numbers else None
        memo = self.model.cached("initial states", dict)
        if key in memo:
            q, qd = memo[key]
            return q.copy(), qd.copy()
        q, qd, closed = complete_state(self.kernel, given, self.params, self.model.t0)
        if key is not None:
            if len(memo) > 256:
                memo.clear()
            memo[key] = (q.copy(), qd.copy())
        return q, qd

    def run(self, t_end: float | None = None, times: Sequence[float] | None = None,
            initial: Mapping[str, float] | None = None, stop_on=None) -> Trajectory:
        """Simulate from the model's initial state to ``t_end``.

        Parameters
        ----------
        t_end : float, optional
            Default: the model's ``[simulation] t_end`` (or the last of *times*).
        times : sequence of float, optional
            Sample exactly at these times (dense output).  Default: the uniform grid of
            ``grid`` times (1001) and each event's state before and after its switch; every
            accepted step and event with ``every_step=True``.
        initial : mapping, optional
            Overrides of initial values.
        stop_on : set of str, optional
            Event types (``"slip"``, ``"stick"``, ``"reverse"``, ``"lift-off"``, ``"release"``...;
            see :mod:`nonideal.simulation.events`) that end the run at the event (the last sample is the
            state at the event, before the switch).  An event whose kind is listed stops
            before the next mode is selected; the others stop when the selected switch is of
            a listed type.

        Returns
        -------
        Trajectory

        Raises
        ------
        IntegrationFailed, MechanicsError (PainleveParadox), InconsistentInitialConditions
        """
        model = self.model
        t0, source = model.t0, None if model.source == "<api>" else model.source
        times, t_end, at_events = output_times(model, times, t_end, self.every_step, self.grid)
        n = self.n
        q0, qd0 = self.initial_state(initial)
        validate_state(self.solver, t0, q0, qd0)
        mode = select_mode(self.solver, t0, q0, qd0)
        q0, qd0 = self._project(mode, t0, q0, qd0)
        y = np.concatenate((q0, qd0, np.zeros(N_WORK + len(self.control_rows) if self.track else 0)))
        atol = self.work_tolerances() if self.track else self.atol
        samples = SampleBuffer(self.max_samples)  # bounded: thinned past max_samples steps
        self.solver.start()
        self._chain = (-np.inf, [])  # the modes events ended at one instant (all marginal there)
        self.fast.start()
        self.fast_contacts.start()
        budget = StepBudget(t0, t_end, source, method=self.method)
        events_log: list[dict] = []
        next_time = 0

        support = SupportWatch(self.model, self.params)  # each support point unique along the motion

        emit = emitter(samples, support)

        # the state at the start of a phase is sampled at the top of the loop, with its motion
        pending = times is None or bool(times.size and abs(times[0] - t0) <= 1e-14 * max(1, abs(t0)))
        if pending and times is not None:
            next_time = 1
        t = t0
        h = None
        tiny = 0
        stopped = False
        projections = 0
        residual_max = {"position": 0.0, "velocity": 0.0}
        Solver = SOLVERS[self.method]
        solver = self.solver
        series = ImpactSeries()
        regularity, inertia = Regularity(self.kernel), MassGuard(self, t0, y)
        changes = solver.charts.changes if solver.charts is not None else 0
        while t < t_end:
            fun = self.rhs(mode)
            events = self.events(mode, t, y)
            drift = solver.system(mode).drift_rows
            kwargs = dict(rtol=self.rtol, atol=atol, max_step=self.max_step)
            if h is not None and self.method not in ("LSODA",):
                kwargs["first_step"] = min(h, t_end - t)
            motion = Motion(solver, mode, t, y)
            if pending:
                emit(t, y, mode, motion)
                pending = False
            solver.set_references(mode, motion, start=True)
            guard_rates = GuardRates(events)  # steps short enough to sample the force guards
            rates = guard_rates.at(motion, h or 1e-3 * (t_end - t))
            max_step = min(self.max_step, guard_rates.limit(rates, motion))
            g_prev = [ev.value(motion) for ev in events]
            watched = regularity.rows(solver.rows(mode))
            level = singular_level(self.rtol) if self.singular == "stop" else JUMP_FROM
            regularity.start(motion, watched)
            tols = [self._tolerance(ev, motion) for ev in events]
            armed = [g > tols[k] for k, g in enumerate(g_prev)]
            # the native code from the first step? (asked once a step: the answer counts steps)
            native = self.fast_contacts.ready(mode, events, armed, drift, watched)
            ode = NativeStart(t, y, kwargs.get("first_step"), t_end, self.rtol, atol, max_step) if native else \
                Solver(fun, t, y, t_end, **dict(kwargs, max_step=max_step))
            restart, first = False, True
            while not restart:
                if native is None:
                    native = self.fast_contacts.ready(mode, events, armed, drift, watched)
                go, native = native, None
                if go:  # natively to a possible event
                    t, y, h, next_time, tiny, step = self.fast_contacts.run(
                        mode, ode, events, tols, armed, t_end, h, times, next_time, emit, budget, residual_max,
                        inertia.floor if inertia.active else -1.0, tiny)
                    if step is None:
                        restart = True
                        continue
                    hits, t_old = step.hits, step.a  # the event located natively in the step from (t, y)
                else:
                    go = self.fast.ready(mode, first, events, drift, watched)  # native code from here?
                    first = False
                    if go is not None:  # "rhs": restart on the native right-hand side; "phase": to the end
                        h, restart = ode.h_abs, True
                        if go == "phase":
                            t, y, next_time, _ = self.fast.run(mode, ode, t_end, times, next_time, emit, budget)
                        continue
                    message = ode.step()
                    if ode.status == "failed":
                        explain_stall(self, ode, mode)
                        raise IntegrationFailed(ode.t, mode.label(), message or "step failed", source)
                    t_old, t_new = ode.t_old, ode.t
                    if solver.charts is not None:  # Lagrange II: change charts at accepted states
                        solver.charts.settle(mode, t_new, ode.y[:n], ode.y[n:2 * n])
                    h = t_new - t_old
                    budget.step(t_new)  # refuses a run that cannot finish
                    tiny = tiny + 1 if h < 1e-9 * min(t_end - t0, 1.0) + 4e-16 * abs(t_new) else 0
                    if tiny > 2000:
                        explain_stall(self, ode, mode)
                        raise IntegrationFailed(
                            t_new, mode.label(), "the step size collapsed below 1e-9 of the time span (or of 1) for "
                            "2000 steps: the right-hand side is not smooth here (a nonlinear constraint at "
                            "a singular point, or a friction law without a sticking mode at zero slip)", source)
                    # the integrator's last evaluation was at (t_new, ode.y): the motion reuses it
                    motion = Motion(solver, mode, t_new, ode.y)
                    g_new = [ev.value(motion) for ev in events]
                    step = Step(solver, mode, ode, motion)
                    inertia.check(step)
                    support.check(t_new, ode.y)
                    rates_new = guard_rates.at(motion, h)
                    hits = event_hits(step, events, armed, tols, g_prev, g_new, (rates, rates_new)) or \
                        (arrest(step, events, armed, g_new, SLIP_LEVEL * (1 + max_abs(motion.qd))) if tiny >= ARREST_STEPS else [])  # a slip's finite-time stop
                    singular = regularity.crossing(step, watched, level) if watched else None
                    passed = None  # a singular instant carried over on the smooth branch
                    if singular is not None and (not hits or singular <= min(hits)[0]):
                        if self.singular == "stop":
                            regularity.stop(self.model, step.motion(singular), watched)
                        passed = regularity.pass_through(self, mode, fun, step, singular, watched, Solver, atol)
                        if passed is None:  # a near miss, or no smooth branch: guard as "stop" does
                            level = singular_level(self.rtol)
                            singular = regularity.crossing(step, watched, level, force=True)
                            if singular is not None and (not hits or singular <= min(hits)[0]):
                                regularity.stop(self.model, step.motion(singular), watched)
                    if passed is not None:
                        t, y, dense, record = passed
                        if t > t_end:  # the end falls within the interval carried over
                            t, y = t_end, dense(t_end)
                        events_log.append(record)
                        if times is None or at_events:
                            ta = record["interval"][0]
                            if at_events:
                                next_time = sample_dense(dense, t_old, np.nextafter(ta, -np.inf), times, next_time, mode, emit)
                            emit(ta, dense(ta), mode)
                        if times is not None:
                            next_time = sample_dense(dense, t_old, t, times, next_time, mode, emit)
                        pending = times is None
                        restart = True
                        continue
                if hits:
                    te, k = min(hits)
                    ye = step.state(te)
                    if times is not None:  # (the default grid: up to the event, which is sampled)
                        next_time = sample_dense(step.dense, t_old, np.nextafter(te, -np.inf) if at_events else te,
                                                 times, next_time, mode, emit)
                    if times is None or at_events:
                        emit(te, ye, mode)  # the state at the event, before the switch
                    # stop on the kind the event watches, or on what the switch would do
                    switched = None if stop_on and events[k].kind in stop_on else \
                        self._switch(te, ye, mode, events[k])
                    if switched is None or (stop_on and switched[2]["type"] in stop_on):
                        if times is not None and not at_events:
                            emit(te, ye, mode)
                        record = events[k].record(te) if switched is None else switched[2]
                        record["mode"] = mode.label()
                        record["stopped"] = True
                        events_log.append(record)
                        t, y = te, ye
                        times = None
                        stopped = True
                        break
                    y, new_mode, record = switched
                    events_log.append(record)
                    limit = series.add(events[k].name, new_mode.contact(events[k].name).label()
                                       if isinstance(events[k], ContactTouch) else str(events[k].name in new_mode.held),
                                       te, ye[:n], ye[n:2 * n], record["normal_velocity"], tols[k]) \
                        if isinstance(events[k], (Touch, ContactTouch)) else None
                    if limit is not None and limit.t < t_end:
                        y, new_mode, record = self._accumulate(limit, y, mode, events[k])
                        events_log.append(record)
                        series.reset(events[k].name)
                        te = limit.t
                        while times is not None and next_time < times.size and times[next_time] < te:
                            emit(times[next_time], y, new_mode)  # within the rest of the series
                            next_time += 1
                    if len(events_log) > self.max_events:
                        raise IntegrationFailed(te, mode.label(), f"more than {self.max_events} mode "
                                                "switches (chattering or Zeno behaviour)", source)
                    mode = new_mode
                    t = te
                    pending = times is None or at_events  # the state after the switch
                    if times is not None and next_time < times.size and abs(times[next_time] - t) <= 1e-14 * max(1, abs(t)):
                        pending = True
                        next_time += 1
                    restart = True
                    continue
                for k in range(len(events)):
                    if not armed[k] and g_new[k] > tols[k]:
                        armed[k] = True
                if solver.reference:  # the slip-stop values change with the reference only
                    solver.set_references(mode, motion)
                    g_new = [ev.value(motion) for ev in events]
                g_prev, rates = g_new, rates_new
                ode.max_step = min(self.max_step, guard_rates.limit(rates, motion))
                # drift control
                res_p, res_v = motion.residuals(drift)
                residual_max["position"] = max(residual_max["position"], res_p)
                residual_max["velocity"] = max(residual_max["velocity"], res_v)
                scale = 1.0 + max_abs(ode.y[:2 * n])
                if max(res_p, res_v) > PROJECTION_TOL * scale:
                    if times is not None:
                        next_time = sample_dense(ode.dense_output(), t_old, t_new, times,
                                                       next_time, mode, emit)
                    y = ode.y.copy()
                    q, qd = self._project(mode, t_new, y[:n], y[n:2 * n])
                    y[:n], y[n:2 * n] = q, qd
                    projections += 1
                    t = t_new
                    pending = times is None
                    restart = True
                    continue
                if times is None:
                    emit(t_new, ode.y, mode, motion, step=True)
                else:
                    next_time = sample_dense(ode.dense_output(), t_old, t_new, times, next_time,
                                                   mode, emit)
                t, y = t_new, ode.y
                if ode.status == "finished":
                    break
                ode = with_step_limit(ode, lambda t_, y_, **kw: Solver(fun, t_, y_, t_end, **dict(kwargs, **kw)))
            if stopped or (not restart and ode.status == "finished"):
                break
        if pending or samples and samples.last_time < t:  # a switch at the end; the thinned last step
            emit(t, y, mode)
        if times is not None:
            while next_time < times.size and times[next_time] <= t + 1e-12 * max(1, abs(t)):
                if not (at_events and samples.last_time >= times[next_time]):  # (the end, sampled)
                    emit(times[next_time], y, mode)
                next_time += 1
        diagnostics = {
            "projections": projections,
            "events": len(events_log),
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
            "form": self.solver.form,
            "stabilization": "coordinate projection when residual > 1e-10 (relative)",
            "output_stride": samples.stride,
            "output": "every step" if self.every_step and times is None else
            (f"a uniform grid of {self.grid} times and each event's state" if at_events else "the requested times"),
        }
        if solver.charts is not None:
            diagnostics["chart_changes"] = solver.charts.changes - changes
        return Trajectory.from_samples(self, samples, events_log, diagnostics, residual_max)


def simulate(model: Model, t_end: float | None = None, times: Sequence[float] | None = None,
             form: str = "lagrange1", **options) -> Trajectory:
    """Simulate *model*: the hybrid motion with exact switching.

    Parameters
    ----------
    model : Model
    t_end : float, optional
    times : sequence of float, optional
        Output exactly at these times.
    form : str
        Formalism used to evaluate the accelerations.
    **options
        ``parameters``, ``rtol``, ``atol``, ``method``, ``max_step``, ``independent``,
        ``initial``, ``detect_jam``, ``specialize``, ``grid`` (the output's uniform times,
        default ``[simulation] grid`` or 1001, with each event's states), ``every_step`` (the
        output at every accepted step instead), ``max_samples`` (with ``every_step``: step
        samples kept, default 5000; beyond, the step output is thinned --
        ``diagnostics["output_stride"]`` -- events and requested times are always kept;
        ``None`` keeps every step), ``native``
        (numba for the phases it computes, :mod:`nonideal.simulation.fast`: None -- the
        default -- after a phase's first 1000 steps, True at once, False never).

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> from nonideal import gallery, simulate
    >>> traj = simulate(gallery.load("chaplygin-sleigh"), t_end=1.0, times=[0.0, 1.0])
    >>> traj.t.tolist()
    [0.0, 1.0]
    """
    allowed = ("parameters", "rtol", "atol", "method", "max_step", "independent", "max_events",
               "detect_jam", "specialize", "initial", "stop_on", "max_samples", "singular", "native",
               "grid", "every_step")
    unknown = [k for k in options if k not in allowed]
    if unknown:
        from ..errors import did_you_mean
        raise ModelError([f"simulate: unknown option '{k}'{did_you_mean(k, allowed)}; allowed: "
                          + ", ".join(allowed) for k in unknown])
    if (ext := extension_of(model)) is not None:  # third order: the extended model's motion, read back
        return reduce(ext, simulate(ext.model, t_end, times, form, **options), options.get("parameters"))
    check_arguments(model, t_end, times, form, options)
    initial = options.pop("initial", None)
    stop_on = options.pop("stop_on", None)
    sim = Simulation(model, form=form, **options)
    return sim.run(t_end=t_end, times=times, initial=initial, stop_on=stop_on)
