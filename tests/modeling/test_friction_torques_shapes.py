"""Friction torques on contacts from geometry: the spin and rolling angular velocities derived
from the shape (``spin = omega_rel . n``, ``rolling`` its components along the surface's
tangents), checked against hand derivations, and the bad inputs refused by name."""

import numpy as np
import pytest
import sympy as sp

from nonideal.errors import ModelError
from nonideal.gallery import load as load_example
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR


def test_ball_from_a_shape_is_the_hand_written_ball():
    shaped = simulate(load_model(DATA_DIR / "torques" / "ball_shape.toml"), t_end=5.0)
    hand = simulate(load_model(DATA_DIR / "torques" / "ball_rolling_resistance.toml"), t_end=5.0)
    assert [e["contact"] for e in shaped.events] == ["floor_rolling"]
    assert abs(shaped.events[0]["t"] - hand.events[0]["t"]) < 1e-10
    assert shaped.coordinate("x")[-1] == pytest.approx(hand.coordinate("x")[-1], rel=1e-10)


def _euler_disk(**keys):
    model = load_example("euler-disk")
    c = model.contacts[0]
    from dataclasses import replace

    raw = replace(c, gap=None, slip=(), geometry=None, shape=c.shape, surface=c.surface, **keys)
    return model.replace(contacts=(raw,))


def test_disk_rim_spin_and_rolling_are_derived():
    model = _euler_disk(spin_friction="0.002", rolling_friction="0.0005")
    c = model.contacts[0]
    psi, theta, phi = sp.symbols("psi theta phi")
    dpsi, dtheta, dphi = sp.symbols("psi' theta' phi'")
    # omega = psi' e_z + theta' Rz e_x + phi' R e_y (R = Rz(psi) Rx(theta) Ry(phi))
    spin = dpsi + dphi * sp.sin(theta)
    wx = dtheta * sp.cos(psi) - dphi * sp.sin(psi) * sp.cos(theta)
    wy = dtheta * sp.sin(psi) + dphi * sp.cos(psi) * sp.cos(theta)
    assert sp.simplify(c.spin - spin) == 0
    assert len(c.rolling) == 2
    assert sp.simplify(c.rolling[0] - wx) == 0 and sp.simplify(c.rolling[1] - wy) == 0


def test_euler_disk_with_torques_loses_energy_to_them():
    model = _euler_disk(spin_friction="0.002", rolling_friction="0.0005")
    tr = simulate(model, t_end=0.3)
    W = tr.energy["friction_work"]
    assert W[-1] < 0 and np.all(np.diff(W) <= 1e-14)
    assert tr.diagnostics["energy_balance_max"] < 1e-10
    p = model.parameter_values
    # at t0 the disk pivots at Omega sin^2(alpha) about the vertical, N = m g (centre at rest)
    alpha, Omega = p["alpha"], np.sqrt(4 * p["g"] / (p["a"] * np.sin(p["alpha"])))
    spin0 = np.array(tr.contacts["table_spin"]["slip"])[0, 0]
    assert spin0 == pytest.approx(Omega * np.sin(alpha) ** 2, rel=1e-12)
    torque0 = np.array(tr.contacts["table_spin"]["friction"])[0, 0]
    assert torque0 == pytest.approx(-0.002 * tr.contacts["table_spin"]["normal"][0], rel=1e-12)


@pytest.mark.parametrize("keys, words", [
    (dict(spin_friction="0.002", spin="psi'"), "spin is derived from the shape and the surface; remove it"),
    (dict(rolling_friction="0.001", rolling=("psi'",)), "rolling is derived from the shape"),
])
def test_given_angular_velocity_with_a_shape_is_refused(keys, words):
    with pytest.raises(ModelError, match=words):
        _euler_disk(**keys)


def test_spin_friction_on_a_point_contact_is_refused(tmp_path):
    text = (DATA_DIR / "torques" / "ball_shape.toml").read_text()
    text = text.replace('shape = { type = "sphere", radius = "r" }', 'shape = { type = "point", center = [0, 0, "-r"] }')
    text = text.replace('rolling_friction = "l"', 'spin_friction = "l"')
    path = tmp_path / "point.toml"
    path.write_text(text)
    with pytest.raises(ModelError) as info:
        load_model(path)
    message = str(info.value)
    assert "spin_friction on a point contact" in message and "remove spin_friction" in message


def test_a_planar_ball_cannot_pivot(tmp_path):
    text = (DATA_DIR / "torques" / "ball_shape.toml").read_text().replace('rolling_friction = "l"',
                                                                          'spin_friction = "l"')
    path = tmp_path / "planar.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match="body 'ball' cannot pivot on the surface with these coordinates"):
        load_model(path)
