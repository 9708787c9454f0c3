"""Painleve's two points on a smooth line in (x, y, theta) (Manglieva & Beknazarov 2022, sec. 1.1,
(1.35)-(1.39)): the seed's Lagrange-II equations, the normal force (1.28), the misprint in (1.29)."""

import numpy as np
import pytest

from nonideal import FORMS, derive, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.painleve_two_points import MASSES, multipliers, random_states
from nonideal.gallery.painleve_two_points import build as build_redundant
from nonideal.gallery.painleve_two_points_xtheta import build, normal_force_1_39, residuals
from tests.helpers import cli_json as _cli

NAME = "painleve-two-points-xtheta"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]
M, M1, L, G = 1.0, 2.0, 0.5, 9.81


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 4.0, 201))


def test_lagrange_equations_1_35_1_37_hold(traj):
    th, thd = traj.coordinate("theta"), traj.velocity("theta")
    r35, r37 = residuals(th, thd, traj.qdd[:, 0], traj.qdd[:, 2], M, M1, L, G)
    assert np.max(np.abs(r35)) < 1e-9 and np.max(np.abs(r37)) < 1e-9
    # the printed second equation of (1.29) (-g cos theta) is off by 2 g cos(theta)
    printed = L * traj.qdd[:, 2] - traj.qdd[:, 0] * np.sin(th) + G * np.cos(th)
    assert np.allclose(printed, 2 * G * np.cos(th), atol=1e-9)
    assert np.max(np.abs(printed)) > 18.0


def test_initial_accelerations(model):
    ev = evaluate(model)
    # theta = 0.3, theta' = 1: from (1.35), (1.37)
    assert ev.qdd[0] == pytest.approx(2.298657589, abs=1e-9)
    assert ev.qdd[2] == pytest.approx(20.10230145, abs=1e-8)
    assert ev.multipliers["line"] == pytest.approx(-10.52105812, abs=1e-8)


def test_normal_force_is_1_28_and_1_39(traj):
    th, thd = traj.coordinate("theta"), traj.velocity("theta")
    _, lam = multipliers(th, thd, M, M1, L, G)
    assert np.max(np.abs(traj.multipliers["line"] - lam)) < 1e-9 * np.max(np.abs(lam))
    R_y = normal_force_1_39(th, thd, traj.qdd[:, 2], M, M1, L, G)
    assert np.max(np.abs(traj.multipliers["line"] - R_y)) < 1e-9 * np.max(np.abs(lam))


@pytest.mark.parametrize("m, m1", MASSES)
def test_for_any_masses(m, m1):
    mod = build(m=m, m1=m1)
    for theta, thetad, xd in random_states():
        ev = evaluate(mod, at={"x": 0.0, "y": 0.0, "theta": theta, "x'": xd, "y'": 0.0, "theta'": thetad})
        _, lam = multipliers(theta, thetad, m, m1, L, G)
        assert ev.multipliers["line"] == pytest.approx(float(lam), rel=1e-12)
        r35, r37 = residuals(theta, thetad, ev.qdd[0], ev.qdd[2], m, m1, L, G)
        assert abs(r35) < 1e-11 and abs(r37) < 1e-11


def test_same_motion_as_the_redundant_model(traj):
    red = simulate(build_redundant(), times=traj.t)
    th = np.arctan2(red.coordinate("y1") - red.coordinate("y"), red.coordinate("x1") - red.coordinate("x"))
    assert np.max(np.abs(traj.coordinate("x") - red.coordinate("x"))) < 1e-8
    assert np.max(np.abs(traj.coordinate("theta") - np.unwrap(th))) < 1e-8
    lam = red.multipliers["line"]
    assert np.max(np.abs(traj.multipliers["line"] - lam)) < 1e-7 * np.max(np.abs(lam))


def test_invariants(traj):
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8
    E = traj.energy["energy"]
    assert np.max(np.abs(E - E[0])) < 1e-8 * np.max(np.abs(E))
    # horizontal momentum (m + m1) x' - m1 l sin(theta) theta' (dT/dx') is conserved
    px = (M + M1) * traj.velocity("x") - M1 * L * np.sin(traj.coordinate("theta")) * traj.velocity("theta")
    assert np.max(np.abs(px - px[0])) < 1e-8


def test_reduced_forms_keep_x_and_theta(model):
    eom = derive(model, "maggi")
    assert eom.eliminated == ("line",)
    assert set(eom.unknowns) == {"x''", "theta''"}


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,1,2", "--json")
    th, thd = np.array(sim["q"]["theta"]), np.array(sim["qdot"]["theta"])
    _, lam = multipliers(th, thd, M, M1, L, G)
    assert np.allclose(sim["multipliers"]["line"], lam, rtol=1e-9)
    ev = _cli("evaluate", path, "--at", "theta=pi/2, theta'=2, x'=0", "--json")
    # M1 at the bottom: x'' = 0, theta'' = 0, lambda = -(m + m1) g - m1 l theta'^2 = -33.43
    assert ev["qddot"]["x"] == pytest.approx(0.0, abs=1e-12)
    assert ev["qddot"]["theta"] == pytest.approx(0.0, abs=1e-12)
    assert ev["multipliers"]["line"] == pytest.approx(-33.43, abs=1e-12)
