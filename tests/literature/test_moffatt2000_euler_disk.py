"""Euler's disk in steady precession (Moffatt 2000, Nature 404, 833): a disk rolling on its
rim with its centre at rest precesses at Omega^2 = 4 g/(a sin alpha) -- derived in the
gallery module's docstring; here also for other inclinations and radii."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.gallery import euler_disk as example


@pytest.mark.parametrize("a, alpha", [(0.04, 0.3), (0.1, 0.8), (0.05, 1.2)])
def test_steady_precession_rate(a, alpha):
    model = gallery.load(example.NAME) if (a, alpha) == (0.04, 0.3) else example.build(a=a, alpha=alpha, t_end=0.5)
    r = example.check(model)
    assert r["Omega_given"] == pytest.approx(np.sqrt(4 * 9.81 / (a * np.sin(alpha))), rel=1e-14)
    assert r["inclination_drift"] < 1e-8 and r["precession_error"] < 1e-8 and r["centre_drift"] < 1e-8
    assert not r["events"]


def test_a_different_rate_is_not_steady():
    r = example.check(example.build(Omega=1.05 * np.sqrt(4 * 9.81 / (0.04 * np.sin(0.3)))))
    assert r["inclination_drift"] > 1e-3
