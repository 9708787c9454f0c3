"""A satellite whose acceleration (order 3) or jerk (order 4) keeps its magnitude, the ideal
program ``d/dt |r^(n-1)|^2 / 2 = 0`` realized by the generalized Gauss principle of order n
(Yushkov 1999, ch. IV, sec. 5; appendix D writes the satellite's equations in polar
coordinates).  The principle is a statement about vectors: the reaction's derivative of order
n - 2 is along the gradient.  Written in Cartesian and in polar coordinates, the same program
from the same initial state and force must give the same motion -- which holds only with the
covariant derivative of the force in the metric of the mass matrix (with the plain derivatives
of the polar components the two motions part by 0.24 within 3 s at order 3)."""

import numpy as np
import pytest
import sympy as sp

from nonideal.modeling.model import Constraint, Model
from nonideal.simulation.hybrid import simulate

TIMES = np.linspace(0.0, 3.0, 31)
SETTINGS = {"t_end": 3.0, "rtol": 1e-12, "atol": 1e-13}


def _polar_program(n: int) -> sp.Expr:
    """``x^(n-1) x^(n) + y^(n-1) y^(n)`` with ``x = r cos(phi)``, ``y = r sin(phi)``, in the
    symbols ``r``, ``r'``, ... the model uses."""
    t = sp.Symbol("t")
    r, ph = sp.Function("r")(t), sp.Function("phi")(t)
    X, Y = r * sp.cos(ph), r * sp.sin(ph)
    expr = sp.diff(X, t, n - 1) * sp.diff(X, t, n) + sp.diff(Y, t, n - 1) * sp.diff(Y, t, n)
    sub = {}
    for k in range(n, 0, -1):
        sub[sp.diff(r, t, k)] = sp.Symbol("r" + "'" * k)
        sub[sp.diff(ph, t, k)] = sp.Symbol("phi" + "'" * k)
    return sp.expand(expr.subs(sub).subs({r: sp.Symbol("r"), ph: sp.Symbol("phi")}))


@pytest.mark.parametrize("n", [3, 4])
def test_cartesian_and_polar_coordinates_give_one_motion(n):
    # at t0: r = 1, phi = 0, so the polar basis (e_r, e_phi = r e_theta) is the Cartesian one
    # and the force's components (and those of its covariant derivatives) are the same numbers
    forces = ((0.3, 0.2), (0.1, -0.2))[: n - 2]
    initial = forces if n > 3 else forces[0]
    p = "'"
    cartesian = Model(name="cartesian", coordinates=["x", "y"], parameters={"m": 1.0, "k": 1.0},
                      kinetic="m/2*(x'^2 + y'^2)", potential="-k*m/sqrt(x^2 + y^2)",
                      constraints=[Constraint("thrust", f"x{p * (n - 1)}*x{p * n} + y{p * (n - 1)}*y{p * n}",
                                              initial=initial)],
                      initial={"x": 1.0, "y": 0.0, "x'": 0.0, "y'": 1.1}, simulation=SETTINGS)
    polar = Model(name="polar", coordinates=["r", "phi"], parameters={"m": 1.0, "k": 1.0},
                  kinetic="m/2*(r'^2 + r^2*phi'^2)", potential="-k*m/r",
                  constraints=[Constraint("thrust", _polar_program(n), initial=initial)],
                  initial={"r": 1.0, "phi": 0.0, "r'": 0.0, "phi'": 1.1}, simulation=SETTINGS)
    a, b = simulate(cartesian, times=TIMES), simulate(polar, times=TIMES)
    r, phi = b.q[:, 0], b.q[:, 1]
    assert np.max(np.abs(a.q[:, 0] - r * np.cos(phi))) < 1e-9
    assert np.max(np.abs(a.q[:, 1] - r * np.sin(phi))) < 1e-9
    assert np.ptp(phi) > 1.0                          # the basis turns a good deal
    # the reaction as a vector: its polar components are its projections on (e_r, r e_theta)
    Rx, Ry = a.controls["thrust"]["u_1"], a.controls["thrust"]["u_2"]
    Rr = Rx * np.cos(phi) + Ry * np.sin(phi)
    Rphi = r * (-Rx * np.sin(phi) + Ry * np.cos(phi))
    assert np.max(np.abs(b.controls["thrust"]["u_1"] - Rr)) < 1e-8
    assert np.max(np.abs(b.controls["thrust"]["u_2"] - Rphi)) < 1e-8
    for tr in (a, b):
        assert tr.diagnostics["energy_balance_relative"] < 1e-8
