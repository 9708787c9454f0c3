"""Constraints that become singular along a motion stop the run with exit code 3, naming the
constraints, the time and the state -- instead of passing through the pole of the multipliers
with no word (two constraints that become dependent; a nonholonomic constraint whose gradient
vanishes)."""

import math

import pytest

from nonideal.errors import SingularMotion
from nonideal.modeling.modelfile import load_model
from nonideal.simulation import simulate
from tests.helpers import DATA_DIR, run_cli


def test_constraints_that_become_dependent_stop_the_run_at_t_pi():
    model = load_model(DATA_DIR / "dependent_in_motion.toml")
    with pytest.raises(SingularMotion) as info:
        simulate(model)
    err = info.value
    assert err.exit_code == 3
    assert err.t == pytest.approx(math.pi, abs=1e-5)
    assert err.details["constraints"] == "circle, program"
    assert abs(err.state["x"]) < 1e-5 and err.state["y"] == pytest.approx(1.0, abs=1e-9)
    assert "became dependent" in str(err)


def test_before_the_dependent_configuration_the_motion_is_the_program():
    traj = simulate(load_model(DATA_DIR / "dependent_in_motion.toml"), t_end=3.0, times=[1.0, 2.0, 3.0])
    assert traj.q[:, 0] == pytest.approx([math.sin(1.0), math.sin(2.0), math.sin(3.0)], abs=1e-8)
    assert traj.q[:, 1] == pytest.approx([-math.cos(1.0), -math.cos(2.0), -math.cos(3.0)], abs=1e-9)


def test_a_vanishing_nonholonomic_gradient_is_detected_along_the_motion():
    model = load_model(DATA_DIR / "vanishing_gradient.toml")
    with pytest.raises(SingularMotion) as info:
        simulate(model)
    err = info.value
    assert err.details["constraint"] == "cone"
    # the gradient (-2 a^2 x', -2 a^2 y', 2 z') vanishes with x' (y' = 0, z' = a |x'|)
    assert abs(err.state["x'"]) < 1e-5 and abs(err.state["z'"]) < 1e-5
    assert "lost its gradient" in str(err)
    traj = simulate(model, t_end=err.t * 0.99)  # up to there the run is regular
    assert traj.t[-1] == pytest.approx(err.t * 0.99)


def test_cli_exit_code_3_names_the_constraints():
    proc = run_cli("simulate", DATA_DIR / "dependent_in_motion.toml")
    assert proc.returncode == 3, proc.stderr
    assert "'circle', 'program' became dependent" in proc.stderr and "at t = 3.14159" in proc.stderr
    assert "Traceback" not in proc.stderr
