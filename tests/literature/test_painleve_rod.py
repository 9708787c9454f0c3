"""Painleve's rod on a rough floor: effective normal compliance b(theta, mu), the critical
coefficient (1 + 3cos^2)/(3 sin cos) (min 4/3 at tan = 2) vs critical_friction, the paradox
(inconsistent and indeterminate, API and CLI exit code 3), the consistent case (slide, stick,
slip, fall flat) against hand-derived reduced equations, energy, all forms, CLI."""

import json
import re

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.errors import PainleveParadox
from nonideal.gallery.painleve_rod import (
    build,
    compliance,
    critical_mu,
    library_critical_mu,
    pivot_forces,
    reference_events,
    region_plot,
    sliding_normal_force,
)
from tests.helpers import run_cli as _cli

MU_C_11 = (1 + 3 * np.cos(1.1) ** 2) / (3 * np.sin(1.1) * np.cos(1.1))   # 1.333544...


@pytest.fixture(scope="module")
def model():
    return gallery.load("painleve-rod")


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model)


# ----------------------------------------------------------------------------- (a) the region


def test_critical_coefficient_minimum_is_four_thirds_at_tan_2():
    th = np.linspace(0.05, np.pi / 2 - 0.05, 200001)
    k = int(np.argmin(critical_mu(th)))
    assert critical_mu(np.arctan(2.0)) == pytest.approx(4 / 3, rel=1e-15)
    assert np.tan(th[k]) == pytest.approx(2.0, rel=1e-4)
    assert critical_mu(np.pi / 4) == pytest.approx(5 / 3, rel=1e-15)
    assert critical_mu(1.1) == pytest.approx(1.333544026068, rel=1e-11)


@pytest.mark.parametrize("theta", [0.2, np.pi / 6, np.pi / 4, float(np.arctan(2.0)), 1.1, 1.3, 1.5])
def test_critical_friction_reproduces_closed_form(model, theta):
    lib, b = library_critical_mu(model, theta, s=-1.0)
    assert lib == pytest.approx(critical_mu(theta), rel=1e-10)
    assert b == pytest.approx(compliance(theta, 0.5, -1.0), rel=1e-10)
    # sliding towards the rod (s = +1): b grows with mu, no paradox
    assert library_critical_mu(model, theta, s=+1.0)[0] is None


@pytest.mark.parametrize("mu", [0.0, 0.5, 1.0, 2.0, 3.0])
def test_effective_compliance_formula(mu):
    th = 1.1
    _, b = library_critical_mu(build(mu=mu), th, s=-1.0)
    expected = 1 + 3 * np.cos(th) ** 2 - 3 * mu * np.sin(th) * np.cos(th)   # m = 1
    assert b == pytest.approx(expected, rel=1e-12, abs=1e-13)
    assert (b < 0) == (mu > MU_C_11)


def test_region_plot_png(tmp_path):
    png = region_plot(tmp_path / "region.png", [(1.1, 2.0, "paradox")])
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


# ----------------------------------------------------------------------------- (b) the paradox


def test_inconsistent_region_stops_with_paradox():
    p = build(mu=2.0).parameter_values
    assert -p["g"] < 0                             # g_free'' = -g at theta' = 0
    with pytest.raises(PainleveParadox) as info:
        simulate(build(mu=2.0))
    msg = str(info.value)
    assert "Painleve paradox (inconsistency) at contact(s) A" in msg
    assert f"critical friction coefficient: {MU_C_11:.6g}" in msg
    assert f"effective normal compliance b = dg''/dN: {compliance(1.1, 2.0, -1.0):.6g}" in msg
    assert info.value.t == 0.0 and info.value.state["theta"] == pytest.approx(1.1)


def test_indeterminate_region_stops_with_paradox():
    # l sin(theta) theta'^2 = 0.5 sin(1.1) 36 = 16.04 > g: the free gap acceleration is positive
    assert 0.5 * np.sin(1.1) * 36 - 9.81 > 0
    with pytest.raises(PainleveParadox) as info:
        simulate(build(mu=2.0, xd0=-5.0, thetad0=6.0))
    msg = str(info.value)
    assert "Painleve paradox (indeterminacy) at contact(s) A" in msg
    assert "[A:separated, B:separated]" in msg and "[A:slide-, B:separated]" in msg
    assert f"critical friction coefficient: {MU_C_11:.6g}" in msg


def test_below_the_critical_coefficient_no_paradox():
    # same states with mu = 1.3 < mu_c(1.1): sliding continues (inconsistent state) or the rod
    # leaves the floor (indeterminate state: separation is the only consistent choice)
    tr = simulate(build(mu=1.3), t_end=0.05)
    assert tr.modes[0] == "A:slide-, B:separated"
    N0 = tr.contacts["A"]["normal"][0]
    assert N0 == pytest.approx(sliding_normal_force(1.1, 0.0, -1.0, build(mu=1.3).parameter_values), rel=1e-12)
    tr = simulate(build(mu=1.3, xd0=-5.0, thetad0=6.0), t_end=0.05)
    assert tr.modes[0] == "A:separated, B:separated"


def _variant(tmp_path, name, mu, xd0, thetad0):
    text = gallery.model_path("painleve-rod").read_text()
    text = re.sub(r'^mu = \{ value = [0-9.]+', f"mu = {{ value = {mu}", text, flags=re.M)
    text = re.sub(r'^"x\'" = .*$', f'"x\'" = {xd0}', text, flags=re.M)
    text = re.sub(r'^"theta\'" = .*$', f'"theta\'" = {thetad0}', text, flags=re.M)
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("kind, xd0, thetad0", [("inconsistency", -1.0, 0.0), ("indeterminacy", -5.0, 6.0)])
def test_cli_paradox_exit_code_3(tmp_path, kind, xd0, thetad0):
    path = _variant(tmp_path, f"rod_{kind}.toml", 2.0, xd0, thetad0)
    out = tmp_path / "never.json"
    proc = _cli("simulate", path, "--json", out, cwd=tmp_path)
    assert proc.returncode == 3, proc.stderr
    assert not out.exists()
    assert f"Painleve paradox ({kind}) at contact(s) A" in proc.stderr
    assert f"critical friction coefficient: {MU_C_11:.6g}" in proc.stderr


# ----------------------------------------------------------------------------- (c) normal case


def test_slide_stick_slip_fall_flat_event_times(model, traj):
    ref = reference_events(model.parameter_values)
    ev = traj.events
    assert [(e["type"], e["contact"], e["mode"]) for e in ev] == [
        ("stick", "A", "A:stick, B:separated"),
        ("slip", "A", "A:slide+, B:separated"),
        ("touch", "B", "A:stick, B:stick")]
    for e in ev:
        assert e["t"] == pytest.approx(ref[e["type"]], rel=1e-9)
    assert ref["stick"] == pytest.approx(0.2229811587, rel=1e-8)
    # the rod ends flat and at rest
    assert abs(traj.at("theta")) < 1e-12 and abs(traj.at("y")) < 1e-12
    assert np.max(np.abs(traj.qd[-1])) < 1e-12


def test_forces_along_the_phases(model):
    p = model.parameter_values
    times = np.linspace(0, 0.7, 141)
    tr = simulate(model, times=times)
    th, thd = tr.coordinate("theta"), tr.velocity("theta")
    A = tr.contacts["A"]
    mode = np.array(A["mode"])
    N = np.array(A["normal"])
    F = np.array(A["friction"])[:, 0]
    U = np.array(A["slip"])[:, 0]
    slide = np.char.startswith(mode, "slide")
    stick = mode == "stick"
    assert slide.sum() > 20 and stick.sum() > 20
    # sliding: N = -g_free''/b with b = (1 + 3cos^2 + 3 mu s sin cos)/m, F = -mu s N
    s = np.sign(U[slide])
    assert set(s) == {-1.0, 1.0}
    assert np.allclose(N[slide], sliding_normal_force(th[slide], thd[slide], s, p), rtol=1e-10)
    assert np.allclose(F[slide], -0.5 * s * N[slide], rtol=1e-12)
    # sticking: the rod pivots about A; friction within the cone
    thdd, F_piv, N_piv = pivot_forces(th[stick], thd[stick], p)
    assert np.allclose(tr.qdd[stick, 2], thdd, rtol=1e-10)
    assert np.allclose(F[stick], F_piv, rtol=1e-9, atol=1e-10)
    assert np.allclose(N[stick], N_piv, rtol=1e-10)
    assert np.all(np.abs(F[stick]) <= 0.5 * N[stick] + 1e-12)
    assert np.all(N >= 0) and np.all(compliance(th[slide], 0.5, s) > 0)


def test_energy_balance_impact_and_friction_work(model, traj):
    ref = reference_events(model.parameter_values)
    E = traj.energy
    E0 = 9.81 * 0.5 * np.sin(1.1) + 0.5            # m g l sin(theta0) + m x'^2/2, m = 1
    assert E["energy"][0] == pytest.approx(E0, rel=1e-14)
    # the plastic touch-down stops the rod dead: it loses all its kinetic energy
    assert E["impact_work"][-1] == pytest.approx(-ref["kinetic_energy_at_touch"], rel=1e-9)
    assert E["friction_work"][-1] + E["impact_work"][-1] == pytest.approx(-E0, rel=1e-10)
    assert np.all(np.diff(E["friction_work"]) <= 1e-10)      # fixed floor: power <= 0
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert traj.diagnostics["constraint_residual_max"] < 1e-9


def test_all_forms_agree(model):
    # both ends touching = the rod flat, sliding; the tilted rod with A alone, slide and stick
    assert compare_forms(model, contact_state="slide").worst() < 1e-10
    single = build(upper_end=False)
    for state in ("slide", "stick"):
        report = compare_forms(single, contact_state=state)
        assert report.states == 20
        assert set(report.accelerations) >= {"lagrange2", "maggi", "appell", "shulgin", "gauss"}
        assert report.worst() < 1e-10, report


def test_gallery_run(tmp_path):
    out = gallery.module("painleve-rod").run(verbose=False, png=tmp_path / "r.png")
    assert out["ok"] and (tmp_path / "r.png").stat().st_size > 20_000


def test_cli_simulate_json(tmp_path):
    proc = _cli("simulate", gallery.model_path("painleve-rod"), "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
            "diagnostics"} <= set(d)
    assert set(d["contacts"]) == {"A", "B"}
    assert {"normal", "friction", "slip", "mode"} <= set(d["contacts"]["A"])
    assert d["contacts"]["A"]["mode"][0] == "slide-" and d["contacts"]["B"]["mode"][0] == "separated"
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("stick", "A"), ("slip", "A"), ("touch", "B")]
    assert d["events"][2]["t"] == pytest.approx(0.70353011625, rel=1e-9)
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8


def test_examples_run_writes_no_file_unasked(tmp_path):
    import tempfile
    from pathlib import Path

    from tests.helpers import run_cli

    target = Path(tempfile.gettempdir()) / "painleve_rod_region.png"
    before = target.stat().st_mtime if target.exists() else None
    proc = run_cli("examples", "run", "painleve-rod", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "region plot: not drawn" in proc.stdout
    assert list(tmp_path.iterdir()) == []
    assert (target.stat().st_mtime if target.exists() else None) == before
