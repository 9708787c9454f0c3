"""Stability classics against their closed forms: the sleeping top (Maievski), Watt's governor
(Vyshnegradsky), the rolling disk (nonholonomic, W^2 > g/(3r)), and the inverted double
pendulum on a cart (A checked against sympy.physics.mechanics; LQR; nonlinear closed loop)."""

import numpy as np
import pytest
import sympy as sp

from nonideal import gallery
from nonideal.analysis.stability.control import lqr, simulate_closed_loop
from nonideal.analysis.stability.linearize import linearize


def _match(eigs, ref, tol):
    return max(min(abs(z - r) for r in ref) for z in eigs) <= tol


@pytest.mark.parametrize("factor", [0.97, 1.03])
def test_sleeping_top_maievski(factor):
    m, A, C, l, g = 1.0, 0.02, 0.03, 0.1, 9.81
    A_O, mgl = A + m * l * l, m * g * l
    wc = 2 * np.sqrt(A_O * mgl) / C
    lin = linearize(gallery.load("sleeping-top"), about="steady", at={"c'": factor * wc})
    z = np.roots([A_O ** 2, C ** 2 * (factor * wc) ** 2 - 2 * A_O * mgl, mgl ** 2]).astype(complex)
    assert _match(lin.eigenvalues, np.concatenate([np.sqrt(z), -np.sqrt(z)]), 1e-9)
    assert lin.verdict == ("critical" if factor > 1 else "unstable")
    assert lin.ignorable == ("c",) and lin.family == ("c'",)


def test_sleeping_top_condition_in_all_parameters_is_maievski():
    lin = linearize(gallery.load("sleeping-top"), about="steady", at="c'=w",
                    symbolic=["A", "C", "m", "g", "l", "w"])
    A, C, m, g, l, w = sp.symbols("A C m g l w")
    maievski = C ** 2 * w ** 2 - 4 * (A + m * l ** 2) * m * g * l
    # one condition is Maievski's (up to a positive factor); check its sign agrees everywhere
    rng = np.random.default_rng(1)
    found = False
    for cond in lin.conditions:
        agree = True
        for _ in range(20):
            vals = {s: rng.uniform(0.1, 2.0) for s in (A, C, m, g, l)}
            vals[w] = rng.uniform(0.1, 30.0)
            agree &= bool(cond.subs(vals)) == bool(maievski.subs(vals) > 0)
        found |= agree
    assert found, lin.conditions


def test_watt_governor_vyshnegradsky():
    p = {"m": 1.0, "l": 0.3, "n": 2.0, "g": 9.81, "b": 0.5, "J": 1.0, "k": 10.0, "F": 5.0}
    phi0 = np.arccos(p["F"] / p["k"])
    w0 = np.sqrt(p["g"] / (p["l"] * p["n"] ** 2 * np.cos(phi0)))
    module = gallery.module("watt-governor")
    lin = linearize(gallery.load("watt-governor"), about="steady", at={"phi": 0.8, "theta'": 3.5})
    assert lin.q["phi"] == pytest.approx(phi0, abs=1e-9) and lin.qdot["theta"] == pytest.approx(w0, rel=1e-9)
    s2 = np.sin(phi0) ** 2
    ref = np.roots([1, p["b"] / (p["m"] * p["l"] ** 2), p["n"] ** 2 * w0 ** 2 * s2,
                    2 * p["n"] ** 2 * w0 * p["k"] * s2 * np.cos(phi0) / p["J"]])
    assert _match(lin.eigenvalues, ref, 1e-9)
    Jc = 2 * p["m"] * p["l"] ** 2 * p["F"] / (p["b"] * w0)       # b J w0 = 2 m l^2 F
    for J, verdict in ((1.02 * Jc, "asymptotically stable"), (0.98 * Jc, "unstable")):
        assert linearize(module.build(J=J), about="steady", at={"phi": phi0, "theta'": w0}).verdict == verdict
    sym = linearize(gallery.load("watt-governor"), about="steady",
                    at="phi=acos(F/k), theta'=sqrt(g*k/(l*n^2*F))", symbolic=["J"])
    Js = sp.Symbol("J")
    bounds = [float(r) for c in sym.conditions for r in sp.solve(sp.Eq(c.lhs - c.rhs, 0), Js) if r.is_real]
    assert any(abs(b - Jc) < 1e-9 * Jc for b in bounds)


@pytest.mark.parametrize("factor", [0.95, 1.05])
def test_rolling_disk_upright(factor):
    r, g = 0.5, 9.81
    W = factor * np.sqrt(g / (3 * r))
    lin = linearize(gallery.load("rolling-disk"), about="steady", at={"phi'": W, "psi": 0.4})
    w2 = 0.8 * (3 * W * W - g / r)
    assert lin.variables == ("theta", "psi'", "theta'") and lin.family == ("phi'",)
    assert set(lin.ignorable) == {"x", "y", "psi", "phi"} and lin.dependent == ("x'", "y'")
    assert _match(lin.eigenvalues, [0.0, np.sqrt(complex(-w2)), -np.sqrt(complex(-w2))], 1e-9)
    assert lin.verdict == ("critical" if factor > 1 else "unstable")


def test_double_pendulum_cart_against_sympy_mechanics_and_lqr():
    import sympy.physics.mechanics as me

    x, t1, t2 = me.dynamicsymbols("x th1 th2")
    u = me.dynamicsymbols("u")
    mc, m1, m2, l1, l2, g = 1.0, 0.5, 0.5, 0.6, 0.6, 9.81
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P0 = O.locatenew("P0", x * N.x)
    P1 = P0.locatenew("P1", l1 * (sp.sin(t1) * N.x + sp.cos(t1) * N.y))
    P2 = P1.locatenew("P2", l2 * (sp.sin(t2) * N.x + sp.cos(t2) * N.y))
    for P in (P0, P1, P2):
        P.set_vel(N, P.pos_from(O).dt(N))
    parts = [me.Particle("c", P0, mc), me.Particle("a", P1, m1), me.Particle("b", P2, m2)]
    Lg = me.Lagrangian(N, *parts) - (m1 * g * P1.pos_from(O).dot(N.y) + m2 * g * P2.pos_from(O).dot(N.y))
    LM = me.LagrangesMethod(Lg, [x, t1, t2], forcelist=[(P0, u * N.x)], frame=N)
    LM.form_lagranges_equations()
    op = {x: 0, t1: 0, t2: 0, x.diff(): 0, t1.diff(): 0, t2.diff(): 0, u: 0}
    op.update({x.diff().diff(): 0, t1.diff().diff(): 0, t2.diff().diff(): 0})
    A_ref, B_ref, _ = LM.linearize(q_ind=[x, t1, t2], qd_ind=[x.diff(), t1.diff(), t2.diff()],
                                   A_and_B=True, op_point=op)
    lin = linearize(gallery.load("double-pendulum-cart-lqr"), controls=["u"], keep=["x"])
    assert np.allclose(lin.A, np.array(A_ref, float), atol=1e-10)
    assert np.allclose(lin.B, np.array(B_ref, float), atol=1e-12)
    reg = lqr(lin, 1.0, 1.0)
    P = reg.P
    riccati = lin.A.T @ P + P @ lin.A - P @ lin.B @ lin.B.T @ P + np.eye(6)
    assert np.max(np.abs(riccati)) < 1e-9 * np.max(np.abs(P))
    assert np.max(reg.closed_loop_eigenvalues.real) < 0
    traj = simulate_closed_loop(gallery.load("double-pendulum-cart-lqr"), lin, reg, {"th1": 0.1},
                                t_end=20.0, times=[0.0, 20.0])
    assert np.max(np.abs(traj.q[-1])) < 1e-3 and np.max(np.abs(traj.qd[-1])) < 1e-3
