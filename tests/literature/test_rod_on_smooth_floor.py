"""A rod spun upright with one end on a floor (acceptance problem p10): with mu = mu_static = 0
the contact is frictionless -- one touching state ("smooth"), only touch and lift-off events,
the end moves freely along the floor (x' = 0 throughout, the rod obeys
(s^2 + 1/3) theta'' + s c theta'^2 = g s / l while touching).  A contact is frictionless when
its coefficients vanish at the simulation's parameters: overriding f gives it friction again."""

import json
import subprocess
import sys

import numpy as np
import pytest

from nonideal import simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model
from nonideal.plotting import mode_colors
from tests.helpers import DATA_DIR

FILE = DATA_DIR / "friction" / "rod_floor_spin.toml"
L, G = 0.5, 9.81
T_TOUCH, T_LIFT = 0.136637893931, 0.941909656717     # before: the same, with spurious "stick"s


@pytest.fixture(scope="module")
def model():
    return load_model(FILE)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, t_end=1.0)


def test_one_touching_state_and_only_touch_and_lift_off(traj):
    assert [(e["type"], e["contact"], e["mode"]) for e in traj.events] == [
        ("touch", "floor", "floor:smooth"), ("lift-off", "floor", "floor:separated")]
    assert [e["t"] for e in traj.events] == pytest.approx([T_TOUCH, T_LIFT], rel=1e-9)
    assert set(traj.contacts["floor"]["mode"]) == {"separated", "smooth"}
    assert mode_colors(traj) == {"separated": "#dddddd", "smooth": "#8ab17d"}


def test_frictionless_motion(traj):
    touching = np.array([m == "smooth" for m in traj.contacts["floor"]["mode"]])
    assert touching.sum() > 20
    assert np.max(np.abs(traj.velocity("x"))) < 1e-12
    assert np.max(np.abs(np.array(traj.contacts["floor"]["friction"]))) == 0.0
    th, w = traj.coordinate("theta")[touching], traj.velocity("theta")[touching]
    s, c = np.sin(th), np.cos(th)
    assert np.max(np.abs(traj.qdd[touching, 2] - (G * s / L - s * c * w * w) / (s * s + 1 / 3))) < 1e-9
    assert traj.diagnostics["energy_balance_relative"] < 1e-10


def test_parameter_override_gives_friction_back(model):
    rough = simulate(model, t_end=1.0, parameters={"f": 0.3})
    states = set(rough.contacts["floor"]["mode"]) - {"separated"}
    assert states and states <= {"stick", "slide+", "slide-"}
    assert "smooth" not in states and rough.events[0]["type"] == "touch"


def test_evaluate_and_cross_check(model):
    touching = {"y": 0.5 * np.cos(0.4), "theta": 0.4, "y'": -0.5 * np.sin(0.4) * 2.0, "theta'": 2.0}
    ev = evaluate(model, at=touching)
    assert ev.mode == "floor:smooth" and ev.contacts["floor"]["friction"] == [0.0]
    for state in ("stick", "slide"):
        assert compare_forms(model, contact_state=state, count=5).worst() < 1e-10


def test_cli_json_modes(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "nonideal", "simulate", str(FILE), "--t-end", "1",
                           "--json", "--csv", str(tmp_path / "rod.csv")],
                          capture_output=True, text=True, check=True)
    d = json.loads(proc.stdout)
    assert [e["type"] for e in d["events"]] == ["touch", "lift-off"]
    assert set(d["contacts"]["floor"]["mode"]) == {"separated", "smooth"}
    assert "floor:smooth" in (tmp_path / "rod.csv").read_text()
