"""Stability along a programmed (servo) motion: A(t) on the constraint manifold, the verdict
from the fundamental matrix / Persidsky's bound, the time-varying controllability W(t)."""

import numpy as np
import pytest

from nonideal.analysis.program import linearize_program
from nonideal.modeling.model import Constraint, Model

K, B_, V = 4.0, 0.5, 0.8


def servo_model(b=B_):
    """x follows the programme x = v t (a servo force along x); y is a damped oscillator whose
    stiffness grows along the programme: A(t) = [[0, 1], [-k (1 + x(t)), -b]]."""
    return Model("programmed stiffness", ["x", "y"], {"k": K, "b": b, "v": V, "u": 0.0},
                 kinetic="(x'^2 + y'^2)/2", potential="k*(1 + x)*y^2/2", forces={"y": "-b*y' + u"},
                 constraints=[Constraint.servo("programme", "x - v*t", reaction=["1", "0"])],
                 initial={"x": 0.0, "y": 0.0, "x'": V, "y'": 0.0}, simulation={"t_end": 4.0})


def test_A_of_t_follows_the_programme_and_the_servo_coordinate_is_eliminated():
    p = linearize_program(servo_model(), controls=["u"], samples=41)
    assert p.variables == ("y", "y'") and p.dependent == ("x", "x'")
    for t, A in zip(p.t, p.A):
        assert np.allclose(A, [[0, 1], [-K * (1 + V * t), -B_]], atol=1e-10)
    assert np.allclose(p.B[:, :, 0], [0, 1])
    assert p.verdict == "asymptotically stable" and p.exponent < 0
    assert np.all(p.controllability_rank == 2)     # W = [B, -A B] = [[0, -1], [1, b]]


def test_undamped_growing_stiffness_is_not_asymptotically_stable():
    p = linearize_program(servo_model(b=0.0), samples=41)
    assert p.verdict != "asymptotically stable"
    # negative damping: the perturbations grow
    q = linearize_program(servo_model(b=-0.4), samples=41)
    assert q.verdict == "unstable" and q.exponent > 0.1
