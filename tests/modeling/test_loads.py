"""Loads ([[loads]]): forces at points and torques on planar and spatial bodies become
generalized forces by virtual work."""

import numpy as np
import pytest

from nonideal import ModelError, Model, PlanarBody, Particle, Torque
from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model

PLANAR_TORQUE = """
[model]
name = "free planar body with a torque"
[parameters]
m = 2.0
I = 0.5
tau = 1.5
[coordinates]
q = ["x", "y", "theta"]
[[bodies]]
type = "planar"
name = "plate"
mass = "m"
inertia = "I"
position = ["x", "y"]
angle = "2*theta"
[[loads]]
type = "torque"
name = "motor"
body = "plate"
torque = "tau*cos(theta)"
[initial]
x = 0
y = 0
theta = 0.3
"x'" = 0
"y'" = 0
"theta'" = 0
"""


def test_torque_on_a_planar_body_by_name(tmp_path):
    # the body turns by 2 theta: Q_theta = 2 tau cos(theta), T = I (2 theta')^2 / 2
    path = tmp_path / "plate.toml"
    path.write_text(PLANAR_TORQUE)
    qdd = evaluate(load_model(path)).to_dict()["qddot"]
    assert qdd["theta"] == pytest.approx(2 * 1.5 * np.cos(0.3) / (4 * 0.5), rel=1e-14)
    assert qdd["x"] == qdd["y"] == 0


def test_torque_on_a_planar_body_through_the_api():
    m = Model(name="plate", coordinates=["theta"], parameters={"I": 0.5},
              bodies=[PlanarBody("plate", 1, "I", ["0", "0"], "theta")],
              loads=[Torque("motor", "3", body="plate")], initial={"theta": 0, "theta'": 0})
    assert evaluate(m).to_dict()["qddot"]["theta"] == pytest.approx(6.0)


def test_torque_errors_name_the_body(tmp_path):
    bad = PLANAR_TORQUE.replace('torque = "tau*cos(theta)"', 'torque = ["0", "0", "tau"]')
    path = tmp_path / "bad.toml"
    path.write_text(bad)
    with pytest.raises(ModelError, match="body 'plate' is planar: its torque is one expression"):
        load_model(path)
    with pytest.raises(ModelError, match="body 'plat' is not a body of this model .did you mean 'plate'"):
        Model(name="x", coordinates=["theta"], bodies=[PlanarBody("plate", 1, 1, ["0", "0"], "theta")],
              loads=[Torque("motor", "3", body="plat")], initial={"theta": 0, "theta'": 0})
    with pytest.raises(ModelError, match="body 'bob' is a particle: a torque acts on a planar or rigid body"):
        Model(name="x", coordinates=["x"], bodies=[Particle("bob", 1, ["x", "0"])],
              loads=[Torque("motor", "3", body="bob")], initial={"x": 0, "x'": 0})
