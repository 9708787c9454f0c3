"""The native right-hand side and guards of modes with contacts: the same numbers as the
index path of the mode system and as the events' values, at random states of sliding
(one and two slip components) and sticking modes."""

import math
from pathlib import Path

import numpy as np
import pytest

from nonideal import gallery
from nonideal.modeling.modelfile import load_model
from nonideal.modes.motion import Motion
from nonideal.modes.types import SLIDE, STICK, ContactState, Mode
from nonideal.numeric import contact_integrator, contact_system, native
from nonideal.simulation import guards as py_guards
from nonideal.simulation import hybrid
from nonideal.simulation.hybrid import Simulation
from nonideal.simulation.rhs import saddle_point_rhs

from tests.helpers import PACKAGE_ROOT
from tests.systems import rough_rattleback

pytest.importorskip("numba")

SPHERE = Path(PACKAGE_ROOT) / "benchmarks" / "friction_sphere.toml"


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(native.CACHE_ENV, str(tmp_path / "cache"))


def _setup(model, mode, y, t=0.0):
    sim = Simulation(model, native=True, specialize=False)
    fc = sim.fast_contacts
    assert fc.native
    sim.solver.set_references(mode, Motion(sim.solver, mode, t, y))
    S, contacts = fc._system_arrays(mode)
    for k, c in enumerate(contacts):
        ref = sim.solver.reference.get(c)
        S[13][k] = ref is not None
        if ref is not None:
            S[12][k, :len(ref)] = ref
    return sim, fc, S, contacts


def _states(sim, rng, count=6):
    n = sim.n
    q0, qd0 = sim.initial_state()
    for _ in range(count):
        y = np.concatenate((q0 + rng.uniform(-0.3, 0.3, n), qd0 + rng.uniform(-2, 2, n), np.zeros(5)))
        yield rng.uniform(0, 1), y


def _sphere_modes(model):
    return [Mode(contacts=(("plane", ContactState(SLIDE, (1.0, 0.0))),)),
            Mode(contacts=(("plane", ContactState(STICK)),))]


@pytest.mark.parametrize("which", ["sphere slide", "sphere stick", "incline slide+", "incline slide-",
                                   "incline stick"])
def test_native_right_hand_side_agrees_with_the_index_path(which):
    if which.startswith("sphere"):
        model = load_model(SPHERE)
        mode = _sphere_modes(model)[0 if "slide" in which else 1]
    else:
        model = gallery.load("block-on-incline")
        name = model.contacts[0].name
        cs = ContactState(STICK) if "stick" in which else ContactState(SLIDE, (1.0 if "+" in which else -1.0,))
        mode = Mode(contacts=((name, cs),))
    rng = np.random.default_rng(7)
    sim = Simulation(model, native=True, specialize=False)
    for t, y in _states(sim, rng):
        sim, fc, S, _ = _setup(model, mode, y, t)
        ref = saddle_point_rhs(sim, mode)(t, y)
        got = np.empty_like(y)
        assert fc.native.loop.rhs(fc.native.kernel, S, t, y, got)
        scale = 1 + np.abs(ref).max()
        assert np.allclose(got, ref, rtol=0, atol=1e-12 * scale), (got - ref)


def _rattleback_modes(model):
    return [Mode(contacts=(("table", ContactState(SLIDE, (0.6, 0.8))),)),
            Mode(contacts=(("table", ContactState(STICK)),))]


@pytest.mark.parametrize("body", ["sphere", "rattleback"])
def test_native_guards_agree_with_the_events(body, tmp_path):
    """Also where the LU of the saddle-point system interchanges rows (the rattleback): the
    effective normal compliance (the Jam guard) read from the factors was wrong there (the
    interchanges applied between the eliminations), -0.22 for 1.61."""
    model = load_model(SPHERE) if body == "sphere" else rough_rattleback(tmp_path, 0.2)
    rng = np.random.default_rng(11)
    for mode in (_sphere_modes if body == "sphere" else _rattleback_modes)(model):
        sim = Simulation(model, native=True, specialize=False)
        for t, y in _states(sim, rng, 4):
            sim, fc, S, contacts = _setup(model, mode, y, t)
            motion = Motion(sim.solver, mode, t, y)
            events = sim.events(mode, t, y)
            tols = [sim._tolerance(ev, motion) for ev in events]
            E = fc._event_arrays(mode, events, tols, contacts, [True] * len(events))
            dy = np.empty_like(y)
            assert fc.native.loop.rhs(fc.native.kernel, S, t, y, dy)
            g, scale = np.empty(len(events)), np.empty(len(events))
            fc.native.loop.guards(S, E, g, scale)
            for k, ev in enumerate(events):
                want = ev.value(motion)
                assert math.isclose(g[k], want, rel_tol=1e-11, abs_tol=1e-11 * ev.scale(motion)), ev
                assert math.isclose(scale[k], ev.scale(motion), rel_tol=1e-12), ev
            kinds = {type(ev).__name__ for ev in events}
            assert kinds == ({"Lift", "SlipStop", "Jam"} if mode.contacts[0][1].state == SLIDE
                             else {"Lift", "SlipStart"})


def test_the_native_tests_use_the_hybrid_loops_constants():
    assert contact_integrator.PROBE_NEAR == py_guards.PROBE_NEAR
    assert contact_integrator.SLOPE_STEP == py_guards.SLOPE_STEP
    assert contact_integrator.RATE_STEP == py_guards.RATE_STEP
    assert contact_integrator.RESOLVE == py_guards.RESOLVE
    assert contact_integrator.PROBES == py_guards.PROBES
    assert contact_integrator.NEAR_END == py_guards.NEAR_END
    assert contact_integrator.PROJECTION_TOL == hybrid.PROJECTION_TOL


def test_the_inverse_entries_from_the_lu_factors():
    """(K^-1)_{ii} from the native LU (partial pivoting, whole rows interchanged) equals the
    inverse's diagonal, for matrices whose factorization interchanges rows at several steps."""
    rng = np.random.default_rng(3)
    for s in (3, 5, 9):
        interchanged = 0
        for _ in range(5):
            A = rng.normal(size=(s, s))
            K = A.flatten(order="F")  # column-major, as the saddle-point system
            piv = np.zeros(s, dtype=np.int64)
            assert contact_system._lu(K, np.zeros(s), piv, s)
            interchanged += int(np.sum(piv != np.arange(s)) >= 2)
            want = np.diag(np.linalg.inv(A))
            got = [contact_system._inverse_entry(K, piv, s, i) for i in range(s)]
            assert np.allclose(got, want, rtol=1e-10, atol=1e-12)
        assert interchanged >= 1
