"""Bounded memory and runs that cannot finish.

A simulation's output is, by default, a uniform grid of :data:`GRID` times and each event's
state before and after its switch (:func:`output_times`): its size does not depend on the
steps.  On request (``every_step=True``) it keeps the state at every accepted step and at every
event; a long run (a pendulum to ``t_end = 1e5``: a million steps) would hold all of them; a run whose end
is out of reach (``t_end = 1e8``, or a stiff spring resolved by an explicit method) would grow
without bound.  Three limits keep every run bounded:

* :class:`SampleBuffer` keeps at most :data:`MAX_SAMPLES` step samples: when full, it drops
  every other step sample (never an event's or a requested time's) and from then on keeps one
  step in 2, 4, ... -- the output stays a faithful picture of the motion on a grid twice as
  coarse, said in ``diagnostics["output_stride"]``.  ``max_samples=None`` keeps every step
  (asked for explicitly);
* :func:`check_times`: at most :data:`MAX_TIMES` requested sample times;
* :class:`StepBudget`: after :data:`PROBE_STEPS` steps, and every as many after, the number of
  steps the run needs is extrapolated from its progress; above :data:`MAX_STEPS` the run is
  refused, naming the estimate and what to change.  Likewise its time (the processor time of
  the thread that runs it, so that a busy machine does not count; not the process's: with
  BLAS or numba threads alive, reading the process's clock sums over every thread and took
  0.3-10 ms a call on a loaded machine, more than a whole short run), extrapolated once the run has taken
  :data:`PROBE_SECONDS`: above :data:`MAX_SECONDS` it is refused (a stiff
  spring, k = 1e9, integrated by Radau at rtol 1e-10 to t_end = 1 would take 3e6 steps of
  0.5 ms: 25 minutes; it is refused after a second or two).
"""

from __future__ import annotations

import numbers
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..equations.formalisms import FORMS
from ..errors import ModelError, short_repr
from ..modeling.arguments import real_number, require_form, require_mapping, require_model, sample_times

__all__ = ["Sample", "MAX_SAMPLES", "MAX_TIMES", "MAX_STEPS", "PROBE_STEPS", "MAX_SECONDS", "PROBE_SECONDS", "Block", "SampleBuffer", "StepBudget",
           "check_times", "check_arguments", "sample_dense", "GRID", "output_times", "emitter"]

MAX_SAMPLES = 5_000
"""Step samples kept by default (events and requested times come on top): a long run's
output stays a few megabytes of JSON (a rigid body with four contacts: ~0.9 kB per sample)
however many steps it takes; ``max_samples=None`` keeps every step."""
GRID = 1001
"""Uniform sample times of a run's output by default, ``t0`` and ``t_end`` included; each
event's state before and after its switch comes on top (``grid=``, ``--grid``; every accepted
step instead with ``every_step=True``, ``--every-step``)."""
MAX_TIMES = 200_000
"""Requested sample times (``--times``, ``times=``) at most."""
MAX_STEPS = 5_000_000
"""Integrator steps a run may need (extrapolated from its progress) before it is refused."""
PROBE_STEPS = 2_000
"""Steps between two extrapolations."""
MAX_SECONDS = 600.0
"""Processor time a run may need (extrapolated from its progress) before it is refused."""
PROBE_SECONDS = 1.0
"""Processor time a run takes before its total is extrapolated (read every 64 steps)."""


def emitter(samples: "SampleBuffer", support):
    """The run's ``emit(t, y, mode, motion=None, step=False)``: one sample into *samples*
    (*support*: the watch of the support points, :class:`~nonideal.modeling.shapes.watch.
    SupportWatch`, checked at each); ``emit.many(T, Y, mode, QDD, step)`` the samples of a
    native phase in a mode without rows or contacts, ``emit.rows(T, Y, mode, step)`` samples of
    one mode whose motion is still to be solved -- each as one :class:`Block`."""
    def emit(t, yy, md, motion=None, step=False):
        support.check(t, yy)
        samples.add(Sample(float(t), np.array(yy, dtype=float), md, motion), step)

    def rows(T, Y, md, step=False):
        if support.watched:
            for k in range(len(T)):
                support.check(T[k], Y[k])
        samples.add_block(Block(np.array(T, dtype=float), np.array(Y, dtype=float), None, md), step)

    emit.many = lambda T, Y, md, QDD, step=False: samples.add_block(Block(T, Y, QDD, md), step)
    emit.rows = rows
    return emit


def output_times(model, times, t_end, every_step: bool, grid: int):
    """``(times, t_end, at_events)`` of a run: the requested *times* checked (the end time
    defaults to the model's, or to the last of *times*); else, unless *every_step*, the uniform
    grid of *grid* times from ``t0`` to the end, with ``at_events`` true: each event's state
    before and after its switch is sampled too.  ``times=None``: every accepted step."""
    t0, source = model.t0, None if model.source == "<api>" else model.source
    if times is not None:
        times = np.array([float(s) for s in times])
        if not np.all(np.isfinite(times)):
            raise ModelError("--times: the sample times must be finite numbers")
        if times.size > 1 and np.any(np.diff(times) <= 0):
            raise ModelError("--times: the sample times must be strictly increasing "
                             f"(got {', '.join(f'{v:g}' for v in times)})")
        if times.size and times[0] < t0:
            raise ModelError(f"--times: {times[0]} is before t0 = {t0}")
        check_times(times)
    if t_end is None:
        t_end = float(times[-1]) if times is not None and times.size else model.simulation.t_end
    if t_end is None:
        raise ModelError("no end time: give [simulation] t_end in the model or --t-end", source)
    if times is not None and times.size and times[-1] > t_end:
        t_end = float(times[-1])
    if times is not None or every_step:
        return times, t_end, False
    if isinstance(grid, bool) or not isinstance(grid, numbers.Integral) or not 2 <= grid <= MAX_TIMES:
        raise ModelError(f"grid: must be an integer from 2 to {MAX_TIMES}, the output's uniform "
                         f"sample times (got {grid!r})")
    grid = np.linspace(t0, t_end, grid)
    grid[-1] = t_end
    return grid, t_end, True


def check_times(times: np.ndarray) -> None:
    """Refuse more than :data:`MAX_TIMES` sample times (each becomes a sample in memory)."""
    if times.size > MAX_TIMES:
        raise ModelError(f"--times: {times.size} sample times requested; at most {MAX_TIMES} "
                         "(every one is kept in memory): sample more coarsely or split the run")


@dataclass(frozen=True)
class Sample:
    """One sample of a run: time, state, mode, and the Motion at the state when the simulation
    already has it."""

    t: float
    y: np.ndarray
    mode: Any
    motion: Any = None


class Block:
    """Samples of one mode as arrays: times *t*, states *y* (one row each) and accelerations
    *qdd* -- a native phase in a mode without rows or contacts (the motion is the
    derivative's; no :class:`~nonideal.modes.motion.Motion` per sample) -- or ``qdd=None``:
    samples whose motion is still to be solved (the output grid's, a native contact phase's
    steps), all at once when the trajectory is assembled."""

    __slots__ = ("t", "y", "qdd", "mode")

    def __init__(self, t: np.ndarray, y: np.ndarray, qdd: np.ndarray, mode):
        self.t, self.y, self.qdd, self.mode = t, y, qdd, mode

    def __len__(self) -> int:
        return len(self.t)

    def rows(self, keep) -> "Block":
        return Block(self.t[keep], self.y[keep], None if self.qdd is None else self.qdd[keep], self.mode)


class SampleBuffer(list):
    """The samples of a run, at most *limit* of them taken at plain steps (see the module
    docstring).  ``add(sample, step=True)``: a step sample, subject to the stride;
    :meth:`add_block`: many at once (:class:`Block`), kept exactly as one by one."""

    def __init__(self, limit: int | None = MAX_SAMPLES):
        super().__init__()
        self.limit = limit
        self.stride = 1
        self._steps = 0          # step samples kept
        self._seen = 0           # step samples offered since the stride last changed
        self._is_step: list[bool] = []

    def add(self, sample, step: bool = False) -> None:
        if step and self.limit is not None:
            self._seen += 1
            if self._seen % self.stride:
                return
            if self._steps >= self.limit:
                self._thin()
        self.append(sample)
        self._is_step.append(step)
        self._steps += step

    def add_block(self, block: Block, step: bool = False) -> None:
        """Add the samples of *block*; step samples are kept or dropped as :meth:`add` would,
        one by one."""
        if not step or self.limit is None:
            self._append_block(block, step)
            return
        i, n = 0, len(block)
        while i < n:
            j = i + (-(self._seen + 1)) % self.stride  # the next row the stride keeps
            if j >= n:
                self._seen += n - i
                return
            if self._steps >= self.limit:  # full: thin, then keep row j (as add does)
                self._thin()
                self._append_block(block.rows(slice(j, j + 1)), True)
                i = j + 1
                continue
            rows = np.arange(j, n, self.stride)[:self.limit - self._steps]
            last = int(rows[-1])
            self._append_block(block if rows.size == n else block.rows(
                slice(j, last + 1) if self.stride == 1 else rows), True)
            self._seen += last + 1 - i
            i = last + 1

    def _append_block(self, block: Block, step: bool) -> None:
        if len(block):
            self.append(block)
            self._is_step.append(step)
            self._steps += len(block) if step else 0

    @property
    def last_time(self) -> float | None:
        """The time of the last sample kept (None: none)."""
        if not self:
            return None
        last = self[-1]
        return float(last.t[-1]) if isinstance(last, Block) else last.t

    def _thin(self) -> None:
        """Drop every other step sample; double the stride."""
        keep, flags, parity = [], [], 0
        for sample, step in zip(self, self._is_step):
            if step and isinstance(sample, Block):
                # row r leaves the parity at parity ^ ((r + 1) % 2): kept where that is 1
                after = parity ^ ((np.arange(len(sample)) + 1) % 2)
                parity ^= len(sample) % 2
                sample = sample.rows(after == 1)
                if not len(sample):
                    continue
            elif step:
                parity ^= 1
                if not parity:
                    continue
            keep.append(sample)
            flags.append(step)
        self[:] = keep
        self._is_step = flags
        self._steps = sum(len(s) if isinstance(s, Block) else 1 for s, f in zip(keep, flags) if f)
        self.stride *= 2
        self._seen = 0


class StepBudget:
    """Refuses a run whose extrapolated number of steps exceeds :data:`MAX_STEPS`, or whose
    extrapolated processor time exceeds :data:`MAX_SECONDS`."""

    def __init__(self, t0: float, t_end: float, source: str | None, limit: int = MAX_STEPS,
                 seconds: float | None = None, method: str = "DOP853"):
        self.t0, self.t_end, self.source, self.limit = t0, t_end, source, limit
        self.seconds, self.method = MAX_SECONDS if seconds is None else seconds, method
        self.steps = 0
        self.start = time.thread_time()

    def step(self, t: float) -> None:
        self.steps += 1
        if self.steps % 64 or t <= self.t0:
            return
        self._check(t, self.steps % PROBE_STEPS == 0)

    def _check(self, t: float, probe: bool) -> None:
        progress = (t - self.t0) / (self.t_end - self.t0)
        elapsed = time.thread_time() - self.start
        if probe and self.steps / progress > self.limit:
            self._refuse(t, f"{self.steps} steps", f"about {self.steps / progress:.2g} steps",
                         f"{self.limit:.0e} steps")
        if elapsed >= PROBE_SECONDS and elapsed / progress > self.seconds:
            self._refuse(t, f"{elapsed:.2g} s", f"about {elapsed / progress:.2g} s",
                         f"{self.seconds:g} s")

    def advance(self, t: float, steps: int) -> None:
        """*steps* steps taken at once (natively) up to *t*, then checked."""
        self.steps += steps
        if steps and t > self.t0:
            self._check(t, self.steps >= PROBE_STEPS)

    def _refuse(self, t: float, spent: str, needed: str, limit: str):
        other = ("an explicit integrator (--method DOP853) for a motion that oscillates fast rather "
                 "than decays: an implicit one resolves each oscillation with many more, shorter "
                 "steps") if self.method in ("Radau", "BDF", "LSODA") else \
            "a stiff integrator (--method Radau or BDF) for a stiff model"
        raise ModelError(
            f"simulate: this run cannot finish: after {spent} it has reached t = {t:.6g} of "
            f"t_end = {self.t_end:.6g}, so it would need {needed} (the limit is {limit}): give an "
            f"earlier end time (--t-end), a looser tolerance (rtol), or {other}", self.source)


def check_arguments(model, t_end, times, form, options: dict) -> None:
    """The arguments of :func:`~nonideal.simulate`, checked before any work (the command line's
    checks, for the Python API): a Model, a finite end time after ``t0``, sample times that are
    numbers, positive tolerances and step bound, a positive sample limit."""
    f = "simulate"
    require_model(model, f)
    require_form(form, f, [*FORMS, "gauss"])
    t_end = real_number(t_end, f, "t_end")
    if t_end is not None and t_end <= model.t0:
        raise ModelError(f"{f}: t_end = {t_end:g} is not after t0 = {model.t0:g}")
    sample_times(times, f)
    real_number(options.get("rtol"), f, "rtol", positive=True)
    if options.get("atol") is not None and np.ndim(options["atol"]) == 0:
        real_number(options["atol"], f, "atol", positive=True)
    real_number(options.get("max_step"), f, "max_step", positive=True)
    for name in ("parameters", "initial"):
        require_mapping(options.get(name), f, name, "{'m': 2.0}")
        for key, value in (options.get(name) or {}).items():
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise ModelError(f"{f}: {name}[{key!r}] must be a number, got {short_repr(value)} "
                                 f"(e.g. {name}={{{key!r}: 1.0}})")
    native = options.get("native")
    if native is not None and not isinstance(native, bool):
        raise ModelError(f"{f}: native must be True, False or None (after a phase's first steps), got {native!r}")
    grid = options.get("grid")
    if grid is not None and (isinstance(grid, bool) or not isinstance(grid, numbers.Integral) or grid < 2):
        raise ModelError(f"{f}: grid must be an integer >= 2 (the output's uniform sample times), got {grid!r}")
    if options.get("every_step") is not None and not isinstance(options["every_step"], bool):
        raise ModelError(f"{f}: every_step must be True or False, got {options['every_step']!r}")
    if grid is not None and options.get("every_step"):
        raise ModelError(f"{f}: grid and every_step=True: choose one output (a uniform grid or every step)")
    if grid is not None and grid > MAX_TIMES:
        raise ModelError(f"{f}: grid = {grid}: at most {MAX_TIMES} sample times (every one is kept in memory)")
    limit = options.get("max_samples", MAX_SAMPLES)
    if limit is not None and (isinstance(limit, bool) or not isinstance(limit, numbers.Integral)
                              or limit < 2):
        raise ModelError(f"{f}: max_samples must be an integer >= 2 or None, got {limit!r}")


def sample_dense(dense, t_old, t_new, times, next_time, mode, emit) -> int:
    """Emit the requested *times* in ``[t_old, t_new]`` from the dense output (all of them in
    one evaluation and one block where the dense output takes an array of times, as SciPy's
    does); the index of the next one."""
    end = int(np.searchsorted(times, t_new, side="right"))
    if end - next_time > 1 and hasattr(emit, "rows"):
        ts = times[next_time:end]
        ts = ts[ts >= t_old]
        try:
            Y = np.asarray(dense(ts)) if ts.size > 1 else None
        except (TypeError, ValueError):
            Y = None
        if Y is not None and Y.ndim == 2 and Y.shape[1] == ts.size:
            emit.rows(ts, Y.T, mode)
            return end
    while next_time < times.size and times[next_time] <= t_new:
        if times[next_time] >= t_old:
            emit(times[next_time], dense(times[next_time]), mode)
        next_time += 1
    return next_time
