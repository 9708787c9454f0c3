"""Manglieva & Beknazarov 2022, (3.22): the regulator with an elastic intermediate wheel --
the library's characteristic polynomial is the determinant (3.22); the printed expansion's
sign misprints; Hurwitz minors and verdict."""

import numpy as np
import sympy as sp

from nonideal import gallery
from nonideal.analysis.stability.linearize import linearize

MOD = gallery.module("regulator-elastic-wheel")


def test_library_polynomial_is_the_determinant_and_hurwitz_decides():
    lin = linearize(gallery.load("regulator-elastic-wheel"), about="steady", at={"phi1'": 10.0})
    ref = MOD.determinant_coefficients(MOD.DEFAULTS)
    mine = [float(c) for c in sp.Poly(lin.characteristic_polynomial, sp.Symbol("s")).all_coeffs()]
    assert np.allclose(mine, ref, rtol=1e-9)
    assert np.allclose([float(h) for h in lin.hurwitz], MOD.hurwitz(ref), rtol=1e-8)
    assert all(float(h) > 0 for h in lin.hurwitz) and lin.verdict == "asymptotically stable"
    assert linearize(MOD.build(beta=-4.0), about="steady", at={"phi1'": 10.0}).verdict == "unstable"


def test_printed_expansion_differs_from_the_determinant_in_the_documented_signs():
    mu, th, m0, F1, P2, P3, P4, a, b, V0, al, be = sp.symbols("mu theta m0 Phi1 Phi2 Phi3 Phi4 a b V0 alpha beta")
    D = sp.Matrix([[th * mu, F1 * mu + P2, 0, -b], [P3, m0 * mu ** 2 + P4, -a, 0], [0, mu, -mu, -V0],
                   [0, 0, -V0 * al, mu + V0 * be]])
    a1, b1 = V0 * al, V0 * be
    printed = (th * m0 * mu ** 5 - th * m0 * b1 * mu ** 4 + mu ** 3 * (th * m0 * a1 * V0 + P3 * F1 - P4 * th - a * th)
               + mu ** 2 * (b1 * (P3 * F1 - P4 * th - a * th) + P3 * P2)
               + mu * (b1 * P3 * P2 - a1 * (V0 * (P3 * F1 - P4 * th) - b * P3)) - a1 * V0 * P3 * P2)
    true = sp.Poly(sp.expand(-D.det()), mu).all_coeffs()
    shown = sp.Poly(sp.expand(printed), mu).all_coeffs()
    wrong = {5 - k: sorted(str(t) for t in set(sp.Add.make_args(sp.expand(c2))) - set(sp.Add.make_args(sp.expand(c1))))
             for k, (c1, c2) in enumerate(zip(true, shown))}
    assert wrong == {5: [], 4: ["-V0*beta*m0*theta"], 3: ["-Phi4*theta", "Phi1*Phi3"],
                     2: ["-Phi4*V0*beta*theta", "Phi1*Phi3*V0*beta", "Phi2*Phi3"], 1: ["Phi2*Phi3*V0*beta"], 0: []}


def test_hurwitz_coefficients_and_minors_in_the_paper_notation():
    """a0..a5 derived from (3.22) (with Z~ = Z - 2 a theta) are theta0 m0 times the library's
    coefficients; the printed a2..a5 are not (a5 even has the wrong sign), nor are the printed
    Delta1 (beta1 dropped) and Delta2."""
    lin = linearize(gallery.load("regulator-elastic-wheel"), about="steady", at={"phi1'": 10.0})
    mine = [float(c) for c in sp.Poly(lin.characteristic_polynomial, sp.Symbol("s")).all_coeffs()]
    true = MOD.hurwitz_coefficients(MOD.DEFAULTS)
    assert np.allclose([true[0] * c for c in mine], true, rtol=1e-9)
    printed = MOD.hurwitz_coefficients(MOD.DEFAULTS, printed=True)
    for k in (2, 3, 4, 5):
        assert abs(printed[k] - true[k]) > 0.1 * abs(true[k]), k
    assert printed[5] == -true[5]
    minors = MOD.hurwitz(true)
    a0 = true[0]
    assert np.allclose([m / a0 ** (k + 1) for k, m in enumerate(minors)],
                       [float(h) for h in lin.hurwitz], rtol=1e-8)
    D1, D2 = MOD.printed_minors(MOD.DEFAULTS)
    assert abs(D1 - minors[0]) > 0.1 * minors[0] and abs(D2 - minors[1]) > 0.1 * minors[1]


def test_3_21_has_lambda_not_its_rate():
    """The last equation of (3.21) linearizes psi' = (alpha lambda - beta psi) R omega1 (3.17):
    the model with lambda reproduces the determinant (3.22) (first test); with lambda' (as
    printed) the characteristic polynomial would differ -- its s^1 and s^0 coefficients."""
    mu, th, m0, F1, P2, P3, P4, a, b, V0, al, be = sp.symbols("mu theta m0 Phi1 Phi2 Phi3 Phi4 a b V0 alpha beta")
    row = lambda last: sp.Matrix([[th * mu, F1 * mu + P2, 0, -b], [P3, m0 * mu ** 2 + P4, -a, 0],
                                  [0, mu, -mu, -V0], [0, 0, last, mu + V0 * be]])
    right = sp.expand(row(-V0 * al).det())
    printed = sp.expand(row(-V0 * al * mu).det())
    assert sp.expand(right - printed) != 0
