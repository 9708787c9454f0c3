"""The native kernel and phases (numba): the same numbers as the NumPy/SciPy path, a disk
cache that survives corrupt entries, and generated code that contains only arithmetic."""

import math

import numpy as np
import pytest

from nonideal.gallery.nlink_pendulum import build as pendulum
from nonideal.modeling.modelfile import load_model
from nonideal.numeric import native
from nonideal.numeric.kernel import kernel_of
from nonideal.simulation import fast
from nonideal.simulation.hybrid import Simulation, simulate

from tests.helpers import DATA_DIR

numba = pytest.importorskip("numba")


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    """Every test with its own cache directory."""
    monkeypatch.setenv(native.CACHE_ENV, str(tmp_path / "cache"))
    monkeypatch.setattr(native, "_LOADED", {})
    return tmp_path / "cache"


def _random_inputs(kernel, rng, count=5):
    return [rng.uniform(-2, 2, len(kernel.symbols)) for _ in range(count)]


@pytest.mark.parametrize("model", [lambda: pendulum(3, q0=0.4), lambda: load_model(DATA_DIR / "pendulum_xy.toml"),
                                   lambda: load_model(DATA_DIR / "polar_coordinates.toml")],
                         ids=["3-link pendulum", "pendulum in x, y", "polar coordinates"])
def test_native_kernel_agrees_with_the_compiled_kernel(model):
    kernel = kernel_of(model())
    nat = native.native_of(kernel)
    assert nat is not None
    rng = np.random.default_rng(3)
    for x in _random_inputs(kernel, rng):
        ref = kernel.dynamics.raw(x).copy()
        got = nat.evaluate(x)
        assert np.allclose(got, ref, rtol=1e-13, atol=1e-13 * (1 + np.abs(ref).max()))


def test_a_pendulum_run_natively_matches_the_scipy_path():
    model = pendulum(2, q0=0.5)
    kw = dict(t_end=5.0, rtol=1e-10, atol=1e-12)
    ref = simulate(model, native=False, **kw)
    got = simulate(model, native=True, **kw)
    # the same method and step-size control; at rtol 1e-10 DOP853's error estimate is at the
    # level of the stages' rounding, so the steps differ slightly, the motion does not
    assert abs(len(got.t) - len(ref.t)) <= 0.05 * len(ref.t)
    assert got.t[-1] == ref.t[-1] == 5.0
    assert np.allclose(got.q[-1], ref.q[-1], rtol=0, atol=1e-8)
    assert np.allclose(got.qd[-1], ref.qd[-1], rtol=0, atol=1e-8)
    assert abs(got.energy["energy"] - got.energy["energy"][0]).max() < 1e-8
    # reproducible bit for bit between runs
    again = simulate(model, native=True, **kw)
    assert np.array_equal(again.q, got.q) and np.array_equal(again.t, got.t)


def test_requested_times_come_from_the_native_dense_output():
    model = pendulum(1, q0=0.5)
    times = np.linspace(0.0, 30.0, 61)
    ref = simulate(model, times=times, rtol=1e-10, atol=1e-12, native=False)
    got = simulate(model, times=times, rtol=1e-10, atol=1e-12, native=True)
    assert np.array_equal(got.t, times)
    assert np.allclose(got.q, ref.q, atol=1e-9)
    assert np.allclose(got.qdd, ref.qdd, atol=1e-8)


def test_every_native_step_keeps_the_acceleration_at_its_state():
    """The samples of a native phase carry the loop's own q'' (no solve again): at every
    kept state it is the pendulum's -g/l sin(q)."""
    got = simulate(pendulum(1, q0=0.5), t_end=20.0, rtol=1e-10, atol=1e-12, native=True)
    assert len(got.t) > 100
    assert np.allclose(got.qdd[:, 0], -9.81 * np.sin(got.q[:, 0]), rtol=0, atol=1e-12)


def test_a_phase_tiers_up_after_its_first_steps(monkeypatch):
    """native=None: SciPy's first NATIVE_STEPS steps, then natively -- the same result as
    either path alone (to rounding)."""
    monkeypatch.setattr(fast, "NATIVE_STEPS", 50)
    model = pendulum(1, q0=1.0)
    kw = dict(t_end=50.0, rtol=1e-10, atol=1e-12)
    ref = simulate(model, native=False, **kw)
    sim = Simulation(model, rtol=1e-10, atol=1e-12)
    got = sim.run(t_end=50.0)
    assert sim.fast.native  # loaded by the tier-up
    assert np.array_equal(got.t[:50], ref.t[:50])  # SciPy's steps first
    assert np.allclose(got.q[-1], ref.q[-1], atol=1e-8) and np.allclose(got.qd[-1], ref.qd[-1], atol=1e-8)


def test_works_are_integrated_natively():
    """A force that is not potential: the power integrated with the motion (the state's work
    components) and the energy balance as on the SciPy path."""
    model = load_model(DATA_DIR / "blowup.toml")
    ref = simulate(model, t_end=0.2, native=False)
    got = simulate(model, t_end=0.2, native=True)
    assert np.allclose(got.q[-1], ref.q[-1], rtol=1e-10)
    assert np.allclose(got.energy["active_work"][-1], ref.energy["active_work"][-1], rtol=1e-9)
    assert abs(got.energy["balance"]).max() < 1e-6 * abs(got.energy["active_work"]).max()


def test_the_native_right_hand_side_with_constraint_rows():
    """Rows (the saddle-point LU): the native right-hand side equals the NumPy one."""
    model = load_model(DATA_DIR / "pendulum_xy.toml")
    ref_sim, sim = Simulation(model, native=False), Simulation(model, native=True)
    q0, qd0 = sim.initial_state(None)
    from nonideal.modes.switching import select_mode

    mode = select_mode(sim.solver, 0.0, q0, qd0)
    sim.solver.system(mode).dependent(np.array([[1.2, -1.6]]))  # decided, as the first state does
    f, g = sim.rhs(mode), ref_sim.rhs(mode)
    assert f.__qualname__.startswith("FastPhases")
    y = np.concatenate((q0, qd0 + [0.8, 0.6], np.zeros(5)))
    assert np.allclose(f(0.3, y), g(0.3, y), rtol=1e-13, atol=1e-13)
    # and a whole run with drift projection and energy balance
    a = simulate(model, t_end=2.0, native=True, rtol=1e-10, atol=1e-12)
    b = simulate(model, t_end=2.0, native=False, rtol=1e-10, atol=1e-12)
    assert np.allclose(a.q[-1], b.q[-1], atol=1e-9)


def test_without_numba_the_numpy_path_runs(monkeypatch):
    """The extra absent: native_of answers None and every option keeps the NumPy path,
    bit for bit the same as native=False."""
    monkeypatch.setattr(native, "available", lambda: False)
    model = pendulum(1, q0=0.5)
    ref = simulate(model, t_end=5.0, native=False)
    got = simulate(model, t_end=5.0, native=True)
    assert np.array_equal(got.q, ref.q) and np.array_equal(got.t, ref.t)


def test_the_cache_is_reused_and_a_corrupt_entry_rebuilt(cache):
    model = pendulum(2, q0=0.5)
    kernel = kernel_of(model)
    source = native.module_source(kernel)
    assert native.native_of(kernel) is not None
    files = sorted(cache.glob("nonideal_native_*.py"))
    assert len(files) == 1 and files[0].read_text() == source
    compiled = list((cache / "__pycache__").glob(files[0].stem + ".*"))
    assert compiled  # numba's cache beside it
    # corrupt both: the source truncated, numba's files garbage; a fresh process state
    files[0].write_text(source[:100])
    for f in compiled:
        f.write_bytes(b"garbage")
    native._LOADED.clear()
    again = pendulum(2, q0=0.5)
    nat = native.native_of(kernel_of(again))
    assert nat is not None and files[0].read_text() == source
    x = np.linspace(-1, 1, len(kernel.symbols))
    assert np.allclose(nat.evaluate(x), kernel.dynamics.raw(x), rtol=1e-13, atol=1e-14)


def test_the_option_is_checked():
    from nonideal.errors import ModelError

    with pytest.raises(ModelError, match="native must be True, False or None"):
        simulate(pendulum(1), t_end=1.0, native="yes")


def test_the_cache_location(monkeypatch, tmp_path):
    monkeypatch.delenv(native.CACHE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert native.cache_dir() == tmp_path / "xdg" / "nonideal"
    monkeypatch.setenv(native.CACHE_ENV, str(tmp_path / "mine"))
    assert native.cache_dir() == tmp_path / "mine"


@pytest.mark.parametrize("text", ["__import__('os')", "x0.real", "open('f')", "[a0]", "a0 if a1 else a2",
                                  "lambda: 1", "'text'", "eval('1')"])
def test_generated_code_admits_only_arithmetic(text):
    with pytest.raises(native.NotNative):
        native._checked(text, {"a0", "a1", "a2", "x0"})


def test_checked_expressions_keep_their_meaning():
    out = native._checked("(1/3)*a0**2 + sqrt(a1) + abs(a0) + atan2(a0, a1) + pi + sign(a1)", {"a0", "a1"})
    value = eval(out, {"math": math, "_sign": lambda v: math.copysign(1.0, v) if v else 0.0},  # noqa: S307
                 {"a0": -0.5, "a1": 2.0})
    assert value == pytest.approx((1 / 3) * 0.25 + math.sqrt(2) + 0.5 + math.atan2(-0.5, 2) + math.pi + 1)


def test_a_signal_during_native_code_takes_effect_after_it():
    import os
    import signal

    done = []
    with pytest.raises(KeyboardInterrupt):
        with fast.deferred_signals():
            os.kill(os.getpid(), signal.SIGINT)
            done.append(True)  # not interrupted inside
    assert done == [True]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


needs_cc = pytest.mark.skipif(__import__("nonideal.numeric.cloop", fromlist=["compiler"]).compiler() is None,
                              reason="no C compiler")


@needs_cc
@pytest.mark.parametrize("make, times", [
    (lambda: pendulum(3, q0=0.4), None), (lambda: pendulum(3, q0=0.4), np.linspace(0, 4, 41)),
    (lambda: __import__("nonideal").gallery.load("heavy-symmetric-top"), None)],
    ids=["3-link, every step", "3-link, 41 times", "heavy symmetric top"])
def test_a_phase_in_c_is_the_numba_phase_bit_for_bit(make, times, monkeypatch):
    """The phase loop compiled in C with the mode's right-hand side (taken when a C compiler is
    found) gives the numba loop's trajectory exactly: states, accelerations, multipliers,
    energies; the C loop is really used."""
    from nonideal.numeric import cloop

    model = make()
    kw = dict(t_end=4.0, times=times, rtol=1e-10, atol=1e-12, native=True)
    monkeypatch.setenv(fast.C_LOOP_ENV, "0")
    ref = simulate(model, **kw)
    monkeypatch.delenv(fast.C_LOOP_ENV)
    calls = []
    original = cloop.Loop.phase_arrays
    monkeypatch.setattr(cloop.Loop, "phase_arrays", lambda self, *a: calls.append(1) or original(self, *a))
    got = simulate(model, **kw)
    assert calls
    assert len(got.t) > 40 and np.array_equal(got.t, ref.t)
    for name in ("q", "qd", "qdd"):
        assert np.array_equal(getattr(got, name), getattr(ref, name))
    for name in ref.multipliers:
        assert np.array_equal(got.multipliers[name], ref.multipliers[name])
    assert np.array_equal(got.energy["energy"], ref.energy["energy"])


@needs_cc
def test_a_c_right_hand_side_that_differs_from_numba_is_not_used(cache, monkeypatch):
    """The generated C is trusted only where its right-hand side is numba's bit for bit: a
    wrong one (here: gravity doubled) leaves the phase to the numba loop, with its results."""
    from nonideal.numeric import cmode

    model = pendulum(1, q0=0.5)
    kw = dict(t_end=3.0, rtol=1e-10, atol=1e-12, native=True)
    monkeypatch.setenv(fast.C_LOOP_ENV, "0")
    ref = simulate(model, **kw)
    monkeypatch.delenv(fast.C_LOOP_ENV)
    original = cmode.rhs_source
    monkeypatch.setattr(cmode, "rhs_source", lambda *a: original(*a).replace(
        "nonideal_kernel(x, z);", "nonideal_kernel(x, z); z[NZ - 1] *= 2.0;"))
    sim = Simulation(model, native=True, rtol=1e-10, atol=1e-12)
    got = sim.run(t_end=3.0)
    assert np.array_equal(got.q, ref.q)
    assert all(entry is None or entry[0] is None for key, entry in model._derived.items()
               if isinstance(key, tuple) and key[0] == "c loop")
    assert not list(cache.glob("c/*.agrees")), "a disagreeing library recorded as agreeing"


@needs_cc
def test_the_agreement_of_a_c_library_is_recorded_once(cache, monkeypatch):
    """The C right-hand side is compared with numba's once per library (at a fixed generic
    state, so the outcome does not depend on the run); a later process (here: the same model
    built afresh, the loaded modules forgotten) finds the record and neither compares again
    nor loads the numba module (by default, ``native=None``, nothing else needs it); the
    trajectory is the same bit for bit."""
    from nonideal.numeric import cloop

    kw = dict(t_end=60.0, rtol=1e-10, atol=1e-12)
    first = simulate(pendulum(2, q0=0.5), **kw)
    assert len(list(cache.glob("c/*.agrees"))) == 1
    monkeypatch.setattr(native, "_LOADED", {})
    model = pendulum(2, q0=0.5)
    native_rhs = []
    original = native.Native.__init__

    def spying(self, *a):
        original(self, *a)
        rhs = self.rhs
        self.rhs = lambda *b: native_rhs.append(1) or rhs(*b)
    monkeypatch.setattr(native.Native, "__init__", spying)
    calls = []
    phase = cloop.Loop.phase_arrays
    monkeypatch.setattr(cloop.Loop, "phase_arrays", lambda self, *a: calls.append(1) or phase(self, *a))
    second = simulate(model, **kw)
    assert calls and native_rhs == []
    assert native._LOADED == {}  # the numba module not even loaded: the C library suffices
    assert np.array_equal(first.q, second.q) and np.array_equal(first.qdd, second.qdd)
