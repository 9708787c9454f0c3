"""Linearization about equilibria and steady motions: closed forms, the constraint manifold
(no spurious zero eigenvalues), ignorable coordinates, Newton, symbolic conditions, errors."""

import numpy as np
import pytest
import sympy as sp
from scipy.linalg import expm

from nonideal.analysis.stability.linearize import linearize
from nonideal.errors import LinearizationUndefined, ModelError, NotAnEquilibrium
from nonideal.modeling.bodies import Particle
from nonideal.modeling.model import Constraint, Model
from nonideal.simulation import simulate

G, L = 9.81, 2.0


def pendulum():
    return Model("pendulum", ["th"], {"g": G, "l": L}, kinetic="l^2*th'^2/2", potential="-g*l*cos(th)")


def cartesian_pendulum():
    return Model("pendulum in x, y", ["x", "y"], {"g": G, "l": L, "m": 1.0}, kinetic="m*(x'^2 + y'^2)/2",
                 potential="m*g*y", constraints=[Constraint.holonomic("rod", "x^2 + y^2 - l^2")],
                 initial={"x": 0.3, "y": -1.9})


def cart_pendulum(M=2.0, m=0.5, l=0.8):
    return Model("cart-pendulum", ["x", "th"], {"M": M, "m": m, "l": l, "g": G, "u": 0.0},
                 bodies=[Particle("cart", "M", ["x", "0"]), Particle("bob", "m", ["x + l*sin(th)", "l*cos(th)"])],
                 gravity=["0", "-g"], forces={"x": "u"})


def test_pendulum_newton_finds_the_bottom_and_the_frequency():
    lin = linearize(pendulum(), at={"th": 0.3})
    assert abs(lin.q["th"]) < 1e-9 and lin.residual == pytest.approx(G / L * np.sin(0.3), rel=1e-9)
    assert lin.variables == ("th", "th'")
    w = np.sqrt(G / L)
    assert np.allclose(sorted(lin.eigenvalues.imag), [-w, w], rtol=1e-10) and np.all(lin.eigenvalues.real == 0)
    assert lin.verdict == "critical" and lin.frequencies == pytest.approx((w,), rel=1e-10)
    top = linearize(pendulum(), at={"th": 3.0})
    assert top.q["th"] == pytest.approx(np.pi, abs=1e-9)
    assert top.verdict == "unstable" and max(top.eigenvalues.real) == pytest.approx(w, rel=1e-10)


def test_holonomic_constraint_gives_no_spurious_eigenvalue():
    lin = linearize(cartesian_pendulum(), at={"x": 0.3})
    assert lin.variables == ("x", "x'") and lin.dependent == ("y", "y'")
    assert lin.q["y"] == pytest.approx(-L, abs=1e-9)
    w = np.sqrt(G / L)
    assert len(lin.eigenvalues) == 2
    assert np.allclose(sorted(lin.eigenvalues.imag), [-w, w], rtol=1e-9)
    # the multiplier's curvature term is in the stiffness: the same frequency as in th
    assert lin.frequencies == pytest.approx((w,), rel=1e-9)


def test_cart_pendulum_closed_form_ignorable_cart_and_controllability():
    M, m, l = 2.0, 0.5, 0.8
    lin = linearize(cart_pendulum(M, m, l), controls=["u"])
    assert lin.ignorable == ("x",) and lin.variables == ("th", "x'", "th'")
    s2 = G * (M + m) / (M * l)          # inverted pendulum on a free cart
    assert max(lin.eigenvalues.real) == pytest.approx(np.sqrt(s2), rel=1e-10)
    assert lin.verdict == "unstable"
    kept = linearize(cart_pendulum(M, m, l), controls=["u"], keep=["x"])
    assert kept.variables == ("x", "th", "x'", "th'")
    assert kept.controllability == {"rank": 4, "n": 4}
    iu = kept.variables.index("x'")
    assert kept.B[iu, 0] == pytest.approx(1 / M, rel=1e-12)   # x'' = u/M at th = 0


def test_symbolic_conditions_in_named_parameters():
    lin = linearize(pendulum(), at={"th": 0.1}, symbolic=["g", "l"])
    g, l = sp.symbols("g l")
    assert sp.simplify(lin.A_symbolic - sp.Matrix([[0, 1], [-g / l, 0]])) == sp.zeros(2, 2)
    assert sp.simplify(lin.characteristic_polynomial - (sp.Symbol("s") ** 2 + g / l)) == 0


def test_perturbation_follows_the_linear_solution_with_a_constraint():
    model = cartesian_pendulum()
    lin = linearize(model, at={"x": 0.0})
    eps, times = 1e-5, np.linspace(0.0, 2.0, 5)
    traj = simulate(model.replace(initial={"x": 0.0, "x'": eps, "y": -L}), times=times)
    lin_x = [(expm(lin.A * t) @ np.array([0.0, eps]))[0] for t in times]
    assert np.max(np.abs(traj.q[:, 0] - lin_x)) < 1e-3 * eps


def test_not_an_equilibrium_names_the_residual_and_the_fix():
    with pytest.raises(NotAnEquilibrium) as err:
        linearize(pendulum(), at={"th": 0.5}, exact=True)
    text = str(err.value)
    assert "th'' = " + f"{-G / L * np.sin(0.5):.6g}" in text and "Fix:" in text and "--exact" in text
    pushed = Model("pushed", ["x"], {"f": 1.0}, kinetic="x'^2/2", forces={"x": "f"})
    with pytest.raises(NotAnEquilibrium, match="did not converge"):
        linearize(pushed, at={"x": 0.0})
    with pytest.raises(ModelError, match="at rest"):
        linearize(pendulum(), at={"th'": 1.0})
    with pytest.raises(ModelError, match="not a parameter"):
        linearize(pendulum(), symbolic=["gg"])


def test_dependent_constraint_rows_make_the_linearization_undefined():
    model = Model("doubled", ["x", "y"], {"l": 1.0}, kinetic="(x'^2 + y'^2)/2", potential="y",
                  constraints=[Constraint.holonomic("a", "x^2 + y^2 - l^2"),
                               Constraint.holonomic("b", "2*x^2 + 2*y^2 - 2*l^2")],
                  initial={"x": 0.0, "y": -1.0})
    with pytest.raises(LinearizationUndefined, match="dependent"):
        linearize(model, at={"x": 0.0, "y": -1.0})


def test_a_given_dependent_velocity_is_not_silently_replaced():
    """The rolling disk's x' follows from psi', theta', phi' (rolling): a steady state asked with
    x' = 9 while the constraints give x' = r phi' cos(psi) is refused, naming the velocity and
    the independent ones -- it must never be linearized about another state."""
    from nonideal import ModelError, gallery
    from nonideal.analysis.stability.linearize import linearize

    model = gallery.load("rolling-disk")
    with pytest.raises(ModelError, match=r"x' = 9 cannot be held.*psi', theta', phi'"):
        linearize(model, about="steady", at={"x'": 9.0})
    # the value the constraints give is accepted
    r, w = model.parameter_values["r"], 5.0
    assert linearize(model, about="steady", at={"phi'": w, "x'": r * w}).verdict
