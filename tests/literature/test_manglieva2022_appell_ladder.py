"""Appell's ladder on a smooth wall and floor (Manglieva & Beknazarov 2022, sec. 1.3, problem 2,
f_A = f_B = 0): detachment at cos(alpha) = (2/3) cos(alpha0) (the seed prints 2 cos(alpha0)),
reactions, release and landing times by quadrature, plastic landing in the energy balance."""

import numpy as np
import pytest

from nonideal import FORMS, FormNotApplicable, gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.appell_ladder import (
    build,
    landing_time,
    phase_model,
    reactions_closed,
    reactions_published,
    release,
)
from tests.helpers import cli_json as _cli

NAME = "appell-ladder"
OTHER_FORMS = [f for f in FORMS if f != "lagrange1"] + ["gauss"]
M, L, G, A0 = 2.0, 1.25, 9.81, 0.3


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model)


def _events(tr):
    return {e["constraint"]: e for e in tr.events}


def test_initial_reactions(model):
    ev = evaluate(model)
    s, c = np.sin(A0), np.cos(A0)
    assert ev.multipliers["wall"] == pytest.approx(0.75 * M * G * s * c, rel=1e-12)
    assert ev.multipliers["wall"] == pytest.approx(4.154356998, abs=1e-8)
    assert ev.multipliers["floor"] == pytest.approx(M * G / 4 * (1 + 3 * c * c), rel=1e-12)
    assert ev.qdd[2] == pytest.approx(3 * G / (4 * L) * s, rel=1e-12)


def test_release_angle_and_time(traj):
    ev = _events(traj)
    alpha_r, ad_r, t_r = release(A0, L, G)
    assert np.cos(alpha_r) == pytest.approx(2 / 3 * np.cos(A0), rel=1e-15)
    assert alpha_r == pytest.approx(0.8803374880586, abs=1e-12)
    k = int(np.searchsorted(traj.t, ev["wall"]["t"]))
    assert abs(traj.q[k, 2] - alpha_r) < 1e-9
    assert abs(traj.qd[k, 2] - ad_r) < 1e-9
    assert abs(ev["wall"]["t"] - t_r) < 1e-9
    assert t_r == pytest.approx(0.72735092207, abs=1e-10)
    # the seed's "cos(alpha) = 2 cos(alpha0)" has no solution for alpha0 < 60 degrees
    assert 2 * np.cos(A0) > 1.9


@pytest.mark.parametrize("alpha0", [0.7, 1.2])
def test_release_angle_other_starts(alpha0):
    tr = simulate(build(alpha0=alpha0), t_end=2.0)
    ev = _events(tr)
    k = int(np.searchsorted(tr.t, ev["wall"]["t"]))
    alpha_r, _, t_r = release(alpha0, L, G)
    assert abs(tr.q[k, 2] - alpha_r) < 1e-9
    assert abs(ev["wall"]["t"] - t_r) < 1e-8
    if 2 * np.cos(alpha0) < 1:   # the printed condition gives a wrong angle where it has a solution
        assert abs(np.arccos(2 * np.cos(alpha0)) - alpha_r) > 0.3


def test_reactions_before_release(model):
    t_r = release(A0, L, G)[2]
    tr = simulate(model, times=np.linspace(0, 0.999 * t_r, 101))
    al, ald = tr.coordinate("alpha"), tr.velocity("alpha")
    RA, RB = reactions_published(al, ald, M, L, G)
    RA2, RB2 = reactions_closed(al, A0, M, G)
    assert np.max(np.abs(tr.multipliers["wall"] - RA)) < 1e-9
    assert np.max(np.abs(tr.multipliers["floor"] - RB)) < 1e-9
    assert np.max(np.abs(RA - RA2)) < 1e-9 and np.max(np.abs(RB - RB2)) < 1e-9
    assert np.max(np.abs(ald ** 2 - 1.5 * G / L * (np.cos(A0) - np.cos(al)))) < 1e-9
    assert np.all(RA > 0) and RA[-1] < 0.05   # the wall reaction decreases to zero at release


def test_sliding_on_the_floor_and_landing(traj):
    ev = _events(traj)
    u = np.sqrt(2 / 9 * G * L * np.cos(A0) ** 3)
    after = traj.t > ev["wall"]["t"]
    phase2 = after & (traj.t < ev["top_on_floor"]["t"])
    assert np.max(np.abs(traj.velocity("x")[after] - u)) < 1e-9
    assert np.all(traj.multipliers["wall"][after] == 0.0)
    assert np.min(traj.multipliers["floor"][phase2]) > 3.0      # the foot stays on the floor
    assert abs(ev["top_on_floor"]["t"] - landing_time(A0, L, G, M)) < 1e-9
    flat = traj.t > ev["top_on_floor"]["t"]
    assert np.allclose(traj.coordinate("alpha")[flat], np.pi / 2, atol=1e-12)
    assert np.allclose(traj.multipliers["floor"][flat], M * G / 2, atol=1e-9)
    assert np.allclose(traj.multipliers["top_on_floor"][flat], M * G / 2, atol=1e-9)


def test_energy_balance_with_the_plastic_landing(traj):
    ev = _events(traj)
    E0 = M * G * L * np.cos(A0)
    E_after = M * G * L * np.cos(A0) ** 3 / 9
    E = traj.energy["energy"]
    assert E[0] == pytest.approx(E0, rel=1e-14)
    assert ev["top_on_floor"]["energy_change"] == pytest.approx(E_after - E0, abs=1e-8)
    assert ev["top_on_floor"]["energy_change"] == pytest.approx(-21.0536866553, abs=1e-8)
    assert E[-1] == pytest.approx(E_after, abs=1e-8)
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] <= 1e-8
    # the impact loss is booked as work of the (impulsive) reactions
    assert traj.energy["impact_work"][-1] == pytest.approx(E_after - E0, abs=1e-8)


@pytest.mark.parametrize("phase", [("wall", "floor"), ("floor",)], ids=["wall+floor", "floor"])
@pytest.mark.parametrize("form", OTHER_FORMS)
def test_form_agrees_with_lagrange1_in_each_phase(model, form, phase):
    # compare_forms takes every unilateral constraint as held; all three at once leave only the
    # flat configuration, so each contact phase is checked as a bilateral model
    try:
        report = compare_forms(phase_model(model, phase), forms=[form], count=20)
    except FormNotApplicable as exc:
        pytest.skip(f"{form} not applicable: {exc}")
    assert report.states == 20
    assert report.worst() < 1e-10, report


@pytest.mark.parametrize("form", OTHER_FORMS)
def test_hybrid_motion_does_not_depend_on_the_form(model, traj, form):
    try:
        tr = simulate(model, form=form)
    except FormNotApplicable as exc:
        pytest.skip(f"{form} not applicable: {exc}")
    ev, ref = _events(tr), _events(traj)
    assert abs(ev["wall"]["t"] - ref["wall"]["t"]) < 1e-10
    assert abs(ev["top_on_floor"]["t"] - ref["top_on_floor"]["t"]) < 1e-10
    assert np.max(np.abs(tr.q[-1] - traj.q[-1])) < 1e-9
    assert tr.multipliers["floor"][-1] == pytest.approx(M * G / 2, abs=1e-9)


def test_cli_simulate_and_evaluate():
    path = str(gallery.model_path(NAME))
    sim = _cli("simulate", path, "--json")
    ev = {e["constraint"]: e for e in sim["events"]}
    assert ev["wall"]["t"] == pytest.approx(release(A0, L, G)[2], abs=1e-9)
    assert ev["top_on_floor"]["energy_change"] == pytest.approx(-21.0536866553, abs=1e-8)
    assert sim["qdot"]["x"][-1] == pytest.approx(np.sqrt(2 / 9 * G * L * np.cos(A0) ** 3), abs=1e-9)
    out = _cli("evaluate", path, "--at", "x=l*sin(0.6), y=l*cos(0.6), alpha=0.6, x'=l*cos(0.6), y'=-l*sin(0.6), alpha'=1", "--json")
    RA, RB = reactions_published(0.6, 1.0, M, L, G)
    assert out["multipliers"]["wall"] == pytest.approx(RA, rel=1e-12)
    assert out["multipliers"]["floor"] == pytest.approx(RB, rel=1e-12)
