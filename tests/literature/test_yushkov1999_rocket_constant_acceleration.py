"""A rocket keeping |r''| = w with a thrust along its velocity (Yushkov 1999, ch. IV: a
second-order constraint nonlinear in the accelerations, the mixed problem of dynamics), in a
uniform field: speed, time and thrust against the closed form (a quadrature in the velocity's
angle), and the stop where the two roots of the thrust meet."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.errors import MechanicsError
from nonideal.gallery import rocket_constant_acceleration as rocket
from nonideal.simulation.hybrid import simulate


def test_speed_time_and_thrust_match_the_closed_form():
    model = gallery.load(rocket.NAME)
    p = model.parameter_values
    times = np.linspace(0.0, 2.0, 9)
    tr = simulate(model, times=times)
    theta = np.arctan2(tr.qd[:, 1], tr.qd[:, 0])
    v = np.hypot(tr.qd[:, 0], tr.qd[:, 1])
    assert theta[0] - theta[-1] > 0.7          # the path bends over: gravity matters
    for k in range(len(times)):
        assert v[k] == pytest.approx(rocket.speed(theta[k], p), abs=1e-8)
        assert times[k] == pytest.approx(rocket.time(theta[k], p), abs=1e-8)
    assert np.max(np.abs(tr.multipliers["thrust"] - rocket.thrust(theta, p))) < 1e-8
    assert np.max(np.abs(np.hypot(tr.qdd[:, 0], tr.qdd[:, 1]) - p["w"])) < 1e-9
    # the thrust's work is the change of energy (gravity is in the potential)
    E = tr.energy["energy"]
    assert tr.energy["reaction_work"][-1] == pytest.approx(E[-1] - E[0], rel=1e-10)
    # the control's work: Simpson's rule over the 9 samples of its power
    assert tr.controls["thrust"]["work"][-1] == pytest.approx(E[-1] - E[0], rel=1e-5)


def test_weak_thrust_stops_where_the_roots_meet():
    with pytest.raises(MechanicsError, match="selects nothing") as info:
        simulate(rocket.build(t_end=5.0, w=9.0))
    angle = np.arctan2(info.value.state["y'"], info.value.state["x'"])
    assert angle == pytest.approx(np.arccos(9.0 / 9.81), abs=1e-4)
