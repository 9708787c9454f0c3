"""Equilibrium under servo-constraints (Béghin 1922; Appell 1911: the equations of motion with
the inertia terms dropped, plus the finite servo relations): the controls that hold a system
at rest, and the cases where no control can."""

import numpy as np
import pytest

from nonideal.analysis.checks import check_model
from nonideal.analysis.contact.statics import servo_equilibrium
from nonideal.modeling.model import Constraint, Model


def _pendulum(th0=0.7):
    return Model(name="held pendulum", coordinates=["theta"],
                 parameters={"m": 2.0, "g": 9.81, "l": 0.5, "th0": th0},
                 kinetic="m/2*l^2*theta'^2", potential="-m*g*l*cos(theta)",
                 constraints=[Constraint.servo("hold", "theta - th0", ["1"])],
                 initial={"theta": "th0", "theta'": 0})


@pytest.mark.parametrize("th0", [0.3, 0.7, 2.5])
def test_the_torque_that_holds_a_pendulum(th0):
    found = servo_equilibrium(_pendulum(th0))
    assert found.equilibrium
    assert found.controls["hold"] == pytest.approx(2.0 * 9.81 * 0.5 * np.sin(th0), rel=1e-12)


def test_check_reports_the_equilibrium_when_the_initial_state_is_at_rest():
    report = check_model(_pendulum())
    assert report.to_dict()["servo_equilibrium"]["equilibrium"] is True
    assert any("is an equilibrium under the servo-constraints" in n for n in report.notes)
    moving = check_model(_pendulum(0.7).replace(
        constraints=(Constraint.servo("hold", "theta - th0 - 0.1*t", ["1"]),), initial={"theta": "th0"}))
    assert "servo_equilibrium" not in moving.to_dict()       # not at rest: no statics answer


def test_a_control_that_cannot_balance_gravity():
    # a point kept on the incline y = x tan(a) by a force along x only: at rest the weight has
    # no balancing force -- not an equilibrium, whatever the control
    model = Model(name="incline", coordinates=["x", "y"], parameters={"m": 1.0, "g": 9.81, "a": 0.3},
                  kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                  constraints=[Constraint.servo("path", "y - x*tan(a)", ["1", "0"])],
                  initial={"x": 0, "y": 0, "x'": 0, "y'": 0})
    found = servo_equilibrium(model)
    assert not found.equilibrium and found.residual == pytest.approx(1.0)
    assert "cannot balance the forces" in found.reasons[0]


def test_a_velocity_program_does_not_admit_rest():
    model = Model(name="speed", coordinates=["x"], parameters={"m": 1.0, "v": 2.0}, kinetic="m/2*x'^2",
                  constraints=[Constraint.servo("cruise", "x' - v", ["1"])], initial={"x": 0, "x'": 2.0})
    found = servo_equilibrium(model, q=[0.0])
    assert not found.equilibrium and "'cruise' does not admit rest" in found.reasons[0]
