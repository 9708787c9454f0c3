"""The Chaplygin sleigh in speeds v, w (Yushkov 1999, appendix A): the quasi-velocity forms
print the appendix's equations, the initial state given in speeds, the closed form, and the
speeds and outputs in every output of the command line."""

import csv
import json

import numpy as np
import pytest

from nonideal import derive, gallery, simulate
from nonideal.gallery.chaplygin_sleigh import closed_form
from tests.helpers import run_cli


@pytest.fixture(scope="module")
def model():
    return gallery.load("chaplygin-sleigh-speeds")


@pytest.mark.parametrize("form", ["kane", "boltzmann_hamel", "poincare_chetaev", "appell"])
def test_quasi_velocity_forms_print_the_sleigh_equations(model, form):
    eom = derive(model, form)
    assert eom.unknowns == ("v'", "w'")
    assert eom.readable() == ["m*(v' - a*w**2) = 0", "(I + a**2*m)*w' + a*m*v*w = 0"]


def test_structure_and_hamel_coefficients_are_shown(model):
    pc = derive(model, "poincare_chetaev").as_text()
    assert "c^sigma[knife]_v,w = -1" in pc
    bh = derive(model, "boltzmann_hamel").as_text()
    assert "gamma^sigma[knife]_v,w = -1" in bh and "gamma^sigma[knife]_w,v = 1" in bh


def test_without_speeds_the_independent_velocities_are_used():
    eom = derive(gallery.load("chaplygin-sleigh"), "kane")
    assert eom.unknowns == ("x''", "theta''")
    assert any("no [speeds] declared" in n for n in eom.notes)


@pytest.mark.parametrize("form", ["lagrange1", "kane", "chaplygin", "voronets"])
def test_closed_form(model, form):
    p = model.parameter_values
    times = np.linspace(0, 5, 11)
    tr = simulate(model, times=times, form=form)
    v, w, th = closed_form(times, p["m"], p["I"], p["a"], 1.0, 1.5)
    assert np.max(np.abs(tr.speeds["v"] - v)) < 1e-9
    assert np.max(np.abs(tr.speeds["w"] - w)) < 1e-9
    assert np.max(np.abs(tr.coordinate("theta") - th)) < 1e-9
    assert np.max(np.abs(tr.outputs["reaction"] - tr.outputs["predicted_reaction"])) < 1e-9


def test_json_csv_and_text_hold_speeds_and_outputs(tmp_path, model):
    out = tmp_path / "sl.json"
    csv_path = tmp_path / "sl.csv"
    r = run_cli("simulate", str(gallery.model_path("chaplygin-sleigh-speeds")), "--times", "0,1,2",
                "--json", str(out), "--csv", str(csv_path))
    assert r.returncode == 0, r.stderr
    d = json.loads(out.read_text())
    p = model.parameter_values
    v, w, _ = closed_form(np.array([0.0, 1.0, 2.0]), p["m"], p["I"], p["a"], 1.0, 1.5)
    assert np.allclose(d["speeds"]["v"], v, atol=1e-9) and np.allclose(d["speeds"]["w"], w, atol=1e-9)
    assert np.allclose(d["speeds"]["s"], 0.0, atol=1e-10)
    assert np.allclose(d["outputs"]["reaction"], d["multipliers"]["knife"], rtol=1e-14)
    assert np.allclose(d["outputs"]["E"], d["energy"]["kinetic"], rtol=1e-14)
    rows = list(csv.DictReader(csv_path.open()))
    assert float(rows[1]["v"]) == pytest.approx(v[1], abs=1e-9)
    assert float(rows[2]["reaction"]) == pytest.approx(d["multipliers"]["knife"][2], rel=1e-12)
    r = run_cli("simulate", str(gallery.model_path("chaplygin-sleigh-speeds")), "--t-end", "1")
    assert r.returncode == 0 and "v(t_end)" in r.stdout and "(output;" in r.stdout


def test_evaluate_json_speeds_and_rates(tmp_path):
    r = run_cli("evaluate", str(gallery.model_path("chaplygin-sleigh-speeds")), "--at",
                "theta=0.3, v=2, w=0.5", "--form", "kane", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["speeds"] == pytest.approx({"v": 2.0, "w": 0.5, "s": 0.0}, abs=1e-12)
    m, I, a = 2.0, 0.3, 0.4
    assert d["speeds_dot"]["v"] == pytest.approx(a * 0.25, rel=1e-12)
    assert d["speeds_dot"]["w"] == pytest.approx(-m * a * 2.0 * 0.5 / (I + m * a * a), rel=1e-12)
    assert d["qdot"]["x"] == pytest.approx(2.0 * np.cos(0.3), rel=1e-12)


def test_run_is_ok():
    assert gallery.run("chaplygin-sleigh-speeds", verbose=False)["ok"]


def test_plot_has_the_speed_and_output_panels(tmp_path):
    png = tmp_path / "sl.png"
    r = run_cli("simulate", str(gallery.model_path("chaplygin-sleigh-speeds")), "--t-end", "1", "--plot", png)
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 10000
