"""Two points on a rod with the midpoint velocity along the rod (Manglieva & Beknazarov 2022,
sec. 1.3, problem 1, f = 0): multipliers (1.87), (1.89), the first integral behind (1.92)."""

import numpy as np
import pytest

from nonideal import FORMS, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.painleve_conditional_constraint import (
    angle,
    build,
    build_lagrange2,
    first_integral,
    line_force_1_89,
    multipliers,
    printed_integral,
)
from tests.helpers import cli_json as _cli

NAME = "painleve-conditional-constraint"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]
M1, M2, L, G, X = 1.0, 2.0, 0.8, 9.81, 1.5


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 5.0, 251))


def _at(theta, thetad, l=L):
    """An admissible state (x1 = 0) with theta, theta' (x1' from (1.88))."""
    v = l * thetad / (2 * np.sin(theta))
    return {"x1": 0.0, "y1": 0.0, "x2": l * np.cos(theta), "y2": l * np.sin(theta),
            "x1'": v, "y1'": 0.0, "x2'": v - l * np.sin(theta) * thetad, "y2'": l * np.cos(theta) * thetad}


def test_initial_state_numbers(model):
    ev = evaluate(model)
    # (m1 + m2) x1'' = X + m2 g sin(2 theta0) at theta0 = 1
    assert ev.qdd[0] == pytest.approx((X + M2 * G * np.sin(2.0)) / 3, rel=1e-12)
    assert ev.qdd[0] == pytest.approx(6.446805171, abs=1e-9)
    assert ev.multipliers["line"] == pytest.approx(-18.45015898, abs=1e-8)
    assert ev.multipliers["line"] == pytest.approx(line_force_1_89(1.0, 0.5, M1, M2, L, G), rel=1e-12)
    # Chetaev's rule: the midpoint reaction is lambda_2 (-sin, cos) on each point
    R = np.array(ev.reactions["midpoint"]["generalized"])
    lam2 = ev.multipliers["midpoint"]
    e = np.array([-np.sin(1.0), np.cos(1.0)])
    assert np.allclose(R, np.concatenate((lam2 * e, lam2 * e)), atol=1e-12)


def test_multipliers_1_87_1_89_along_the_motion(traj):
    th, thd = angle(traj.q, traj.qd)
    lam1, lam2, lam = multipliers(th, thd, traj.velocity("x1"), M1, M2, L, G, X)
    scale = np.max(np.abs(lam))
    assert np.max(np.abs(traj.multipliers["rod"] - lam1)) < 1e-9 * scale
    assert np.max(np.abs(traj.multipliers["midpoint"] - lam2)) < 1e-9 * scale
    assert np.max(np.abs(traj.multipliers["line"] - lam)) < 1e-9 * scale
    assert np.max(np.abs(traj.multipliers["line"] - line_force_1_89(th, thd, M1, M2, L, G))) < 1e-9 * scale
    assert th.min() < 1.0 and th.max() > 2.2      # M2 swings through the bottom


@pytest.mark.parametrize("m1, m2, Xv", [(1.0, 1.0, 0.0), (3.0, 0.5, -2.0), (0.2, 5.0, 4.0)])
def test_multipliers_for_other_masses_and_forces(m1, m2, Xv):
    mod = build(m1=m1, m2=m2, X=Xv)
    rng = np.random.default_rng(3)
    for _ in range(6):
        theta, thetad = rng.uniform(0.2, 2.9), rng.uniform(-3, 3)
        ev = evaluate(mod, at=_at(theta, thetad))
        x1d = L * thetad / (2 * np.sin(theta))
        lam1, lam2, lam = multipliers(theta, thetad, x1d, m1, m2, L, G, Xv)
        scale = max(abs(lam1), abs(lam2), abs(lam))
        assert abs(ev.multipliers["rod"] - lam1) < 1e-12 * scale
        assert abs(ev.multipliers["midpoint"] - lam2) < 1e-12 * scale
        assert abs(ev.multipliers["line"] - line_force_1_89(theta, thetad, m1, m2, L, G)) < 1e-12 * scale
        assert (m1 + m2) * ev.qdd[0] == pytest.approx(Xv + m2 * G * np.sin(2 * theta), abs=1e-11)


def test_at_rest_values_and_the_printed_sign_misprint():
    theta = 0.9
    ev = evaluate(build(), at=_at(theta, 0.0))
    s, c = np.sin(theta), np.cos(theta)
    k = M2 / (M1 + M2)
    lam1 = k * (X * c + M2 * G * c * c * s - (M1 + M2 * s * s) * G * s)
    printed = k * (X * c - M2 * G * c * c * s + (M1 + M2 * s * s) * G * s)
    assert ev.multipliers["rod"] == pytest.approx(lam1, rel=1e-12)
    assert abs(ev.multipliers["rod"] - printed) > 5.0
    combo = ev.multipliers["rod"] * c + ev.multipliers["midpoint"] * s
    assert combo == pytest.approx(k * (X - M1 * G * np.sin(2 * theta)), rel=1e-12)
    assert ev.multipliers["line"] == pytest.approx(-(M1 + M2) * G + 2 * M2 * G * c * c, rel=1e-12)


def test_first_integral_corrects_1_92(traj):
    th = angle(traj.q, traj.qd)[0]
    x1 = traj.coordinate("x1")
    I = first_integral(th, x1, L)
    assert I[0] == pytest.approx(np.tan(0.5), rel=1e-14)
    assert np.max(np.abs(I - I[0])) < 1e-9
    # the printed tan(theta/2) = e^{x1} is neither satisfied nor even constant (l != 2)
    Ip = printed_integral(th, x1)
    assert abs(Ip[0] - 1.0) > 0.4 and np.max(Ip) - np.min(Ip) > 0.5


def test_equation_of_motion_energy_and_lagrange2(traj):
    th = angle(traj.q, traj.qd)[0]
    x1, x1d = traj.coordinate("x1"), traj.velocity("x1")
    assert np.max(np.abs((M1 + M2) * traj.qdd[:, 0] - X - M2 * G * np.sin(2 * th))) < 1e-8
    E = 0.5 * (M1 + M2) * x1d ** 2 - M2 * G * L * np.sin(th) - X * x1
    assert np.max(np.abs(E - E[0])) < 1e-8
    assert np.max(np.abs(traj.energy["active_work"] - X * (x1 - x1[0]))) < 1e-10
    one = simulate(build_lagrange2(), times=traj.t)
    assert np.max(np.abs(one.coordinate("theta") - th)) < 1e-8
    # (1.98) with f = 0, evaluated on the one-coordinate model
    thd, thdd = one.velocity("theta"), one.qdd[:, 0]
    s, c = np.sin(one.coordinate("theta")), np.cos(one.coordinate("theta"))
    lhs = (M1 + M2) * L / 4 * (thdd / s ** 2 - c * thd ** 2 / s ** 3)
    assert np.max(np.abs(lhs - M2 * G * c - X / (2 * s))) < 1e-9


def test_invariants(traj):
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,1,3", "--json")
    q = np.array([sim["q"][c] for c in ("x1", "y1", "x2", "y2")]).T
    qd = np.array([sim["qdot"][c] for c in ("x1", "y1", "x2", "y2")]).T
    th, thd = angle(q, qd)
    assert np.allclose(first_integral(th, q[:, 0], L), np.tan(0.5), rtol=1e-9)
    assert np.allclose(sim["multipliers"]["line"], line_force_1_89(th, thd, M1, M2, L, G), rtol=1e-9)
    ev = _cli("evaluate", path, "--json")
    assert ev["qddot"]["x1"] == pytest.approx(6.446805171, abs=1e-9)
    assert ev["multipliers"]["line"] == pytest.approx(-18.45015898, abs=1e-8)
