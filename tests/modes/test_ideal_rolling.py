"""Ideal rolling while in contact (``mu = "inf"``): how it is read and refused, its two states,
the impact that stops the slip on touching (closed form: angular momentum about the contact
point), the start that would slip, and what check / evaluate / realizability / derive say."""

import json
import math

import numpy as np
import pytest

from nonideal import ModelError, gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.contact.realizability import realizability
from nonideal.modeling.contacts import Contact, Coulomb, IdealRolling
from nonideal.modeling.model import Model
from nonideal.modeling.modelfile import load_model
from nonideal.modes.solver import ModeSolver
from nonideal.modes.switching import contact_options
from nonideal.numeric.kernel import kernel_of, parameter_vector
from tests.helpers import run_cli

DROP = """
[model]
name = "Ball dropped spinning onto a plane"
format = 1

[parameters]
m = 1.0
g = 9.81
r = 0.1
v0 = {v0}
w0 = {w0}
h = {h}

[coordinates]
q = ["x", "y", "phi"]

[energy]
kinetic = "m/2*(x'^2 + y'^2) + m*r^2/5*phi'^2"
potential = "m*g*y"

[[contacts]]
name = "floor"
gap = "y - r"
slip = ["x' + r*phi'"]
{friction}

[initial]
x = 0.0
y = "h"
phi = 0.0
"x'" = "v0"
"y'" = 0.0
"phi'" = "w0"

[simulation]
t_end = 1.0
"""


def _file(tmp_path, friction='mu = "inf"', v0=2.0, w0=5.0, h=0.5):
    """The ball dropped from height *h* (0.1: touching) with speed *v0* and spin *w0*."""
    path = tmp_path / "drop.toml"
    path.write_text(DROP.format(friction=friction, v0=v0, w0=w0, h=h), encoding="utf-8")
    return path


@pytest.mark.parametrize("written", ['mu = "inf"', 'mu = "Inf"', "mu = inf", 'mu = "infinity"',
                                     'mu = "inf"\nmu_static = "inf"'])
def test_read_as_ideal_rolling(tmp_path, written):
    model = load_model(_file(tmp_path, written))
    assert isinstance(model.contacts[0].friction, IdealRolling)


@pytest.mark.parametrize("written, says", [
    ('mu = "inf"\nmu_static = 0.5', "finite mu_static"),
    ('mu = 0.3\nmu_static = "inf"', "mu_static = inf"),
    ('mu = "inf"\nfriction = "regularized"\neps = 1e-3', "regularized law with infinite mu"),
    ('mu = "inf"\neps = 1e-3', "eps has no meaning for ideal rolling"),
])
def test_refused_combinations_name_the_contact_and_the_fix(tmp_path, written, says):
    with pytest.raises(ModelError) as err:
        load_model(_file(tmp_path, written))
    assert says in str(err.value) and "floor" in str(err.value)


def test_python_api_reads_coulomb_inf_as_ideal_rolling():
    for friction in (Coulomb(math.inf), Coulomb("inf"), IdealRolling()):
        model = Model(name="b", coordinates=["x", "y"], parameters={"g": 9.81},
                      kinetic="(x'^2 + y'^2)/2", potential="g*y",
                      contacts=[Contact("floor", "y", ("x'",), friction)],
                      initial={"x": 0, "y": 0, "x'": 0, "y'": 0})
        assert isinstance(model.contacts[0].friction, IdealRolling)


def test_closed_rolling_contact_has_only_separated_and_rolling_states(tmp_path):
    model = load_model(_file(tmp_path, h=0.1))
    solver = ModeSolver(kernel_of(model), parameter_vector(model))
    assert solver.rolling == {0} and not solver.frictionless
    q, qd = np.array([0.0, 0.1, 0.0]), np.array([1.0, 0.0, -10.0])   # rolling: U = 0
    kin = solver.ck.fn.raw(solver.input(0.0, q, qd), np.empty(solver.ck.size))
    states = [cs.state for cs in contact_options(solver, kin, (1.1, 11.0))[0]]
    assert states == ["separated", "stick"]


@pytest.mark.parametrize("v0, w0, e", [(2.0, 5.0, 0.0), (2.0, 0.0, 0.0), (-1.0, 30.0, 0.0)])
def test_touch_is_an_impact_that_stops_the_slip(tmp_path, v0, w0, e):
    """Landing on the plane: the tangential impulse is unbounded, so the slip stops at once and
    the angular momentum about the contact point is conserved: v+ = (5 v0 - 2 r w0)/7."""
    path = _file(tmp_path, v0=v0, w0=w0)
    tr = simulate(load_model(path))
    assert [(ev["type"], ev["mode"]) for ev in tr.events] == [("touch", "floor:stick")]
    v_plus = (5 * v0 - 2 * 0.1 * w0) / 7
    assert tr.at("x'") == pytest.approx(v_plus, rel=1e-12, abs=1e-12)
    assert tr.at("phi'") == pytest.approx(-v_plus / 0.1, rel=1e-12, abs=1e-11)
    assert tr.diagnostics["energy_balance_relative"] < 1e-10     # the impact loss is accounted
    assert np.max(np.abs(tr.energy["friction_work"])) < 1e-10   # rolling: no friction work


def test_a_start_that_slips_is_refused(tmp_path):
    out = run_cli("simulate", _file(tmp_path, h=0.1))
    assert out.returncode == 2
    assert "rolls ideally (mu = inf) but slips" in out.stderr and "U = 2.5" in out.stderr


def test_check_skips_painleve_analysis():
    from nonideal.analysis.checks import check_model

    report = check_model(gallery.load("ball-off-sphere"))
    entry = report.to_dict()["contacts"][0]
    assert entry["ideal_rolling"] and entry["mu"] == "inf" and entry["critical_mu"] is None
    assert "ideal rolling: friction unbounded" in report.as_text()
    assert "critical mu =" not in report.as_text() and "no Painleve paradox" in report.determinacy


def test_evaluate_and_realizability_of_ideal_rolling():
    model = gallery.load("ball-off-sphere")
    ev = evaluate(model).to_dict()["contacts"]["sphere"]
    # from rest at theta0: N = m g cos(theta0), F = 2/7 m g sin(theta0) (see the gallery example)
    assert ev["normal"] == pytest.approx(9.81 * np.cos(0.1), rel=1e-12)
    assert ev["friction_needed"] == pytest.approx(2 / 7 * 9.81 * np.sin(0.1), rel=1e-12)
    assert ev["ideal_rolling"] and ev["mu"] == "inf" and "margin" not in ev
    rep = realizability(model)
    c = rep.contacts["sphere"]
    assert rep.realizable and c.ideal_rolling and c.ratio == 0.0
    assert json.loads(json.dumps(rep.to_dict(), allow_nan=False))["contacts"]["sphere"]["margin"] == "inf"
    assert "an infinite mu realizes any rolling" in rep.as_text()


def test_derive_shows_an_ideal_nonholonomic_and_unilateral_constraint():
    from nonideal import derive

    model = gallery.load("ball-off-sphere")
    eom = derive(model, "lagrange1")
    assert any("rolling ideally (mu = inf) -- an ideal nonholonomic constraint" in n for n in eom.notes)
    assert [str(m) for m in eom.multipliers] == ["lambda_sphere", "lambda_sphere_t"]
    refused = run_cli("derive", gallery.model_path("ball-off-sphere"), "--contact", "sphere=slide+")
    assert refused.returncode == 2 and "never slides" in refused.stderr
