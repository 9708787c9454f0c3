"""SymEngine -> SymPy conversion (:func:`nonideal.symbols.to_sp`): the same SymPy objects as
``sympy.sympify``, built without re-canonicalizing (issue 2, benchmark proposal P2)."""

import pytest
import symengine as se
import sympy as sp

from nonideal.equations.formalisms import FORMS
from nonideal.errors import FormNotApplicable
from nonideal.analysis.derivation import derive
from nonideal.gallery import chaplygin_sleigh, knife_chain, nlink_pendulum
from nonideal.modeling.symbols import to_sp


def test_special_nodes_match_sympify():
    x, y = se.symbols("x y")
    exprs = [-(x + 2 * y), 2 * (x - y) * 3, -(x + y) * se.cos(x), se.exp(x) * 2, se.sqrt(2) * x,
             se.atan2(x, y) ** 2, 1 / (2 * x), se.Min(x, y), se.pi * x + se.Rational(1, 3),
             x + 2 * (y + 1) - se.sin(-x) * (x - y) ** se.Rational(3, 2), se.Float(0.25) * x]
    for e in exprs:
        assert to_sp(e) == sp.sympify(e), e
    M = se.Matrix([[x, -(x + y)], [y, se.cos(x - y)]])
    assert to_sp(M) == sp.Matrix(2, 2, [sp.sympify(e) for e in M])


@pytest.mark.parametrize("model", [nlink_pendulum.build(4), knife_chain.build(3), chaplygin_sleigh.build()],
                         ids=["pendulum4", "knife_chain3", "chaplygin_sleigh"])
def test_equations_of_motion_match_sympify(model):
    for form in FORMS:
        try:
            eom = derive(model, form)
        except FormNotApplicable:   # (chaplygin: the knife chain is not a Chaplygin system)
            continue
        for name, expr in (("A", eom.A_), ("c", eom.c_), ("Q_f", eom.Qf_), ("G", eom.G_),
                           ("gamma", eom.gamma_), ("R", eom.R_), ("r", eom.r_)):
            assert to_sp(expr) == sp.Matrix(*expr.shape, [sp.sympify(e) for e in expr]), (form, name)
        ref = sp.Matrix([sp.sympify(e) for e in eom.Qf_]) - sp.Matrix([sp.sympify(e) for e in eom.c_])
        assert eom.forcing == ref, form
