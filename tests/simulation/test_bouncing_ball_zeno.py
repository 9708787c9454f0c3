"""Impacts that repeat: a ball bouncing on a floor (restitution 0 < e < 1) and a block bouncing
off a wall on a rough incline, against the closed form of their geometric series of impacts
(the accumulation -- Zeno -- time run through, the state after it at rest)."""

import math
import tomllib

import numpy as np
import pytest

from nonideal.modeling.modelfile import load_model, model_from_dict
from nonideal.simulation import simulate
from nonideal.simulation.zeno import ImpactSeries
from tests.helpers import DATA_DIR, cli_json

G = 9.81


def ball(path, e):
    """The model file with restitution *e*."""
    text = (DATA_DIR / path).read_text().replace("e = 0.5", f"e = {e}")
    return model_from_dict(tomllib.loads(text), str(path))


def closed_form_impacts(e, count, h0=1.0):
    t1 = math.sqrt(2 * h0 / G)
    v1 = G * t1
    return [t1 + 2 * v1 / G * sum(e ** j for j in range(1, k + 1)) for k in range(count)], \
        t1 + 2 * v1 * e / (G * (1 - e))


@pytest.mark.parametrize("path", ["bouncing_ball.toml", "bouncing_ball_unilateral.toml"])
@pytest.mark.parametrize("e", [0.3, 0.5, 0.9])
def test_impact_times_and_accumulation_against_the_geometric_series(path, e):
    traj = simulate(ball(path, e), t_end=12.0)
    impacts = [ev for ev in traj.events if ev["type"] in ("touch", "contact")]  # contact, constraint
    zeno = traj.events[-1]
    assert zeno["type"] == "zeno" and zeno["impacts"] == len(impacts)
    closed, t_inf = closed_form_impacts(e, len(impacts))
    assert np.max(np.abs(np.array([ev["t"] for ev in impacts]) - closed)) < 1e-11
    assert zeno["t"] == pytest.approx(t_inf, abs=1e-11)
    assert zeno["ratio"] == pytest.approx(e, rel=1e-9)
    # at rest on the floor after the accumulation, all the energy m g h0 lost in the impacts
    assert abs(traj.q[-1, 1]) < 1e-12 and abs(traj.qd[-1, 1]) < 1e-12
    assert traj.t[-1] == 12.0
    assert traj.energy["impact_work"][-1] == pytest.approx(-G, rel=1e-10)
    assert abs(traj.energy["balance"][-1]) < 1e-9


def test_block_bouncing_off_a_wall_on_a_rough_incline_accumulates_at_the_closed_form():
    model = load_model(DATA_DIR / "incline_wall_bounces.toml")
    traj = simulate(model)
    g, alpha, mu, e, d = 9.81, 0.5, 0.2, 0.5, 1.0
    a_down, a_up = g * (math.sin(alpha) - mu * math.cos(alpha)), g * (math.sin(alpha) + mu * math.cos(alpha))
    t1 = math.sqrt(2 * d / a_down)
    r = e * math.sqrt(a_down / a_up)
    t_inf = t1 + e * a_down * t1 * (1 / a_up + 1 / math.sqrt(a_up * a_down)) / (1 - r)
    zeno = [ev for ev in traj.events if ev["type"] == "zeno"]
    assert len(zeno) == 1 and zeno[0]["contact"] == "wall"
    assert zeno[0]["t"] == pytest.approx(t_inf, abs=1e-10)
    assert zeno[0]["ratio"] == pytest.approx(r, rel=1e-8)
    # between the impacts the block slides up, reverses and slides back: every impact but the
    # first is preceded by a reversal of the incline's slip
    kinds = [ev["type"] for ev in traj.events if ev["t"] < zeno[0]["t"]]
    assert kinds.count("reverse") == kinds.count("touch") - 1
    # afterwards it rests against the wall (tan(alpha) > mu_s: only the wall holds it)
    assert traj.modes[-1] == "plane:stick, wall:smooth"
    assert abs(traj.q[-1, 0]) < 1e-12 and np.max(np.abs(traj.qd[-1])) < 1e-12


def test_a_series_that_is_not_geometric_is_not_cut_short():
    series = ImpactSeries()
    times = [1.0, 2.0, 2.5, 2.8, 2.9, 2.95]  # ratios 0.5, 0.6, 0.33, 0.5: not constant
    assert all(series.add("floor", "m", t, np.zeros(1), np.zeros(1)) is None for t in times)
    series.reset()
    dt = 0.5 ** np.arange(40)
    found = [series.add("floor", "m", t, np.array([t]), np.array([-t])) for t in np.cumsum(dt)]
    limit = next(f for f in found if f is not None)
    assert limit.t == pytest.approx(2.0, rel=1e-14) and limit.ratio == pytest.approx(0.5)
    # another constraint's impact starts a new series
    assert series.add("wall", "m", 10.0, np.zeros(1), np.zeros(1)) is None and series.count == 1


def test_cli_reports_the_accumulation():
    out = cli_json("simulate", DATA_DIR / "bouncing_ball.toml", "--json", "--times", "0,1,2,3")
    zeno = out["events"][-1]
    assert zeno["type"] == "zeno" and zeno["contact"] == "floor"
    assert zeno["t"] == pytest.approx(closed_form_impacts(0.5, 1)[1], abs=1e-11)
    assert out["t"] == [0.0, 1.0, 2.0, 3.0]
    assert out["q"]["y"][2:] == pytest.approx([0.0, 0.0], abs=1e-12)
