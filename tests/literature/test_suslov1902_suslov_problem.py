"""Suslov's problem (Suslov 1902): a rigid body with a fixed point and omega . e3 = 0, in the
speeds w1, w2, w3 (body components of the angular velocity).  Closed form w2 = s tanh(k t +
c0), w1 = w1(0) cosh(c0)/cosh(k t + c0), the reaction torque, and Euler's equations printed."""

import numpy as np
import pytest

from nonideal import derive, evaluate, gallery, simulate
from nonideal.gallery.suslov_problem import build, closed_form


@pytest.fixture(scope="module")
def model():
    return gallery.load("suslov-problem")


@pytest.mark.parametrize("form", ["lagrange1", "kane", "boltzmann_hamel", "poincare_chetaev"])
def test_simulation_follows_the_closed_form(model, form):
    p = model.parameter_values
    times = np.linspace(0.0, 10.0, 21)
    tr = simulate(model, times=times, form=form)
    w1, w2, lam = closed_form(times, p["J1"], p["J2"], p["a"], 1.0, 0.2)
    assert np.max(np.abs(tr.speeds["w1"] - w1)) < 1e-8
    assert np.max(np.abs(tr.speeds["w2"] - w2)) < 1e-8
    assert np.max(np.abs(tr.speeds["w3"])) < 1e-9          # the constraint
    assert np.max(np.abs(tr.multipliers["suslov"] - lam)) < 1e-8
    assert np.max(np.abs(tr.outputs["torque"] - lam)) < 1e-8
    assert np.ptp(tr.outputs["E"]) < 1e-9                    # no torque, ideal constraint


def test_w2_tends_to_the_limit_s():
    tr = simulate(build(t_end=60.0), times=[0.0, 60.0])
    s = tr.outputs["limit_w2"]
    assert s[0] == pytest.approx(np.sqrt((2.0 * 1.0 + 3.0 * 0.04) / 3.0), rel=1e-12)
    assert tr.speeds["w2"][-1] == pytest.approx(s[0], rel=1e-8)
    assert abs(tr.speeds["w1"][-1]) < 1e-5


@pytest.mark.parametrize("form", ["kane", "appell"])
def test_kane_prints_eulers_equations(model, form):
    """Kane's equations, and Gibbs-Appell's in the declared speeds (the acceleration energy
    written in w1', w2')."""
    eom = derive(model, form)
    assert eom.unknowns == ("w1'", "w2'")
    assert eom.readable() == ["J1*w1' + a*w1*w2 = 0", "J2*w2' - a*w1**2 = 0"]
    assert "suslov" in eom.eliminated


def test_evaluate_reports_speeds_and_their_rates(model):
    ev = evaluate(model)
    d = ev.to_dict()
    assert d["speeds"] == pytest.approx({"w1": 1.0, "w2": 0.2, "w3": 0.0}, abs=1e-14)
    assert d["speeds_dot"]["w1"] == pytest.approx(-0.5 * 1.0 * 0.2 / 2.0, rel=1e-12)
    assert d["speeds_dot"]["w2"] == pytest.approx(0.5 * 1.0 / 3.0, rel=1e-12)
    assert d["speeds_dot"]["w3"] == pytest.approx(0.0, abs=1e-13)
    assert d["outputs"]["torque"] == pytest.approx(d["multipliers"]["suslov"], rel=1e-14)


def test_run_is_ok():
    assert gallery.run("suslov-problem", verbose=False)["ok"]
