"""Statically indeterminate sticking (classical rigid-body statics with Coulomb friction): a rod
lying on a rough floor and a three-legged table, pushed by a force that grows linearly.  Both
stick while SOME distribution of the friction forces satisfies every cone -- for the rod only
F_A + F_B = -P is determined, for the table only the sum and the moment of the three
friction forces -- i.e. up to P = mu_s m g, with the symmetric distribution (-P/2 each, -P/3
each) the one with the widest margins; then every contact slips at once, and the body
translates with m x'' = P - mu m g.  Also :func:`nonideal.indeterminate.maxmin` on problems
with known optima."""


import numpy as np
import pytest

from nonideal import simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.modes.indeterminate import maxmin
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

DATA = DATA_DIR / "friction"
G = 9.81


@pytest.fixture(scope="module")
def rod():
    return load_model(DATA / "rod_flat_pushed.toml")


@pytest.fixture(scope="module")
def table():
    return load_model(DATA / "table_three_legs.toml")


# ------------------------------------------------------------------ rod: one slip component

def test_rod_sticks_until_mu_s_m_g_then_both_ends_slip(rod):
    p = rod.parameter_values
    m, c, mu, mu_s = p["m"], p["c"], p["mu"], p["mu_s"]
    t_slip = mu_s * m * G / c
    tr = simulate(rod)
    assert [(e["type"], e["mode"], e["changes"]) for e in tr.events] == [
        ("slip", "A:slide+, B:slide+", {"A": "slip", "B": "slip"})]
    assert tr.events[0]["t"] == pytest.approx(t_slip, rel=1e-12)
    stick = np.array([md == "A:stick, B:stick" for md in tr.modes])
    assert tr.t[stick].max() == pytest.approx(t_slip, rel=1e-12)
    for name in ("A", "B"):
        C = tr.contacts[name]
        assert np.allclose(np.array(C["friction"])[stick, 0], -c * tr.t[stick] / 2, rtol=1e-12, atol=1e-12)
        assert np.allclose(C["normal"], m * G / 2, rtol=1e-12)
    after = ~stick
    assert np.allclose(tr.qdd[after, 0], (c * tr.t[after] - mu * m * G) / m, rtol=1e-12, atol=1e-12)
    assert tr.diagnostics["energy_balance_relative"] < 1e-9


@pytest.mark.parametrize("t_end, rtol", [(1.0, 1e-8), (1.5, None), (1.7, 1e-12)])
def test_rod_below_the_threshold_has_no_event(rod, t_end, rtol):
    tr = simulate(rod, t_end=t_end, **({"rtol": rtol} if rtol else {}))
    assert tr.events == [] and np.max(np.abs(tr.q)) < 1e-12 and np.max(np.abs(tr.qd)) < 1e-12


# ------------------------------------------------------------------ table: two slip components

def test_table_pushed_below_the_threshold_stays(table):
    p = table.parameter_values
    m = p["m"]
    tr = simulate(table, t_end=2.0, parameters={"P0": 7.0, "c": 0.0})   # mu_s m g = 7.848
    assert tr.events == [] and np.max(np.abs(tr.qd)) < 1e-12
    for name in ("leg1", "leg2", "leg3"):
        C = tr.contacts[name]
        assert np.allclose(C["normal"], m * G / 3, rtol=1e-12)
        assert np.allclose(C["friction"], [[-7.0 / 3, 0.0]] * len(tr.t), atol=1e-12)


def test_forms_agree_while_the_legs_stick(table, rod):
    for model in (table, rod):
        assert compare_forms(model, contact_state="stick", count=5).worst() < 1e-12


# ------------------------------------------------------------------ the max-min problem

def test_maxmin_linear_is_the_best_crossing():
    # in one dimension the maximum of the lower envelope of lines is at a crossing of two
    rng = np.random.default_rng(1)
    A, b = rng.normal(size=(7, 1)), rng.normal(size=7)
    w, t = maxmin(A, b, [], cap=100.0)
    crossings = [(b[j] - b[i]) / (A[i, 0] - A[j, 0]) for i in range(7) for j in range(i)]
    assert t == pytest.approx(max(float(np.min(A[:, 0] * x + b)) for x in crossings), abs=1e-14)
    assert t == pytest.approx(float(np.min(A @ w + b)), abs=1e-15)


def test_maxmin_three_discs_sharing_a_load():
    # F_1 + F_2 + F_3 = -P with |F_i| <= mu N - t: the optimum shares P equally (the table)
    P, muN = np.array([3.0, 4.0]), 2.5
    base = np.concatenate([-P / 3] * 3)
    Z = np.linalg.svd(np.hstack([np.eye(2)] * 3))[2][2:].T          # F = base + Z w
    cones = [(np.zeros(4), muN, Z[2 * i:2 * i + 2], base[2 * i:2 * i + 2]) for i in range(3)]
    w, t = maxmin(np.zeros((0, 4)), np.zeros(0), cones, cap=100.0)
    assert t == pytest.approx(muN - 5.0 / 3, abs=1e-14)
    assert np.allclose(base + Z @ w, base, atol=1e-13)


def test_maxmin_random_discs_cannot_be_improved():
    rng = np.random.default_rng(7)
    for _ in range(5):
        cones = [(0.2 * rng.normal(size=3), 2.0 + rng.random(), rng.normal(size=(2, 3)), rng.normal(size=2))
                 for _ in range(3)]
        lin_a, lin_b = rng.normal(size=(2, 3)), 3.0 + rng.random(2)

        def smallest(w):
            discs = [a @ w + b - np.linalg.norm(A @ w + f) for a, b, A, f in cones]
            return min(list(lin_a @ w + lin_b) + discs)
        w, t = maxmin(lin_a, lin_b, cones, cap=100.0)
        assert t < 100.0 and t == pytest.approx(smallest(w), abs=1e-14)
        trials = w + 1e-4 * rng.normal(size=(2000, 3))
        assert max(smallest(v) for v in trials) <= t + 1e-12


def test_maxmin_unbounded_margins_are_capped():
    # a body wedged between two rough supports: squeezing raises both margins without bound
    w, t = maxmin(np.array([[1.0], [1.0]]), np.array([0.0, 0.5]), [], cap=3.0)
    assert t == pytest.approx(3.0, abs=1e-14)
    assert float(np.min(np.array([[1.0], [1.0]]) @ w + [0.0, 0.5])) == pytest.approx(3.0, abs=1e-14)
