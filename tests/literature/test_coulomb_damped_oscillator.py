"""Mass-spring oscillator on a rough floor (Coulomb damping, the classical closed form): every
half cycle lasts pi/omega, is harmonic about +-mu m g/k and ends at a turning point where the
slip velocity vanishes; the block sticks at the first turning point with |x| <= mu_s m g/k.
The events say what happened there: "reverse" at the turning points where the slip changes
sign, "stick" at the last one (a reversal used to be reported as "stick")."""

import subprocess
import sys

import numpy as np
import pytest

from nonideal import simulate
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

FILE = DATA_DIR / "friction" / "spring_rough_floor.toml"
M, K, G, MU, A0 = 1.0, 10.0, 9.81, 0.05, 1.0
HALF = np.pi / np.sqrt(K / M)                # duration of a half cycle
D = MU * M * G / K                           # the amplitude drops by 2 D per half cycle
TURNS = 10                                   # |1 - 2 D n| > D up to n = 9; at n = 10 it sticks


@pytest.fixture(scope="module")
def traj():
    return simulate(load_model(FILE))


def test_turning_points_are_reversals_and_the_last_a_stick(traj):
    types = [e["type"] for e in traj.events]
    assert types == ["reverse"] * (TURNS - 1) + ["stick"]
    modes = [e["mode"] for e in traj.events]
    assert modes == ["floor:slide+", "floor:slide-"] * 4 + ["floor:slide+", "floor:stick"]
    times = np.array([e["t"] for e in traj.events])
    assert np.max(np.abs(times - HALF * np.arange(1, TURNS + 1))) < 1e-9
    assert traj.at("x") == pytest.approx(A0 - 2 * D * TURNS, rel=1e-7)


def test_stop_on_the_recorded_type():
    model = load_model(FILE)
    first = simulate(model, stop_on={"reverse"})
    assert [(e["type"], e["mode"], e["stopped"]) for e in first.events] == [("reverse", "floor:slide-", True)]
    assert first.t[-1] == pytest.approx(HALF, rel=1e-9)
    last = simulate(model, stop_on={"stick"})
    assert [e["type"] for e in last.events] == ["reverse"] * (TURNS - 1) + ["stick"]
    assert last.events[-1]["stopped"] and last.t[-1] == pytest.approx(TURNS * HALF, rel=1e-9)


def test_cli_prints_what_happened():
    proc = subprocess.run([sys.executable, "-m", "nonideal", "simulate", str(FILE)],
                          capture_output=True, text=True, check=True)
    lines = [ln for ln in proc.stdout.splitlines() if "event at" in ln]
    assert lines[0].endswith("reverse floor -> mode [floor:slide+]")
    assert lines[-1].endswith("stick floor -> mode [floor:stick]")
