"""The C right-hand side of a mode against the numba one of the normal path."""

import numpy as np
import pytest

from nonideal.gallery.nlink_pendulum import build as pendulum
from nonideal.modeling.modelfile import load_model
from nonideal.numeric import cloop, cmode, native
from nonideal.simulation.hybrid import Simulation

from tests.helpers import DATA_DIR

pytestmark = pytest.mark.skipif(cloop.compiler() is None, reason="no C compiler")
numba = pytest.importorskip("numba")


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(native.CACHE_ENV, str(tmp_path / "cache"))
    monkeypatch.setattr(native, "_LOADED", {})


@pytest.mark.parametrize("make, track", [
    (lambda: pendulum(3, q0=0.4), False), (lambda: pendulum(4, q0=0.3), True),
    (lambda: load_model(DATA_DIR / "pendulum_xy.toml"), True)],
    ids=["3-link", "4-link with work", "pendulum in x, y (a constraint row)"])
def test_the_c_right_hand_side_is_the_numba_one(make, track, tmp_path):
    from nonideal.modes.switching import select_mode

    sim = Simulation(make(), native=True)
    q0, qd0 = sim.initial_state(None)
    mode = select_mode(sim.solver, 0.0, q0, qd0)
    system = sim.solver.system(mode)
    if system.m:
        system.dependent(np.array([[1.2, -1.6]]))
    nat = native.native_of(sim.kernel)
    w, ix = nat.buffers(system, sim.params, track)
    lib = cloop.Loop(cloop.build(cloop.source(cmode.rhs_source(sim.kernel, w, ix)),
                                 str(tmp_path / "c")), len(q0) * 2 + (5 if track else 0))
    rng = np.random.default_rng(5)
    n = len(q0)
    size = 2 * n + (5 if track else 0)
    for _ in range(5):
        y = np.zeros(size)
        y[:n] = q0 + rng.uniform(-0.2, 0.2, n)
        y[n:2 * n] = qd0 + rng.uniform(-1, 1, n)
        if system.m:  # an admissible velocity of the pendulum in x, y: along the circle
            y[n:2 * n] = rng.uniform(-1, 1) * np.array([-y[1], y[0]])
        want = np.empty(size)
        assert nat.rhs(0.3, y, w.copy(), ix, want)
        got = lib.rhs(0.3, list(y))
        assert got is not None
        assert got == want.tolist()  # the same operations in the same order: bit for bit


def test_a_c_phase_of_the_5_link_pendulum_is_the_native_phase_bit_for_bit(tmp_path):
    from nonideal.modes.switching import select_mode

    sim = Simulation(pendulum(5, q0=0.5), native=True)
    q0, qd0 = sim.initial_state(None)
    system = sim.solver.system(select_mode(sim.solver, 0.0, q0, qd0))
    nat = native.native_of(sim.kernel)
    w, ix = nat.buffers(system, sim.params, False)
    ny = 2 * len(q0)
    lib = cloop.Loop(cloop.build(cloop.source(cmode.rhs_source(sim.kernel, w, ix)),
                                 str(tmp_path / "c")), ny)
    y0 = np.concatenate((q0, qd0))
    f0 = np.array(lib.rhs(0.0, list(y0)))
    atol = np.full(ny, 1e-12)
    times = np.linspace(0.0, 3.0, 61)
    got = lib.phase(0.0, list(y0), list(f0), 1e-3, 3.0, 1e-10, list(atol), times=list(times))
    ref = nat.integrator.phase(nat.kernel, 0.0, y0, f0, 1e-3, 3.0, 1e-10, atol, np.inf, w.copy(),
                               ix, times, 0, 10 ** 9, 0.0)
    assert got[0] == ref[0] == 0 and got[8] == ref[10] > 50
    assert got[6] == ref[6].tolist() and got[7] == ref[7].tolist()
