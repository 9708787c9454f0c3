"""derive --form servo: Béghin's equations (Appell 1911, servo-constraints, (10) and (12)):
the controls kept as multipliers, their control-free combinations listed; the same
accelerations as Lagrange I; the control-free equations hold along the simulated motion."""

import numpy as np
import sympy as sp

from nonideal import gallery
from nonideal.cli import main
from nonideal.analysis.crosscheck import compare_forms
from nonideal.equations.formalisms import derive
from nonideal.gallery import friction_speed_regulator as reg
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR



def _free_residuals(eom, tr, k):
    """The control-free equations (12) at sample k of a trajectory."""
    coords = list(tr.coordinates)
    sub = {sp.Symbol(p): v for p, v in eom.model.parameter_values.items()}
    sub.update({sp.Symbol(c): tr.q[k, i] for i, c in enumerate(coords)})
    sub.update({sp.Symbol(c + "'"): tr.qd[k, i] for i, c in enumerate(coords)})
    sub.update({sp.Symbol(c + "''"): tr.qdd[k, i] for i, c in enumerate(coords)})
    sub[sp.Symbol("t")] = tr.t[k]
    return [float(v.xreplace(sub)) for key, v in eom.extras.items() if key.startswith("control_free")]


def test_parabola_control_free_equation_is_the_difference_of_the_two_equations():
    model = load_model(DATA_DIR / "servo_parabola.toml")
    eom = derive(model, "servo")
    free = [v for k, v in eom.extras.items() if k.startswith("control_free")]
    assert len(free) == 1                                 # n_dof - j = 2 - 1
    m, g = sp.symbols("m g")
    x2, y2 = sp.Symbol("x''"), sp.Symbol("y''")
    assert sp.simplify(free[0] - (m * x2 - m * y2 - m * g)) == 0 or \
        sp.simplify(free[0] + (m * x2 - m * y2 - m * g)) == 0
    tr = simulate(model, t_end=0.3)
    assert max(abs(r) for k in range(len(tr.t)) for r in _free_residuals(eom, tr, k)) < 1e-9


def test_regulator_control_free_equation_is_the_condition_of_dynamics():
    model = gallery.load(reg.NAME)
    eom = derive(model, "servo")
    assert any("acts through the dynamics" in n for n in eom.notes)
    tr = simulate(model, times=np.linspace(0, 1, 11))
    res = [r for k in range(len(tr.t)) for r in _free_residuals(eom, tr, k)]
    assert len(res) == 11 and max(abs(r) for r in res) < 1e-9
    assert compare_forms(model, forms=["servo"], count=5).worst() < 1e-10


def test_cli_prints_beghins_equations(capsys):
    code = main(["derive", str(gallery.model_path(reg.NAME)), "--form", "servo"])
    out = capsys.readouterr().out
    assert code == 0 and "Béghin" in out and "control_free_1" in out and "lambda_speed" in out


def test_gauss_principle_with_controls_agrees_with_lagrange1():
    # generalized Gauss with the controls' columns (Yushkov 1999, ch. III): an independent
    # null-space route, for a servo-constraint, one acting through the dynamics, a quasi-ideal one
    from nonideal.modeling.model import Constraint, Model
    quasi = Model(name="point on a line, quasi-ideal", coordinates=["x", "y"],
                  parameters={"m": 1.5, "g": 9.81, "k": 0.4, "alpha": 0.3, "beta": -0.2},
                  kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                  constraints=[Constraint("line", "y - k*x", transform=(("1", "alpha"), ("beta", "1")))],
                  initial={"x": 0, "y": 0, "x'": 1.0})
    for model in (load_model(DATA_DIR / "servo_parabola.toml"), gallery.load(reg.NAME), quasi):
        assert compare_forms(model, forms=["gauss"], count=6).worst() < 1e-10
