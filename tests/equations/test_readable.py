"""The readable equations: exact (they parse back to the derived equations), folded (no
sin^2 + cos^2, angle sums written as cos(a - b)), grouped and factored like a textbook."""

from __future__ import annotations

import random

import pytest
import symengine as se
import sympy as sp

from nonideal import gallery
from nonideal.equations.formalisms import derive
from nonideal.equations.readable import Printer
from nonideal.gallery.nlink_pendulum import build as pendulum
from nonideal.modeling.expressions import parse_expression


def _fold(expr: str, coordinates=("a", "b")) -> str:
    P = Printer(coordinates)
    return P.expression(se.sympify(expr))


@pytest.mark.parametrize("expr, expected", [
    ("k*sin(a)**2 + k*cos(a)**2", "k"),
    ("m*sin(a)**2/cos(a)**2 + m", "m/cos(a)**2"),                       # tan^2 + 1
    ("sin(a)*sin(b) + cos(a)*cos(b)", "cos(a - b)"),
    ("cos(a)*cos(b) - sin(a)*sin(b)", "cos(a + b)"),
    ("sin(a)*cos(b) - cos(a)*sin(b)", "sin(a - b)"),
    ("sin(b)*cos(a) - sin(a)*cos(b)", "-sin(a - b)"),
    ("sin(a)*cos(b) + cos(a)*sin(b)", "sin(a + b)"),
    ("2*l*sin(a)**2 + 3*l*cos(a)**2", "l*(2 + cos(a)**2)"),                 # the common part
    ("l1*l2*m2*(sin(a)*sin(b) + cos(a)*cos(b)) + l1*l2*m3*(sin(a)*sin(b) + cos(a)*cos(b))",
     "l1*l2*(m2 + m3)*cos(a - b)"),
])
def test_identities_are_folded(expr, expected):
    assert _fold(expr) == expected


def _names(eom) -> dict:
    model = eom.model
    names = {"t": sp.Symbol("t")}
    for c in model.coordinates:
        for suffix in ("", "'", "''"):
            names[c + suffix] = sp.Symbol(c + suffix)
    for p in model.parameter_values:
        names[p] = sp.Symbol(p)
    for m in eom.multipliers:
        names[m] = sp.Symbol(m)
    return names


def _residuals(eom) -> list:
    """lhs - rhs of each equation, from the matrices."""
    a = sp.Matrix(eom.unknown_symbols)
    mu = sp.Matrix(eom.multiplier_symbols)
    out = []
    A, c, Q, B = eom.mass_matrix, eom.inertial_terms, eom.generalized_forces, eom.reaction_matrix
    for i in range(eom.k):
        r = (A[i, :] * a)[0] + c[i] - Q[i]
        if mu.shape[0]:
            r -= (B[i, :] * mu)[0]
        out.append(r)
    G, gamma = eom.constraint_jacobian, eom.constraint_bias
    for i in range(G.shape[0]):
        out.append((G[i, :] * a)[0] + gamma[i])
    return out


CASES = [("chaplygin-sleigh", "maggi"), ("chaplygin-sleigh", "appell"),
         ("painleve-two-points", "lagrange2"), ("painleve-two-points", "lagrange1"),
         ("spherical-pendulum-variable-length", "lagrange1"), ("appell-hamel", "appell"),
         ("nlink-pendulum", "lagrange1")]


@pytest.mark.parametrize("name, form", CASES)
def test_printed_equations_parse_back_to_the_derived_ones(name, form):
    eom = derive(gallery.load(name), form)
    names = _names(eom)
    lines = eom.readable()
    residuals = _residuals(eom)
    assert len(lines) == len(residuals)
    rng = random.Random(1)
    for line, ref in zip(lines, residuals):
        lhs, rhs = line.split(" = ")
        parsed = parse_expression(lhs, names, "lhs") - parse_expression(rhs, names, "rhs")
        for _ in range(3):
            values = {s: sp.Float(rng.uniform(0.2, 0.9)) for s in names.values()}
            got = complex(parsed.xreplace(values).evalf())
            want = complex(ref.xreplace(values).evalf())
            assert abs(got - want) <= 1e-10 * (1 + abs(want)), (line, got, want)


def test_pendulum_prints_like_a_textbook():
    eom = derive(pendulum(3), "lagrange1")
    text = eom.as_text()
    assert ("l3*m3*(l1*cos(q1 - q3)*q1'' + l2*cos(q2 - q3)*q2'' + l3*q3'' - l1*sin(q1 - q3)*q1'**2"
            " - l2*sin(q2 - q3)*q2'**2) = -g*l3*m3*sin(q3)") in text
    assert "l1*(l1*(m1 + m2 + m3)*q1'' + l2*(m2 + m3)*cos(q1 - q2)*q2''" in text
    assert "= -g*l1*(m1 + m2 + m3)*sin(q1)" in text
    assert "**2 + " not in text.replace("'**2 + ", "")       # no sin^2 + cos^2 left
    latex = eom.as_latex()
    assert r"\cos\left(q_{1} - q_{3}\right)" in latex and r"\ddot{q_{3}}" in latex
    d = eom.to_dict()
    assert d["equations"] == eom.readable()
    assert d["mass_matrix"][0][1] == "l1*l2*(m2 + m3)*cos(q1 - q2)"


def test_chaplygin_sleigh_maggi_has_no_pythagorean_leftovers():
    text = derive(gallery.load("chaplygin-sleigh"), "maggi").as_text()
    assert "(I + a**2*m)*theta''" in text
    assert "x''/cos(theta)**2" in text
    assert "sin(theta)**2 + " not in text and "a**2*cos(theta)**2" not in text
