"""Stability conditions in symbolic parameters: derived parameters carried by their definitions,
parameters that enter only through the state, exact arithmetic (no rounding residue), and the
wording of the verdict (Lagrange--Dirichlet only at an equilibrium; P(s) = s Z(s^2) is not even)."""

import dataclasses

import pytest
import sympy as sp

from nonideal.analysis.stability.linearize import linearize
from nonideal.analysis.stability.symbolic import without_residue
from nonideal.errors import ModelError, NotAnEquilibrium
from nonideal.gallery import sleeping_top
from nonideal.modeling.model import Model
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

DISK = DATA_DIR / "rolling_disk_derived_inertia.toml"
w, g, r = sp.symbols("w g r")


def _condition(lin):
    (cond,) = lin.conditions
    return cond


def test_derived_inertia_is_carried_symbolically():
    """A = m r^2/4 and C = m r^2/2 depend on r: the upright disk's condition is 3 r w^2 > g
    (Neimark & Fufaev), not a polynomial with A and C frozen at r = 0.5."""
    lin = linearize(load_model(DISK), about="steady", at="phi'=w", symbolic=["w", "g", "r"])
    cond = _condition(lin)
    assert not cond.atoms(sp.Float)
    # the condition holds exactly where 3 r w^2 > g, at points on either side of the boundary
    for rv, gv in ((0.5, 9.81), (2.0, 1.0), (0.1, 30.0)):
        crit = (gv / (3 * rv)) ** 0.5
        for wv, expect in ((1.01 * crit, True), (0.99 * crit, False)):
            assert bool(cond.subs({w: wv, g: gv, r: rv})) is expect


def test_state_from_the_initial_expression():
    """phi' = w in [initial]: --symbolic w alone gives the condition in w (w^2 > g/(3 r))."""
    lin = linearize(load_model(DISK), about="steady", symbolic=["w"])
    cond = _condition(lin)
    assert cond.free_symbols == {w}
    crit = (9.81 / 1.5) ** 0.5
    assert bool(cond.subs(w, 1.01 * crit)) and not bool(cond.subs(w, 0.99 * crit))


def test_parameter_only_in_a_numeric_state_is_refused():
    """The spin given as a number in --at: w would stay numeric without a word -- refused."""
    with pytest.raises(ModelError, match=r"--symbolic w: it does not appear in A .*phi' = 5"):
        linearize(load_model(DISK), about="steady", at="phi'=5", symbolic=["w"])


def test_no_rounding_residue_in_conditions():
    """The sleeping top in A, C, w: exact coefficients (printed before as
    ``... + 1.38e-20 < 0``)."""
    lin = linearize(sleeping_top.build(), about="steady", at="c'=w", symbolic=["A", "C", "w"])
    for cond in lin.conditions:
        assert not any(abs(float(f)) < 1e-9 for f in cond.atoms(sp.Float)), cond


def test_residue_cleanup_keeps_exact_and_significant_terms():
    A, B = sp.symbols("A B")
    values = {A: 2.0, B: 3.0}
    e = A ** 2 + sp.Float(1.73e-22) * A ** 2 * B + sp.Float(1e-3) * B
    assert without_residue(e, values) == A ** 2 + sp.Float(1e-3) * B
    assert without_residue(A ** 2 + B, values) == A ** 2 + B


def test_steady_motion_verdict_cites_no_lagrange_dirichlet():
    """A top spinning above its pivot: the potential has a maximum there; the verdict cites
    gyroscopic stability, not Lagrange--Dirichlet."""
    lin = linearize(sleeping_top.build(), about="steady", at="c'=w")
    assert lin.verdict == "critical"
    assert "Lagrange--Dirichlet" not in lin.reason
    assert "Kelvin--Chetaev" in lin.reason


def test_odd_polynomial_is_not_called_even():
    """s^3 + c s = s Z(s^2): a zero root and an even factor, not "even in s"."""
    lin = linearize(load_model(DISK), about="steady")
    assert sp.Poly(lin.characteristic_polynomial, sp.Symbol("s")).degree() == 3
    assert "even in s" not in lin.reason
    assert "P(s) = s Z(s^2)" in lin.reason


def spherical_pendulum():
    return Model("spherical pendulum", ["th", "ph"], {"m": 1.0, "l": 1.0, "g": 9.81},
                 kinetic="m*l^2/2*(th'^2 + sin(th)^2*ph'^2)", potential="-m*g*l*cos(th)",
                 initial={"th": 0.5, "ph'": 1.0})


def test_newton_onto_a_coordinate_singularity_is_explained():
    """ph'^2 < g/l: no conical motion; Newton runs onto th = 0 where M is singular.  The
    message says so, with the state, not "dependent constraint rows" of a model without any."""
    with pytest.raises(NotAnEquilibrium) as err:
        linearize(spherical_pendulum(), about="steady", at="th=0.5, ph'=1")
    text = str(err.value)
    assert "constraint rows" not in text
    assert "mass matrix M is singular at the state (th = 0" in text
    assert "no steady motion was found near the guess" in text


def test_conical_motion_found_and_state_printed_cleanly():
    """cos th = g/(l w^2) at w = 5; a coordinate at the rounding level prints as 0."""
    import math

    lin = linearize(spherical_pendulum(), about="steady", at="th=1.1, ph'=5")
    assert lin.q["th"] == pytest.approx(math.acos(9.81 / 25), rel=1e-9)
    noisy = dataclasses.replace(lin, q={"th": lin.q["th"], "ph": 5.88e-13})
    assert "ph = 0," in noisy.as_text() and "e-13" not in noisy.as_text()
