"""Disk on a rough plane driven by a torque c t (classical; seed 001): rolling realizable until
t_loss = mu_s m g (I + m R^2)/(m R c) (slip event, realizability_along, realizability at a
state), sliding afterwards, the epsilon-linear regularized system -> rolling with error
proportional to eps (exact solution of the regularized system), energy, all forms, CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.gallery.disk_rolling_torque import (
    motion,
    needed_friction,
    regularization_error,
    regularized_motion,
    t_loss,
)
from nonideal.analysis.contact.realizability import realizability, realizability_along
from tests.helpers import run_cli as _cli

# m = 2, R = 0.3, I = m R^2/2 = 0.09, I + m R^2 = 0.27, c = 2, mu = mu_s = 0.3, g = 9.81
T_LOSS = 0.3 * 2.0 * 9.81 * 0.27 / (2.0 * 0.3 * 2.0)     # 1.32435


@pytest.fixture(scope="module")
def model():
    return gallery.load("disk-rolling-torque")


@pytest.fixture(scope="module")
def p(model):
    return model.parameter_values


def test_closed_form_numbers(p):
    assert t_loss(p) == pytest.approx(1.32435, rel=1e-14)
    assert needed_friction(1.0, p) == pytest.approx(2.0 * 0.3 * 2.0 / 0.27, rel=1e-14)
    assert needed_friction(T_LOSS, p) == pytest.approx(0.3 * 2.0 * 9.81, rel=1e-14)


def test_rolling_lost_at_t_loss_then_sliding(model, p):
    tr = simulate(model)
    assert [(e["type"], e["contact"], e["mode"]) for e in tr.events] == [("slip", "plane", "plane:slide-")]
    assert tr.events[0]["t"] == pytest.approx(T_LOSS, rel=1e-9)
    times = np.union1d(np.linspace(0, 2, 41), [T_LOSS])
    tr = simulate(model, times=times)
    x, xd, phid = motion(times, p)
    assert np.max(np.abs(tr.coordinate("x") - x)) < 1e-10
    assert np.max(np.abs(tr.velocity("x") - xd)) < 1e-10
    assert np.max(np.abs(tr.velocity("phi") - phid)) < 1e-9
    F = np.array(tr.contacts["plane"]["friction"])[:, 0]
    rolling = times < T_LOSS
    assert np.allclose(F[rolling], needed_friction(times[rolling], p), rtol=1e-10, atol=1e-12)
    assert np.allclose(F[~rolling], 0.3 * 2.0 * 9.81, rtol=1e-12)      # U < 0: +mu N
    assert np.all(np.array(tr.contacts["plane"]["slip"])[~rolling & (times > T_LOSS + 0.01), 0] < 0)


def test_realizability_along_gives_t_loss(model):
    rep = realizability_along(model)
    assert rep.along["lost_at"] == pytest.approx(T_LOSS, rel=1e-9)
    assert rep.along["reason"] == "needed friction reached mu_s N" and rep.along["contact"] == "plane"


@pytest.mark.parametrize("t, ok", [(0.5, True), (1.0, True), (1.5, False)])
def test_realizability_at_a_state_gives_the_needed_force(model, p, t, ok):
    rep = realizability(model, t=t).contacts["plane"]
    F = 2.0 * 0.3 * 2.0 * t / 0.27
    assert rep.needed[0] == pytest.approx(F, rel=1e-12)
    assert rep.normal == pytest.approx(2.0 * 9.81, rel=1e-14)
    assert rep.available == pytest.approx(0.3 * 2.0 * 9.81, rel=1e-14)
    assert rep.margin == pytest.approx(0.3 * 2.0 * 9.81 - F, rel=1e-12)
    assert rep.realizable is ok


def test_regularized_converges_to_rolling_proportional_to_eps(p):
    times = np.linspace(0.0, 1.0, 11)
    coef = 0.09 * needed_friction(1.0, p) / (0.27 * 0.3 * 2.0 * 9.81)     # 0.251696...
    errs = []
    for eps in (1e-2, 1e-3, 1e-4):
        r = regularization_error(p, eps, times)
        # the regularized system itself has an exact solution (linear slip equation)
        assert r["error_vs_regularized_closed_form"] < 1e-9
        assert r["slip_error"] < 1e-9
        assert r["max_slip"] < eps and r["events"] == 0
        # error vs the rolling motion: coef * eps to leading order (next term O(eps^2))
        assert r["error_vs_rolling"] == pytest.approx(coef * eps, rel=0.2 * eps)
        assert r["energy_balance_relative"] < 1e-8
        errs.append(r["error_vs_rolling"])
    assert errs[0] / errs[1] == pytest.approx(10, rel=2e-3)
    assert errs[1] / errs[2] == pytest.approx(10, rel=2e-4)


def test_regularized_closed_form_limits(p):
    # U -> -F* eps/(mu N) after the transient; x' - x'_roll = I U / (I + m R^2)
    eps = 1e-3
    xd, U = regularized_motion(np.array([1.0]), p, eps)
    F = needed_friction(1.0, p)
    assert U[0] == pytest.approx(-F * eps / (0.3 * 2.0 * 9.81), rel=2e-3)
    assert xd[0] - 0.3 * 2.0 / (2 * 0.27) == pytest.approx(0.09 / 0.27 * U[0], rel=1e-12)


def test_energy_balance_and_friction_power(model):
    tr = simulate(model)
    E = tr.energy
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    assert np.max(np.abs((E["energy"] - E["energy"][0]) - E["active_work"] - E["friction_work"])) < 1e-9
    # fixed plane: friction power never positive; zero while rolling
    assert np.all(np.diff(E["friction_work"]) <= 1e-12)
    before = tr.t <= T_LOSS
    assert np.max(np.abs(E["friction_work"][before])) < 1e-12
    # work of the torque while rolling = kinetic energy c^2 t^4 / (8 (I + m R^2))
    k = int(np.searchsorted(tr.t, T_LOSS)) - 1
    assert E["active_work"][k] == pytest.approx(4.0 * tr.t[k] ** 4 / (8 * 0.27), rel=1e-9)


def test_cli_simulate_json_and_realizability(tmp_path):
    path = gallery.model_path("disk-rolling-torque")
    proc = _cli("simulate", path, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
            "diagnostics"} <= set(d)
    plane = d["contacts"]["plane"]
    assert {"normal", "friction", "slip", "mode"} <= set(plane)
    assert plane["mode"][0] == "stick" and plane["mode"][-1] == "slide-"
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("slip", "plane")]
    assert d["events"][0]["t"] == pytest.approx(T_LOSS, rel=1e-9)
    proc = _cli("realizability", path, "--along", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "rolling stops being realizable at t = 1.32435" in proc.stdout
