"""Compiled callables and the saddle-point solver: the fast paths give the same numbers."""

import numpy as np
import pytest
import symengine as se

import nonideal.numeric.kernel as numeric
from nonideal.numeric.kernel import Compiled, SingularMatrix, solve_saddle


def test_compiled_tier_up_is_bit_identical(monkeypatch):
    monkeypatch.setattr(numeric, "TIER_UP_CALLS", 3)
    x, y = se.symbols("x y")
    exprs = {"s": se.sin(x) * y + se.exp(x * y) / (1 + y * y), "v": [x * y, se.cos(x + y) ** 3],
             "M": [[x, y], [y * y, se.log(2 + x * x)]]}
    c = Compiled([x, y], exprs)
    ref = Compiled([x, y], exprs, optimize=True)
    rng = np.random.default_rng(1)
    first_fn = c.fn
    for _ in range(6):
        z = rng.uniform(-2, 2, 2)
        a, b = c(z), ref(z)
        assert a["s"] == b["s"]
        assert np.array_equal(a["v"], b["v"]) and np.array_equal(a["M"], b["M"])
        assert a["M"].shape == (2, 2) and isinstance(a["s"], float)
    if numeric._LLVM:
        assert c.fn is not first_fn  # recompiled with optimization after 3 calls


def test_solve_saddle_with_non_ideal_rows():
    rng = np.random.default_rng(0)
    k, m = 7, 3
    A = rng.random((k, k))
    A = A @ A.T + k * np.eye(k)
    G = rng.random((m, k))
    B = G.T + 0.2 * rng.random((k, m))  # servo-like reaction directions
    b, gamma = rng.random(k), rng.random(m)
    a, mu = solve_saddle(A, b, B, G, gamma)
    assert np.allclose(A @ a - B @ mu, b, atol=1e-13)
    assert np.allclose(G @ a, -gamma, atol=1e-13)
    # inputs untouched, outputs fresh
    a2, mu2 = solve_saddle(A, b, B, G, gamma)
    assert a2 is not a and np.array_equal(a, a2) and np.array_equal(mu, mu2)
    a0, mu0 = solve_saddle(A, b)
    assert np.allclose(A @ a0, b) and mu0.shape == (0,)


def test_solve_saddle_singular_and_nan():
    A = np.eye(2)
    G = np.array([[1.0, 0.0], [2.0, 0.0]])  # dependent rows
    with pytest.raises(SingularMatrix):
        solve_saddle(A, np.ones(2), G.T, G, np.zeros(2))
    with pytest.raises(SingularMatrix):
        solve_saddle(A, np.array([np.nan, 1.0]), G[:1].T, G[:1], np.zeros(1))
