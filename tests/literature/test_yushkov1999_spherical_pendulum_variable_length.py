"""Spherical pendulum of variable length (Yushkov 1999, eq. (1.11)): the multiplier of
``l(t) - |r| = 0`` is the thread tension; the tension works because the constraint is rheonomic."""

import numpy as np
import pytest
from scipy.integrate import simpson

from nonideal import FORMS, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.spherical_pendulum_variable_length import (
    build_spherical,
    length,
    spherical_state,
    tension,
)
from tests.helpers import cli_json as _cli

NAME = "spherical-pendulum-variable-length"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def params(model):
    return model.parameter_values


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 5.0, 1001))


def _tension(p, t, q, qd):
    return tension(t, q, qd, p["m"], p["g"], p["l0"], p["eps"], p["w"])


def test_initial_tension_closed_form(model, params):
    # at t = 0: l = l0, l'' = 0, theta' = 0, phi' = phi0d:  N = m l0 sin^2(theta0) phi0d^2 + m g cos(theta0)
    p = params
    N0 = p["m"] * p["l0"] * np.sin(p["theta0"]) ** 2 * p["phi0d"] ** 2 + p["m"] * p["g"] * np.cos(p["theta0"])
    assert N0 == pytest.approx(9.371826873, abs=1e-9)
    ev = evaluate(model)
    assert ev.multipliers["thread"] == pytest.approx(N0, rel=1e-12)
    # the reaction lambda grad f = -N r/|r| points to the suspension point
    r0 = ev.q / np.linalg.norm(ev.q)
    assert np.allclose(ev.reactions["thread"]["generalized"], -N0 * r0, atol=1e-12)


def test_multiplier_is_the_tension_along_the_motion(traj, params):
    N = traj.multipliers["thread"]
    N_cf = _tension(params, traj.t, traj.q, traj.qd)
    assert np.max(np.abs(N - N_cf)) < 1e-9 * np.max(N_cf)
    assert N.min() > 8.9 and N.max() < 13.5     # the thread stays taut


def test_thread_length_follows_the_program(traj, params):
    ell = np.linalg.norm(traj.q, axis=1)
    assert np.max(np.abs(ell - length(traj.t, params["l0"], params["eps"], params["w"])[0])) < 1e-8
    assert traj.diagnostics["constraint_residual_max"] <= 1e-8


def test_energy_balance_with_the_work_of_the_tension(traj, params):
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    E, W_R = traj.energy["energy"], traj.energy["reaction_work"]
    assert np.max(np.abs(E - E[0] - W_R)) < 1e-8
    # the rheonomic constraint does work: W_R = integral of -N l' dt (Simpson on the closed form)
    _, ld, _ = length(traj.t, params["l0"], params["eps"], params["w"])
    W_quad = simpson(-_tension(params, traj.t, traj.q, traj.qd) * ld, x=traj.t)
    assert abs(W_R[-1]) > 0.5
    assert W_R[-1] == pytest.approx(W_quad, abs=1e-8)
    assert np.max(np.abs(traj.energy["active_work"])) < 1e-12


def test_minimal_coordinates_give_the_same_motion(traj, params):
    keys = ("m", "g", "l0", "eps", "w", "theta0", "phi0d")
    sph = simulate(build_spherical(**{k: params[k] for k in keys}), times=traj.t[::50])
    th, ph, thd, phd = spherical_state(traj.q[::50], traj.qd[::50])
    assert np.max(np.abs(th - sph.coordinate("theta"))) < 1e-8
    assert np.max(np.abs(np.unwrap(ph) - sph.coordinate("phi"))) < 1e-8
    assert np.max(np.abs(phd - sph.velocity("phi"))) < 1e-8


def test_cli_simulate_and_evaluate(params):
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--times", "0,1,2.5", "--json")
    t = np.array(sim["t"])
    q = np.array([sim["q"][c] for c in ("x", "y", "z")]).T
    qd = np.array([sim["qdot"][c] for c in ("x", "y", "z")]).T
    assert t.tolist() == [0.0, 1.0, 2.5]
    N_cf = _tension(params, t, q, qd)
    assert np.allclose(sim["multipliers"]["thread"], N_cf, rtol=1e-9)
    assert sim["diagnostics"]["energy_balance_relative"] < 1e-8
    ev = _cli("evaluate", path, "--json")
    assert ev["multipliers"]["thread"] == pytest.approx(9.371826873, abs=1e-8)
    # at t = 0 the acceleration is -N r/(m l) - g e_z: z'' = N cos(theta0)/m - g
    assert ev["qddot"]["z"] == pytest.approx(9.371826873 * np.cos(0.6) - 9.81, abs=1e-8)
