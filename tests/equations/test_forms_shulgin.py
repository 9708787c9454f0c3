"""Shulgin's equations in redundant coordinates (nonideal/formalisms/shulgin.py), seed 000
(1.61)-(1.64), with Voronets' terms for nonholonomic and rheonomic constraints.  The expected
equations are written out by hand here (SymPy) from the operators E_j, E_0 and compared with
the form's; physics is checked against Lagrange I."""

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

from nonideal import Constraint, FormNotApplicable, Model, Particle
from nonideal.analysis.crosscheck import compare_forms
from nonideal.equations.formalisms import FORMS
from nonideal.analysis.derivation import derive
from nonideal.modeling.symbols import to_se
from tests.systems import sleigh, painleve, rotating_line


S = {n: sp.Symbol(n) for n in ["x", "y", "theta", "x1", "y1", "x'", "y'", "theta'", "x1'", "y1'",
                               "m", "m1", "I", "a", "l", "g", "t", "w"]}


def shulgin_lhs(T, coords, dep, A, A0):
    """(1.64) with Voronets' terms, by hand: ``d/dt dT*/dx_j' - E_j(T*) - sum_b p_b W_bj``
    without the acceleration terms, and ``d2T*/dx_j'dx_i'``.  *A*: dict (b, j) -> A_bj."""
    v = {c: S[c + "'"] for c in coords}
    ind = [c for c in coords if c not in dep]
    vsub = {v[b]: sum(A[b, j] * v[j] for j in ind) + A0[b] for b in dep}
    Tstar = T.xreplace(vsub)

    def E(f, j):
        return sp.diff(f, S[j]) + sum(A[b, j] * sp.diff(f, S[b]) for b in dep)

    def E0(f):
        return sp.diff(f, S["t"]) + sum(A0[b] * sp.diff(f, S[b]) for b in dep)

    def ddt(f):  # along the constrained motion, without accelerations
        return E0(f) + sum(v[i] * E(f, i) for i in ind)

    lhs, mass = [], []
    for j in ind:
        P = sp.diff(Tstar, v[j])
        e = ddt(P) - E(Tstar, j)
        for b in dep:
            W = sum((E(A[b, j], i) - E(A[b, i], j)) * v[i] for i in ind) + E0(A[b, j]) - E(A0[b], j)
            e -= sp.diff(T, v[b]).xreplace(vsub) * W
        lhs.append(e)
        mass.append([sp.diff(P, v[i]) for i in ind])
    return lhs, mass


def agree(expected, got, params, names, count=6, seed=5):
    """Equal at *count* random points (the model's parameter values)."""
    rng = random.Random(seed)
    for _ in range(count):
        point = {S[n]: rng.uniform(-1.2, 1.2) for n in names}
        point.update({S[k]: v for k, v in params.items()})
        a = complex(sp.N(expected.xreplace(point)))
        b = complex(se.sympify(got).subs({to_se(k): v for k, v in point.items()}).n())
        assert abs(a - b) <= 1e-11 * max(1.0, abs(a)), (expected, a, b)


def test_registered():
    assert FORMS["shulgin"].name == "shulgin"


def test_sleigh_voronets_terms_by_hand():
    # y' = x' tan(theta): A_yx = tan(theta), A_ytheta = 0, A_y0 = 0; W_yx = theta'/cos^2,
    # W_ytheta = -x'/cos^2, p_y = m (x' tan(theta) + a theta' cos(theta))
    model = sleigh()
    eom = derive(model, "shulgin")
    assert eom.unknowns == ("x''", "theta''")
    assert "y' = x'*sin(theta)/cos(theta)" in eom.notes
    assert any("Voronets' terms kept" in n for n in eom.notes)
    x, th, xd, yd, thd, m, I, a = (S[n] for n in ["x", "theta", "x'", "y'", "theta'", "m", "I", "a"])
    T = m / 2 * ((xd - a * thd * sp.sin(th)) ** 2 + (yd + a * thd * sp.cos(th)) ** 2) + I / 2 * thd ** 2
    A = {("y", "x"): sp.tan(th), ("y", "theta"): sp.Integer(0)}
    lhs, mass = shulgin_lhs(T, ["x", "y", "theta"], ["y"], A, {"y": sp.Integer(0)})
    names = ["x", "y", "theta", "x'", "theta'"]
    p = model.parameter_values
    for j in range(2):
        agree(lhs[j], eom.c_[j], p, names)
        for i in range(2):
            agree(mass[j][i], eom.A_[j, i], p, names)
    # the Voronets terms are essential: without them (Lagrange II for T*) the equations differ
    Tstar = T.xreplace({yd: xd * sp.tan(th)})
    naive = sp.diff(sp.diff(Tstar, xd), th) * thd - sp.diff(Tstar, x) - sp.tan(th) * sp.diff(Tstar, S["y"])
    point = {x: 0.1, S["y"]: 0.2, th: 0.5, xd: 1.0, thd: 1.5, m: p["m"], I: p["I"], a: p["a"]}
    voronets = complex(sp.N((naive - lhs[0]).xreplace(point))).real
    assert abs(voronets) > 0.5


def test_sleigh_agrees_with_lagrange1():
    report = compare_forms(sleigh(), forms=["shulgin"], count=20)
    assert report.states == 20 and report.worst() < 1e-10, report


def test_holonomic_redundant_coordinates_give_1_64_without_voronets_terms():
    # y' = 0, x1' = x' - (y1 - y) y1'/(x1 - x): Voronets' terms vanish identically and the
    # printed equations are exactly (1.64)
    model = painleve()
    eom = derive(model, "shulgin")
    assert eom.unknowns == ("x''", "y1''")
    assert eom.eliminated == ("line", "rod")
    assert "Voronets' terms vanish identically (integrable constraints): equations (1.64)" in eom.notes
    assert "T*" in eom.extras_
    x, y, x1, y1, xd, y1d, m, m1, g = (S[n] for n in ["x", "y", "x1", "y1", "x'", "y1'", "m", "m1", "g"])
    T = m / 2 * (xd ** 2 + S["y'"] ** 2) + m1 / 2 * (S["x1'"] ** 2 + y1d ** 2)
    A = {("y", "x"): sp.Integer(0), ("y", "y1"): sp.Integer(0),
         ("x1", "x"): sp.Integer(1), ("x1", "y1"): -(y1 - y) / (x1 - x)}
    A0 = {"y": sp.Integer(0), "x1": sp.Integer(0)}
    lhs, mass = shulgin_lhs(T, ["x", "y", "x1", "y1"], ["y", "x1"], A, A0)
    names = ["x", "y", "x1", "y1", "x'", "y1'"]
    p = model.parameter_values
    for j in range(2):
        agree(lhs[j], eom.c_[j], p, names)
        for i in range(2):
            agree(mass[j][i], eom.A_[j, i], p, names)
    # X_j + sum_a A_aj X_a with the potential -g (m y + m1 y1): (0, m1 g)
    agree(sp.Integer(0), eom.Qf_[0], p, names)
    agree(m1 * g, eom.Qf_[1], p, names)
    report = compare_forms(model, forms=["shulgin"], count=20)
    assert report.states == 20 and report.worst() < 1e-10, report


def test_rheonomic_constraint_adds_A0_and_stays_integrable():
    # y cos(wt) = x sin(wt): y' = x' tan(wt) + w (x cos(wt) + y sin(wt))/cos(wt); the terms
    # E_0(A_yx) - E_x(A_y0) = w/cos^2 - w/cos^2 cancel
    model = rotating_line()
    eom = derive(model, "shulgin")
    assert eom.unknowns == ("x''",)
    rel = [n for n in eom.notes if n.startswith("y' = ")]
    assert len(rel) == 1 and "w" in rel[0] and "x'" in rel[0]
    assert any("vanish identically" in n for n in eom.notes)
    x, y, xd, t, w, m, g = (S[n] for n in ["x", "y", "x'", "t", "w", "m", "g"])
    T = m / 2 * (xd ** 2 + S["y'"] ** 2)
    A = {("y", "x"): sp.tan(w * t)}
    A0 = {"y": w * (x * sp.cos(w * t) + y * sp.sin(w * t)) / sp.cos(w * t)}
    lhs, mass = shulgin_lhs(T, ["x", "y"], ["y"], A, A0)
    names = ["x", "y", "x'", "t"]
    p = model.parameter_values
    agree(lhs[0], eom.c_[0], p, names)
    agree(mass[0][0], eom.A_[0, 0], p, names)
    agree(-m * g * sp.tan(w * t), eom.Qf_[0], p, names)
    report = compare_forms(model, forms=["shulgin"], count=20)
    assert report.states == 20 and report.worst() < 1e-10, report


def test_nonlinear_and_second_order_constraints_are_refused():
    base = dict(coordinates=["x", "y", "z"], parameters={"m": 1.0, "a": 0.2},
                bodies=[Particle("P", "m", ["x", "y", "z"])])
    hamel = Model(name="Appell-Hamel", constraints=[Constraint.nonholonomic("cone", "z' - a*sqrt(x'^2 + y'^2)")],
                  **base)
    with pytest.raises(FormNotApplicable, match="'cone'.*not linear in the velocities.*--form maggi or --form appell"):
        derive(hamel, "shulgin")
    second = Model(name="second order", constraints=[Constraint.nonholonomic("acc", "x'' + y'' - a")], **base)
    with pytest.raises(FormNotApplicable, match="'acc' is of second order"):
        derive(second, "shulgin")


def test_knife_chain_8_keeps_its_coefficients_as_auxiliary_symbols_and_agrees_with_lagrange1():
    # written out, the k-th dependent velocity of the chain contains all the earlier ones (the
    # size doubles per link); Shulgin's coefficients and their derivatives become symbols
    # solved numerically, and the equations stay Shulgin's: T*, E_j, Voronets' terms
    from nonideal.gallery.knife_chain import build

    model = build(8)
    eom = derive(model, "shulgin")
    assert eom.auxiliaries and len(eom.unknowns) == 2
    symbols = {str(s) for s in eom.auxiliaries[0].symbols}
    assert "A[theta2,x]" in symbols and "dA[theta2,x]/dtheta1" in symbols
    assert any("auxiliary symbols" in n for n in eom.notes)
    assert any(n.startswith("Voronets' terms kept") for n in eom.notes)
    report = compare_forms(model, forms=["shulgin"], count=10)
    assert report.states == 10 and report.worst() < 1e-10, report


@pytest.mark.parametrize("build", [sleigh, painleve, rotating_line])
def test_auxiliary_coefficients_give_the_explicit_equations(build, monkeypatch):
    # the same derivation with A_aj, A_a0 and their derivatives as symbols (solved from the
    # constraints) gives the same A, c, Q_f at generic points, and the same Voronets terms
    from nonideal.equations.dynamics import dynamics_of
    from nonideal.equations.formalisms import shulgin
    from nonideal.equations.formalisms.base import _evaluate

    model = build()
    explicit = derive(model, "shulgin")
    monkeypatch.setattr(shulgin, "EXPLICIT_FACTOR", 0)
    monkeypatch.setattr(shulgin, "EXPLICIT_FLOOR", 0)
    implicit = derive(model, "shulgin")
    assert not explicit.auxiliaries and implicit.auxiliaries
    assert implicit.unknowns == explicit.unknowns
    assert [n for n in implicit.notes if "Voronets" in n] == [n for n in explicit.notes if "Voronets" in n]
    dyn = dynamics_of(model)
    rng = random.Random(3)
    points = [[rng.uniform(-1.2, 1.2) for _ in range(3 * dyn.n + 1)] for _ in range(5)]
    for X, Y in [(explicit.A_, implicit.A_), (explicit.c_, implicit.c_), (explicit.Qf_, implicit.Qf_),
                 (explicit.r_, implicit.r_)]:
        a = _evaluate(dyn, list(X), points)
        b = _evaluate(dyn, list(Y), points, implicit.auxiliaries)
        for u, v in zip(a, b):
            assert np.max(np.abs(u - v)) <= 1e-10 * max(1.0, np.max(np.abs(u)))


def test_without_eliminated_velocities_the_velocity_terms_are_the_kernels():
    # T* = T, E_j = d/dx_j: (1.64) is Lagrange's equations of T; the kernel's h is their
    # velocity term d/dt dT/dx_j' - dT/dx_j (without accelerations), built from the bodies
    from nonideal.gallery.nlink_pendulum import build

    model = build(4)
    eom, ref = derive(model, "shulgin"), derive(model, "lagrange1")
    assert eom.notes[0].startswith("no ideal constraint to eliminate")
    assert eom.A_ == ref.A_ and eom.c_ == ref.c_ and eom.Qf_ == ref.Qf_


def test_printing():
    eom = derive(sleigh(), "shulgin")
    text = eom.as_text()
    assert text.splitlines()[0].startswith("Shulgin's equations in redundant coordinates")
    assert "(1.61)-(1.64)" in text and "Voronets 1901" in text
    assert "T* = " in text and "note: y' = x'*sin(theta)/cos(theta)" in text
    assert "unknowns: x'', theta''" in text
    assert "% T* = " in eom.as_latex()
