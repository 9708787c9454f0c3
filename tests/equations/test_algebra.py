"""The identity sin^2 + cos^2 = 1 in the mass matrix of points on circles: the entries are the
same functions, shorter, and exact in floating point."""

import math

import numpy as np
import pytest
import symengine as se

from nonideal.equations.algebra import PYTHAGOREAN_OPS_MAX, pythagorean
from nonideal.gallery.nlink_pendulum import build as pendulum
from nonideal.numeric.kernel import kernel_of

x, y, l, m = se.symbols("x y l m")
S, C = se.sin, se.cos


@pytest.mark.parametrize("expr, want", [
    (l**2 * S(x)**2 + l**2 * C(x)**2, l**2),
    ((l * C(x) + C(y))**2 + (l * S(x) + S(y))**2, 1 + l**2 + 2 * l * (S(x) * S(y) + C(x) * C(y))),
    (S(x)**2 * C(y)**2 + C(x)**2 * C(y)**2 + S(y)**2, se.Integer(1)),   # twice
    (S(x)**2 * C(y)**2 + C(x)**2 * C(y)**2 + S(x)**2 * S(y)**2,         # a term in two pairs:
     None),                                                              # one of them
    (S(x)**2 + 2 * C(x)**2, S(x)**2 + 2 * C(x)**2),                     # not a pair
    (S(x)**2 + C(y)**2, S(x)**2 + C(y)**2),                             # other angles
])
def test_pairs_of_squares_become_their_coefficient(expr, want):
    got = pythagorean(expr)
    if want is not None:
        assert se.expand(got - want) == 0
    else:
        assert se.count_ops(got) < se.count_ops(expr)
    # the same function everywhere
    for a, b in [(0.3, -1.2), (2.5, 0.7)]:
        values = {x: a, y: b, l: 1.7}
        assert float(got.subs(values)) == pytest.approx(float(expr.subs(values)), rel=1e-14)


def test_large_sums_are_left_alone():
    big = sum((se.Symbol(f"a{k}") * S(x)**2 for k in range(PYTHAGOREAN_OPS_MAX)), se.Integer(0)) + C(x)**2
    assert pythagorean(big) is big


def test_the_pendulum_mass_matrix_is_m_l_squared():
    """The n-link pendulum's diagonal: sum of m_k l_i^2 (sin^2 + cos^2), now without the
    trigonometric functions, so M_11 of one link is m l^2 exactly at every angle."""
    kernel = kernel_of(pendulum(1, q0=0.5))
    entry = kernel.dyn.mass_entries[(0, 0)]
    assert not entry.atoms(se.sin) and not entry.atoms(se.cos)
    x0 = np.full(len(kernel.symbols), 1.0)
    for angle in np.linspace(-math.pi, math.pi, 7):
        x0[1] = angle
        M = kernel.dynamics.views(kernel.dynamics.raw(x0).copy())["M"]
        assert float(np.ravel(M)[0]) == 1.0  # m = l = 1: exactly
