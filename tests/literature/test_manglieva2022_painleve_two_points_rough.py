"""Painleve's two points on a ROUGH line (Manglieva & Beknazarov 2022, sec. 1.1, (1.18)-(1.29)):
the multipliers (1.27)-(1.28) do not depend on friction for any masses (and Painleve's own
unweighted split (1.4) does unless m = m1), the friction law of the system (the printed
(1.22)-(1.23) have the cases swapped), (1.29) corrected, the stop of M -- stick or slip
reversal -- against the reduced equations integrated by hand, energy, all forms, the CLI.

The split of the reaction into constraint and friction parts and the symbolic friction law are
also tested in ``test_manglieva2022_friction_split.py`` (same model file)."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.painleve_two_points import angle, multipliers, state
from nonideal.gallery.painleve_two_points_rough import (
    REVERSAL,
    build,
    classic_split,
    friction_law_mu,
    independence_of_friction,
    printed_mu,
    reference_events,
    residual_1_4,
    sliding,
    sticking,
    xdd_1_29,
)
from tests.helpers import run_cli as _cli

NAME = "painleve-two-points-rough"
T_STICK = 0.436835182221      # default parameters: M stops and sticks (reference ODE, 1e-12)


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def params(model):
    return model.parameter_values


def test_multipliers_1_27_1_28_do_not_depend_on_friction_for_any_masses():
    # constraint parts with f = 0.3 and f = 0 vs (1.27)-(1.28), four mass ratios, 8 states
    assert independence_of_friction() < 1e-12


@pytest.mark.parametrize("m, m1, depends", [(1.0, 2.0, True), (3.0, 0.5, True), (2.0, 2.0, False)])
def test_painleve_unweighted_split_depends_on_friction_unless_equal_masses(m, m1, depends):
    theta, thetad = 0.7, 1.3
    at = state(theta, thetad, 0.8, 0.5)
    lam_r, mu_r = classic_split(build(m=m, m1=m1), at, theta)
    lam_s, mu_s = classic_split(build(m=m, m1=m1, f=0.0), at, theta)
    assert mu_s == pytest.approx(0.0, abs=1e-12) and abs(mu_r) > 0.1
    # the seed's (1.4) (with m_2 -> m1, theta'^2 -> l theta'^2) holds for the unweighted split
    assert residual_1_4(lam_r, mu_r, theta, thetad, m, m1, 0.5, 9.81) == pytest.approx(0.0, abs=1e-12)
    assert (abs(lam_r - lam_s) > 0.05) is depends
    if not depends:   # m = m1: the corrected (1.5), lambda_1 = -m (l theta'^2 + g sin)/(1 + cos^2)
        assert lam_r == pytest.approx(-m * (0.5 * thetad ** 2 + 9.81 * np.sin(theta)) / (1 + np.cos(theta) ** 2),
                                      rel=1e-12)


@pytest.mark.parametrize("theta, thetad, xd", [(0.6, 0.0, 1.0), (1.1, -0.7, 0.4), (0.3, 1.3, -0.8),
                                               (1.4, 2.0, -0.2)])
def test_friction_law_derived_and_printed_swapped(params, theta, thetad, xd):
    p = params
    ev = evaluate(gallery.load(NAME), at=state(theta, thetad, xd, p["l"]))
    assert ev.contacts["line"]["mode"] == ("slide+" if xd > 0 else "slide-")
    lam = ev.reactions["line"]["constraint_part"][1]                  # the seed's lambda, along +y
    mu = sum(np.array(r["friction_part"]) for r in ev.reactions.values())[0] / p["m"]
    sigma = np.sign(xd)
    assert mu == pytest.approx(friction_law_mu(theta, lam, sigma, p["m"], p["m1"], p["f"]), rel=1e-11)
    assert np.sign(mu) == -sigma                                      # friction opposes x'
    # (1.22)/(1.23) as printed: the law of the other direction
    assert printed_mu(theta, lam, sigma, p["m"], p["m1"], p["f"]) == pytest.approx(
        friction_law_mu(theta, lam, -sigma, p["m"], p["m1"], p["f"]), rel=1e-12)
    # Coulomb (1.20): R_x = mu (m + m1 c^2) is the friction force, R_y = lambda + m1 mu s c = -N
    c, s = np.cos(theta), np.sin(theta)
    F, N = ev.contacts["line"]["friction"][0], ev.contacts["line"]["normal"]
    assert F == pytest.approx(mu * (p["m"] + p["m1"] * c * c), rel=1e-11)
    assert -N == pytest.approx(lam + p["m1"] * mu * s * c, rel=1e-11)
    # the hand-derived reduced equations give the same accelerations and normal force
    xdd, thdd, N_ref = sliding(theta, thetad, sigma, p)
    assert ev.qdd[0] == pytest.approx(xdd, rel=1e-11)
    assert N == pytest.approx(N_ref, rel=1e-11)
    # (1.29) corrected; the printed one is off
    assert xdd_1_29(theta, thetad, sigma, p) == pytest.approx(xdd, rel=1e-11)
    assert abs(xdd_1_29(theta, thetad, sigma, p, printed=True) - xdd) > 1e-2


def test_lambda_along_the_motion_and_stop_with_stick(model, params):
    tr = simulate(model)
    assert [(e["type"], e["mode"]) for e in tr.events] == [("stick", "line:stick")]
    ref = reference_events(params, 0.6, 0.0, 1.0, 3.0)
    assert [m for _, m in ref] == ["stick"]
    assert tr.events[0]["t"] == pytest.approx(ref[0][0], rel=1e-10)
    assert tr.events[0]["t"] == pytest.approx(T_STICK, rel=1e-10)
    after = tr.t > T_STICK + 1e-9
    assert np.ptp(tr.coordinate("x")[after]) < 1e-12
    # while sticking |F| <= f N and F, N are the pendulum's (M fixed)
    th, thd = angle(tr.q, tr.qd)
    F = np.array(tr.contacts["line"]["friction"])[after, 0]
    N = np.array(tr.contacts["line"]["normal"])[after]
    _, F_ref, N_ref = sticking(th[after], thd[after], params)
    assert np.max(np.abs(F - F_ref)) < 1e-9 and np.max(np.abs(N - N_ref)) < 1e-9
    assert np.all(np.abs(F) <= params["f"] * N)
    # the library's rod multiplier before the stop is the physical force, not (1.27)
    lam1, _ = multipliers(th, thd, params["m"], params["m1"], params["l"], params["g"])
    assert np.max(np.abs(tr.multipliers["rod"][~after] - lam1[~after])) > 0.1


def test_slip_reversals_against_the_reduced_equations(params):
    p = {**params, "f": REVERSAL["f"]}
    tr = simulate(build(f=REVERSAL["f"]), t_end=REVERSAL["t_end"])
    ref = reference_events(p, 0.6, 0.0, 1.0, REVERSAL["t_end"])
    lib = [(e["t"], e["mode"].split(":")[1]) for e in tr.events]
    assert [m for _, m in lib] == [m for _, m in ref] == ["slide-", "slide+", "slide-", "stick", "slide+", "stick"]
    assert [e["type"] for e in tr.events] == ["reverse"] * 3 + ["stick", "slip", "stick"]
    for (t, _), (t_ref, _) in zip(lib, ref):
        assert t == pytest.approx(t_ref, rel=1e-9)
    assert lib[0][0] == pytest.approx(0.605470119265, rel=1e-10)


@pytest.mark.parametrize("f", [0.3, REVERSAL["f"]])
def test_energy_balance_friction_power_and_residuals(f):
    tr = simulate(build(f=f), t_end=2.5)
    E, W = tr.energy["energy"], tr.energy["friction_work"]
    assert np.all(np.diff(W) <= 1e-12) and W[-1] < -1.0
    assert abs((E[-1] - E[0]) - W[-1]) < 1e-8 * abs(E[0])
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    assert tr.diagnostics["constraint_residual_max"] < 1e-8


@pytest.mark.parametrize("contact_state", ["slide", "stick"])
def test_all_forms_agree(model, contact_state):
    report = compare_forms(model, contact_state=contact_state)
    assert report.states == 20
    assert set(report.accelerations) >= {"lagrange2", "maggi", "appell", "shulgin", "gauss"}
    assert report.worst() < 1e-10, report


# ------------------------------------------------------------------ command line


def test_cli_examples_run(tmp_path):
    # the example's run() end to end (its "ok" combines every check of the example)
    proc = _cli("examples", "run", NAME, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "printed (1.22)" in proc.stdout and proc.stdout.rstrip().endswith("ok")


@pytest.mark.slow
def test_cli_simulate_and_evaluate_json(tmp_path):
    proc = _cli("simulate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("stick", "line")]
    assert d["events"][0]["t"] == pytest.approx(T_STICK, rel=1e-9)
    line = d["contacts"]["line"]
    assert line["mode"][0] == "slide+" and line["mode"][-1] == "stick"
    assert np.all(np.diff(d["energy"]["friction_work"]) <= 1e-12)
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8
    proc = _cli("evaluate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    e = json.loads(proc.stdout)
    lam1, lam = multipliers(0.6, 0.0, 1.0, 2.0, 0.5, 9.81)
    rod = e["reactions"]["rod"]["constraint_part"]
    assert rod[2:] == pytest.approx([lam1 * np.cos(0.6), lam1 * np.sin(0.6)], rel=1e-10)
    assert e["reactions"]["line"]["constraint_part"][1] == pytest.approx(lam, rel=1e-10)
    assert e["contacts"]["line"]["friction"][0] == pytest.approx(-0.3 * e["contacts"]["line"]["normal"], rel=1e-12)


@pytest.mark.slow
def test_cli_derive_painleve_representation_is_1_18(tmp_path):
    # friction as M V mu: on M (m mu_1, 0), on M1 m1 (mu_1 - mu_2 tan(theta), mu_2); with the
    # seed's single mu (mu_1 = mu, mu_2 = mu sin cos) this is (1.18): m1 mu (cos^2, sin cos)
    proc = _cli("derive", NAME, "--form", "lagrange1", "--friction", "painleve", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    # the readable form: forces (here the friction force M V mu) first, then the multipliers
    assert any(ln.strip().startswith("m*x'' = m*mu_1 + ") and "*lambda_rod/" in ln for ln in lines)
    assert any(ln.strip().startswith("m*y'' = g*m + ") and ln.rstrip().endswith(" - lambda_line")
               for ln in lines)
    assert any(ln.strip().startswith("m1*x1'' = m1*mu_1 + m1*mu_2*(y - y1)/(-x + x1) + ") for ln in lines)
    assert any(ln.strip().startswith("m1*y1'' = m1*(g + mu_2) + ") for ln in lines)
    proc = _cli("derive", NAME, "--form", "lagrange2", "--friction", "painleve", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "= mu_1*(m + m1) - m1*mu_2*y1/sqrt(l**2 - y1**2)" in proc.stdout   # (1.35): mu (m + m1 c^2)
