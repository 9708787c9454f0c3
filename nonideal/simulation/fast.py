"""Phases in native code: the right-hand side of a mode, and whole phases without events,
through numba (:mod:`nonideal.numeric.native`, the optional extra ``fast``).

A phase is integrated natively when nothing in it needs Python between two steps: Lagrange I
(the saddle-point route) with DOP853, no contact rows, no watched event, no constraint row
whose drift is checked, no chart and no singular row to watch -- a pendulum, a chain of free
bodies, a spinning top.  The phase's first steps run on SciPy's DOP853 as every phase does;
after :data:`NATIVE_STEPS` accepted steps (``native=None``, the default: short runs never
pay the compilation), or at once (``native=True``), the loop hands the state, its derivative
and the next step size to the native DOP853 (the same method, tableau and step-size control,
:mod:`nonideal.numeric.integrator`), which integrates to the end of the run.  The right-hand
sides of the other phases of such a mode also come from the native kernel once it is loaded.
``native=False``, or numba absent, keeps the NumPy/SciPy path: the same results to rounding.

Where a C compiler is found, a native phase runs the same loop compiled in C with the mode's
right-hand side inlined (:meth:`FastPhases.c_loop`; :mod:`nonideal.numeric.cloop`): the numba
phase bit for bit, faster.  The samples of a phase in a mode without rows or contacts are
handed over as arrays (``emit.many``), not one by one.

Which path a run takes depends only on its model, options and progress, never on what ran
before or on the disk cache, so a run is reproducible bit for bit.
"""

from __future__ import annotations

import os
import signal
import threading
from contextlib import contextmanager

import numpy as np

from ..modes.motion import Motion
from ..modes.system import system_of
from ..modes.types import Mode

try:  # the C functions that signal.signal and signal.getsignal wrap
    import _signal
except ImportError:  # (another Python implementation)
    _signal = signal

__all__ = ["NATIVE_STEPS", "NATIVE_CHUNK", "C_LOOP_ENV", "FastPhases", "deferred_signals"]

NATIVE_STEPS = 1000
"""Accepted steps of one phase after which it continues natively (with ``native=None``): the
phase has then cost ~0.1-0.5 s in Python, about what loading the native kernel costs the first
time in a process (compiling it the first time ever: 2-4 s for a 10-link pendulum, then read
from the disk cache in ~0.1 s)."""

C_LOOP_ENV = "NONIDEAL_C_LOOP"
"""Environment variable: ``0`` keeps the numba loop for the phases a C compiler could take
(:meth:`FastPhases.c_loop`; the results are the same bit for bit, only slower)."""

_DEFERRED = (int(signal.SIGINT), int(signal.SIGTERM))

NATIVE_CHUNK = 20_000
"""Steps of one native call; between two, the run's step and time budget is checked and
Ctrl-C takes effect (:func:`deferred_signals`)."""


class FastPhases:
    """The native path of one :class:`~nonideal.simulation.hybrid.Simulation`.

    Parameters
    ----------
    sim : Simulation
    option : bool or None
        ``True``: native from the start of every eligible phase; ``None``: after
        :data:`NATIVE_STEPS` steps of a phase; ``False``: never.
    """

    def __init__(self, sim, option: bool | None):
        self.sim = sim
        self.option = option
        self._native = None
        self._buffers: dict = {}
        #: mode structures whose right-hand side is native in this run (all with ``True``)
        self.hot: set = set()
        self._steps: dict = {}
        self._failed: set = set()  # structures whose native phase stopped short in this run
        if option:
            self.native  # load now: a failure to compile shows at once, not mid-run

    @property
    def native(self):
        """The model's :class:`~nonideal.numeric.native.Native`, loaded on first use (False:
        numba absent or the kernel not writable natively)."""
        if self._native is None:
            if self.option is False:
                self._native = False
            else:
                from ..numeric.native import native_of

                with deferred_signals():  # numba compiling: not interruptible cleanly
                    self._native = native_of(self.sim.kernel) or False
        return self._native

    def _identity(self):
        """The native module's ``(key, source, nx, nz)`` (:func:`~nonideal.numeric.native.
        identity_of`: numba not imported), or None: not native (numba absent, the kernel not
        written natively, or it did not compile)."""
        if self.option is False or self._native is False:
            return None
        from ..numeric.native import identity_of

        return identity_of(self.sim.kernel)

    def _system(self, mode: Mode):
        """The mode's system when the native right-hand side computes it, else None."""
        sim = self.sim
        if self.option is False or not sim.solver.route.saddle_point or getattr(sim, "control_rows", None):
            return None  # (the controls' powers of servo rows are integrated on the NumPy path)
        system = sim.solver.system(mode)
        if system.contact_rows or system.blocks is not None or (system.m and system.dependence is not False):
            return None
        return system

    def buffers(self, mode: Mode):
        """``(w, ix)`` of the mode structure (:meth:`Native.buffers
        <nonideal.numeric.native.Native.buffers>`), one pair per structure."""
        key = mode.structure
        if key not in self._buffers:
            from ..numeric.native import buffers

            _, _, nx, nz = self._identity()
            self._buffers[key] = buffers(nx, nz, self.sim.solver.system(mode), self.sim.params, self.sim.track)
        return self._buffers[key]

    def c_loop(self, mode: Mode, t: float, y: np.ndarray):
        """The phase loop of *mode* compiled in C with its right-hand side inlined
        (:mod:`nonideal.numeric.cloop`, :mod:`nonideal.numeric.cmode`), or None: no C compiler,
        ``NONIDEAL_C_LOOP=0`` in the environment, the source does not compile, or its
        right-hand side at *(t, y)* is not the numba one's bit for bit.  Built once per model,
        parameters and mode structure (the library on disk, named by its source's hash)."""
        if os.environ.get(C_LOOP_ENV, "1") == "0":
            return None
        from ..numeric import cloop

        if cloop.compiler() is None:
            return None
        w, ix = self.buffers(mode)
        nx = int(ix[5])
        key = ("c loop", w[:nx].tobytes(), ix.tobytes())
        entry = self.sim.kernel.model.cached(key, lambda: self._build_c_loop(w, ix, y.size))
        if entry is None:
            return None
        loop, checked = entry
        if not checked:
            entry[1] = True
            if not self._agrees(loop, w, ix, t, y):
                entry[0] = loop = None
        return loop

    def _agrees(self, loop, w, ix, t: float, y: np.ndarray) -> bool:
        """Whether the C right-hand side of *loop* is the numba one's bit for bit (the generated
        C is trusted once it computes what numba computes).  Compared at a fixed generic state
        and the agreement recorded on disk beside the library, so that a later process neither
        repeats it nor compiles numba's wrapper for it (0.4 s): the outcome depends on the
        library alone, never on the run.  Where numba's solve fails at that state (a singular
        system), compared at *(t, y)*, the phase's start, and not recorded."""
        marker = f"{loop.path}.{self._identity()[0][:16]}.agrees"
        if os.path.exists(marker):
            return True
        if not self.native:  # (numba installed, but the model did not compile)
            return False
        generic = np.array([0.6180339887498949 * (k + 1) % 1.0 + 0.1 for k in range(y.size)])
        for tc, yc, record in ((0.6180339887498949, generic, True), (t, y, False)):
            want = np.empty(y.size)
            if not self.native.rhs(tc, yc, w.copy(), ix, want):
                continue
            got = loop.rhs(tc, list(yc))
            ok = got is not None and np.array(got).tobytes() == want.tobytes()
            if ok and record:
                try:
                    with open(marker, "w") as fh:
                        fh.write("the C right-hand side equals numba's bit for bit\n")
                except OSError:
                    pass
            return ok
        return False

    def _build_c_loop(self, w, ix, ny):
        from ..numeric import cloop, cmode
        from ..numeric.native import cache_dir

        try:
            path = cloop.build(cloop.source(cmode.rhs_source(self.sim.kernel, w, ix)), str(cache_dir() / "c"))
        except Exception:  # an expression the C printer does not write: the numba loop
            return None
        return None if path is None else [cloop.Loop(path, ny), False]

    def rhs(self, mode: Mode, general):
        """The native right-hand side of *mode* once the native kernel is loaded, else None;
        *general* answers where the system is singular (a named error or the minimum-norm
        solution)."""
        if not (self.option or mode.structure in self.hot):
            return None
        if self._system(mode) is None or not self.native:
            return None
        step = self.native.rhs
        w, ix = self.buffers(mode)
        size = 2 * self.sim.n + (5 if self.sim.track else 0)

        empty = np.empty

        def fun(t, y):
            dy = empty(size)
            if step(t, y, w, ix, dy):
                return dy
            return general(t, y)
        return fun

    def start(self) -> None:
        """A run starts: no mode structure is hot, no step counted."""
        self.hot.clear()
        self._steps.clear()
        self._failed.clear()

    def ready(self, mode: Mode, first: bool, events, drift, watched) -> str | None:
        """Called before each step of a phase in *mode* (*first*: its first step): ``"phase"``
        continue natively to the end, ``"rhs"`` restart on the native right-hand side (events
        or drift still checked in Python after each step), None go on as it is.  With
        ``native=None`` the step counts of each mode structure in the run decide."""
        if self.option is False:
            return None
        key = mode.structure
        if self.option is None:
            count = self._steps[key] = self._steps.get(key, 0) + 1
            if count != NATIVE_STEPS or key in self.hot:
                return None
        elif not first:
            return None
        if key in self._failed or self._system(mode) is None or not self._identity():
            return None  # (numba is loaded only when the phase needs it: not for a C loop known to agree)
        sim = self.sim
        if events or drift[0] or drift[1] or watched or sim.method != "DOP853" or sim.solver.charts is not None:
            if self.option:
                return None
            self.hot.add(key)
            return "rhs"
        return "phase"

    def run(self, mode: Mode, ode, t_end: float, times, next_time: int, emit, budget):
        """Integrate from the solver's accepted state to *t_end*; the samples are emitted
        (every step, or the requested *times* from the dense output).  Returns ``(t, y,
        next_time, finished)``; not finished: the native step failed (a step too small or a
        singular system) at ``(t, y)``, where the SciPy path takes over and explains."""
        w, ix = self.buffers(mode)
        solver, n = self.sim.solver, self.sim.n
        plain = solver.system(mode).m == 0
        t, y, f, h_abs = float(ode.t), np.array(ode.y, dtype=float), np.array(ode.f, dtype=float), float(ode.h_abs)
        loop = self.c_loop(mode, t, y)
        nat = self.native if loop is None else None
        if loop is None and not nat:  # numba installed but the model did not compile
            self._failed.add(mode.structure)
            return t, y, next_time, False
        atol = np.broadcast_to(np.asarray(ode.atol, dtype=float), y.shape).copy()
        grid = np.asarray(times if times is not None else np.zeros(0), dtype=float)
        nt = next_time if times is not None else 0
        # the hybrid loop's watch of collapsing steps: the first such step returns to it
        tiny = 1e-9 * min(t_end - budget.t0, 1.0)
        while True:
            with deferred_signals():
                if loop is not None:
                    status, t, y, f, h_abs, T, Y, DY, count, nt, steps = loop.phase_arrays(
                        t, y, f, h_abs, float(t_end), float(ode.rtol), atol, float(ode.max_step),
                        grid, nt, NATIVE_CHUNK, tiny + 4e-16 * abs(t_end))
                else:
                    status, t, y, f, h_abs, T, Y, DY, count, nt, steps = nat.integrator.phase(
                        nat.kernel, t, y, f, h_abs, float(t_end), float(ode.rtol), atol, float(ode.max_step),
                        w, ix, grid, nt, NATIVE_CHUNK, tiny + 4e-16 * abs(t_end))
            step = times is None
            if plain and not solver.ck:  # nothing but the motion: arrays (emit.many)
                emit.many(T, Y, mode, DY[:, n:2 * n], step)
            elif plain:  # without rows, the derivative holds the whole motion
                system = system_of(solver.kernel, mode)
                QDD = DY[:, n:2 * n]
                for k, tk in enumerate(T.tolist()):
                    emit(tk, Y[k], mode, Motion.in_phase(solver, mode, system, tk, Y[k], QDD[k]), step)
            else:  # the multipliers solved when the trajectory is assembled
                emit.rows(T, Y, mode, step)
            budget.advance(t, steps)
            if status != 1:
                break
        if status != 0:
            self._failed.add(mode.structure)
        return t, y, (nt if times is not None else next_time), status == 0


@contextmanager
def deferred_signals():
    """Ctrl-C (SIGINT) and SIGTERM received while native code runs or compiles take effect when
    it returns (within one chunk of :data:`NATIVE_CHUNK` steps, or once the compilation is
    done): a Python exception raised by a signal inside numba's call would come back as a
    ``SystemError`` ("returned a result with an exception set") or end the process by the
    signal.  The handlers in place before (the command line's: exit 130 / 143) then run.
    (The handlers are swapped through ``_signal``, the C module :mod:`signal` wraps: the same
    calls without converting each handler to and from an enum, 3 instead of 16 us a native
    call.)"""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list = []
    old = {}

    def defer(signum, frame):
        received.append((signum, frame))

    for sig in _DEFERRED:
        handler = _signal.getsignal(sig)
        if handler is not None:
            old[sig] = handler
            _signal.signal(sig, defer)
    try:
        yield
    finally:
        for sig, handler in old.items():
            _signal.signal(sig, handler)
    for signum, frame in received[:1]:
        handler = old[signum]
        if callable(handler):
            handler(signum, frame)  # Python's default raises KeyboardInterrupt
        elif handler == signal.SIG_DFL:
            os.kill(os.getpid(), signum)
