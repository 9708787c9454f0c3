"""Gibbs-Appell equations (nonideal/formalisms/appell.py): derived by differentiating the
acceleration energy S' composed with the constraints; the same equations as Maggi's."""

import numpy as np
import pytest
import symengine as se

from nonideal import Constraint, Model, Particle
from nonideal.analysis.crosscheck import compare_forms
from nonideal.equations.dynamics import dynamics_of
from nonideal.equations.formalisms import FORMS
from nonideal.analysis.derivation import derive
from nonideal.equations.formalisms.base import numeric_instances
from tests.systems import sleigh


def painleve_midpoint(th0=0.3, thd0=0.8):
    v0 = f"l*{thd0}/(2*sin({th0}))"
    return Model(
        name="Painleve two points, midpoint along the rod", coordinates=["x", "y", "x1", "y1"],
        parameters={"m": 1.0, "m1": 2.0, "l": 0.5, "g": 9.81},
        bodies=[Particle("M", "m", ["x", "y"]), Particle("M1", "m1", ["x1", "y1"])],
        gravity=["0", "g"],
        constraints=[Constraint.holonomic("line", "y"),
                     Constraint.holonomic("rod", "(x1 - x)^2 + (y1 - y)^2 - l^2"),
                     Constraint.nonholonomic("midpoint", "(x1 - x)*(y1' + y') - (y1 - y)*(x1' + x')")],
        initial={"x": 0.0, "y": 0.0, "x1": f"l*cos({th0})", "y1": f"l*sin({th0})",
                 "x'": v0, "y'": 0.0, "x1'": f"{v0} - l*sin({th0})*{thd0}",
                 "y1'": f"l*cos({th0})*{thd0}"},
    )


def servo_cart():
    return Model(
        name="cart and pendulum", coordinates=["s", "x", "y"],
        parameters={"M": 2.0, "m": 0.7, "l": 0.9, "g": 9.81, "A": 0.2, "w": 1.5, "th0": 0.4},
        bodies=[Particle("cart", "M", ["s", "0"]), Particle("bob", "m", ["x", "y"])],
        gravity=["0", "-g"],
        constraints=[Constraint.holonomic("rod", "(x - s)^2 + y^2 - l^2"),
                     Constraint.servo("program", "x - A*sin(w*t)", reaction=["1", "0", "0"])],
        initial={"s": "-l*sin(th0)", "x": 0.0, "y": "-l*cos(th0)", "s'": 0.0, "x'": "A*w"},
    )


def appell_hamel():
    return Model(
        name="Appell-Hamel", coordinates=["x", "y", "z"],
        parameters={"m": 1.5, "g": 9.81, "a": 0.2},
        bodies=[Particle("point", "m", ["x", "y", "z"])], gravity=["0", "0", "-g"],
        constraints=[Constraint.nonholonomic("cone", "z' - a*sqrt(x'^2 + y'^2)")],
        initial={"x": 0.0, "y": 0.0, "z": 0.0, "x'": 3.0, "y'": 4.0, "z'": 1.0},
    )


def _max_rel_difference(model, X, Y, count=6):
    """max |X - Y| / max |Y| over generic points (entries of two matrices of equal shape)."""
    dyn = dynamics_of(model)
    diff = [x - y for x, y in zip(X, Y)]
    ref = numeric_instances(dyn, list(Y), count=count, seed=3)
    got = numeric_instances(dyn, diff, count=count, seed=3)
    return max(float(np.nanmax(np.abs(d))) / max(float(np.nanmax(np.abs(r))), 1e-300)
               for d, r in zip(got, ref))


def test_registered():
    assert FORMS["appell"].name == "appell"


@pytest.mark.parametrize("build", [sleigh, painleve_midpoint, servo_cart, appell_hamel])
def test_same_equations_as_maggi(build):
    model = build()
    app, mag = derive(model, "appell"), derive(model, "maggi")
    assert app.unknowns == mag.unknowns and app.multipliers == mag.multipliers
    # A = Hessian of S' = V^T M V, c = dS'/dp' at p' = 0 = V^T (M w + h), Pi = V^T Q, rows alike
    assert _max_rel_difference(model, list(app.A_), list(mag.A_)) < 1e-12
    assert _max_rel_difference(model, list(app.c_), list(mag.c_)) < 1e-12
    assert _max_rel_difference(model, list(app.Qf_), list(mag.Qf_)) < 1e-12
    for X, Y in [(app.B_, mag.B_), (app.G_, mag.G_), (app.gamma_, mag.gamma_), (app.R_, mag.R_)]:
        assert X == Y


def test_mass_matrix_is_the_hessian_of_the_printed_acceleration_energy():
    eom = derive(sleigh(), "appell")
    S = se.sympify(eom.extras_["S"])
    p = [se.Symbol("x''"), se.Symbol("theta''")]
    assert {s.name for s in S.free_symbols} & {"y''"} == set()  # y'' eliminated by the knife
    # A and c are printed with sin^2 + cos^2 folded: equal to the derivatives of S identically,
    # checked at generic states
    zero = {pi: 0 for pi in p}
    diffs = []
    for i in range(2):
        for j in range(2):
            diffs.append(se.diff(S, p[i], p[j]) - eom.A_[i, j])
            assert se.diff(S, p[i], p[j], p[0]) == 0  # S' is quadratic in p'
        diffs.append(se.diff(S, p[i]).subs(zero) - eom.c_[i])
    syms = sorted(set().union(*(d.free_symbols for d in diffs)), key=str)
    fn = se.Lambdify(syms, diffs)
    rng = np.random.default_rng(3)
    for _ in range(5):
        assert np.max(np.abs(fn(rng.uniform(0.2, 1.2, len(syms))))) < 1e-12


def test_acceleration_energy_of_a_kinetic_expression_polar_coordinates():
    # T given as an expression: S from Appell's identity.  For a point in polar coordinates
    # S = m/2 [(r'' - r phi'^2)^2 + (r phi'' + 2 r' phi')^2], so A = diag(m, m r^2) and
    # c = (-m r phi'^2, 2 m r r' phi')
    model = Model(
        name="point in polar coordinates", coordinates=["r", "phi"], parameters={"m": 1.7, "k": 3.0},
        kinetic="m/2*(r'^2 + r^2*phi'^2)", potential="k/2*r^2",
        initial={"r": 1.0, "phi": 0.0, "r'": 0.0, "phi'": 1.0},
    )
    eom = derive(model, "appell")
    r, rd, phid, m = se.symbols("r r' phi' m")
    expected_A = [[m, 0], [0, m * r ** 2]]
    expected_c = [-m * r * phid ** 2, 2 * m * r * rd * phid]
    for i in range(2):
        assert se.expand(eom.c_[i] - expected_c[i]) == 0
        for j in range(2):
            assert se.expand(eom.A_[i, j] - expected_A[i][j]) == 0
    assert se.expand(eom.Qf_[0] + se.Symbol("k") * r) == 0


def test_auxiliary_velocity_coefficients_when_the_inverse_would_blow_up():
    from nonideal.gallery.knife_chain import build

    model = build(8)
    eom = derive(model, "appell")
    assert eom.auxiliaries  # V, w kept as symbols solved numerically
    report = compare_forms(model, forms=["appell"], count=20)
    assert report.states == 20 and report.worst() < 1e-10, report


def test_printing():
    eom = derive(painleve_midpoint(), "appell")
    text = eom.as_text()
    assert text.splitlines()[0].startswith("Gibbs-Appell equations")
    assert "Appell 1899" in text and "(1.65)" in text
    assert "note: S' = S with the dependent accelerations y'', x1'', y1'' eliminated" in text
    assert "unknowns: x''" in text
    latex = derive(sleigh(), "appell").as_latex()
    assert "% S = " in latex and "\\ddot{\\theta}" in latex


@pytest.mark.parametrize("name", ["beta", "gamma", "S"])
def test_parameters_named_like_sympy_functions_in_the_velocity_coefficients(name):
    """A parameter called beta, gamma or S multiplying a velocity in a nonholonomic constraint
    (Keldysh's psi' = alpha lam - beta psi phi1' form): the quasi-velocity forms read it as a
    symbol, not as SymPy's beta/gamma function or singleton registry, and agree with Lagrange I."""
    model = Model(name="symbol names", coordinates=["x", "y", "th"],
                  parameters={"m": 1.0, "J": 0.2, name: 0.7},
                  kinetic="m/2*(x'^2 + y'^2) + J/2*th'^2", potential="m*9.81*y",
                  constraints=[Constraint.nonholonomic("knife", f"y' - {name}*th*x'")],
                  initial={"x": 0.1, "y": 0.0, "th": 0.3, "x'": 1.0, "th'": 0.5})
    for form in ("kane", "maggi", "appell"):
        assert compare_forms(model, forms=[form], count=4).worst() < 1e-10
