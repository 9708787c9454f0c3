"""Contensou's integrals (nonideal.numeric.contensou) against Coulomb's traction summed over the
unit patch by adaptive two-dimensional quadrature in polar coordinates about the patch's centre
(SciPy dblquad, independent of the instantaneous-centre parametrization of the module)."""

import math

import pytest
from scipy.integrate import IntegrationWarning, dblquad

from nonideal.numeric.contensou import contensou


def summed(d: float):
    """Force along the slip and torque about the normal per unit mu N: the unit disk under
    uniform pressure 1/pi sliding at (d, 0) and pivoting at 1 about its centre."""
    def traction(r, th):
        sx, sy = d - r * math.sin(th), r * math.cos(th)
        n = math.hypot(sx, sy)
        return -sx / n, -sy / n

    def fx(r, th):
        return -traction(r, th)[0] * r / math.pi

    def mz(r, th):
        tx, ty = traction(r, th)
        return -(r * math.cos(th) * ty - r * math.sin(th) * tx) * r / math.pi

    opts = dict(epsabs=1e-12, epsrel=1e-12)
    return dblquad(fx, 0, 2 * math.pi, 0, 1, **opts)[0], dblquad(mz, 0, 2 * math.pi, 0, 1, **opts)[0]


@pytest.mark.filterwarnings("ignore", category=IntegrationWarning)
@pytest.mark.parametrize("d", [1e-3, 0.1, 0.5, 0.9, 1.0, 1.5, 3.0, 20.0])
def test_integrals_equal_the_adaptive_sum(d):
    f, m = contensou(d)
    F, M = summed(d)
    # measured: within 2e-15, except m(1e-3) (3.5e-11: the sum's roundoff near the pivot point)
    assert (f, m) == pytest.approx((F, M), abs=1e-10)


def test_the_slopes_in_the_limits():
    # small slip while pivoting: F ~ mu N v/(rho omega); small pivoting while sliding: M ~ mu N/(4 d)
    assert contensou(1e-6)[0] / 1e-6 == pytest.approx(1.0, rel=1e-9)
    assert contensou(1e6)[1] * 4e6 == pytest.approx(1.0, rel=1e-9)
    assert contensou(1e-9)[1] == pytest.approx(2 / 3, rel=1e-12)
    assert contensou(1e9)[0] == pytest.approx(1.0, rel=1e-12)
