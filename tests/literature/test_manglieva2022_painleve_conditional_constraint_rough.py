"""Two points on a rod, midpoint velocity along the rod, M1 in a ROUGH guide (Manglieva &
Beknazarov 2022, sec. 1.3, problem 1, (1.66)-(1.100)): multipliers (1.87), (1.89) independent of
friction, the friction structure (1.79)-(1.80), the friction law ((1.82) printed with the cases
swapped), (1.98) with eps = sign(x1'), (1.99) corrected, the static-friction condition (1.100)
on both sides of both thresholds, the start-stop-stick motion against the equation of motion
integrated by hand, energy, all forms, the CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.contact.friction_law import friction_law
from nonideal.gallery.painleve_conditional_constraint import angle, multipliers
from nonideal.gallery.painleve_conditional_constraint_rough import (
    KEYS,
    acceleration,
    at_rest,
    build,
    driving_force,
    friction_law_mu,
    normal_force,
    printed_mu,
    reference_motion,
    residual_1_98,
    rest_forms,
    split_at,
    sticks_at_rest,
    thresholds,
)
from tests.helpers import run_cli as _cli

NAME = "painleve-conditional-constraint-rough"
T_STOP = 0.6174313731845        # default (X = 15 N): M1 sticks (reference ODE; digits 1e-12)


@pytest.fixture(scope="module")
def model():
    return gallery.load(NAME)


@pytest.fixture(scope="module")
def p(model):
    return model.parameter_values


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model, times=np.linspace(0.0, 1.5, 151))


def _state(theta, v, l):
    """Admissible (x1, y1, x2, y2) state with x1' = v (theta' = 2 v sin(theta)/l)."""
    thd = 2 * v * np.sin(theta) / l
    return (np.array([0.0, 0.0, l * np.cos(theta), l * np.sin(theta)]),
            np.array([v, 0.0, v - l * np.sin(theta) * thd, l * np.cos(theta) * thd]))


@pytest.mark.parametrize("theta, v", [(1.5, 0.7), (0.6, -1.2), (2.4, 0.3), (1.1, 2.0)])
@pytest.mark.parametrize("masses", [(1.0, 2.0), (3.0, 0.5)])
def test_split_multipliers_independent_of_friction_and_friction_law(p, theta, v, masses):
    m1, m2 = masses
    q, qd = _state(theta, v, p["l"])
    params = {**{k: p[k] for k in KEYS}, "m1": m1, "m2": m2}
    rough = split_at(build(**params), q, qd)
    smooth = split_at(build(**{**params, "f": 0.0}), q, qd)
    thd = 2 * v * np.sin(theta) / p["l"]
    lam1, lam2, lam = multipliers(theta, thd, v, m1, m2, p["l"], p["g"], p["X"])
    for r in (rough, smooth):
        assert r[1] == pytest.approx(lam1, rel=1e-11, abs=1e-11)       # (1.87)
        assert r[2] == pytest.approx(lam2, rel=1e-11, abs=1e-11)       # (1.87)
        assert r[3] == pytest.approx(lam, rel=1e-11)                   # (1.89)
    q_ = {**params, "m1": m1, "m2": m2}
    ev, _, _, lam_c, mu, fp = rough
    sigma = np.sign(v)
    # the friction part (1.79)-(1.80): m1 mu (1, 0) on M1, m2 mu (cos 2theta, sin 2theta) on M2
    assert fp == pytest.approx(mu * np.array([m1, 0.0, m2 * np.cos(2 * theta), m2 * np.sin(2 * theta)]),
                               abs=1e-11)
    # the friction law of the system (derived) and (1.82) as printed (cases swapped)
    assert mu == pytest.approx(friction_law_mu(lam_c, sigma, q_), rel=1e-11)
    if lam_c < 0:
        assert printed_mu(lam_c, sigma, q_) == pytest.approx(-mu, rel=1e-11)
    # physical forces: N = -lambda (no friction part along y on M1), R_tau = (m1 + m2) mu
    assert ev.contacts["line"]["normal"] == pytest.approx(-lam_c, rel=1e-11)
    assert ev.contacts["line"]["normal"] == pytest.approx(normal_force(theta, v, q_), rel=1e-11)
    assert ev.contacts["line"]["friction"][0] == pytest.approx((m1 + m2) * mu, rel=1e-11)
    # the equation of motion (*) = corrected (1.99), and (1.98) with eps = sign(x1')
    assert ev.qdd[0] == pytest.approx(acceleration(theta, v, sigma, q_), rel=1e-11)
    thdd = (ev.qdd[3] * np.cos(theta) - (ev.qdd[2] - ev.qdd[0]) * np.sin(theta)) / p["l"]
    assert residual_1_98(theta, thd, thdd, lam_c, sigma, q_) == pytest.approx(0.0, abs=1e-10)
    assert abs(residual_1_98(theta, thd, thdd, lam_c, -sigma, q_)) > 0.1
    printed_99 = p["X"] + m1 * mu + m2 * p["l"] * p["g"] * np.cos(theta)
    assert abs((m1 + m2) * ev.qdd[0] - printed_99) > 0.1


def test_symbolic_friction_law_of_the_system(model):
    import sympy as sp

    x1, y1, l, th = sp.symbols("x1 y1 l theta")
    law = friction_law(model, "line", +1, substitutions={sp.Symbol("x2"): x1 + l * sp.cos(th),
                                                          sp.Symbol("y2"): y1 + l * sp.sin(th)})
    m1, m2, f, lam = sp.symbols("m1 m2 f lambda_line")       # lambda_line = N = -lambda (seed)
    assert sp.simplify(law.effective_mass - (m1 + m2)) == 0 and law.k == 0
    assert sp.simplify(law.mu - (-f * lam / (m1 + m2))) == 0   # = f lambda_seed/(m1 + m2)


@pytest.mark.parametrize("s_dir", [1, -1])
@pytest.mark.parametrize("sign", [1, -1])
def test_friction_law_branches_of_the_bilateral_guide(model, p, s_dir, sign):
    # the guide is bilateral: F = -f s |N|; each sign of N is a branch, and on its own side it
    # is the gallery's mu = -f s |lambda| / (m1 + m2)
    import sympy as sp

    law = friction_law(model, "line", s_dir, normal_sign=sign)
    assert law.bilateral and law.to_dict()["normal_sign"] == sign
    values = {sp.Symbol(k): v for k, v in p.items() if k in ("m1", "m2", "f")}
    lam = sp.Symbol("lambda_line")
    mu = sp.lambdify(lam, law.mu.subs(values))
    for lam_c in (0.8, 2.5):
        assert mu(sign * lam_c) == pytest.approx(friction_law_mu(sign * lam_c, s_dir, p), rel=1e-14)
    assert "branch holds while" in law.as_text()


def test_friction_law_negative_normal_refused_for_a_unilateral_contact():
    from nonideal import gallery
    from nonideal.errors import FormNotApplicable
    from nonideal.modeling.modelfile import load_model

    rod = load_model(gallery.model_path("painleve-rod"))
    name = rod.contacts[0].name
    with pytest.raises(FormNotApplicable, match="unilateral.*normal-sign -1 is for bilateral"):
        friction_law(rod, name, +1, normal_sign=-1)


@pytest.mark.parametrize("side", ["below low", "above low", "below high", "above high"])
def test_static_friction_condition_1_100(p, side):
    lo, hi = thresholds(p["theta0"], p)
    assert lo == pytest.approx(-p["m2"] * p["g"] * np.sin(3.0) - 0.3 * (p["g"] - 2 * p["g"] * np.cos(3.0)), rel=1e-14)
    X = {"below low": lo - 1e-3, "above low": lo + 1e-3, "below high": hi - 1e-3, "above high": hi + 1e-3}[side]
    r = at_rest(p, X)
    inside = side in ("above low", "below high")
    assert r["sticks_(1.100)"] is inside
    assert r["ok"], r
    if inside:   # the guide holds M1 with R_tau = -(X + m2 g sin 2theta0)
        assert r["mode"] == "stick"
        assert r["friction"] == pytest.approx(-(X + p["m2"] * p["g"] * np.sin(2 * p["theta0"])), rel=1e-12)
    else:        # starts in the direction of X + m2 g sin 2theta0, |x1''| = 1e-3/(m1 + m2)
        assert r["mode"] == ("slide-" if side == "below low" else "slide+")
        assert abs(r["x1dd"]) == pytest.approx(1e-3 / 3.0, rel=1e-8)


def test_motion_starts_stops_and_sticks(model, p):
    tr = simulate(model)
    ref = reference_motion(p, p["theta0"], 0.0, 1.5)
    assert [(e["type"], e["mode"]) for e in tr.events] == [("stick", "line:stick")]
    assert [r[1] for r in ref] == ["stick"]
    assert tr.events[0]["t"] == pytest.approx(ref[0][0], rel=1e-10)
    assert tr.events[0]["t"] == pytest.approx(T_STOP, rel=1e-10)
    th, _ = angle(tr.q, tr.qd)
    k = int(np.searchsorted(tr.t, tr.events[0]["t"]))
    assert th[k] == pytest.approx(ref[0][2], rel=1e-9) and tr.q[k, 0] == pytest.approx(ref[0][3], rel=1e-9)
    assert sticks_at_rest(th[-1], p)                   # (1.100) at the stop: at rest for ever
    after = tr.t > T_STOP + 1e-9
    assert np.ptp(tr.q[after], axis=0).max() < 1e-12
    F = np.array(tr.contacts["line"]["friction"])[after, 0]
    assert np.allclose(F, -driving_force(th[after], p), rtol=1e-10)


def test_multipliers_and_law_along_the_motion(model, p, traj):
    th, thd = angle(traj.q, traj.qd)
    v = traj.velocity("x1")
    sliding = np.flatnonzero((traj.t > 0) & (traj.t < T_STOP - 1e-6))[::6]
    assert len(sliding) >= 10
    for k in sliding:
        _, lam1, lam2, lam, mu, _ = split_at(model, traj.q[k], traj.qd[k])
        a1, a2, a0 = multipliers(th[k], thd[k], v[k], p["m1"], p["m2"], p["l"], p["g"], p["X"])
        assert max(abs(lam1 - a1), abs(lam2 - a2), abs(lam - a0)) < 1e-10 * abs(a0)
        assert mu == pytest.approx(friction_law_mu(lam, 1.0, p), rel=1e-10)


def test_energy_integral_and_residuals(p, traj):
    th, _ = angle(traj.q, traj.qd)
    x1 = traj.coordinate("x1")
    I = np.tan(th / 2) * np.exp(-2 * x1 / p["l"])           # kinematic integral of (1.88)
    assert np.max(np.abs(I - I[0])) < 1e-10 * I[0]
    E, W, WX = traj.energy["energy"], traj.energy["friction_work"], traj.energy["active_work"]
    assert np.max(np.abs(WX - p["X"] * (x1 - x1[0]))) < 1e-9
    assert np.max(np.abs((E - E[0]) - WX - W)) < 1e-8 * WX[-1]
    assert np.all(np.diff(W) <= 1e-12) and W[-1] < -1.0
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert traj.diagnostics["constraint_residual_max"] < 1e-8


def test_all_forms_agree_sliding_and_at_rest(model, p):
    report = compare_forms(model, contact_state="slide")
    assert report.states == 20 and report.worst() < 1e-10, report
    assert set(report.accelerations) >= {"lagrange2", "maggi", "appell", "shulgin", "gauss"}
    stick = compare_forms(model, contact_state="stick")
    assert max(stick.multipliers.values()) < 1e-10      # the sticking force and multipliers
    # sticking = complete rest (0 degrees of freedom): q'' = 0 in every form
    rest = rest_forms(p)
    assert max(max(v) for v in rest.values()) < 1e-12, rest


# ------------------------------------------------------------------ command line


def test_cli_examples_run(tmp_path):
    # the example's run() end to end (its "ok" combines every check of the example)
    proc = _cli("examples", "run", NAME, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "(1.100): M1 stays put iff" in proc.stdout and proc.stdout.rstrip().endswith("ok")


@pytest.mark.slow
def test_cli_simulate_evaluate_json(tmp_path):
    proc = _cli("simulate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("stick", "line")]
    assert d["events"][0]["t"] == pytest.approx(T_STOP, rel=1e-9)
    assert d["contacts"]["line"]["mode"][0] == "slide+" and d["contacts"]["line"]["mode"][-1] == "stick"
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8
    # at rest outside (1.100) (X = 15 N > 6.0013 N): M1 starts with v' = (X + m2 g sin 2theta0
    # - f N0)/(m1 + m2), the split's multipliers are (1.87), (1.89) at rest
    proc = _cli("evaluate", NAME, "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    e = json.loads(proc.stdout)
    assert e["contacts"]["line"]["mode"] == "slide+"
    assert e["reactions"]["line"]["constraint_part"][1] == pytest.approx(-3 * 9.81 + 4 * 9.81 * np.cos(1.5) ** 2,
                                                                         rel=1e-12)
    x1dd = (15.0 + 2 * 9.81 * np.sin(3.0) - 0.3 * (9.81 - 2 * 9.81 * np.cos(3.0))) / 3.0
    assert e["qddot"]["x1"] == pytest.approx(x1dd, rel=1e-11)


@pytest.mark.slow
def test_cli_derive_painleve_representation_is_1_83(tmp_path):
    proc = _cli("derive", NAME, "--form", "lagrange1", "--friction", "painleve", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = [ln.strip() for ln in proc.stdout.splitlines()]
    # (1.83): m1 x1'' = X - lambda_1 cos - lambda_2 sin + m1 mu;  m1 y1'' without friction
    assert any(ln.startswith("m1*x1'' = X + m1*mu_1 + ") for ln in lines)
    assert any(ln.startswith("m1*y1'' = g*m1 + ") and ln.endswith(" - lambda_line") and "mu" not in ln
               for ln in lines)
    assert any(ln.startswith("m2*x2'' = ") and "m2*mu_1" in ln for ln in lines)
    assert any(ln.startswith("m2*y2'' = g*m2 + ") and "m2*mu_1" in ln for ln in lines)
    proc = _cli("friction-law", NAME, "--contact", "line", "--json", "--substitute",
                "x2 = x1 + l*cos(theta), y2 = y1 + l*sin(theta)", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    law = json.loads(proc.stdout)
    assert law["effective_mass"] == "m1 + m2" and law["mu"] == "-f*lambda_line/(m1 + m2)"
