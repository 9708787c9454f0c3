"""The C DOP853 loop against SciPy's DOP853 (same tableau, step control and dense output)."""

import math

import numpy as np
import pytest
from scipy.integrate import DOP853

from nonideal.numeric import cloop

pytestmark = pytest.mark.skipif(cloop.compiler() is None, reason="no C compiler")

# a pendulum with a damper and a drive: y = [phi, phi'], phi'' = -sin(phi) - 0.1 phi' + cos(t)
RHS = r"""
#include <math.h>
static int nonideal_rhs(double t, const double *y, double *dy)
{
    dy[0] = y[1];
    dy[1] = -sin(y[0]) - 0.1 * y[1] + cos(t);
    return !(isfinite(dy[1]));
}
"""


def f(t, y):
    return np.array([y[1], -math.sin(y[0]) - 0.1 * y[1] + math.cos(t)])


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    path = cloop.build(cloop.source(RHS), str(tmp_path_factory.mktemp("cloop")))
    assert path is not None
    return cloop.Loop(path, 2)


def numba_phase(t_end, rtol, atol, h0, times=()):
    """The numba loop of the normal path on the same system, entered as a one-coordinate mode
    (x = [t, q, q'], z = [M = 1, F])."""
    numba = pytest.importorskip("numba")
    from nonideal.numeric import integrator

    @numba.cfunc(numba.types.void(numba.types.CPointer(numba.types.float64),
                                  numba.types.CPointer(numba.types.float64)))
    def kern(xp, zp):
        x = numba.carray(xp, 3)
        z = numba.carray(zp, 2)
        z[0] = 1.0
        z[1] = -math.sin(x[1]) - 0.1 * x[2] + math.cos(x[0])

    ix = np.array([1, 0, -1, 0, 1, 3, 2, 0, 0, 1], dtype=np.int64)
    w = np.zeros(7)
    y0 = np.array([1.0, 0.0])
    return integrator.phase(kern, 0.0, y0, f(0.0, y0), h0, t_end, rtol, np.full(2, atol),
                            np.inf, w, ix, np.asarray(times, float), 0, 10 ** 9, 0.0)


def start(rtol, atol):
    return DOP853(f, 0.0, np.array([1.0, 0.0]), 20.0, rtol=rtol, atol=atol).h_abs


def test_every_step_is_the_numba_loop_bit_for_bit(loop):
    rtol, atol = 1e-10, 1e-12
    h0 = start(rtol, atol)
    status, t, y, fy, h, Tc, Yc, DYc, steps = loop.phase(
        0.0, [1.0, 0.0], list(f(0.0, [1.0, 0.0])), h0, 20.0, rtol, [atol, atol])
    assert status == 0 and t == 20.0 and steps == len(Tc) > 50
    ref = numba_phase(20.0, rtol, atol, h0)
    assert ref[0] == 0 and ref[10] == steps and ref[4] == h
    assert list(ref[5]) == Tc
    assert ref[6].tolist() == Yc and ref[7].tolist() == DYc


def test_every_step_agrees_with_scipy_to_the_tolerance(loop):
    # SciPy sums the stages with np.dot (another order of the same sums): its error estimate,
    # a difference of nearly equal stages, differs in the last digits, so the step sizes
    # drift apart and the states agree to the tolerance, not to rounding
    rtol, atol = 1e-10, 1e-12
    s = DOP853(f, 0.0, np.array([1.0, 0.0]), 20.0, rtol=rtol, atol=atol)
    out = loop.phase(0.0, [1.0, 0.0], list(f(0.0, [1.0, 0.0])), s.h_abs, 20.0, rtol,
                     [atol, atol])
    while s.status == "running":
        s.step()
    assert out[8] == pytest.approx(81, abs=3)
    assert np.allclose(out[2], s.y, rtol=1e-8, atol=1e-9)


def test_dense_output_at_times_is_the_numba_loop_bit_for_bit(loop):
    rtol, atol = 1e-10, 1e-12
    h0 = start(rtol, atol)
    times = list(np.linspace(0.0, 20.0, 401))
    out = loop.phase(0.0, [1.0, 0.0], list(f(0.0, [1.0, 0.0])), h0, 20.0, rtol,
                     [atol, atol], times=times, cap=7)  # small buffers: resumed many times
    assert out[0] == 0 and out[5] == times
    full = loop.phase(0.0, [1.0, 0.0], list(f(0.0, [1.0, 0.0])), h0, 20.0, rtol,
                      [atol, atol], times=times, cap=100000)
    assert full[6] == out[6] and full[8] == out[8]  # resuming changes no bit
    ref = numba_phase(20.0, rtol, atol, h0, times)
    assert ref[6].tolist() == out[6] and ref[7].tolist() == out[7]


def test_status_singular_and_max_steps(loop, tmp_path):
    bad = RHS.replace("return !(isfinite(dy[1]));", "return t > 1.0;")
    lp = cloop.Loop(cloop.build(cloop.source(bad), str(tmp_path)), 2)
    out = lp.phase(0.0, [1.0, 0.0], [0.0, -math.sin(1.0) + 1.0], 1e-3, 5.0, 1e-10, [1e-12] * 2)
    assert out[0] == 3 and out[1] <= 1.0
    out = loop.phase(0.0, [1.0, 0.0], [0.0, -math.sin(1.0) + 1.0], 1e-3, 5.0, 1e-10,
                     [1e-12] * 2, max_steps=10)
    assert out[0] == 1 and out[8] == 10 and len(out[5]) == 10


def test_no_compiler_means_no_library(tmp_path, monkeypatch):
    monkeypatch.setenv("CC", "")
    monkeypatch.setenv("PATH", str(tmp_path))
    assert cloop.compiler() is None
    assert cloop.build(cloop.source(RHS), str(tmp_path / "x")) is None


def test_library_reused_by_source_hash(tmp_path):
    a = cloop.build(cloop.source(RHS), str(tmp_path))
    b = cloop.build(cloop.source(RHS), str(tmp_path))
    c = cloop.build(cloop.source(RHS.replace("0.1 *", "0.2 *")), str(tmp_path))
    assert a == b != c
