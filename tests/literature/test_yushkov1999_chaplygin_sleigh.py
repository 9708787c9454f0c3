"""Chaplygin sleigh, free motion (Yushkov 1999, appendix A): closed form, all forms, invariants."""

import numpy as np
import pytest

from nonideal import derive, gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.gallery.chaplygin_sleigh import build, closed_form


@pytest.fixture(scope="module")
def model():
    return gallery.load("chaplygin-sleigh")


def test_closed_form_velocity_turn_and_reaction(model):
    p = model.parameter_values
    times = np.linspace(0, 5, 21)
    tr = simulate(model, times=times)
    th = tr.coordinate("theta")
    v = tr.velocity("x") * np.cos(th) + tr.velocity("y") * np.sin(th)
    v_cf, w_cf, th_cf = closed_form(times, p["m"], p["I"], p["a"], 1.0, 1.5)
    assert np.max(np.abs(v - v_cf)) < 1e-9
    assert np.max(np.abs(tr.velocity("theta") - w_cf)) < 1e-9
    assert np.max(np.abs(th - th_cf)) < 1e-9
    J = p["I"] + p["m"] * p["a"] ** 2
    assert np.max(np.abs(tr.multipliers["knife"] - p["m"] * p["I"] * v_cf * w_cf / J)) < 1e-9


def test_energy_and_constraint_invariants(model):
    tr = simulate(model)
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    assert tr.diagnostics["constraint_residual_max"] < 1e-8
    E = tr.energy["energy"]
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-8
    # the ideal knife edge does no work
    assert np.max(np.abs(tr.energy["reaction_work"])) < 1e-8


def test_zero_reaction_free_motion_when_mass_at_G():
    tr = simulate(build(I=0.0), times=np.linspace(0, 3, 7))
    assert np.max(np.abs(tr.multipliers["knife"])) < 1e-9
    xg = tr.coordinate("x") + 0.4 * np.cos(tr.coordinate("theta"))
    assert np.allclose(np.diff(xg), 0.5 * 1.0, atol=1e-8)


def test_all_forms_agree(model):
    report = compare_forms(model, count=20)
    assert report.states == 20
    assert report.worst() < 1e-10, report


def test_maggi_eliminates_the_knife_edge(model):
    eom = derive(model, "maggi")
    assert eom.multipliers == ()
    assert eom.eliminated == ("knife",)
    assert len(eom.unknowns) == 2
