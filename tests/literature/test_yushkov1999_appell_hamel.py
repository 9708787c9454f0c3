"""The Appell-Hamel nonlinear nonholonomic constraint z' = a sqrt(x'^2 + y'^2) (Chetaev's rule):
lambda = m g/(1 + a^2), s(t) = s0 - g a t/(1 + a^2), constant direction, energy conserved."""

import numpy as np
import pytest

from nonideal import FORMS, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.appell_hamel import build, closed_form, end_time
from tests.helpers import cli_json as _cli

NAME = "appell-hamel"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]
M, G, A = 1.5, 9.81, 0.2


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 2.0, 41))


def test_multiplier_and_reaction_direction(model):
    ev = evaluate(model)
    lam = M * G / (1 + A * A)
    assert lam == pytest.approx(14.149038461538, abs=1e-11)
    assert ev.multipliers["cone"] == pytest.approx(lam, rel=1e-13)
    # Chetaev: R = lambda (-a x'/s, -a y'/s, 1) with (x', y') = (3, 4), s = 5
    assert np.allclose(ev.reactions["cone"]["generalized"], lam * np.array([-A * 0.6, -A * 0.8, 1.0]),
                       atol=1e-12)
    assert ev.qdd[2] == pytest.approx(-G * A * A / (1 + A * A), rel=1e-13)


def test_closed_form_motion(traj):
    q_cf, qd_cf = closed_form(traj.t, G, A, 3.0, 4.0)
    assert np.max(np.abs(traj.q - q_cf)) < 1e-10
    assert np.max(np.abs(traj.qd - qd_cf)) < 1e-10
    s = np.hypot(traj.velocity("x"), traj.velocity("y"))
    assert np.allclose(s, 5.0 - G * A * traj.t / (1 + A * A), atol=1e-10)
    assert s[-1] == pytest.approx(1.226923076923, abs=1e-10)
    assert np.allclose(traj.multipliers["cone"], M * G / (1 + A * A), atol=1e-10)
    # the horizontal direction does not turn
    assert np.allclose(np.arctan2(traj.velocity("y"), traj.velocity("x")), np.arctan2(4.0, 3.0), atol=1e-12)
    assert end_time(G, A, 3.0, 4.0) == pytest.approx(2.650357, abs=1e-6)


def test_energy_conserved_though_the_reaction_has_a_vertical_part(traj):
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8
    E = traj.energy["energy"]
    assert np.max(np.abs(E - E[0])) < 1e-9 * abs(E[0])
    assert np.max(np.abs(traj.energy["reaction_work"])) < 1e-9
    # the vertical component alone does lambda * (z - z0) > 0
    assert M * G / (1 + A * A) * traj.coordinate("z")[-1] > 17.0


@pytest.mark.parametrize("a", [0.05, 1.0, 3.0])
def test_other_slopes(a):
    tr = simulate(build(a=a), t_end=0.6, times=[0.0, 0.3, 0.6])   # t* = s0 (1 + a^2)/(g a) > 1 s
    q_cf, qd_cf = closed_form(tr.t, G, a, 3.0, 4.0)
    assert np.max(np.abs(tr.q - q_cf)) < 1e-10
    assert np.allclose(tr.multipliers["cone"], M * G / (1 + a * a), rtol=1e-10)


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,1,2", "--json")
    s = np.hypot(sim["qdot"]["x"], sim["qdot"]["y"])
    assert np.allclose(s, 5.0 - G * A * np.array([0, 1, 2]) / (1 + A * A), atol=1e-10)
    assert np.allclose(sim["multipliers"]["cone"], 14.149038461538, atol=1e-9)
    ev = _cli("evaluate", path, "--at", "x'=0, y'=2, z'=0.4", "--json")
    assert ev["multipliers"]["cone"] == pytest.approx(14.149038461538, abs=1e-9)
    assert ev["qddot"]["y"] == pytest.approx(-G * A / (1 + A * A), abs=1e-12)
    assert ev["qddot"]["x"] == pytest.approx(0.0, abs=1e-12)
