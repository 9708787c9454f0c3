"""Lagrange's equations of the second kind (nonideal/formalisms/lagrange2.py): elimination of
the holonomic constraints by minimal coordinates, branches, transfer of forces, the remaining
rows, the map back to every acceleration, printing and the cases it refuses."""

import numpy as np
import pytest
import symengine as se
import sympy as sp

from nonideal import Constraint, FormNotApplicable, Model, Particle, PlanarBody
from nonideal.modeling.bodies import Force
from nonideal.equations.dynamics import dynamics_of
from nonideal.equations.formalisms import FORMS
from nonideal.analysis.derivation import derive
from nonideal.numeric.kernel import FormSystem, kernel_of, parameter_vector
from tests.systems import painleve


def values(expr, **point):
    """Numeric value of a SymEngine expression at named symbol values."""
    return float(se.sympify(expr).subs({se.Symbol(k.replace("_d", "'")): v for k, v in point.items()}))


def test_registered():
    assert FORMS["lagrange2"].name == "lagrange2"


def test_painleve_redundant_two_unknowns_and_the_substitution():
    eom = derive(painleve(), "lagrange2")
    assert eom.unknowns == ("x''", "y1''")
    assert eom.independent == ("x", "y1")
    assert eom.eliminated == ("line", "rod")
    assert eom.multipliers == ()
    assert eom.A_.shape == (2, 2)
    assert "y = 0" in eom.notes
    # of the two roots x1 = x -/+ sqrt(l^2 - y1^2) the one through the initial state (x1 > x)
    assert any(n.startswith("x1 = x + sqrt(l**2 - y1**2)") and "initial value x1 = 0.477668" in n
               for n in eom.notes), eom.notes
    # the reduced mass matrix: T = m x'^2/2 + m1 (x1'^2 + y1'^2)/2, x1' = x' - y1 y1'/c, c = sqrt(l^2 - y1^2)
    m, m1, l, y1 = 1.0, 2.0, 0.5, 0.2
    c = np.sqrt(l * l - y1 * y1)
    A = [[values(eom.A_[i, j], m=m, m1=m1, l=l, y1=y1) for j in range(2)] for i in range(2)]
    assert np.allclose(A, [[m + m1, -m1 * y1 / c], [-m1 * y1 / c, m1 * (1 + y1 * y1 / (c * c))]],
                       rtol=1e-14)


def test_acceleration_map_satisfies_the_constraints():
    # q'' = R a + r satisfies G q'' + gamma = 0 for any a: R spans the tangent space and r is
    # the second time derivative of the solved constraints
    model = painleve()
    eom = derive(model, "lagrange2")
    dyn = dynamics_of(model)
    rows = dyn.rows()
    rng = np.random.default_rng(1)
    l = 0.5
    for _ in range(5):
        x, y1 = rng.uniform(-1, 1), rng.uniform(-0.4, 0.4)
        qd_ind = rng.normal(size=2)
        x1 = x + np.sqrt(l * l - y1 * y1)
        x1d = qd_ind[0] - y1 * qd_ind[1] / np.sqrt(l * l - y1 * y1)
        subs = {se.Symbol("x"): x, se.Symbol("y"): 0.0, se.Symbol("x1"): x1, se.Symbol("y1"): y1,
                se.Symbol("x'"): qd_ind[0], se.Symbol("y'"): 0.0, se.Symbol("x1'"): x1d,
                se.Symbol("y1'"): qd_ind[1], se.Symbol("l"): l}
        R = np.array([[float(eom.R_[i, j].subs(subs)) for j in range(2)] for i in range(4)])
        r = np.array([float(eom.r_[i].subs(subs)) for i in range(4)])
        a = rng.normal(size=2)
        qdd = R @ a + r
        assert qdd[0] == a[0] and qdd[3] == a[1]
        for row in rows:
            G = np.array([float(se.sympify(g).subs(subs)) for g in row.G])
            gamma = float(se.sympify(row.gamma).subs(subs))
            assert abs(G @ qdd + gamma) < 1e-12


def test_kept_coordinates_and_branch_follow_the_user():
    eom = derive(painleve(), "lagrange2", independent=("x", "x1"))
    assert eom.unknowns == ("x''", "x1''")
    assert any(n.startswith("y1 = sqrt(") for n in eom.notes), eom.notes
    # the same system started below the line: the negative root
    eom = derive(painleve(th0=-0.3, thd0=0.8), "lagrange2", independent=("x", "x1"))
    assert any(n.startswith("y1 = -sqrt(") and "initial value y1 = -0.14776)" in n
               for n in eom.notes), eom.notes
    # the model's [forms] independent is used by default
    assert derive(painleve(independent=("x", "x1")), "lagrange2").unknowns == ("x''", "x1''")
    # fewer coordinates than kept ones (the reduced forms' choice): they are kept, the rest chosen
    assert "x1''" in derive(painleve(), "lagrange2", independent=("x1",)).unknowns


def test_wrong_number_of_kept_coordinates_is_refused():
    with pytest.raises(FormNotApplicable, match="lagrange2 keeps 2 coordinates"):
        derive(painleve(), "lagrange2", independent=("x", "x1", "y1"))
    with pytest.raises(FormNotApplicable, match="'xx' is not a coordinate"):
        derive(painleve(), "lagrange2", independent=("xx",))


def test_bead_on_a_parabola_energy_forces_and_loads_are_transferred():
    # T and V given as expressions, a declared generalized force on the eliminated y and a load
    # applied at the bead: after y = c x^2 the equation is the closed form
    #   m (1 + 4 c^2 x^2) x'' + 4 m c^2 x x'^2 = -2 c x m g + 2 c x F + P (1 + 2 c x)
    model = Model(
        name="bead on a parabola", coordinates=["x", "y"],
        parameters={"m": 0.8, "g": 9.81, "c": 0.6, "F": 1.3, "P": 0.4},
        kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y", forces={"y": "F"},
        loads=[Force("push", ["x", "y"], ["P", "P"])],
        constraints=[Constraint.holonomic("parabola", "y - c*x^2")],
        initial={"x": 0.5, "x'": 0.2},
    )
    eom = derive(model, "lagrange2")
    assert eom.unknowns == ("x''",)
    assert eom.notes[0] == "y = c*x**2"
    m, g, c, F, P = 0.8, 9.81, 0.6, 1.3, 0.4
    for x, xd in [(0.5, 0.2), (-1.1, 0.7), (0.3, -2.0)]:
        pt = dict(x=x, x_d=xd, m=m, g=g, c=c, F=F, P=P)
        assert values(eom.A_[0, 0], **pt) == pytest.approx(m * (1 + 4 * c * c * x * x), rel=1e-14)
        assert values(eom.c_[0], **pt) == pytest.approx(4 * m * c * c * x * xd * xd, rel=1e-14)
        assert values(eom.Qf_[0], **pt) == pytest.approx(
            -2 * c * x * m * g + 2 * c * x * F + P * (1 + 2 * c * x), rel=1e-14)


def test_rotating_line_rheonomic_closed_form():
    # the bead's distance r along the line y cos(wt) = x sin(wt): r'' = r w^2 - g sin(wt), so
    # with x = r cos(wt):  x'' = -g sin(wt) cos(wt) - 2 w r' sin(wt)
    w, g = 0.7, 9.81
    model = Model(
        name="bead on a rotating line", coordinates=["x", "y"],
        parameters={"m": 1.3, "w": w, "g": g},
        bodies=[Particle("P", "m", ["x", "y"])], gravity=["0", "-g"],
        constraints=[Constraint.holonomic("line", "y*cos(w*t) - x*sin(w*t)")],
        initial={"x": 0.8, "y": 0.0, "x'": 0.3, "y'": "0.8*w"},
    )
    eom = derive(model, "lagrange2")
    assert eom.unknowns == ("x''",)
    assert eom.notes[0] == "y = x*sin(t*w)/cos(t*w)"
    fs = FormSystem(eom)
    kernel, params = kernel_of(model), parameter_vector(model)
    for t, x, xd in [(0.0, 0.8, 0.3), (0.9, -0.4, 1.2), (1.7, 1.5, -0.6)]:
        c, s = np.cos(w * t), np.sin(w * t)
        r, rd = x / c, xd / c + x * w * s / c ** 2
        y, yd = r * s, rd * s + r * w * c
        a, mu, qdd = fs.solve(kernel.state_input(t, [x, y], [xd, yd], params))
        assert a[0] == pytest.approx(-g * s * c - 2 * w * rd * s, rel=1e-12)
        assert qdd[1] == pytest.approx((r * w * w - g * s) * s + 2 * rd * w * c - r * w * w * s, rel=1e-12)


def test_without_holonomic_constraints_it_is_lagrange1_in_routh_voss_form():
    model = Model(
        name="Chaplygin sleigh", coordinates=["x", "y", "theta"],
        parameters={"m": 2.0, "I": 0.3, "a": 0.4},
        bodies=[PlanarBody("sleigh", "m", "I", ["x + a*cos(theta)", "y + a*sin(theta)"], "theta")],
        constraints=[Constraint.nonholonomic("knife", "-x'*sin(theta) + y'*cos(theta)")],
        initial={"x": 0.0, "y": 0.0, "theta": 0.0, "x'": 1.0, "theta'": 1.5},
    )
    eom, ref = derive(model, "lagrange2"), derive(model, "lagrange1")
    assert "Routh-Voss" in eom.title and eom.title != ref.title
    assert eom.citation != ref.citation
    assert eom.unknowns == ref.unknowns and eom.multipliers == ("lambda_knife",)
    for name in ("A_", "c_", "Qf_", "B_", "G_", "gamma_", "R_", "r_"):
        assert getattr(eom, name) == getattr(ref, name), name


def test_servo_constraint_is_kept_with_its_multiplier():
    model = Model(
        name="cart and pendulum", coordinates=["s", "x", "y"],
        parameters={"M": 2.0, "m": 0.7, "l": 0.9, "g": 9.81, "A": 0.2, "w": 1.5, "th0": 0.4},
        bodies=[Particle("cart", "M", ["s", "0"]), Particle("bob", "m", ["x", "y"])],
        gravity=["0", "-g"],
        constraints=[Constraint.holonomic("rod", "(x - s)^2 + y^2 - l^2"),
                     Constraint.servo("program", "x - A*sin(w*t)", reaction=["1", "0", "0"])],
        initial={"s": "-l*sin(th0)", "x": 0.0, "y": "-l*cos(th0)", "s'": 0.0, "x'": "A*w"},
    )
    eom = derive(model, "lagrange2")
    assert eom.eliminated == ("rod",)
    assert eom.multipliers == ("lambda_program",)
    assert eom.unknowns == ("s''", "x''")
    assert eom.notes[0].startswith("y = -sqrt(")  # the bob hangs below the cart
    # reaction (1, 0, 0) by virtual work on (s, x); the program x = A sin(wt) differentiated twice
    assert list(eom.B_) == [1, 0] and list(eom.G_) == [0, 1]
    t, A, w = 0.7, 0.2, 1.5
    assert values(eom.gamma_[0], t=t, A=A, w=w) == pytest.approx(A * w * w * np.sin(w * t), rel=1e-14)


def test_zero_degrees_of_freedom_the_motion_is_the_program():
    model = Model(
        name="point on a prescribed circle", coordinates=["x", "y"], parameters={"m": 1.0, "w": 2.0},
        bodies=[Particle("P", "m", ["x", "y"])],
        constraints=[Constraint.holonomic("cx", "x - cos(w*t)"), Constraint.holonomic("cy", "y - sin(w*t)")],
        initial={"x": 1.0, "y": 0.0},
    )
    eom = derive(model, "lagrange2")
    assert eom.unknowns == () and eom.A_.shape == (0, 0)
    t = 0.4
    r = [values(e, t=t, w=2.0) for e in eom.r_]
    assert r == pytest.approx([-4 * np.cos(2 * t), -4 * np.sin(2 * t)], rel=1e-14)


def test_no_closed_form_is_not_applicable_and_says_what_to_do():
    model = Model(
        name="transcendental constraint", coordinates=["x", "y"], parameters={"m": 1.0},
        bodies=[Particle("P", "m", ["x", "y"])],
        constraints=[Constraint.holonomic("kepler", "x + sin(x) + y + sin(y) - 1")],
        initial={"x": 0.3},
    )
    with pytest.raises(FormNotApplicable) as exc:
        derive(model, "lagrange2")
    msg = str(exc.value)
    assert "'kepler'" in msg and "no closed-form solution" in msg
    assert "--form lagrange1" in msg and "--form maggi" in msg and "[forms] independent" in msg
    # the same system is fine in the forms that keep the redundant coordinates
    assert derive(model, "maggi").unknowns


def test_printing_names_the_form_the_source_and_the_substitution():
    eom = derive(painleve(), "lagrange2")
    text = eom.as_text()
    assert text.splitlines()[0].startswith("Lagrange equations of the second kind")
    assert "(1.55)-(1.56)" in text and "Yushkov 1999" in text
    assert "note: x1 = x + sqrt(l**2 - y1**2)" in text
    assert "T = " in text and "unknowns: x'', y1''" in text
    latex = eom.as_latex()
    assert "\\ddot{x}" in latex and "\\ddot{y_{1}}" in latex and "% T = " in latex
    d = eom.to_dict()
    assert d["eliminated"] == ["line", "rod"] and d["independent"] == ["x", "y1"]
    # the kernel's equations do not depend on the eliminated coordinates
    free = set().union(*[sp.sympify(e).free_symbols for e in eom.equations()])
    assert {s.name for s in free} & {"y", "x1", "y'", "x1'", "y''", "x1''"} == set()


def test_branch_through_the_completed_initial_state():
    # y1 not given: the library completes it from the rod (Newton from 0.1 gives y1 > 0 for
    # x1 - x = l cos(0.3)), and Lagrange II takes the root through that completed state
    base = painleve(th0=-0.3)
    initial = {k: v for k, v in base.initial.items() if k not in ("y1", "y1'")}
    eom = derive(base.replace(initial=initial), "lagrange2", independent=("x", "x1"))
    assert any(n.startswith("y1 = sqrt(") and "initial value y1 = 0.14776)" in n
               for n in eom.notes), eom.notes


def test_quasi_ideal_holonomic_constraint_is_kept():
    from nonideal.analysis.crosscheck import compare_forms

    model = Model(
        name="point on a plane and a quasi-ideal parabolic cylinder", coordinates=["x", "y", "z"],
        parameters={"m": 1.0, "g": 9.81, "c": 0.5, "al": 0.3, "be": 0.2},
        bodies=[Particle("P", "m", ["x", "y", "z"])], gravity=["0", "-g", "0"],
        constraints=[Constraint.holonomic("plane", "z - x/10"),
                     Constraint("curve", "y - c*x^2", transform=(("1", "al", "0"), ("be", "1", "0"),
                                                                  ("0", "0", "1")))],
        initial={"x": 0.4, "x'": 0.3},
    )
    eom = derive(model, "lagrange2")
    assert eom.eliminated == ("plane",) and eom.multipliers == ("lambda_curve",)
    report = compare_forms(model, forms=["lagrange2"], count=20)
    assert report.states == 20 and report.worst() < 1e-10
    from nonideal.numeric.consistency import complete_state
    from nonideal.modes.types import Mode
    from nonideal.modes.solver import ModeSolver

    kernel, params = kernel_of(model), parameter_vector(model)
    q, qd, _ = complete_state(kernel, model.numeric_initial(), params, 0.0)
    ref = ModeSolver(kernel, params, "lagrange1").solve(0.0, q, qd, Mode())
    mine = ModeSolver(kernel, params, "lagrange2").solve(0.0, q, qd, Mode())
    lam = ref.multiplier(kernel.row_index["curve"])
    assert abs(lam) > 1.0 and mine.direct["curve"] == pytest.approx(lam, rel=1e-12)


def test_the_branch_of_the_chart_can_be_chosen_at_a_state():
    # a pendulum in (x, y): x eliminated; the root follows the branch point's sign of x
    from nonideal.modeling.symbols import to_sp

    m = Model(name="pendulum", coordinates=["x", "y"], parameters={"l": 1.0, "g": 9.81},
              kinetic="(x'^2 + y'^2)/2", potential="g*y",
              constraints=[Constraint.holonomic("rod", "x^2 + y^2 - l^2")],
              initial={"x": 0.6, "y": -0.8, "x'": 0.0})
    x, y, l = sp.symbols("x y l")
    at_start = derive(m, "lagrange2", independent=("y",))
    there = derive(m, "lagrange2", independent=("y",), branch={"x": -0.6, "y": -0.8})
    assert sp.simplify(to_sp(at_start.extras_["chart"][0]) - (x - sp.sqrt(l**2 - y**2))) == 0
    assert sp.simplify(to_sp(there.extras_["chart"][0]) - (x + sp.sqrt(l**2 - y**2))) == 0
