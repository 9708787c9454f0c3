"""Appell's ladder with friction on the wall and the floor (Manglieva & Beknazarov 2022, sec. 1.3,
problem 2, (1.101)-(1.110)): (1.105)-(1.106) against Newton-Euler for unequal coefficients and
both sliding directions, the quadrature (1.109) and the reactions (1.110) (corrected; the printed
ones are off) along the simulated motion, the stop of the pushed ladder and its release from
the wall against the closed form, Painleve's split (constraint parts = smooth reactions), the
seed's representation in every form, energy, the CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.errors import FormNotApplicable
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.contact.friction_law import painleve_model, touching_contacts
from nonideal.gallery.appell_ladder_rough import (
    alpha_dd_1_106,
    alpha_limit,
    along,
    build,
    check_1_106,
    closed_form,
    normal_forces_1_105,
    painleve_representation,
    rate2,
    reactions_1_110,
    smooth_reactions,
    state,
)
from tests.helpers import run_cli as _cli

NAME = "appell-ladder-rough"
# default push (alpha0 = 0.9, alpha0' = -1, f = 0.3): stop and release (quadrature, 1e-12)
T_STOP, ALPHA_STOP = 0.154056011169, 0.822171234292
T_RELEASE, ALPHA_RELEASE = 0.770181353890, 1.214078950093


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def p(model):
    return model.parameter_values


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 0.9, 181))


def test_closed_form_numbers(p):
    cf = closed_form(p)
    assert cf["alpha_stop"] == pytest.approx(ALPHA_STOP, abs=1e-11)
    assert cf["t_stop"] == pytest.approx(T_STOP, abs=1e-11)
    assert cf["alpha_release"] == pytest.approx(ALPHA_RELEASE, abs=1e-11)
    assert cf["t_release"] == pytest.approx(T_RELEASE, abs=1e-11)
    assert cf["alpha_limit"] == pytest.approx(np.arctan(0.6 / 0.91), rel=1e-14) and cf["slides_back"]
    # at the stop alpha'^2 = 0, at the release R_A^n = 0 (both branches of (1.109))
    assert rate2(cf["alpha_stop"], p["alpha0"], 1.0, -1.0, p) == pytest.approx(0.0, abs=1e-12)
    r2 = rate2(cf["alpha_release"], cf["alpha_stop"], 0.0, 1.0, p)
    assert reactions_1_110(cf["alpha_release"], r2, 1.0, p)[0] == pytest.approx(0.0, abs=1e-10)


def test_1_105_1_106_unequal_coefficients_both_directions():
    r = check_1_106(f_A=0.2, f_B=0.45, count=12)
    assert r["states"] >= 8
    assert r["errors"]["alpha_dd"] < 1e-12 and r["errors"]["R_n"] < 1e-12
    # Painleve's split: the constraint parts are the smooth reactions, whatever the friction
    assert r["errors"]["split"] < 1e-12
    # the seed's (1.106) is for alpha' > 0; pushed up (alpha' < 0) the friction reverses
    assert r["printed_equation_backwards_min_error"] > 0.1


@pytest.mark.parametrize("alpha, alphad", [(0.7, 1.3), (1.0, -0.8)])
def test_physical_normal_forces_depend_on_friction_constraint_parts_do_not(alpha, alphad):
    at = state(alpha, alphad, 1.25)
    rough, smooth = evaluate(build(top=False), at=at), evaluate(build(f_A=0.0, f_B=0.0, top=False), at=at)
    p = build().parameter_values
    SA, SB = smooth_reactions(alpha, alphad, p)
    for name, S in (("wall", SA), ("floor", SB)):
        assert rough.contacts[name]["constraint_multiplier"] == pytest.approx(S, rel=1e-12)
        assert smooth.contacts[name]["normal"] == pytest.approx(S, rel=1e-12)
        assert abs(rough.contacts[name]["normal"] - S) > 0.05
    sigma = np.sign(alphad)
    add = alpha_dd_1_106(alpha, alphad, sigma, p)
    assert rough.qdd[2] == pytest.approx(add, rel=1e-12)
    RA, RB = normal_forces_1_105(alpha, alphad, add, sigma, p)
    assert rough.contacts["wall"]["normal"] == pytest.approx(RA, rel=1e-12)
    assert rough.contacts["floor"]["normal"] == pytest.approx(RB, rel=1e-12)
    # Coulomb at both ends, opposite to the slip
    for name in ("wall", "floor"):
        c = rough.contacts[name]
        assert c["friction"][0] == pytest.approx(-0.3 * c["normal"] * np.sign(c["slip"][0]), rel=1e-12)


def test_stop_slide_back_and_release_events(model):
    tr = simulate(model)
    assert [(e["type"], e["contact"]) for e in tr.events] == [("reverse", "wall"), ("lift-off", "wall")]
    assert tr.events[0]["mode"].startswith("wall:slide-, floor:slide+")       # reverses, no stick
    assert tr.events[0]["t"] == pytest.approx(T_STOP, rel=1e-10)
    assert tr.events[1]["t"] == pytest.approx(T_RELEASE, rel=1e-10)
    for e, alpha in zip(tr.events, (ALPHA_STOP, ALPHA_RELEASE)):
        k = int(np.searchsorted(tr.t, e["t"]))
        assert tr.q[k, 2] == pytest.approx(alpha, abs=1e-10)
    assert np.tan(ALPHA_STOP) > np.tan(alpha_limit(model.parameter_values))


def test_quadrature_and_reactions_along_the_motion(p, traj):
    al = along(traj, closed_form(p), p)
    assert min(al["samples"]) > 20
    assert al["rate2 (1.109)"] < 1e-9            # alpha'^2 (1/s^2) vs (1.109) corrected
    assert al["alpha_dd (1.108)"] < 1e-9
    assert al["reactions (1.110)"] < 1e-10       # relative to m g
    assert al["min R_A, R_B before release"] > 0
    # the printed (1.109) (g^2, e^{b alpha}) and (1.110) do not describe the motion
    assert al["printed (1.109)"] > 1.0
    assert al["printed R_A (1.110)"] > 0.05 and al["printed R_B (1.110)"] > 0.05


def test_ladder_held_by_static_friction_after_a_stronger_push():
    # pushed from alpha0 = 0.7 with alpha0' = -1.2 it stops below alpha_lim and stays
    m = build(alpha0=0.7, alphad0=-1.2, t_end=0.6)
    p = m.parameter_values
    cf = closed_form(p)
    assert not cf["slides_back"] and cf["alpha_stop"] < cf["alpha_limit"]
    tr = simulate(m)
    assert tr.events[0]["type"] == "stick" and tr.events[0]["t"] == pytest.approx(cf["t_stop"], rel=1e-9)
    after = tr.t > cf["t_stop"] + 1e-9
    assert np.max(np.abs(tr.q[after, 2] - cf["alpha_stop"])) < 1e-9
    assert np.max(np.abs(tr.qd[after])) < 1e-9


@pytest.mark.parametrize("t_end, rtol", [(1.0, None), (2.0, None), (2.0, 1e-12), (1.7, 1e-8)])
def test_ladder_at_rest_stays_without_events(t_end, rtol):
    # both ends sticking: four rows on three coordinates, the reactions statically
    # indeterminate; the best admissible distribution holds it (the minimum-norm one gave a
    # "slip" at a time that followed the step size)
    m = build(alpha0=0.4, alphad0=0.0, top=False)
    p = m.parameter_values
    tr = simulate(m, t_end=t_end, **({"rtol": rtol} if rtol else {}))
    assert tr.events == [] and set(tr.modes) == {"wall:stick, floor:stick"}
    assert np.max(np.abs(tr.q - tr.q[0])) < 1e-12 and np.max(np.abs(tr.qd)) < 1e-12
    assert tr.q[0, 2] == pytest.approx(0.4, abs=1e-14)
    mg = p["m"] * p["g"]
    for name in ("wall", "floor"):
        c = tr.contacts[name]
        F, N = np.array(c["friction"])[:, 0], np.array(c["normal"])
        assert np.all(np.abs(F) < 0.3 * N - 1.0)                 # inside the cones, widely
    # the distribution with the widest margins: F_A = 0 (the wall's margin binds)
    wall, floor = tr.contacts["wall"], tr.contacts["floor"]
    N_A = mg / 2 * np.tan(0.4)
    assert np.allclose(wall["normal"], N_A, rtol=1e-13) and np.allclose(wall["friction"], 0.0, atol=1e-12)
    assert np.allclose(floor["normal"], mg, rtol=1e-13) and np.allclose(floor["friction"], -N_A, rtol=1e-13)


def test_ladder_at_rest_forms_and_evaluate():
    m = build(alpha0=0.4, alphad0=0.0, top=False)
    assert compare_forms(m, contact_state="stick").worst() < 1e-12
    ev = evaluate(m)
    assert ev.mode == "wall:stick, floor:stick"
    margins = [ev.contacts[n]["margin"] for n in ("wall", "floor")]
    mg = m.parameter_values["m"] * m.parameter_values["g"]
    N_A = mg / 2 * np.tan(0.4)
    assert margins == pytest.approx([0.3 * N_A, 0.3 * mg - N_A], rel=1e-12)


def test_steep_ladder_at_rest_balances_both_margins():
    # stopped at alpha_s = 0.583 below alpha_lim: F_A > 0 makes both margins equal (small)
    tr = simulate(build(alpha0=0.7, alphad0=-1.2, t_end=1.5))
    assert [e["type"] for e in tr.events] == ["stick"]
    after = tr.t > tr.events[0]["t"]
    margins = [0.3 * np.array(tr.contacts[n]["normal"])[after] - np.abs(np.array(tr.contacts[n]["friction"])[after, 0])
               for n in ("wall", "floor")]
    assert np.all(margins[0] > 0.02) and np.allclose(margins[0], margins[1], rtol=1e-9, atol=1e-12)


def test_energy_friction_power_residuals(traj):
    E, W = traj.energy["energy"], traj.energy["friction_work"]
    assert np.all(np.diff(W) <= 1e-12) and W[-1] < -1.0
    assert abs((E[-1] - E[0]) - W[-1]) < 1e-8 * abs(E[0])
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert traj.diagnostics["constraint_residual_max"] < 1e-8


def test_landing_flat_with_friction_impact(model):
    tr = simulate(model, t_end=1.2)
    touch = [e for e in tr.events if e["type"] == "touch"]
    assert touch and touch[0]["contact"] == "top"
    assert tr.q[-1, 2] == pytest.approx(np.pi / 2, abs=1e-9) and np.max(np.abs(tr.qd[-1])) < 1e-9
    # everything the ladder had is dissipated by friction and the impact (flat: V = 0)
    E = tr.energy
    assert E["energy"][-1] == pytest.approx(0.0, abs=1e-9)
    assert E["friction_work"][-1] + E["impact_work"][-1] == pytest.approx(-E["energy"][0], rel=1e-9)
    assert tr.diagnostics["energy_balance_relative"] < 1e-8


def test_seed_representation_in_every_form():
    # contacts as ideal constraints + M V mu (the --friction painleve model), mu from the split:
    # every form reproduces the physical accelerations
    assert painleve_representation() < 1e-12


def test_painleve_representation_closes_only_touching_contacts(model):
    assert touching_contacts(model) == ["wall", "floor"]
    assert touching_contacts(model, {"top": "stick"}) == ["wall", "floor", "top"]
    pm, mus = painleve_model(model, touching_contacts(model))
    assert mus == ["mu_1"] and [c.name for c in pm.constraints] == ["wall", "floor"]
    with pytest.raises(FormNotApplicable, match="no possible velocity"):
        painleve_model(model)          # all three contacts closed: no motion left


# ------------------------------------------------------------------ command line


def test_cli_examples_run(tmp_path):
    # the example's run() end to end (its "ok" combines every check of the example)
    proc = _cli("examples", "run", NAME, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "leaves the wall" in proc.stdout and proc.stdout.rstrip().endswith("ok")


@pytest.mark.slow
def test_cli_simulate_and_evaluate_json(tmp_path):
    proc = _cli("simulate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("reverse", "wall"), ("lift-off", "wall")]
    assert d["events"][1]["t"] == pytest.approx(T_RELEASE, rel=1e-9)
    assert d["contacts"]["wall"]["mode"][0] == "slide+" and d["contacts"]["wall"]["mode"][-1] == "separated"
    assert np.all(np.diff(d["energy"]["friction_work"]) <= 1e-12)
    proc = _cli("evaluate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    e = json.loads(proc.stdout)
    SA, SB = smooth_reactions(0.9, -1.0, build().parameter_values)
    assert e["contacts"]["wall"]["constraint_multiplier"] == pytest.approx(SA, rel=1e-12)
    assert e["contacts"]["floor"]["constraint_multiplier"] == pytest.approx(SB, rel=1e-12)
    assert e["qddot"]["alpha"] == pytest.approx(alpha_dd_1_106(0.9, -1.0, -1.0, build().parameter_values), rel=1e-12)


@pytest.mark.slow
def test_cli_derive_painleve_representation_is_lagrange_ii_with_q_friction(tmp_path):
    # (ml^2 + J) alpha'' = m g l sin(alpha) + Q_mp, Q_mp = (m l^2 + J) mu  (seed (1.102), (1.56))
    proc = _cli("derive", NAME, "--form", "lagrange2", "--friction", "painleve", "--simplify", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "4*alpha''*l**2*m/3 = l*m*(g*sin(alpha) + 4*l*mu_1/3)" in proc.stdout
    proc = _cli("derive", NAME, "--form", "maggi", "--friction", "painleve", "--contact", "top=stick", cwd=tmp_path)
    assert proc.returncode == 2 and "no possible velocity" in proc.stderr
