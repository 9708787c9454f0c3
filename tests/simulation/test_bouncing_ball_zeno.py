"""Impacts that repeat: a ball bouncing on a floor (restitution 0 < e < 1) and a block bouncing
off a wall on a rough incline, against the closed form of their geometric series of impacts
(the accumulation -- Zeno -- time run through, the state after it at rest)."""

import math
import tomllib

import numpy as np
import pytest

from nonideal.modeling.modelfile import load_model, model_from_dict
from nonideal.simulation import simulate
from nonideal.simulation.zeno import RESOLVE, ImpactSeries
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
    assert all(series.add("floor", "m", t, np.zeros(1), np.zeros(1), 1e-9, 1.0) is None for t in times)
    series.reset()
    dt = 0.5 ** np.arange(40)
    # flights of speed 1: jumped over once the last one's excursion dt/4 is below RESOLVE tol
    tol = 1e-6
    found = [series.add("floor", "m", t, np.array([t]), np.array([-t]), 1.0, tol) for t in np.cumsum(dt)]
    k = next(i for i, f in enumerate(found) if f is not None)
    assert dt[k] / 4 <= RESOLVE * tol < dt[k - 1] / 4
    limit = found[k]
    assert limit.t == pytest.approx(2.0, rel=1e-14) and limit.ratio == pytest.approx(0.5)
    # another constraint's impacts are another series; between a series' last two impacts
    # they make it wait for its next one
    assert series.add("wall", "m", 10.0, np.zeros(1), np.zeros(1)) is None and series.count == 1
    series.reset()
    t_a, t_b = 1.0 + np.cumsum(dt), 1.3 + np.cumsum(0.25 ** np.arange(40))
    merged = sorted([(t, "a") for t in t_a] + [(t, "b") for t in t_b])
    limits = {}
    for t, name in merged:
        if name not in limits:
            found = series.add(name, "m", t, np.array([t]), np.array([-t]), 1.0, tol)
            if found is not None:
                limits[name] = found
    assert limits["a"].t == pytest.approx(3.0, rel=1e-12)
    assert limits["b"].t == pytest.approx(1.3 + 4 / 3, rel=1e-12)


def test_cli_reports_the_accumulation():
    out = cli_json("simulate", DATA_DIR / "bouncing_ball.toml", "--json", "--times", "0,1,2,3")
    zeno = out["events"][-1]
    assert zeno["type"] == "zeno" and zeno["contact"] == "floor"
    assert zeno["t"] == pytest.approx(closed_form_impacts(0.5, 1)[1], abs=1e-11)
    assert out["t"] == [0.0, 1.0, 2.0, 3.0]
    assert out["q"]["y"][2:] == pytest.approx([0.0, 0.0], abs=1e-12)


def test_a_long_series_is_run_through_while_the_run_resolves_it():
    """e = 0.99: 1400 impacts to the accumulation at 89.85 s; the run bounces on as long as
    the flights rise above the tolerance (about 800 impacts) and never rests a ball that still
    moves: the impact times and the height between impacts against the closed form."""
    e = 0.99
    closed, t_inf = closed_form_impacts(e, 900)
    closed = np.array(closed)
    k = np.array([10, 200, 400, 600, 700])  # midway through these flights
    mid = (closed[k] + closed[k + 1]) / 2
    traj = simulate(ball("bouncing_ball.toml", e), t_end=90.0, times=np.concatenate((mid, [90.0])))
    impacts = np.array([ev["t"] for ev in traj.events if ev["type"] == "touch"])
    zeno = traj.events[-1]
    assert zeno["type"] == "zeno" and zeno["impacts"] == len(impacts) > 700
    assert np.max(np.abs(impacts - closed[:len(impacts)])) < 1e-8
    assert zeno["t"] == pytest.approx(t_inf, abs=1e-8)
    # apex halfway through flight k: v_k^+ (dt/2) - g (dt/2)^2 / 2 = g dt^2 / 8
    dt = closed[k + 1] - closed[k]
    assert traj.q[:len(k), 1] == pytest.approx(G * dt ** 2 / 8, rel=1e-7, abs=1e-12)
    assert abs(traj.q[-1, 1]) < 1e-12 and abs(traj.qd[-1, 1]) < 1e-12


def balls(heights, e=0.5):
    """Independent balls, each on its own floor."""
    n = len(heights)
    return model_from_dict({
        "model": {"name": "Balls on their own floors", "format": 1},
        "parameters": {"m": 1.0, "g": G, "e": e},
        "coordinates": {"q": [f"x{i}" for i in range(n)] + [f"y{i}" for i in range(n)]},
        "energy": {"kinetic": " + ".join(f"m/2*(x{i}'^2 + y{i}'^2)" for i in range(n)),
                   "potential": " + ".join(f"m*g*y{i}" for i in range(n))},
        "contacts": [{"name": f"floor{i}", "gap": f"y{i}", "slip": [f"x{i}'"], "mu": 0,
                      "restitution": "e"} for i in range(n)],
        "initial": {**{f"y{i}": h for i, h in enumerate(heights)},
                    **{f"x{i}": 0.0 for i in range(n)},
                    **{f"{c}{i}'": 0.0 for i in range(n) for c in "xy"}},
        "simulation": {"t_end": 3.5},
    }, "<test>")


@pytest.mark.parametrize("count", [2, 8])
def test_independent_balls_each_accumulate_at_their_own_time(count):
    """Each ball's impacts are a series of their own, accumulating at 3 sqrt(2 h/g) (e = 0.5)
    while the others go on bouncing."""
    heights = [1.0 + 0.37 * i for i in range(count)]
    traj = simulate(balls(heights))
    for i, h in enumerate(heights):
        mine = [ev for ev in traj.events if ev.get("contact") == f"floor{i}"]
        zeno = [ev for ev in mine if ev["type"] == "zeno"]
        assert len(zeno) == 1 and zeno[0] is mine[-1]
        closed, t_inf = closed_form_impacts(0.5, len(mine) - 1, h)
        assert np.max(np.abs(np.array([ev["t"] for ev in mine[:-1]]) - closed)) < 1e-11
        assert zeno[0]["t"] == pytest.approx(3 * math.sqrt(2 * h / G), abs=1e-11)
        assert t_inf == pytest.approx(3 * math.sqrt(2 * h / G), rel=1e-14)
    assert np.max(np.abs(traj.q[-1])) < 1e-12 and np.max(np.abs(traj.qd[-1])) < 1e-12
    assert traj.energy["impact_work"][-1] == pytest.approx(-G * sum(heights), rel=1e-10)
