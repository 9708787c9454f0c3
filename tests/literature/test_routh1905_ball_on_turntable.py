"""A ball rolling on a turntable (Routh 1905, Advanced Rigid Dynamics, §243): the centre
circles at (2/7) W -- the contact declared by its shape and the turning plane only."""

import numpy as np

from nonideal import gallery
from nonideal.gallery import ball_on_turntable as example


def test_centre_circles_at_two_sevenths_of_the_table_rate():
    model = gallery.load(example.NAME)
    r = example.check(model)
    assert r["v0"] == [0.0, 0.04]         # completed from rolling: W e_z x rho0, at rest on the table
    assert abs(r["circling_rate"] / (2 / 7 * 2.0) - 1) < 1e-8
    assert r["position_error"] < 1e-8 and r["velocity_error"] < 1e-8
    assert r["height_error"] < 1e-10 and not r["events"]


def test_circling_rate_does_not_depend_on_the_spin_or_the_table_rate():
    r = example.check(example.build(W=3.5, spin=(0.0, 0.0, 3.0)))
    assert abs(r["circling_rate"] / (2 / 7 * 3.5) - 1) < 1e-8
    assert r["position_error"] < 1e-8


def test_check_completes_the_velocities_from_rolling():
    """x', y', z' are not given: `check` completes them from the closed rolling contact."""
    from tests.helpers import run_cli
    out = run_cli("check", gallery.model_path(example.NAME))
    assert out.returncode == 0, out.stderr
    assert "completed from the constraints: x', y', z'" in out.stdout
