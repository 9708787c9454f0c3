"""Parameter sweeps (nonideal.analysis.studies.sweep): the grid, the rows against closed forms and
against single runs, failing points, derived parameters, resumed sweeps, parallel workers and
a Dask LocalCluster giving the same rows."""

import math

import numpy as np
import pytest

from nonideal import gallery
from nonideal.analysis.studies.sweep import (Axis, PointRunner, SweepTask, flatten, grid, parse_vary,
                                     point_key, sweep)
from nonideal.errors import ModelError
from nonideal.gallery.block_on_incline import closed_form
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate

BLOCK = gallery.model_path("block-on-incline")


def test_parse_vary_ranges_and_lists():
    assert parse_vary("mu=0:1:5").values == (0.0, 0.25, 0.5, 0.75, 1.0)
    assert parse_vary("mu = 0.3:0.9:1").values == (0.3,)
    assert parse_vary("theta=0.1,-0.2,3e-1").values == (0.1, -0.2, 0.3)
    for bad, words in (("mu", "NAME=START:STOP:N"), ("mu=0:1", "three parts"),
                       ("mu=0:1:x", "whole number"), ("mu=0:1:0", "at least 1"),
                       ("mu=a,b", "'a' is not a number"), ("2mu=1,2", "not a parameter name"),
                       ("mu=0:inf:3", "finite")):
        with pytest.raises(ModelError, match=words):
            parse_vary(bad)


def test_grid_is_the_product_first_axis_slowest():
    points = grid([Axis("a", (1.0, 2.0)), Axis("b", (10.0, 20.0, 30.0))])
    assert points == [{"a": a, "b": b} for a in (1.0, 2.0) for b in (10.0, 20.0, 30.0)]
    with pytest.raises(ModelError, match="given 2 times"):
        grid([Axis("a", (1.0,)), Axis("a", (2.0,))])


def test_block_sweep_against_the_closed_form():
    """Sticks iff tan(alpha) <= mu_s; the stop at t1 = v0/(g (sin a + mu cos a)); the heat of
    friction mu N times the path -- at every point of a 3 x 2 grid."""
    axes = [parse_vary("alpha=0.25,0.4,0.55"), parse_vary("mu_s=0.3,0.5")]
    result = sweep(BLOCK, axes, "simulate", workers=1)
    base = gallery.load("block-on-incline").parameter_values
    assert len(result.rows) == 6 and not result.failed
    for row in result.rows:
        p = {**base, **row["parameters"]}
        cf = closed_form(p)
        s = row["summary"]
        (event,) = s["events"]
        assert event["type"] == ("stick" if math.tan(p["alpha"]) <= p["mu_s"] else "reverse")
        assert event["t"] == pytest.approx(cf["t1"], rel=1e-9)
        t_end = s["t_end"]
        path = cf["d"] if cf["sticks"] else 2 * cf["d"] - s["q"]["x"]
        assert s["friction_heat"] == pytest.approx(p["mu"] * cf["N"] * path, rel=1e-8)
        if cf["sticks"]:
            assert s["q"]["x"] == pytest.approx(cf["d"], rel=1e-9)
        else:
            x_end = cf["d"] - cf["a_down"] * (t_end - cf["t1"]) ** 2 / 2
            assert s["q"]["x"] == pytest.approx(x_end, rel=1e-8)


def test_points_equal_single_runs_of_the_rebuilt_model():
    """The compiled model with the point's numbers gives what the model file with --set gives."""
    result = sweep(BLOCK, [parse_vary("mu=0.1,0.35")], "simulate", workers=1)
    for row in result.rows:
        model = load_model(BLOCK, parameters={"mu": row["parameters"]["mu"]})
        traj = simulate(model)
        assert row["summary"]["q"]["x"] == pytest.approx(traj.q[-1, 0], rel=1e-12, abs=1e-14)
        assert row["summary"]["friction_heat"] == pytest.approx(
            -traj.energy["friction_work"][-1], rel=1e-10)


MODEL = """
[model]
name = "dropped on an incline from a height"
format = 1
[parameters]
m = 1.0
g = 9.81
alpha = 0.4
mu = 0.3
h = 0.2
v0 = "sqrt(2*g*h)"
T = 0.5
[coordinates]
q = ["x", "y"]
[energy]
kinetic = "m/2*(x'^2 + y'^2)"
potential = "m*g*(x*sin(alpha) + y*cos(alpha))"
[[contacts]]
name = "plane"
gap = "y"
slip = ["x'"]
mu = "mu"
[initial]
x = 0.0
y = 0.0
"x'" = "v0"
"y'" = 0.0
[simulation]
t_end = "T"
"""


def test_derived_parameters_and_rebuilt_models(tmp_path):
    """A derived parameter follows the varied one (v0 = sqrt(2 g h)); a parameter that sets the
    end time cannot be a number of the equations: its points rebuild the model."""
    path = tmp_path / "drop.toml"
    path.write_text(MODEL)
    runner = PointRunner(SweepTask(str(path), "simulate"))
    assert runner.fast(("h",)) and not runner.fast(("T",))
    result = sweep(str(path), [parse_vary("h=0.05,0.2"), parse_vary("T=0.05,0.1")],
                   "simulate", workers=1)
    g, a, mu = 9.81, 0.4, 0.3
    for row in result.rows:
        h, T = row["parameters"]["h"], row["parameters"]["T"]
        v0 = math.sqrt(2 * g * h)
        dec = g * (math.sin(a) + mu * math.cos(a))
        assert row["summary"]["t_end"] == T
        assert v0 / dec > T   # still sliding up at T
        assert row["summary"]["qdot"]["x"] == pytest.approx(v0 - dec * T, rel=1e-10)


def test_failing_points_are_recorded_and_the_sweep_goes_on():
    result = sweep(BLOCK, [parse_vary("m=-1,2")], "evaluate", workers=1)
    bad, good = result.rows
    assert bad["exit_code"] == 2 and "m" in bad["message"] and bad["summary"] == {}
    assert good["exit_code"] == 0 and good["message"] == "ok"
    p = {**gallery.load("block-on-incline").parameter_values, "m": 2.0}
    assert good["summary"]["qddot"]["x"] == pytest.approx(-closed_form(p)["a_up"], rel=1e-12)
    assert result.failed == [bad]


def test_unknown_parameter_is_reported_before_any_point():
    with pytest.raises(ModelError, match="mu_s") as info:
        sweep(BLOCK, [parse_vary("mus=0.1,0.2"), parse_vary("zzz=1,2")], "simulate")
    assert len(info.value.problems) == 2


def test_resume_runs_only_the_missing_points():
    axes = [parse_vary("alpha=0.3,0.5"), parse_vary("mu_s=0.3,0.5")]
    full = sweep(BLOCK, axes, "simulate", workers=1)
    done = [dict(r, message="from the journal") for r in full.rows[:3]]
    new = []
    resumed = sweep(BLOCK, axes, "simulate", workers=1, done=done, on_row=new.append)
    assert [point_key(r["parameters"]) for r in new] == [point_key(full.rows[3]["parameters"])]
    assert [r["message"] for r in resumed.rows] == ["from the journal"] * 3 + ["ok"]
    assert [r["summary"] for r in resumed.rows] == [r["summary"] for r in full.rows]


def test_local_workers_give_the_rows_of_one_process():
    axes = [parse_vary("alpha=0.25:0.55:4"), parse_vary("mu_s=0.3,0.5")]
    one = sweep(BLOCK, axes, "simulate", workers=1)
    two = sweep(BLOCK, axes, "simulate", workers=2, chunk=1)
    assert two.workers == 2
    assert two.rows == one.rows


def test_flatten_names_the_columns():
    row = {"parameters": {"mu": 0.2}, "exit_code": 0, "message": "ok",
           "summary": {"q": {"x": 1.0}, "qdot": {"x": 2.0}, "friction_heat": 3.0,
                       "events": [{"t": 0.5, "type": "stick"}, {"t": 0.75, "type": "slip"}],
                       "eigenvalues": [[-1.0, 2.0]]}}
    assert flatten(row) == {"mu": 0.2, "exit_code": 0, "message": "ok", "q.x": 1.0,
                            "qdot.x": 2.0, "friction_heat": 3.0, "events": "stick@0.5;slip@0.75",
                            "events.count": 2, "events.first": "stick", "eigenvalues.0.0": -1.0, "eigenvalues.0.1": 2.0}


@pytest.mark.slow
def test_dask_local_cluster_gives_the_local_rows():
    distributed = pytest.importorskip("distributed")
    axes = [parse_vary("alpha=0.25,0.55"), parse_vary("mu_s=0.3,0.5")]
    local = sweep(BLOCK, axes, "simulate", workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = sweep(BLOCK, axes, "simulate", client=client)
            by_address = sweep(BLOCK, axes, "simulate", scheduler=cluster.scheduler_address)
    assert remote.rows == local.rows
    assert by_address.rows == local.rows
