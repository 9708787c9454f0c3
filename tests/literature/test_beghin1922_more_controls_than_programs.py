"""Béghin's indeterminate case r < j (Appell 1911, servo-constraints): one program, two control
directions; the controls are chosen by a stated rule -- least norm by default, least
``u^T W u`` with a given cost -- and checked against the closed form of that minimization."""

import numpy as np
import pytest

from nonideal.analysis.checks import check_model
from nonideal.errors import ModelError
from nonideal.modeling.model import Constraint, Model
from nonideal.modeling.modelfile import model_from_dict
from nonideal.simulation.hybrid import simulate

M, G = 2.0, 9.81
A = np.array([1 / np.sqrt(2), 1.0])       # the two directions' y-components: d1 = (1, 1)/sqrt(2), d2 = (0, 1)


def _model(cost=None):
    return Model(name="climb at constant speed with two thrusters", coordinates=["x", "y"],
                 parameters={"m": M, "g": G, "v": 1.0},
                 kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
                 constraints=[Constraint("climb", "y' - v", "servo",
                                         controls=(("1/sqrt(2)", "1/sqrt(2)"), ("0", "1")), cost=cost)],
                 initial={"x": 0, "y": 0, "x'": 0, "y'": 1.0}, simulation={"t_end": 1.0})


@pytest.mark.parametrize("weights", [None, (1.0, 4.0), (3.0, 0.5)])
def test_least_cost_controls_match_the_closed_form(weights):
    cost = None if weights is None else (((str(weights[0]), "0"), ("0", str(weights[1]))))
    tr = simulate(_model(cost), times=np.linspace(0, 1, 5))
    W = np.diag(weights or (1.0, 1.0))
    # the program y'' = 0 needs a . u = m g: u = W^-1 a (m g)/(a W^-1 a)
    u = np.linalg.solve(W, A) * M * G / (A @ np.linalg.solve(W, A))
    c = tr.controls["climb"]
    assert np.max(np.abs(c["u_1"] - u[0])) < 1e-10 and np.max(np.abs(c["u_2"] - u[1])) < 1e-10
    assert np.max(np.abs(tr.qdd[:, 1])) < 1e-10                      # the program holds
    assert np.max(np.abs(tr.qdd[:, 0] - u[0] / np.sqrt(2) / M)) < 1e-10
    # every other split of m g between the thrusters costs more
    for s in (-0.1, 0.1):
        other = u + s * np.array([A[1], -A[0]])
        assert other @ W @ other > u @ W @ u


def test_check_states_the_rule_and_the_model_file_accepts_columns():
    data = {"model": {"name": "two thrusters", "format": 1},
            "parameters": {"m": M, "g": G, "v": 1.0}, "coordinates": {"q": ["x", "y"]},
            "energy": {"kinetic": "m/2*(x'^2 + y'^2)", "potential": "m*g*y"},
            "constraints": [{"name": "climb", "type": "servo", "expr": "y' - v",
                             "reaction": [["1/sqrt(2)", "1/sqrt(2)"], ["0", "1"]],
                             "cost": [[1, 0], [0, 4]]}],
            "initial": {"x": 0, "y": 0, "x'": 0, "y'": 1.0}}
    report = check_model(model_from_dict(data, "<test>"))
    assert "r = 1 program(s), j = 2 control direction(s): indeterminate" in report.determinacy
    assert "least cost u^T W u" in report.determinacy
    data["constraints"][0]["cost"] = [[1, 2], [2, 1]]
    with pytest.raises(ModelError, match="cost must be positive definite"):
        model_from_dict(data, "<test>")
    data["constraints"][0]["cost"] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    with pytest.raises(ModelError, match="cost must be 2x2"):
        model_from_dict(data, "<test>")


def test_least_force_in_the_inverse_mass_metric_is_the_ideal_reaction():
    # Yushkov 1999, ch. III: among the forces that enforce a program, the one least in the
    # metric of M^-1 (Gauss) is the ideal reaction.  A point of masses (m1, m2) along x and y
    # (anisotropic), the program x^2/4 + y^2 - 1 = 0, controls along both axes
    def model(constraint):
        return Model(name="ellipse", coordinates=["x", "y"], parameters={"m1": 1.0, "m2": 3.0, "g": 9.81},
                     kinetic="m1/2*x'^2 + m2/2*y'^2", potential="m2*g*y", constraints=[constraint],
                     initial={"x": 2.0, "y": 0.0, "y'": 0.8}, simulation={"t_end": 1.0})
    times = np.linspace(0, 1, 6)
    ideal = simulate(model(Constraint.holonomic("path", "x^2/4 + y^2 - 1")), times=times)
    gauss = simulate(model(Constraint("path", "x^2/4 + y^2 - 1", "servo", controls=(("1", "0"), ("0", "1")),
                                      cost=(("1/m1", "0"), ("0", "1/m2")))), times=times)
    assert np.max(np.abs(gauss.q - ideal.q)) < 1e-9
    plain = simulate(model(Constraint("path", "x^2/4 + y^2 - 1", "servo", controls=(("1", "0"), ("0", "1")))),
                     times=times)
    assert np.max(np.abs(plain.q - ideal.q)) > 1e-3           # least Euclidean norm: another force
    # the least Euclidean-norm force, M^-1 G^T mu here, is not along the path's normal G^T
    u = np.column_stack([plain.controls["path"]["u_1"], plain.controls["path"]["u_2"]])
    grad = np.column_stack([plain.q[:, 0] / 2, 2 * plain.q[:, 1]])
    cross = u[:, 0] * grad[:, 1] - u[:, 1] * grad[:, 0]
    assert np.max(np.abs(cross)) > 1e-3


def test_least_norm_controls_with_a_non_ideal_constraint_beside_them():
    """The least-cost controls need P^T G^T, P the compliance under the other constraints; P is
    not symmetric when another constraint is realized along a direction of its own.  Here
    z' = x' is kept by a force along z alone, so a force along z moves nothing and the program
    z' = c t can only be kept through x: x'' = (u1 + u2)/(sqrt(2) m) = c, the least-norm
    controls u1 = u2 = m c/sqrt(2), y'' = 0.  (With P G^T the program's direction vanished.)"""
    c = 0.7
    model = Model(name="program reached through a non-ideal constraint", coordinates=["x", "y", "z"],
                  parameters={"m": M, "c": c},
                  kinetic="m/2*(x'^2 + y'^2 + z'^2)",
                  constraints=[Constraint("follow", "z' - x'", "servo", reaction=("0", "0", "1")),
                               Constraint("program", "z' - c*t", "servo",
                                          controls=(("1/sqrt(2)", "1/sqrt(2)", "0"),
                                                    ("1/sqrt(2)", "-1/sqrt(2)", "0")))],
                  initial={"x": 0, "y": 0, "z": 0, "x'": 0, "y'": 0, "z'": 0},
                  simulation={"t_end": 1.0})
    tr = simulate(model, times=np.linspace(0, 1, 5))
    u = tr.controls["program"]
    assert np.max(np.abs(u["u_1"] - M * c / np.sqrt(2))) < 1e-10
    assert np.max(np.abs(u["u_2"] - M * c / np.sqrt(2))) < 1e-10
    assert np.allclose(tr.qdd, [[c, 0.0, c]] * 5, atol=1e-10)
