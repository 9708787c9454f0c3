"""The split rule of a statically indeterminate contact set (``[simulation] split``).

A block at rest on a rough incline (angle alpha) against a smooth wall at the foot of the
slope, pushed up the slope by P = c t: its weight component W = m g sin(alpha) and the push are
carried by the incline's friction F (positive up the slope) and the wall's normal force N_w,
and equilibrium along the slope fixes only their sum,

    F + N_w = W - P,       N_p = m g cos(alpha),       admissible: N_w >= 0, |F| <= L = mu_s N_p.

Closed forms derived here (the tests check them):

* widest margin -- maximize min(N_w, L - F, L + F): for P = 0, F = (W - L)/2 when L >= W (the
  friction points DOWN the slope, pressing the block into the wall), F = 0 when L < W;
* least norm -- minimize c_w N_w^2 + c_f F^2 on the line F + N_w = W - P: F = c_w (W - P)/(c_w + c_f)
  when that is admissible; F = L (and N_w = W - P - L) when it exceeds L; F = W - P, N_w = 0
  when W - P < 0 (the wall takes no load, friction all of it, until P = W + L).

The rule changes what is reported, never the motion or its events: the block stays at rest
with both rules, and the accelerations and states agree.  The least-norm rule on a table's
two-component friction discs is checked against an independent solution of the same
minimization (SLSQP on the table's own equilibrium equations)."""

import json
import tomllib

import numpy as np
import pytest
from scipy.optimize import minimize

from nonideal import simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.errors import ModelError
from nonideal.modeling.modelfile import model_from_dict
from tests.helpers import DATA_DIR, run_cli

BLOCK = DATA_DIR / "friction" / "block_incline_wall.toml"
TABLE = DATA_DIR / "friction" / "table_three_legs.toml"
G = 9.81


_MODELS = {}


def block(split=None, weights=None):
    """The block's model with a split rule (one per rule: compiled once)."""
    key = (split, json.dumps(weights, sort_keys=True))
    if key not in _MODELS:
        data = tomllib.loads(BLOCK.read_text())
        if split:
            data["simulation"]["split"] = split
        if weights:
            data["simulation"]["split_weights"] = weights
        _MODELS[key] = model_from_dict(data, str(BLOCK))
    return _MODELS[key]


def loads(model, **parameters):
    p = {**model.parameter_values, **parameters}
    W = p["m"] * G * np.sin(p["alpha"])
    Np = p["m"] * G * np.cos(p["alpha"])
    return W, Np, p["mu_s"] * Np


def forces(ev):
    c = ev.to_dict()["contacts"]
    return c["plane"]["friction"][0], c["wall"]["normal"], c["plane"]["normal"]


CASES = [("widest-margin", None), ("least-norm", None), ("least-norm", {"wall": 3.0}),
         ("least-norm", {"plane": [1.0, 0.25]})]


@pytest.mark.parametrize("mu_s, mu", [(0.8, 0.6), (0.2, 0.1)])
@pytest.mark.parametrize("split, weights", CASES)
def test_every_rule_balances_and_stays_in_the_cones(split, weights, mu_s, mu):
    model = block(split, weights)
    W, Np, L = loads(model, mu_s=mu_s)
    ev = evaluate(model, parameters={"mu_s": mu_s, "mu": mu})
    F, Nw, Nplane = forces(ev)
    assert F + Nw == pytest.approx(W, rel=1e-12) and Nplane == pytest.approx(Np, rel=1e-12)
    assert Nw >= -1e-12 and abs(F) <= L * (1 + 1e-12)
    assert np.allclose(ev.qdd, 0.0, atol=1e-12)
    ind = ev.to_dict()["indeterminate"]
    assert ind["split"] == split and set(ind["ranges"]) == {"F plane", "N wall"}
    lo, hi, shown = ind["ranges"]["F plane"]
    assert lo == pytest.approx(-L, rel=1e-9) and hi == pytest.approx(min(L, W), rel=1e-9)
    assert shown == pytest.approx(F, abs=1e-12)


@pytest.mark.parametrize("mu_s, mu", [(0.8, 0.6), (0.2, 0.1)])
def test_widest_margin_closed_form(mu_s, mu):
    model = block()
    W, _, L = loads(model, mu_s=mu_s)
    F, Nw, _ = forces(evaluate(model, parameters={"mu_s": mu_s, "mu": mu}))
    expected = (W - L) / 2 if L >= W else 0.0
    assert F == pytest.approx(expected, abs=1e-9 * W)
    if L >= W:   # the case users meet first: friction down the slope, into the wall
        assert F < 0 and Nw > W


@pytest.mark.parametrize("mu_s, mu, weights", [(0.8, 0.6, None), (0.8, 0.6, {"wall": 3.0}),
                                               (0.8, 0.6, {"plane": [1.0, 0.25]}),
                                               (0.2, 0.1, None)])
def test_least_norm_closed_form(mu_s, mu, weights):
    model = block("least-norm", weights)
    W, _, L = loads(model, mu_s=mu_s)
    cw = (weights or {}).get("wall", 1.0)
    cf = (weights or {}).get("plane", [1.0, 1.0])[1]
    expected = min(cw * W / (cw + cf), L)
    F, Nw, _ = forces(evaluate(model, parameters={"mu_s": mu_s, "mu": mu}))
    assert F == pytest.approx(expected, rel=1e-10) and Nw == pytest.approx(W - expected, rel=1e-10)
    if (mu_s, weights) == (0.2, None):
        assert F == pytest.approx(L, rel=1e-12)   # the cone binds: W/2 > L


def test_the_rules_differ_where_they_should_and_never_in_the_motion():
    """Pushed up the slope (P = c t) the block stays until P = W + L with either rule; the
    least-norm split unloads the wall at P = W, the widest margin keeps it loaded."""
    times = np.linspace(0.0, 2.0, 9)
    runs = {}
    for split in ("widest-margin", "least-norm"):
        model = block(split)
        runs[split] = simulate(model, t_end=2.0, times=times, parameters={"c": 5.0})
    W, _, L = loads(model)
    P = 5.0 * times
    assert 5.0 * 2.0 < W + L
    a, b = runs["widest-margin"], runs["least-norm"]
    assert a.events == [] == b.events and np.array_equal(a.q, b.q) and np.allclose(a.qdd, 0, atol=1e-12)
    Fa, Fb = (np.array(r.contacts["plane"]["friction"])[:, 0] for r in (a, b))
    Na, Nb = (np.asarray(r.contacts["wall"]["normal"]) for r in (a, b))
    assert np.allclose(Fa + Na, W - P, atol=1e-12) and np.allclose(Fb + Nb, W - P, atol=1e-12)
    closed_F = np.where(W - P > 0, (W - P) / 2, W - P)
    assert np.allclose(Fb, closed_F, atol=1e-10) and np.allclose(Nb, W - P - closed_F, atol=1e-10)
    # widest margin: min(N_w, L - |F|) maximal: N_w = L + F with F = (W - P - L)/2 (here F < 0)
    assert np.allclose(Fa, (W - P - L) / 2, atol=1e-10)
    assert np.all(Na > 0.5) and np.all(Nb[P > W] < 1e-12)
    for r, split in ((a, "widest-margin"), (b, "least-norm")):
        ind = r.diagnostics["indeterminate"]
        assert ind["split"] == split and ind["phases"][0]["t"] == [0.0, 2.0]
        lo, hi, shown = ind["phases"][0]["end"]["N wall"]
        assert lo == pytest.approx(0.0, abs=1e-9) and hi == pytest.approx(W + L - 10.0, rel=1e-9)


@pytest.mark.parametrize("split", ["widest-margin", "least-norm"])
def test_pushed_past_the_limit_the_block_breaks_away_up_the_slope(split):
    """At P = W + L (t* = (W + L)/c) the incline's friction reaches its limit with the wall
    unloaded: the block slides up the slope, leaving the wall.  Several sticking choices are
    marginal at that instant (the wall touching or not); each is dropped in turn and the run
    goes on sliding (it used to switch between the two sticking choices forever).  After t*:
    m x'' = c (t - t*) + (mu_s - mu) m g cos(alpha)."""
    model = block(split)
    W, Np, L = loads(model)
    c, T = 5.0, 2.5
    t_star = (W + L) / c
    run = simulate(model, t_end=T, parameters={"c": c})
    assert run.events[0]["t"] == pytest.approx(t_star, abs=1e-8)
    assert run.modes[-1] == "plane:slide+, wall:separated" and len(run.events) <= 3
    p = model.parameter_values
    s = T - t_star
    x = c * s ** 3 / (6 * p["m"]) + (p["mu_s"] - p["mu"]) * G * np.cos(p["alpha"]) * s ** 2 / 2
    assert run.q[-1][0] == pytest.approx(x, rel=1e-7)


def test_least_norm_on_friction_discs_matches_an_independent_minimization():
    """The three-legged table pushed by P = 7 (below mu_s m g = 7.85), its first leg four times
    stiffer tangentially than the others (weight 0.25): that leg takes more friction, up to its
    disc |F_1| = mu_s m g/3.  Reference: SLSQP on the table's equilibrium equations in the leg
    forces (sum F_x = -P, sum F_y = 0, sum (x_i F_yi - y_i F_xi) = 0, |F_i| <= mu_s N_i)."""
    data = tomllib.loads(TABLE.read_text())
    data["parameters"].update(P0=7.0, c=0.0)
    data["simulation"].update(split="least-norm", split_weights={"leg1": [1.0, 0.25]})
    p = data["parameters"]
    ev = evaluate(model_from_dict(data, str(TABLE))).to_dict()
    got = np.array([ev["contacts"][f"leg{i}"]["friction"] for i in (1, 2, 3)]).ravel()
    limit = p["mu_s"] * p["m"] * G / 3
    b = np.radians([90.0, 210.0, 330.0])
    x, y = p["d"] * np.cos(b), p["d"] * np.sin(b)
    c = np.array([0.25, 0.25, 1, 1, 1, 1])
    cons = [{"type": "eq", "fun": lambda f: [f[0::2].sum() + 7.0, f[1::2].sum(),
                                             (x * f[1::2] - y * f[0::2]).sum()]}]
    cons += [{"type": "ineq", "fun": lambda f, i=i: limit ** 2 - f[2 * i] ** 2 - f[2 * i + 1] ** 2}
             for i in range(3)]
    ref = minimize(lambda f: c @ f ** 2, np.full(6, -7.0 / 3) * [1, 0, 1, 0, 1, 0], constraints=cons,
                   method="SLSQP", options={"ftol": 1e-15, "maxiter": 500})
    assert ref.success
    assert np.allclose(got, ref.x, atol=1e-6)
    assert np.hypot(*got[:2]) == pytest.approx(limit, rel=1e-9)   # the stiff leg's disc binds
    assert ev["indeterminate"]["split"] == "least-norm"


def test_split_keys_are_checked():
    with pytest.raises(ModelError) as err:
        block("least-nrm")
    assert "did you mean 'least-norm'" in str(err.value)
    with pytest.raises(ModelError) as err:
        block("least-norm", {"wal": 2.0, "plane": [1.0, 2.0, 3.0]})
    text = str(err.value)
    assert "'wal' is not a constraint or contact (did you mean 'wall'?)" in text
    assert "plane must be a number > 0, or [normal, tangential]" in text
    with pytest.raises(ModelError, match="used by split = \"least-norm\" only"):
        block(None, {"wall": 2.0})


def test_the_cli_states_the_rule_and_the_ranges(tmp_path):
    path = tmp_path / "block.toml"
    path.write_text(BLOCK.read_text() + 'split = "least-norm"\n')
    out = json.loads(run_cli("evaluate", path, "--json", "-").stdout)
    assert out["indeterminate"]["split"] == "least-norm"
    text = run_cli("simulate", path, "--t-end", "0.5").stdout
    assert "statically indeterminate reactions" in text and "least norm" in text
    assert "N wall: shown 2.3515823, admissible from 0 to 11.590432" in text
