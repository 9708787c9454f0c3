"""Long runs stay in bounded memory, runs that cannot finish are refused within seconds, and
the Python API checks its arguments as the command line does."""

import math
import time

import numpy as np
import pytest

import nonideal
from nonideal.errors import ModelError, SingularSystem
from nonideal.modeling.modelfile import load_model, model_from_dict
from nonideal.simulation import simulate
from nonideal.simulation import budget
from nonideal.simulation.budget import MAX_TIMES, SampleBuffer
from nonideal.simulation.trajectory import Sample
from tests.helpers import DATA_DIR, run_cli


@pytest.fixture(scope="module")
def pendulum():
    return load_model(DATA_DIR / "pendulum_long.toml")


def test_long_run_is_thinned_to_the_sample_limit_and_keeps_its_end(pendulum):
    traj = simulate(pendulum, t_end=500.0, max_samples=200, every_step=True)
    stride = traj.diagnostics["output_stride"]
    assert stride > 1 and len(traj.t) <= 2 * 200 + 2
    assert traj.t[-1] == 500.0 and np.all(np.diff(traj.t) > 0)
    exact = simulate(pendulum, t_end=500.0, times=[500.0])
    assert traj.q[-1] == pytest.approx(exact.q[-1], abs=1e-12)
    # energy is conserved along the thinned samples too
    assert np.ptp(traj.energy["energy"]) < 1e-6


def test_sample_buffer_keeps_events_and_halves_steps():
    buf = SampleBuffer(limit=4)
    for k in range(20):
        buf.add(("step", k), step=True)
        if k == 5:
            buf.add(("event", k))
    assert ("event", 5) in buf and sum(1 for s in buf if s[0] == "step") <= 4
    assert buf.stride == 8
    steps = [s[1] for s in buf if s[0] == "step"]
    assert steps == sorted(steps) and all(b - a == buf.stride for a, b in zip(steps[1:], steps[2:]))


@pytest.mark.parametrize("limit", [None, 3, 4, 7])
def test_a_block_of_samples_is_kept_as_one_by_one(limit):
    """A native phase's samples given at once (arrays) keep the rows the buffer keeps when
    they come one by one: the stride, the thinning, the events between them."""
    rng = np.random.default_rng(limit or 0)
    one, many = SampleBuffer(limit=limit), SampleBuffer(limit=limit)
    k = 0
    for _ in range(12):
        size = int(rng.integers(0, 9))
        t = np.arange(k, k + size, dtype=float)
        step = bool(rng.integers(0, 4))
        block = budget.Block(t, np.c_[t, -t], t[:, None] * 2.0, "mode")
        for r in range(size):
            one.add(Sample(t[r], block.y[r], "mode"), step)
        many.add_block(block, step)
        k += size
        if rng.integers(0, 3) == 0:  # an event between two phases
            one.add(Sample(k - 0.5, np.zeros(2), "event"))
            many.add(budget.Block(np.array([k - 0.5]), np.zeros((1, 2)), np.zeros((1, 1)), "event"))

    def rows(buf):
        return [float(t) for b in buf for t in np.atleast_1d(b.t)], \
            [tuple(y) for b in buf for y in np.atleast_2d(b.y)]
    assert rows(many) == rows(one)
    assert many.stride == one.stride and many._steps == one._steps
    if limit is not None:
        assert many._steps <= limit


def test_a_run_that_cannot_finish_is_refused(pendulum, monkeypatch):
    monkeypatch.setattr(budget, "MAX_SECONDS", 1e9)  # the count of steps, not the clock
    with pytest.raises(ModelError, match=r"cannot finish.*about 1e\+10 steps"):
        simulate(pendulum)  # t_end = 1e9


STIFF = {"model": {"name": "Stiff spring", "format": 1},
         "parameters": {"m": 1.0, "k": 1e9}, "coordinates": {"q": ["x"]},
         "energy": {"kinetic": "m/2*x'^2", "potential": "k/2*x^2"},
         "initial": {"x": 1.0, "x'": 0.0}, "simulation": {"t_end": 1.0, "method": "Radau"}}


def test_radau_on_a_stiff_spring_finishes_a_short_run_and_refuses_a_long_one_within_seconds():
    model = model_from_dict(STIFF, "stiff.toml")
    w = math.sqrt(1e9)
    period = 2 * math.pi / w
    traj = simulate(model, t_end=period, times=[period / 4, period])  # ~600 Radau steps
    assert traj.q[:, 0] == pytest.approx([0.0, 1.0], abs=1e-7)
    assert traj.qd[0, 0] == pytest.approx(-w, rel=1e-8)
    # to t_end = 1: 5000 periods, 3e6 steps of about 0.5 ms -- refused after PROBE_SECONDS
    start = time.process_time()
    with pytest.raises(ModelError, match=r"cannot finish: after .* s it has reached.*about .* s "
                                         r"\(the limit is 600 s\).*--method DOP853"):
        simulate(model)
    assert time.process_time() - start < 30 * budget.PROBE_SECONDS


def test_too_many_requested_times_are_refused(pendulum):
    with pytest.raises(ModelError, match=f"at most {MAX_TIMES}"):
        simulate(pendulum, times=np.linspace(0, 2, 10 ** 7))


def test_a_vanishing_mass_is_named_as_the_cause():
    with pytest.raises(SingularSystem, match=r"mass matrix becomes singular.*t = 0\.99999"):
        simulate(load_model(DATA_DIR / "vanishing_mass.toml"))


@pytest.mark.parametrize("call, message", [
    (lambda m: simulate(None), "simulate: the model must be a Model"),
    (lambda m: simulate("pend.toml"), "read the file first: simulate(load_model('pend.toml')"),
    (lambda m: simulate(m, t_end=-1), "t_end = -1 is not after t0 = 0"),
    (lambda m: simulate(m, t_end=math.nan), "t_end must be a finite number"),
    (lambda m: simulate(m, times=[]), "times is empty"),
    (lambda m: simulate(m, times="abc"), "times must be a sequence of numbers"),
    (lambda m: simulate(m, t_end=1, rtol=-1), "rtol must be positive"),
    (lambda m: simulate(m, t_end=1, max_step=0), "max_step must be positive"),
    (lambda m: simulate(m, t_end=1, parameters=[1]), "parameters must be a mapping"),
    (lambda m: nonideal.derive(m, None), "derive: form must be one of"),
    (lambda m: nonideal.derive({}, "maggi"), "derive: the model must be a Model"),
    (lambda m: nonideal.evaluate(m, at=[1, 2]), "evaluate: at must be a mapping"),
    (lambda m: model_from_dict("x"), "model_from_dict: data must be a dict"),
])
def test_api_arguments_are_checked(pendulum, call, message):
    with pytest.raises(ModelError) as info:
        call(pendulum)
    assert message in str(info.value)


@pytest.mark.parametrize("velocity", [0.0, 1.0])
def test_a_mass_matrix_that_becomes_singular_at_rest_is_reported_where_it_happens(tmp_path, velocity):
    """(1 - t) x'^2/2 without a potential: from rest x'' = x'/(1 - t) stays 0, so the motion
    does not stall at t = 1 and ran on to t = 2 with exit 0; the mass matrix is watched at
    every step and the run ends with exit 2 at t = 1 (to the 1e-6 of its size at which it
    counts as singular)."""
    text = (DATA_DIR / "vanishing_mass.toml").read_text()
    text = text.replace('potential = "k*x^2/2"', 'potential = "0"').replace('"x\'" = 0.0', f'"x\'" = {velocity}')
    path = tmp_path / "vanishing_mass_at_rest.toml"
    path.write_text(text)
    with pytest.raises(SingularSystem) as info:
        simulate(load_model(path))
    assert info.value.exit_code == 2
    message = str(info.value)
    assert "the mass matrix becomes singular along the motion at t = 0.99999" in message
    proc = run_cli("simulate", path)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
