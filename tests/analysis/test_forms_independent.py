"""``[forms] independent``: one list, one meaning for every form -- the coordinates kept
independent as far as the constraints allow (Lagrange II keeps them; Maggi/Appell/Shulgin take
their independent velocities among them; the linearization keeps them); too many, or a list the
constraints cannot keep, is refused with both counts."""

import numpy as np
import pytest

from nonideal import Constraint, FormNotApplicable, Model, ModelError
from nonideal.analysis.derivation import derive
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.stability.linearize import linearize


def sleigh(independent=None, swap=False):
    """A Chaplygin sleigh on a spring (k x^2/2) with a flywheel s geared to its heading
    (s = theta, holonomic): n = 4 coordinates, h = 1, k = 1 -> 3 independent coordinates,
    2 independent velocities."""
    rows = [Constraint.holonomic("gear", "s - theta"),
            Constraint.nonholonomic("knife", "-x'*sin(theta) + y'*cos(theta) + a*theta'")]
    return Model("geared sleigh", ["x", "y", "theta", "s"], {"m": 2.0, "J": 0.3, "Js": 0.1, "a": 0.2, "k": 3.0},
                 kinetic="m/2*(x'^2 + y'^2) + J/2*theta'^2 + Js/2*s'^2", potential="k*x^2/2",
                 constraints=rows[::-1] if swap else rows,
                 initial={"x": 0.3, "y": 0.1, "theta": 0.4, "s": 0.4, "x'": 0.5, "theta'": 0.7},
                 independent=independent)


def test_the_coordinates_list_serves_every_form():
    m = sleigh(("x", "y", "theta"))                        # n - h = 3 coordinates
    assert set(derive(m, "lagrange2").independent) == {"x", "y", "theta"}
    ref = evaluate(m).qdd
    for form in ("maggi", "appell", "shulgin"):
        eom = derive(m, form)
        assert len(eom.unknowns) == 2 and "s''" not in eom.unknowns          # chosen among the listed
        assert set(eom.independent) <= {"x", "y", "theta"}
        np.testing.assert_allclose(evaluate(m, form=form).qdd, ref, rtol=1e-10, atol=1e-12)


def test_exactly_the_velocities_are_taken_as_given():
    m = sleigh(("x", "theta"))                             # n - h - k = 2 velocities
    assert derive(m, "maggi").unknowns == ("x''", "theta''")
    assert {"x", "theta"} <= set(derive(m, "lagrange2").independent)
    np.testing.assert_allclose(evaluate(m, form="appell").qdd, evaluate(m).qdd, rtol=1e-10, atol=1e-12)


def test_too_many_coordinates_are_refused_by_every_consumer_with_both_counts():
    m = sleigh(("x", "y", "theta", "s"))
    for form in ("maggi", "appell"):
        with pytest.raises(FormNotApplicable, match=r"at most 3.*3 independent coordinates|list at most 3"):
            derive(m, form)
    with pytest.raises(FormNotApplicable, match="leave 3"):
        derive(m, "lagrange2")
    with pytest.raises(ModelError, match="list at most 3"):
        linearize(m, at={"x": 0.0, "theta": 0.0, "s": 0.0})


def test_a_list_the_constraints_cannot_keep_is_refused():
    # theta and s are tied by the gear: one of them must be dependent
    with pytest.raises(ModelError, match="cannot keep"):
        linearize(sleigh(("theta", "s")), at={"x": 0.0, "theta": 0.0, "s": 0.0})


def test_linearization_keeps_the_listed_coordinates_whatever_the_constraint_order():
    """The holonomic rows' velocities are eliminated first even when a nonholonomic row comes
    first in the file: the same variables and the same A."""
    a = linearize(sleigh(("x", "y", "theta")), at={"x": 0.0, "theta": 0.0, "s": 0.0}, keep=["y"])
    b = linearize(sleigh(("x", "y", "theta"), swap=True), at={"x": 0.0, "theta": 0.0, "s": 0.0}, keep=["y"])
    assert a.variables == b.variables and "s" not in a.variables and "x" in a.variables
    np.testing.assert_allclose(a.A, b.A, atol=1e-12)
    np.testing.assert_allclose(np.sort_complex(a.eigenvalues), np.sort_complex(b.eigenvalues), atol=1e-12)
