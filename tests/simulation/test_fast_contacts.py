"""Phases of modes with contacts in native code: the same events at the same instants and the
same motion as the Python path, with the steps between events taken natively."""

from pathlib import Path

import numpy as np
import pytest

from nonideal import gallery
from nonideal.gallery import stick_slip_oscillator
from nonideal.modeling.modelfile import load_model
from nonideal.numeric import native
from nonideal.simulation import fast
from nonideal.simulation.hybrid import Simulation

from tests.helpers import DATA_DIR, PACKAGE_ROOT
from tests.simulation.test_fast_forcing_stick_slip import block

pytest.importorskip("numba")

SPHERE = Path(PACKAGE_ROOT) / "benchmarks" / "friction_sphere.toml"
OBLIQUE = {"x'": 2.0, "y'": 1.0, "a'": -20.0, "b'": 5.0}


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(native.CACHE_ENV, str(tmp_path / "cache"))


def _both(model, **kw):
    """(Python path, native path, the native path's FastContacts) of one run."""
    ref = Simulation(model, native=False).run(**kw)
    sim = Simulation(model, native=True)
    got = sim.run(**kw)
    return ref, got, sim.fast_contacts


def _same_events(ref, got, tol):
    assert [e["type"] for e in got.events] == [e["type"] for e in ref.events]
    assert [e.get("contact") for e in got.events] == [e.get("contact") for e in ref.events]
    assert np.allclose([e["t"] for e in got.events], [e["t"] for e in ref.events], rtol=0, atol=tol)


@pytest.mark.parametrize("initial", [{}, OBLIQUE], ids=["sliding along x", "oblique slip"])
def test_the_friction_sphere_stops_slipping_at_the_same_instant(initial):
    model = load_model(SPHERE)
    ref, got, fc = _both(model, initial=initial)
    assert fc.native_steps > 0 and fc.located == 1 and fc.handbacks == 0  # the stop located natively
    assert len(got.events) == 1
    _same_events(ref, got, 1e-12)
    # rolling from the event on: v = v0 - (2/7) U0 whatever the law (the closed form)
    qd0 = np.array([initial.get("x'", 2.0), initial.get("y'", 0.0)])
    U0 = qd0 + 0.1 * np.array([-initial.get("b'", 0.0), initial.get("a'", 0.0)])
    assert np.allclose(got.qd[-1][:2], qd0 - 2 / 7 * U0, rtol=0, atol=1e-12)
    assert np.allclose(got.q[-1], ref.q[-1], rtol=0, atol=1e-10)
    assert np.allclose(got.qd[-1], ref.qd[-1], rtol=0, atol=1e-10)


def test_a_stiff_stick_slip_cycle_every_event_as_on_the_python_path(monkeypatch):
    """Every switch located natively, and no step taken in Python: each phase starts native,
    its guard that the switch left at zero (not armed) watched natively as the scan does."""
    from scipy.integrate import DOP853

    model = stick_slip_oscillator.build(k=1e6, t_end=0.03)
    ref = Simulation(model, native=False).run(t_end=0.03)
    stepped, step = [], DOP853.step

    def counting_step(self):
        stepped.append(1)
        return step(self)

    monkeypatch.setattr(DOP853, "step", counting_step)
    sim = Simulation(model, native=True)
    got = sim.run(t_end=0.03)
    assert len(ref.events) >= 8
    _same_events(ref, got, 1e-10)
    fc = sim.fast_contacts
    assert fc.native_steps > 0 and fc.located == len(got.events)  # every switch located natively
    assert stepped == [] and fc.handbacks == 0


def test_short_slips_under_a_fast_force_every_event_as_on_the_python_path():
    model = block(0.0, 8.0, 2000.0)
    ref, got, fc = _both(model, t_end=0.02)
    assert len(ref.events) >= 4
    _same_events(ref, got, 1e-10)
    assert np.allclose(got.q[-1], ref.q[-1], rtol=0, atol=1e-9)
    assert fc.native_steps > 0 and fc.located == len(got.events)


def test_a_bouncing_ball_bounces_at_the_same_instants():
    model = gallery.load("bouncing-ball")
    ref, got, fc = _both(model, t_end=3.0)
    assert len(ref.events) >= 4
    _same_events(ref, got, 1e-9)
    assert fc.native_steps > 0


def test_a_native_run_is_reproducible_bit_for_bit():
    model = load_model(SPHERE)
    a = Simulation(model, native=True).run(initial=OBLIQUE)
    b = Simulation(model, native=True).run(initial=OBLIQUE)
    assert a.events[0]["t"] == b.events[0]["t"]
    assert np.array_equal(a.q, b.q) and np.array_equal(a.qd, b.qd)


def test_requested_times_come_from_the_native_dense_output():
    model = load_model(SPHERE)
    times = np.linspace(0.0, 1.0, 41)
    ref = Simulation(model, native=False).run(times=times, initial=OBLIQUE)
    got = Simulation(model, native=True).run(times=times, initial=OBLIQUE)
    assert np.array_equal(got.t, times) and np.array_equal(ref.t, times)
    assert np.allclose(got.q, ref.q, rtol=0, atol=1e-10)
    assert np.allclose(got.qd, ref.qd, rtol=0, atol=1e-10)


def test_by_default_a_short_run_stays_on_the_python_path():
    model = load_model(SPHERE)
    sim = Simulation(model)
    sim.run(initial=OBLIQUE)
    assert sim.fast_contacts.native_steps == 0
    assert fast.NATIVE_STEPS > 100


def test_the_located_steps_dense_output_is_scipys():
    """The step in which the native loop located an event hands its dense output to the hybrid
    loop (the grid's samples up to the event come from it): SciPy's DOP853 interpolant of the
    same coefficients, at a time and at an array of times, and the event's own state."""
    from scipy.integrate._ivp.rk import Dop853DenseOutput

    from nonideal.simulation.fast_contacts import LocatedStep

    rng = np.random.default_rng(5)
    y, F = rng.normal(size=6), rng.normal(size=(7, 6))
    step = LocatedStep(0.3, 0.02, y, F, 0.31, 2, np.full(6, 7.0))
    ref = Dop853DenseOutput(0.3, 0.32, y, F)
    s = np.linspace(0.3, 0.32, 5)
    assert np.allclose(step.dense(s), ref(s), rtol=0, atol=1e-14)
    assert np.allclose(step.dense(0.305), ref(0.305), rtol=0, atol=1e-14)
    assert step.hits == [(0.31, 2)] and (step.a, step.b) == (0.3, 0.32)
    assert np.array_equal(step.state(0.31), np.full(6, 7.0))


def test_a_phase_that_starts_natively_takes_scipys_first_step():
    """A phase that goes native from its first step makes no SciPy solver: the native loop
    evaluates its derivative and chooses the first step as SciPy's ``select_initial_step``
    does for DOP853 (Hairer, Norsett & Wanner 1993, II.4), here on the right-hand side it
    integrates (the runs that start so: the sphere's test above)."""
    from scipy.integrate._ivp.common import select_initial_step

    from nonideal.modes.switching import select_mode

    model = load_model(SPHERE)
    sim = Simulation(model, native=True)
    q, qd = sim.initial_state(OBLIQUE)
    mode = select_mode(sim.solver, 0.0, q, qd)
    nat, S = sim.fast_contacts.native, sim.fast_contacts._with_references(mode)
    y = np.concatenate((q, qd, np.zeros(5)))
    atol = sim.work_tolerances()

    def fun(t, y):
        dy = np.empty(y.size)
        assert nat.loop.rhs(nat.kernel, S, t, np.ascontiguousarray(y), dy)
        return dy

    f = fun(0.0, y)
    for t_end, max_step in ((1.0, np.inf), (1.0, 1e-4), (1e-9, np.inf)):
        want = select_initial_step(fun, 0.0, y, t_end, max_step, f, 1, 7, sim.rtol, atol)
        got = nat.loop.initial_step(nat.kernel, S, 0.0, y, f, t_end, max_step, sim.rtol, atol, np.empty(y.size))
        assert got == pytest.approx(want, rel=1e-12)
    assert select_initial_step(fun, 0.0, y, 1.0, np.inf, f, 1, 7, sim.rtol, atol) < 1e-2  # (not the cap)


def test_the_native_path_is_asked_once_a_step(monkeypatch):
    """Whether the next step goes native is asked once before each step (the answer counts a
    mode's steps and a hand-back's wait), also at a phase's first step, asked before the
    phase's solver is made: as many questions as steps taken on the Python path."""
    from scipy.integrate import DOP853

    from nonideal.simulation.fast_contacts import FastContacts

    asked, stepped = [], []
    ready, step = FastContacts.ready, DOP853.step

    def counting_ready(self, *args):
        asked.append(1)
        return ready(self, *args)

    def counting_step(self):
        stepped.append(1)
        return step(self)

    monkeypatch.setattr(FastContacts, "ready", counting_ready)
    monkeypatch.setattr(DOP853, "step", counting_step)
    tr = Simulation(load_model(SPHERE), native=False).run(initial=OBLIQUE)
    assert len(tr.events) == 1 and len(stepped) >= 5
    assert len(asked) == len(stepped)


def test_a_phase_that_starts_natively_reads_its_guards_at_its_start():
    """A rod spun upright on a smooth floor leaves it at once: the first phase starts with its
    touch guard at zero, not armed, and goes native from its first step (the native loop
    watches a guard that is not armed as the scan does).  Its guards are read at the start
    -- not at the state where the first step was chosen, 1e-4 s on (a gap of 7e-8 there
    made a dip to zero in the first step, a touch at 1e-8 s) -- and the run has the Python
    path's two events: the landing at 0.1366 s and the lift-off at 0.9419 s."""
    model = load_model(DATA_DIR / "friction" / "rod_floor_spin.toml")
    ref, got, fc = _both(model, t_end=1.0)
    assert fc.native_steps > 0
    assert [(e["type"], e["mode"]) for e in got.events] == [("touch", "floor:smooth"), ("lift-off", "floor:separated")]
    _same_events(ref, got, 1e-9)
