"""The default output: a uniform grid of times with each event's state before and after its
switch (memory and file size bounded by the grid, not by the run's steps); every step on
request (``every_step=True``, ``--every-step``)."""

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.errors import ModelError
from nonideal.modeling.modelfile import model_from_dict
from nonideal.simulation.budget import GRID
from tests.helpers import run_cli
from nonideal.gallery.nlink_pendulum import build as pendulum
from tests.systems import sphere_on_plane


def _split(traj):
    """The grid samples (times of no event) and, per event time, the samples at it."""
    events = sorted({float(e["t"]) for e in traj.events})
    at_event = np.isin(traj.t, events)
    return at_event, events


@pytest.mark.parametrize("name, t_end", [("bouncing-ball", 2.0), ("block-on-incline", None),
                                          ("painleve-rod", None)])
def test_the_default_output_is_the_grid_and_each_events_states(name, t_end):
    # (mode systems compiled after a number of calls would change the last digits between runs)
    model, exact = gallery.load(name), dict(specialize=False)
    traj = simulate(model, t_end=t_end, **exact)
    end = traj.t[-1]
    grid = np.linspace(model.t0, end, GRID)
    at_event, events = _split(traj)
    assert events, "a model without events tests nothing here"
    assert np.array_equal(traj.t[~at_event], grid[~np.isin(grid, events)])
    assert np.all(np.diff(traj.t) >= 0)
    assert "uniform grid of 1001" in traj.diagnostics["output"]
    # the grid's samples are the dense output of the same run: the run on the same requested
    # times gives them bit for bit
    asked = simulate(model, t_end=t_end, times=grid, **exact)
    keep = ~np.isin(grid, events)
    assert np.array_equal(traj.q[~at_event], asked.q[keep])
    assert np.array_equal(traj.qd[~at_event], asked.qd[keep])
    # each event's states, before and after the switch, are those of the run on every step
    steps = simulate(model, t_end=t_end, every_step=True, **exact)
    assert [e["t"] for e in steps.events] == [e["t"] for e in traj.events]
    for te in events:
        mine, theirs = traj.t == te, steps.t == te
        assert mine.sum() == theirs.sum() >= 1
        assert np.array_equal(traj.q[mine], steps.q[theirs])
        assert np.array_equal(traj.qd[mine], steps.qd[theirs])
    switches = [e for e in traj.events if e["type"] not in ("zeno",)]
    assert sum((traj.t == e["t"]).sum() == 2 for e in switches) >= len(switches) - 1


def test_a_long_native_run_is_bounded_by_the_grid():
    # 300 s of a pendulum: thousands of steps (native, in compiled code), 1001 samples
    model = pendulum(1, q0=0.5)
    traj = simulate(model, t_end=300.0)
    assert len(traj.t) == GRID and np.array_equal(traj.t, np.linspace(0.0, 300.0, GRID))
    asked = simulate(model, t_end=300.0, times=np.linspace(0.0, 300.0, GRID))
    assert np.array_equal(traj.q, asked.q) and np.array_equal(traj.qdd, asked.qdd)
    steps = simulate(model, t_end=300.0, every_step=True)
    assert len(steps.t) > 2000 and steps.diagnostics["output"] == "every step"
    assert traj.q[-1] == pytest.approx(steps.q[-1], abs=1e-12)


def test_a_grid_of_n_times_and_a_stop_at_an_event():
    model = sphere_on_plane(pull=0.0, spin=(3.0, 0.0))   # slides, then rolls: one event
    traj = simulate(model, grid=11)
    at_event, events = _split(traj)
    assert len(events) == 1 and (traj.t == events[0]).sum() == 2
    assert np.array_equal(traj.t[~at_event], np.linspace(0.0, 0.1, 11))
    stopped = simulate(model, grid=11, stop_on={"stick"})
    assert stopped.t[-1] == events[0] and (stopped.t == events[0]).sum() == 1
    assert np.array_equal(stopped.t[:-1], np.linspace(0.0, 0.1, 11)[np.linspace(0.0, 0.1, 11) < events[0]])


def test_the_model_file_chooses_the_output():
    def model(**simulation):
        return model_from_dict({
            "model": {"name": "fall"}, "parameters": {"g": 9.81}, "coordinates": {"q": ["x"]},
            "energy": {"kinetic": "x'^2/2", "potential": "g*x"}, "initial": {"x": 1.0, "x'": 0.0},
            "simulation": {"t_end": 0.4, **simulation}}, "fall.toml")
    assert simulate(model(grid=5)).t.tolist() == [0.0, 0.1, 0.2, 0.30000000000000004, 0.4]
    steps = simulate(model(every_step=True))
    assert steps.diagnostics["output"] == "every step" and len(steps.t) != 5
    assert len(simulate(model(every_step=True), grid=3).t) == 3   # the call's choice wins
    for bad, message in (({"grid": 1}, "grid: must be an integer from 2"), ({"grid": 2.5}, "grid"),
                         ({"every_step": "yes"}, "every_step: must be true")):
        with pytest.raises(ModelError, match=message):
            model(**bad)


@pytest.mark.parametrize("options, message", [
    ({"grid": 1}, "grid must be an integer >= 2"), ({"grid": True}, "grid must be"),
    ({"grid": 10 ** 7}, "at most"), ({"every_step": 1.0}, "every_step must be"),
    ({"grid": 5, "every_step": True}, "choose one output")])
def test_the_api_checks_the_output_options(options, message):
    with pytest.raises(ModelError, match=message):
        simulate(gallery.load("bouncing-ball"), **options)


def test_a_simulation_object_checks_its_grid():
    from nonideal.simulation.hybrid import Simulation

    with pytest.raises(ModelError, match="grid: must be an integer from 2"):
        Simulation(gallery.load("bouncing-ball"), grid=1).run(t_end=0.1)


def test_the_command_line_chooses_the_output(tmp_path):
    out = tmp_path / "o.json"
    done = run_cli("simulate", "bouncing-ball", "--t-end", "0.4", "--grid", "5", "--json", str(out))
    assert done.returncode == 0, done.stderr
    import json

    data = json.loads(out.read_text())
    assert data["t"] == [0.0, 0.1, 0.2, 0.30000000000000004, 0.4] and "grid of 5" in data["diagnostics"]["output"]
    for argv, message in ((["--grid", "3", "--every-step"], "choose one output"),
                          (["--times", "0,1", "--grid", "3"], "choose one output"),
                          (["--grid", "1"], "--grid: must be an integer >= 2")):
        done = run_cli("simulate", "bouncing-ball", *argv, "--json", str(tmp_path / "x.json"))
        assert done.returncode == 2 and message in done.stderr
        assert not (tmp_path / "x.json").exists()


def test_grid_samples_of_a_native_run_are_solved_natively_as_in_python(monkeypatch):
    """The grid's samples of a run that went native are solved in one native call per mode;
    their accelerations, multipliers and contact records are the Python evaluation's."""
    pytest.importorskip("numba")
    from nonideal.simulation.fast_contacts import FastContacts
    from nonideal.simulation.hybrid import Simulation

    model = sphere_on_plane(pull=0.3, spin=(3.0, 1.0))   # oblique slide, then roll
    calls = []
    original = FastContacts.sample_motions
    monkeypatch.setattr(FastContacts, "sample_motions",
                        lambda self, *a: calls.append(original(self, *a)) or calls[-1])
    got = Simulation(model, native=True, specialize=False).run()
    assert calls and all(c is not None for c in calls) and sum(int(c.ok.sum()) for c in calls) >= 1000
    monkeypatch.setattr(FastContacts, "sample_motions", lambda self, *a: None)
    ref = Simulation(model, native=True, specialize=False).run()
    assert np.array_equal(got.t, ref.t) and np.array_equal(got.q, ref.q)
    assert np.allclose(got.qdd, ref.qdd, rtol=1e-12, atol=1e-12)
    for key, value in ref.contacts["plane"].items():
        if key == "mode":
            assert list(got.contacts["plane"][key]) == list(value)
        else:   # normal, friction, slip, gap, mu_static
            assert np.allclose(got.contacts["plane"][key], value, rtol=1e-12, atol=1e-12), key
    assert [e["type"] for e in got.events] == ["stick"]


@pytest.mark.parametrize("name", ["block-on-incline", "painleve-rod", "coin-slide-roll", "bouncing-ball",
                                  "rattleback", "painleve-conditional-constraint-rough"])
def test_the_columns_of_a_native_batch_are_those_of_each_samples_motion(name, monkeypatch):
    """``SampleBatch.contact_columns`` (one NumPy operation per column for all the samples of a
    mode) reports what ``Motion.contact_record`` reports sample by sample from the same solution:
    normal force, friction (stick: its multipliers; slide: along the slip, 1 or 2 components),
    slip, gap, mu_s -- separated, sticking and sliding contacts of six gallery models, one with
    constraint rows (multipliers)."""
    pytest.importorskip("numba")
    from nonideal.simulation.fast_contacts import FastContacts

    batches = []
    original = FastContacts.sample_motions
    monkeypatch.setattr(FastContacts, "sample_motions",
                        lambda self, *a: batches.append(original(self, *a)) or batches[-1])
    model = gallery.load(name)
    simulate(model, native=True, grid=201, t_end=min(model.simulation.t_end or 1.0, 1.0))
    checked = 0
    for batch in (b for b in batches if b is not None):
        rows = np.flatnonzero(batch.ok)
        for c in range(len(batch.mode.contacts)):
            columns = batch.contact_columns(c, rows)
            for k, r in enumerate(rows):
                motion = batch.motion(r)
                record = motion.contact_record(c)
                for got, want in zip(columns, record[1:]):
                    assert np.allclose(got[k], want, rtol=1e-13, atol=1e-13)
                assert np.allclose(batch.values(rows)[k], motion.values, rtol=1e-13, atol=1e-13)
                checked += 1
    assert checked, f"{name}: no phase went native: nothing compared"
