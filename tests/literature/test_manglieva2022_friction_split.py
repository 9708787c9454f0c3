"""Painleve's split and the friction law of the system (Manglieva & Beknazarov 2022, sec. 1.1-1.2).

Two points joined by a rod, M on a rough line (y axis down, gravity +y), in redundant
coordinates (x, y, x1, y1).  The seed's claims checked here:

* the constraint forces lambda of the split R = G^T lambda + M V mu do not depend on friction
  (any masses) -- (1.27)-(1.28) hold with and without friction;
* the friction part produces accelerations along the possible velocities only, with the
  structure (1.15)/(1.17): on M (m mu, 0), on M1 m1 mu (cos^2, sin cos);
* the friction law mu(lambda) (1.22)-(1.23).  Derived here: for x' > 0
  mu = f lambda / (m + m1 cos^2 theta - f m1 sin theta cos theta) with the seed's lambda (the
  vertical reaction multiplier, < 0); the seed prints this expression for x' < 0 and
  -f lambda/(m + m1 cos^2 + f m1 sin cos) for x' > 0: the two cases are swapped (the printed
  x' > 0 law would make friction accelerate the point).
"""

import numpy as np
import pytest
import sympy as sp

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.contact.friction_law import friction_law, painleve_model
from nonideal.analysis.derivation import derive


@pytest.fixture(scope="module")
def model():
    # the gallery's model file (nonideal/gallery/painleve_two_points_rough.toml)
    return gallery.load("painleve-two-points-rough")


def _state(theta, thetad, xd):
    return {"theta": theta, "thetad": thetad, "xd": xd}


@pytest.mark.parametrize("masses", [(1.0, 2.0), (3.0, 0.5), (1.0, 1.0)])
@pytest.mark.parametrize("theta,thetad,xd", [(0.6, 0.0, 1.0), (1.1, -0.7, 0.4), (0.3, 1.3, -0.8)])
def test_constraint_forces_do_not_depend_on_friction(model, masses, theta, thetad, xd):
    m, m1 = masses
    l, g = 0.5, 9.81
    at = {"x": 0.0, "y": 0.0, "x1": l * np.cos(theta), "y1": l * np.sin(theta),
          "x'": xd, "y'": 0.0, "x1'": xd - l * np.sin(theta) * thetad, "y1'": l * np.cos(theta) * thetad}
    rough = model.replace(parameters={**model.parameter_values, "m": m, "m1": m1})
    smooth = model.replace(parameters={**model.parameter_values, "m": m, "m1": m1, "f": 0.0})
    er, es = evaluate(rough, at=at), evaluate(smooth, at=at)
    # constraint parts (Painleve split) are the same with and without friction
    for name in ("rod", "line"):
        assert np.allclose(er.reactions[name]["constraint_part"], es.reactions[name]["constraint_part"],
                           rtol=1e-10, atol=1e-10)
    # and they are the seed's (1.27)-(1.28): the rod force on M1 is lambda1 (cos, sin)
    lam1 = -(l * thetad ** 2 + g * np.sin(theta)) * m * m1 / (m + m1 * np.cos(theta) ** 2)
    lam = -m * g + lam1 * np.sin(theta)
    rod = np.array(er.reactions["rod"]["constraint_part"])
    assert rod[2:] == pytest.approx(lam1 * np.array([np.cos(theta), np.sin(theta)]), rel=1e-10)
    # our gap is -y (normal force upward = -lambda of the seed)
    line = np.array(er.reactions["line"]["constraint_part"])
    assert line[1] == pytest.approx(lam, rel=1e-10)
    # the physical normal force does depend on friction while sliding
    assert er.contacts["line"]["normal"] != pytest.approx(es.contacts["line"]["normal"], rel=1e-6)


def test_friction_part_has_the_seeds_structure(model):
    theta = 0.6
    ev = evaluate(model)
    fp = np.array(ev.reactions["line"]["friction_part"]) + np.array(ev.reactions["rod"]["friction_part"])
    m, m1 = 1.0, 2.0
    mu = fp[0] / m
    # (1.15), (1.17): rho = m mu (1, 0); rho1 = m1 mu (cos^2, sin cos)
    assert fp == pytest.approx([m * mu, 0.0, m1 * mu * np.cos(theta) ** 2,
                                m1 * mu * np.sin(theta) * np.cos(theta)], abs=1e-12)
    # and all parts add up to the total reaction M q'' - F
    total = sum(np.array(r["constraint_part"]) + np.array(r["friction_part"]) for r in ev.reactions.values())
    generalized = sum(np.array(r["generalized"]) for r in ev.reactions.values())
    assert total == pytest.approx(generalized, abs=1e-12)


def test_friction_law_of_the_system(model):
    x, y, x1, y1, l, th = sp.symbols("x y x1 y1 l theta")
    subs = {x1: x + l * sp.cos(th), y1: y + l * sp.sin(th)}
    m, m1, f, lam_line = sp.symbols("m m1 f lambda_line")
    lam_seed = -lam_line  # the seed's lambda is the y (down) component
    plus = friction_law(model, "line", +1, substitutions=subs)
    minus = friction_law(model, "line", -1, substitutions=subs)
    assert sp.simplify(plus.effective_mass - (m + m1 * sp.cos(th) ** 2)) == 0  # (1.13)
    derived_plus = f * lam_seed / (m + m1 * sp.cos(th) ** 2 - f * m1 * sp.sin(th) * sp.cos(th))
    derived_minus = -f * lam_seed / (m + m1 * sp.cos(th) ** 2 + f * m1 * sp.sin(th) * sp.cos(th))
    assert sp.simplify(plus.mu - derived_plus) == 0
    assert sp.simplify(minus.mu - derived_minus) == 0
    # the seed's (1.22) (printed for x' > 0) is our x' < 0 law: the cases are swapped
    seed_122 = -f * lam_seed / (m1 * sp.cos(th) ** 2 + m1 * sp.sin(th) * sp.cos(th) * f + m)
    assert sp.simplify(minus.mu - seed_122) == 0
    # friction opposes the motion: for x' > 0 and the point pressed on the line (lambda_seed < 0)
    val = plus.mu.subs({m: 1, m1: 2, f: 0.3, th: 0.6, lam_line: 10.0})
    assert float(val) < 0


def test_friction_law_matches_the_simulation(model):
    tr = simulate(model, times=np.linspace(0, 0.4, 5))
    law = friction_law(model, "line", +1)
    for k in range(1, len(tr.t)):
        ev = evaluate(model, at={c: tr.q[k, i] for i, c in enumerate(tr.coordinates)} |
                      {c + "'": tr.qd[k, i] for i, c in enumerate(tr.coordinates)})
        assert ev.contacts["line"]["mode"] == "slide+"
        values = {sp.Symbol(c): v for c, v in zip(tr.coordinates, tr.q[k])}
        values.update({sp.Symbol(n): v for n, v in model.parameter_values.items()})
        values[sp.Symbol("lambda_line")] = ev.contacts["line"]["constraint_multiplier"]
        assert float(law.N.subs(values)) == pytest.approx(ev.contacts["line"]["normal"], rel=1e-10)
        assert float(law.F.subs(values)) == pytest.approx(ev.contacts["line"]["friction"][0], rel=1e-10)


def test_simulated_motion_stops_and_balances_energy(model):
    tr = simulate(model)
    stick = [e for e in tr.events if e["type"] == "stick"]
    assert len(stick) == 1 and stick[0]["t"] == pytest.approx(0.436835182221, rel=1e-9)
    assert tr.diagnostics["energy_balance_relative"] < 1e-9
    assert tr.diagnostics["constraint_residual_max"] < 1e-8
    W = tr.energy["friction_work"]
    assert np.all(np.diff(W) <= 1e-12)          # friction never does positive work
    assert W[-1] < -0.1
    x = tr.coordinate("x")
    after = tr.t > stick[0]["t"] + 1e-9
    assert np.ptp(x[after]) < 1e-9               # M stays put once it sticks


@pytest.mark.parametrize("state", ["slide", "stick"])
def test_every_form_and_gauss_agree_with_friction(model, state):
    report = compare_forms(model, contact_state=state)
    assert report.states == 20
    assert report.worst() < 1e-10, report


def test_equations_with_friction_in_the_seeds_representation(model):
    pm, mus = painleve_model(model)
    assert mus == ["mu_1", "mu_2"]
    lag = derive(pm, "lagrange1").as_text()
    assert "mu_1" in lag and "lambda_line" in lag           # (1.53): multipliers and M V mu
    mag = derive(pm, "maggi").as_text()
    assert "mu_1" in mag and "lambda_line" not in mag       # (1.65): reactions eliminated
    # Lagrange I (1.53): friction enters as M V mu with V the possible velocities
    eom = derive(pm, "lagrange1")
    Qf = eom.generalized_forces
    m = sp.Symbol("m")
    assert sp.simplify(Qf[0] - m * sp.Symbol("mu_1")) == 0


def test_every_row_and_the_total_balance(model):
    # each row's parts add up to its physical reaction; the ideal rod gets a friction part
    # too (friction at the line changes the rod's force: seed 000, (1.14)-(1.17)); summed over
    # the rows the friction parts have the seed's structure (test above)
    d = evaluate(model).to_dict()
    tot = d["reaction_total"]
    for name, r in d["reactions"].items():
        assert np.array(r["constraint_part"]) + np.array(r["friction_part"]) == pytest.approx(
            np.array(r["generalized"]), abs=1e-12), name
    assert np.max(np.abs(d["reactions"]["rod"]["friction_part"])) > 1e-3
    assert np.array(tot["constraint_part"]) + np.array(tot["friction_part"]) == pytest.approx(
        np.array(tot["generalized"]), abs=1e-12)
    assert tot["generalized"] == pytest.approx(
        sum(np.array(r["generalized"]) for r in d["reactions"].values()), abs=1e-12)
