"""A run drawn from a few output times (--times) shows its mode switch and the friction's jump
at the event's instant: the drawing uses the events and the dense output, not the samples."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

from nonideal import gallery  # noqa: E402
from nonideal.cli.simulate import plot_grid  # noqa: E402
from nonideal.plotting import mode_intervals  # noqa: E402
from nonideal.simulation import simulate  # noqa: E402
from tests.helpers import run_cli  # noqa: E402


def _coarse():
    return simulate(gallery.load("block-on-incline"), times=[0.0, 0.5, 1.0, 1.5])


def test_mode_switch_drawn_at_the_event():
    traj = _coarse()
    (event,) = [e for e in traj.events if e["type"] == "stick"]
    (slide, stick) = mode_intervals(traj, "plane")
    assert slide[2].startswith("slide") and stick[2] == "stick"
    assert slide[1] == stick[0] == event["t"]          # 0.4594, not the sample 0.5
    assert abs(event["t"] - 0.5) > 0.04


def test_drawn_grid_is_dense_and_holds_the_events():
    traj = _coarse()
    grid = plot_grid(traj)
    te = traj.events[0]["t"]
    assert te in grid and np.all(np.diff(grid) > 0) and len(grid) > 600
    assert set(traj.t) <= set(grid)
    drawn = simulate(gallery.load("block-on-incline"), t_end=traj.t[-1], times=grid)
    friction = np.asarray(drawn.contacts["plane"]["friction"], dtype=float)[:, 0]
    k = int(np.searchsorted(grid, te))
    # the sliding friction mu N holds up to the event, the sticking one right after it
    assert abs(friction[k - 1] - friction[k + 2]) > 0.1 * abs(friction[k - 1])


def test_cli_plot_with_a_few_times(tmp_path):
    png = tmp_path / "p.png"
    r = run_cli("simulate", "block-on-incline", "--times", "0,0.5,1,1.5", "--plot", png)
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 10_000
