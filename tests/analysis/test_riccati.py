"""The Riccati classifier (nonideal.analysis.stability.riccati): every case and sign against a numerical
solution, the blow-up times, the limits."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from nonideal.analysis.stability.riccati import riccati_regime

CASES = [  # A, B, omega0, case, behaviour
    (0.5, 0.35, 0.0, 1, "blow-up"), (-0.4, -0.2, 0.5, 1, "blow-up"),
    (1.0, 0.0, 0.3, 2, "blow-up"), (1.0, 0.0, -0.3, 2, "limit"), (1.0, 0.0, 0.0, 2, "constant"),
    (-0.5, 1.06, 0.0, 3, "limit"), (1.5, -0.35, 0.0, 3, "limit"), (1.5, -0.35, 0.6, 3, "blow-up"),
    (-0.5, 1.06, -2.0, 3, "blow-up"), (0.0, 0.7, 0.1, 4, "linear growth"),
    (0.0, 0.0, 0.4, 4, "constant"),
]


@pytest.mark.parametrize("A,B,w0,case,behaviour", CASES)
def test_regime_and_closed_form_against_the_integrated_equation(A, B, w0, case, behaviour):
    reg = riccati_regime(A, B, w0)
    assert (reg.case, reg.behaviour) == (case, behaviour)
    T = 0.99 * reg.blowup_time if reg.blowup_time else 6.0
    t = np.linspace(0, T, 50)
    sol = solve_ivp(lambda _, w: A * w * w + B, (0, T), [w0], t_eval=t, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(sol.y[0] - reg.omega(t)) / np.maximum(1, np.abs(sol.y[0]))) < 1e-8
    if behaviour == "blow-up":   # near t*, omega ~ 1/(A (t* - t)): the pole of the solution
        t_near = reg.blowup_time * (1 - 1e-6)
        assert reg.omega(t_near) * A * (reg.blowup_time - t_near) == pytest.approx(1, rel=1e-4)
    if behaviour == "limit":
        long = reg.omega(np.array([1e9]))[0]   # case 2 decays like 1/(A t) only
        assert long == pytest.approx(reg.limit, abs=1e-8)


def test_limits_are_the_stable_equilibria():
    c = math.sqrt(1.06 / 0.5)
    assert riccati_regime(-0.5, 1.06).limit == pytest.approx(c)     # A < 0: +c
    assert riccati_regime(0.5, -1.06).limit == pytest.approx(-c)    # A > 0: -c
    assert riccati_regime(0.5, -1.06, c).behaviour == "constant"     # the unstable one
