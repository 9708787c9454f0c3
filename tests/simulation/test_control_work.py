"""A servo-constraint's control work is integrated with the motion, not by quadrature over the
output samples: with a few output times it still equals the closed form."""

import numpy as np
import pytest

from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

M, A, W = 2.0, 0.3, 2.5


@pytest.mark.parametrize("form", ["lagrange1", "maggi"])
def test_work_of_a_harmonic_program(form):
    """x = A sin(W t) held by a force along x, nothing else acting: the control does the work
    of the kinetic energy, m/2 (x'^2 - x'(0)^2) = m A^2 W^2 (cos^2(W t) - 1)/2, and the
    force is u = m x'' = -m A W^2 sin(W t)."""
    model = Model("shaken mass", ["x", "y"], {"m": M, "a": A, "w": W},
                  kinetic="m/2*(x'^2 + y'^2)",
                  constraints=[Constraint.servo("program", "x - a*sin(w*t)", ["1", "0"])],
                  initial={"x": 0.0, "y": 0.0, "y'": 0.0}, simulation={"rtol": 1e-10, "atol": 1e-12})
    times = np.array([0.0, 0.3, 0.7, 1.3, 2.0])
    tr = simulate(model, times=times, form=form)
    ctl = tr.controls["program"]
    assert np.allclose(ctl["force"], -M * A * W ** 2 * np.sin(W * times), atol=1e-7)
    exact = M * A ** 2 * W ** 2 * (np.cos(W * times) ** 2 - 1) / 2
    assert np.max(np.abs(ctl["work"] - exact)) < 1e-8 * np.max(np.abs(exact))
    # the samples alone could not give it: Simpson's rule on them is off by percents
    from scipy.integrate import cumulative_simpson

    simpson = cumulative_simpson(ctl["power"], x=times, initial=0.0)
    assert np.max(np.abs(simpson - exact)) > 1e-2 * np.max(np.abs(exact))
