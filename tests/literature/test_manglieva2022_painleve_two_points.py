"""Painleve's two points on a smooth line, redundant coordinates (Manglieva & Beknazarov 2022,
sec. 1.1): multipliers (1.27)-(1.28) for any masses, the misprint (1.5), invariants, all forms."""

import numpy as np
import pytest

from nonideal import FORMS, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.painleve_two_points import (
    MASSES,
    angle,
    build,
    multipliers,
    printed_1_5,
    random_states,
    state,
)
from tests.helpers import cli_json as _cli

NAME = "painleve-two-points"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 4.0, 201))


def test_initial_multipliers_published_values(model):
    # theta = 0.3, theta' = 1, m = 1, m1 = 2, l = 0.5, g = 9.81
    lam1, lam = multipliers(0.3, 1.0, 1.0, 2.0, 0.5, 9.81)
    assert lam1 == pytest.approx(-2.406123513, abs=1e-9)
    assert lam == pytest.approx(-10.52105812, abs=1e-8)
    ev = evaluate(model)
    assert ev.multipliers["rod"] == pytest.approx(float(lam1), rel=1e-12)
    assert ev.multipliers["line"] == pytest.approx(float(lam), rel=1e-12)
    # sign mapping: the force on M1 is lambda_rod (cos theta, sin theta) (seed (1.16))
    R = np.array(ev.reactions["rod"]["generalized"])
    assert np.allclose(R[2:], lam1 * np.array([np.cos(0.3), np.sin(0.3)]), atol=1e-12)
    assert np.allclose(R[:2], -R[2:], atol=1e-12)


def test_multipliers_along_the_motion_are_1_27_and_1_28(model, traj):
    p = model.parameter_values
    th, thd = angle(traj.q, traj.qd)
    lam1, lam = multipliers(th, thd, p["m"], p["m1"], p["l"], p["g"])
    assert np.max(np.abs(traj.multipliers["rod"] - lam1)) < 1e-9 * np.max(np.abs(lam1))
    assert np.max(np.abs(traj.multipliers["line"] - lam)) < 1e-9 * np.max(np.abs(lam))
    # M1 swings through the bottom (theta = pi/2) and the rod stays in tension
    assert th.max() > 1.9 and np.all(traj.multipliers["rod"] < 0)


@pytest.mark.parametrize("m, m1", MASSES)
def test_multipliers_for_any_masses(m, m1):
    mod = build(m=m, m1=m1)
    for theta, thetad, xd in random_states():
        ev = evaluate(mod, at=state(theta, thetad, xd, 0.5))
        lam1, lam = multipliers(theta, thetad, m, m1, 0.5, 9.81)
        assert ev.multipliers["rod"] == pytest.approx(float(lam1), rel=1e-12)
        assert ev.multipliers["line"] == pytest.approx(float(lam), rel=1e-12)


def test_printed_1_5_is_a_misprint():
    # m = m1 = 2: (1.27) gives -m (l theta'^2 + g sin theta)/(1 + cos^2 theta), not (1.5)
    ev = evaluate(build(m=2.0, m1=2.0), at=state(0.7, 1.3, 0.0, 0.5))
    correct = -2.0 * (0.5 * 1.3 ** 2 + 9.81 * np.sin(0.7)) / (1 + np.cos(0.7) ** 2)
    assert ev.multipliers["rod"] == pytest.approx(correct, rel=1e-12)
    assert correct == pytest.approx(-9.0408199061, abs=1e-9)
    assert abs(printed_1_5(0.7, 1.3, 9.81) - correct) > 3.0


def test_invariants(model, traj):
    p = model.parameter_values
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8
    E = traj.energy["energy"]
    assert np.max(np.abs(E - E[0])) < 1e-8 * np.max(np.abs(E))
    px = p["m"] * traj.velocity("x") + p["m1"] * traj.velocity("x1")
    assert np.max(np.abs(px - px[0])) < 1e-10
    assert np.max(np.abs(traj.coordinate("y"))) < 1e-10


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,1,2", "--json")
    q = np.array([sim["q"][c] for c in ("x", "y", "x1", "y1")]).T
    qd = np.array([sim["qdot"][c] for c in ("x", "y", "x1", "y1")]).T
    th, thd = angle(q, qd)
    lam1, lam = multipliers(th, thd, 1.0, 2.0, 0.5, 9.81)
    assert np.allclose(sim["multipliers"]["rod"], lam1, rtol=1e-9)
    assert np.allclose(sim["multipliers"]["line"], lam, rtol=1e-9)
    ev = _cli("evaluate", path, "--at", "x=0, y=0, x1=0, y1=l, x'=0, y'=0, x1'=1, y1'=0", "--json")
    # theta = pi/2, theta' = -2 (M1 at the bottom, M at rest): the rod force is vertical, M does
    # not accelerate, the tension is m1 (g + l theta'^2) = 23.62; lambda = -m g - 23.62
    assert ev["multipliers"]["rod"] == pytest.approx(-23.62, abs=1e-12)
    assert ev["multipliers"]["line"] == pytest.approx(-9.81 - 23.62, abs=1e-12)
    assert ev["qddot"]["x"] == pytest.approx(0.0, abs=1e-12)
