"""Two particles with perpendicular velocities x1'x2' + y1'y2' = 0 (a Chetaev constraint
homogeneous of degree 2): closed-form multiplier, energy conservation, independent integration."""

import numpy as np
import pytest

from nonideal import FORMS, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.perpendicular_velocities import energy, multiplier, reference
from tests.helpers import cli_json as _cli

NAME = "perpendicular-velocities"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]
ARGS = (1.0, 2.0, 3.0, 5.0, 2.0)   # m1, m2, k1, k2, d


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 10.0, 201))


def test_initial_multiplier(model):
    ev = evaluate(model)
    # F1.v2/m1 = -2.4, F2.v1/m2 = -0.9, |v2|^2/m1 + |v1|^2/m2 = 1.36
    assert ev.multipliers["perpendicular"] == pytest.approx(3.3 / 1.36, rel=1e-13)
    # Chetaev: reaction lambda (v2, v1)
    lam = 3.3 / 1.36
    assert np.allclose(ev.reactions["perpendicular"]["generalized"], lam * np.array([0.8, 0.0, 0.0, 1.2]),
                       atol=1e-12)


def test_multiplier_along_the_motion(traj):
    lam = multiplier(traj.q, traj.qd, *ARGS)
    assert np.max(np.abs(traj.multipliers["perpendicular"] - lam)) < 1e-9
    assert lam.min() < -8 and lam.max() > 11     # the reaction changes sign: non-trivial


def test_energy_conserved_and_constraint_kept(traj):
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8
    E = energy(traj.q, traj.qd, *ARGS)
    assert np.max(np.abs(E - E[0])) < 1e-9 * E[0]
    assert np.max(np.abs(traj.energy["reaction_work"])) < 1e-9
    phi = np.sum(traj.qd[:, :2] * traj.qd[:, 2:], axis=1)
    assert np.max(np.abs(phi)) < 1e-9


def test_independent_integration(traj):
    q, qd = reference(traj.t, *ARGS)
    assert np.max(np.abs(traj.q - q)) < 1e-8
    assert np.max(np.abs(traj.qd - qd)) < 1e-8


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,2,5", "--json")
    names = ("x1", "y1", "x2", "y2")
    q = np.array([sim["q"][c] for c in names]).T
    qd = np.array([sim["qdot"][c] for c in names]).T
    assert np.allclose(sim["multipliers"]["perpendicular"], multiplier(q, qd, *ARGS), atol=1e-9)
    E = energy(q, qd, *ARGS)
    assert np.allclose(E, E[0], rtol=1e-9)
    ev = _cli("evaluate", path, "--json")
    assert ev["multipliers"]["perpendicular"] == pytest.approx(2.426470588235, abs=1e-11)
    assert ev["qddot"]["x1"] == pytest.approx((-3.0 + 2.426470588235 * 0.8) / 1.0, abs=1e-11)
