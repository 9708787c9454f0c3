"""Briskin et al. 2021, sec. 3.1: a point on a line with a quasi-ideal constraint -- the
reactions (3.5), accelerations (3.6), heat (3.7), the work (3.8, corrected: G l (beta k^2 -
alpha)/D) and the minimum of I = |A| + chi W (3.10) against closed forms, and the split of the
reaction into its ideal and control parts."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.studies.quasi_ideal import actuator_heat, criterion, design_measures
from nonideal.errors import ModelError
from nonideal.gallery.briskin_point_on_line import (build, closed_form, criterion_of_u,
                                                    optimum_closed_form)
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import cli_json

PATH = gallery.model_path("briskin-point-on-line")
CASES = [(0.0, 0.0), (0.3, -0.4), (-1.0, 2.0), (1.5, -2.0), (0.45, 2.0)]


@pytest.mark.parametrize("alpha,beta", CASES)
def test_reactions_and_accelerations_3_5_3_6(alpha, beta):
    model = load_model(PATH, parameters={"alpha": alpha, "beta": beta})
    cf = closed_form(model.parameter_values, 1.0)
    ev = evaluate(model).to_dict()
    # the row's multiplier mu (R = adj(A) grad f mu) and the paper's lambda = det(A) mu
    assert ev["multipliers"]["line"] == pytest.approx(cf["mu"], rel=1e-12)
    line = ev["reactions"]["line"]
    assert line["det_A"] == pytest.approx(1 - alpha * beta, rel=1e-12, abs=1e-15)
    assert line["lambda"] == pytest.approx(cf["lambda"], rel=1e-12, abs=1e-12)
    assert ev["reactions"]["line"]["generalized"] == pytest.approx([cf["R_x"], cf["R_y"]], rel=1e-12, abs=1e-12)
    assert [ev["qddot"]["x"], ev["qddot"]["y"]] == pytest.approx([cf["a_x"], cf["a_y"]], rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("alpha,beta", CASES[1:4])
def test_heat_3_7_and_work_3_8_corrected(alpha, beta):
    model = load_model(PATH, parameters={"alpha": alpha, "beta": beta})
    p = model.parameter_values
    cf = closed_form(p, 1.0)
    m = design_measures(model, t_end=1.0)
    assert m["heat"] == pytest.approx(cf["heat"], rel=1e-11)
    assert m["work"] == pytest.approx(cf["work"], rel=1e-10)
    assert m["criterion"] == pytest.approx(abs(cf["work"]) + cf["heat"], rel=1e-11)
    # the printed (3.8), l (beta k - alpha)/D, is not the work (it drops G, and k^2 -> k)
    assert abs(cf["work_printed"] - cf["work"]) > 0.1 * abs(cf["work"])
    # energy balance: the reactions' work is the kinetic energy gained minus the work of G
    ax, k, l = cf["a_x"], p["k"], cf["l"]
    assert cf["work"] == pytest.approx(p["m"] * ax * (1 + k * k) * l - p["G"] * k * l, rel=1e-12)


def test_ideal_and_control_parts_of_the_reaction():
    """The ideal part is G (k, 1)/(1 + k^2) whatever the transform; the control part lies along
    the line; at alpha = beta k^2 it vanishes (the ideal reaction)."""
    data = cli_json("evaluate", PATH, "--set", "alpha=0.3", "--set", "beta=-0.4", "--json")
    line = data["reactions"]["line"]
    assert line["kind"] == "quasi-ideal"
    G, k = 9.81, 0.5
    assert line["ideal_part"] == pytest.approx([G * k / (1 + k * k), G / (1 + k * k)], rel=1e-12)
    control = np.array(line["control_part"])
    assert abs(control[0] * k + control[1]) < 1e-12 and np.linalg.norm(control) > 1
    assert np.array(line["ideal_part"]) + control == pytest.approx(line["generalized"], rel=1e-12)
    ideal = evaluate(load_model(PATH, parameters={"beta": 0.8, "alpha": 0.8 * k * k})).to_dict()
    assert ideal["reactions"]["line"]["control_part"] == pytest.approx([0, 0], abs=1e-12)


def test_heat_rate_and_its_running_integral():
    """Constant reactions: the heat rate mu_x R_x^2 + mu_y R_y^2 at every sample, its running
    integral linear in time (the model built with the Python API, losses given there)."""
    model = build(alpha=0.3, beta=-0.4)
    traj = simulate(model, times=np.linspace(0, 1, 101))
    heat = actuator_heat(model, traj)
    rate = heat["rate"]["line"]
    assert rate == pytest.approx(rate[0], rel=1e-12)  # constant reactions: a constant rate
    assert heat["total"][-1] == pytest.approx(rate[0] * 1.0, rel=1e-12)
    assert heat["heat"]["line"][50] == pytest.approx(rate[0] * 0.5, rel=1e-12)


def test_losses_are_expressions_in_the_parameters(tmp_path):
    text = PATH.read_text().replace('losses = ["mu_x", "mu_y"]', 'losses = ["mu_x", "x"]')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    with pytest.raises(ModelError, match="losses must be numbers or expressions in the parameters"):
        load_model(bad)
    bad.write_text(PATH.read_text().replace('losses = ["mu_x", "mu_y"]', 'losses = ["mu_x"]'))
    with pytest.raises(ModelError, match="losses"):
        load_model(bad)


def test_criterion_depends_on_the_reaction_direction_only():
    """I(alpha, beta) = I(u) with u = R_x: two transforms with the same R_x give the same I."""
    p = load_model(PATH).parameter_values
    a = closed_form({**p, "alpha": 0.3, "beta": -0.4}, 1.0)
    # beta' chosen so that R_x is the same at alpha' = -0.2
    G, k = p["G"], p["k"]
    u = a["R_x"]
    alpha2 = -0.2
    beta2 = ((1 + k * k - k * alpha2) - G * (k - alpha2) / u) / k
    b = closed_form({**p, "alpha": alpha2, "beta": beta2}, 1.0)
    assert b["R_x"] == pytest.approx(u, rel=1e-12)
    assert b["criterion"] == pytest.approx(a["criterion"], rel=1e-12)
    assert criterion_of_u(u, p, 1.0) == pytest.approx(criterion(a["work"], a["heat"]), rel=1e-12)


@pytest.mark.slow
def test_minimum_of_the_criterion_3_10():
    from nonideal.analysis.studies.design import minimize_criterion
    from nonideal.analysis.studies.sweep import parse_vary

    p = {**load_model(PATH).parameter_values, "mu_x": 0.2}
    exact = optimum_closed_form(p, 1.0)
    u = np.linspace(-20, 20, 40001)
    assert exact["criterion"] == pytest.approx(criterion_of_u(u, p, 1.0).min(), rel=1e-6)
    best = minimize_criterion(PATH, [parse_vary("alpha=-1:1:5"), parse_vary("beta=-1:1:5")],
                              settings={"mu_x": "0.2"})
    assert best.value == pytest.approx(exact["criterion"], rel=1e-7)
    assert best.value <= best.grid_value
    at = closed_form({**p, **best.x}, 1.0)
    assert at["R_x"] == pytest.approx(exact["u"], rel=1e-3)


def test_simulate_reports_the_heat_next_to_the_work():
    data = cli_json("simulate", PATH, "--set", "alpha=0.3", "--set", "beta=-0.4", "--json")
    cf = closed_form({**load_model(PATH).parameter_values, "alpha": 0.3, "beta": -0.4}, 1.0)
    assert data["actuator_heat"]["total"] == pytest.approx(cf["heat"], rel=1e-11)
    assert data["actuator_heat"]["by_constraint"] == {"line": pytest.approx(cf["heat"], rel=1e-11)}
    assert data["energy"]["reaction_work"][-1] == pytest.approx(cf["work"], rel=1e-10)


def test_singular_transform_alpha_beta_1_is_computed():
    """alpha = -0.5, beta = -2 (alpha beta = 1, a grid point of figs. 2-4 at k = 0.5): A is
    singular and R = A^-1 grad f lambda does not exist, but the definition A R = lambda grad f
    (1.3) fixes the motion: R along adj(A) grad f = (k - alpha, 1 - beta k) = (1, 2) with
    lambda = 0.  R = G (1, 2)/D, D = 1 + k^2 - k (alpha + beta) = 2.5: (3.924, 7.848), mu = G/D."""
    G = 9.81
    data = cli_json("evaluate", PATH, "--set", "alpha=-0.5", "--set", "beta=-2", "--json")
    line = data["reactions"]["line"]
    assert line["generalized"] == pytest.approx([3.924, 7.848], rel=1e-12)
    assert data["multipliers"]["line"] == pytest.approx(G / 2.5, rel=1e-12)
    assert line["det_A"] == 0.0 and line["lambda"] == 0.0
    # the point accelerates along the line: x'' = R_x/m, y'' = R_y/m - G/m = -k x''
    assert [data["qddot"]["x"], data["qddot"]["y"]] == pytest.approx([3.924, -1.962], rel=1e-12)
    # R solves the definition: A R = lambda grad f = 0
    A = np.array([[1, -0.5], [-2, 1]])
    assert A @ np.array(line["generalized"]) == pytest.approx([0, 0], abs=1e-12)
    # and the motion runs: work and heat as in the closed form (it holds at alpha beta = 1)
    cf = closed_form({**load_model(PATH).parameter_values, "alpha": -0.5, "beta": -2.0}, 1.0)
    sim = cli_json("simulate", PATH, "--set", "alpha=-0.5", "--set", "beta=-2", "--json")
    assert sim["energy"]["reaction_work"][-1] == pytest.approx(cf["work"], abs=1e-9)
    assert sim["actuator_heat"]["total"] == pytest.approx(cf["heat"], rel=1e-11)


def test_alpha_beta_to_1_converges_to_the_singular_motion():
    """alpha beta -> 1 along beta = 1/alpha - eps (alpha = -0.5): R, mu and the accelerations
    converge continuously to the values at alpha beta = 1, and lambda = det(A) mu -> 0 linearly
    in det A."""
    at_one = evaluate(load_model(PATH, parameters={"alpha": -0.5, "beta": -2.0})).to_dict()
    R1 = np.array(at_one["reactions"]["line"]["generalized"])
    gaps = []
    for eps in (1e-1, 1e-2, 1e-3, 1e-4, 1e-6):
        beta = -2.0 - eps
        ev = evaluate(load_model(PATH, parameters={"alpha": -0.5, "beta": beta})).to_dict()
        line = ev["reactions"]["line"]
        cf = closed_form({**load_model(PATH).parameter_values, "alpha": -0.5, "beta": beta}, 1.0)
        assert line["generalized"] == pytest.approx([cf["R_x"], cf["R_y"]], rel=1e-12)
        assert line["det_A"] == pytest.approx(-0.5 * eps, rel=1e-9)
        assert line["lambda"] == pytest.approx(line["det_A"] * ev["multipliers"]["line"], rel=1e-12)
        gaps.append(float(np.max(np.abs(np.array(line["generalized"]) - R1))))
    # |R(eps) - R(0)| = O(eps): each step of 10 in eps shrinks the gap about tenfold
    assert gaps[-1] < 1e-5 and all(b < 0.2 * a for a, b in zip(gaps, gaps[1:]))


@pytest.mark.parametrize("alpha, beta, expect", [
    (0.5, 2.0, "adj(A) grad f = 0"),
    (0.5, 2.0, "the reaction is indeterminate"),
])
def test_singular_transform_without_direction_is_explained(alpha, beta, expect):
    """alpha = 0.5, beta = 2: det A = 0 and adj(A) grad f = 0 -- grad f is in the range of A,
    A R = lambda grad f leaves a family of reactions (and D = 0).  The message says which, not
    "not differentiable ... gradient NaN"."""
    from nonideal.errors import MechanicsError

    model = load_model(PATH, parameters={"alpha": alpha, "beta": beta})
    with pytest.raises(MechanicsError) as err:
        evaluate(model)
    text = str(err.value)
    assert "transform A is singular (det A = 0)" in text and expect in text
    assert "not differentiable" not in text
