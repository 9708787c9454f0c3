"""Manglieva & Beknazarov 2022, (3.14)-(3.19): the nonlinear regulator with an elastic wheel --
the library's equations against the derived ones (and not the printed (3.17)), the steady motion
(3.18) and the conditions (3.19) for it to exist, the other steady motions and the first
approximation about (3.18)."""

import re

import numpy as np
import pytest
import sympy as sp

from nonideal import gallery
from nonideal.analysis.evaluation import evaluate
from nonideal.analysis.stability.linearize import linearize
from tests.helpers import cli_json, run_cli

NAME = "regulator-elastic-wheel-nonlinear"
MOD = gallery.module(NAME)


def _states(count, seed):
    rng = np.random.default_rng(seed)
    x0 = MOD.DEFAULTS["x0"]
    for _ in range(count):
        yield (x0 + rng.uniform(-0.015, 0.015), rng.uniform(-0.02, 0.02), rng.uniform(-0.1, 0.1),
               rng.uniform(2, 20), rng.uniform(-1, 1))


def test_equations_of_motion_are_the_derived_ones():
    """phi1'' and x'' at random states (lam, psi, x' nonzero): the derived equations -- F(x) =
    J2 r1^2/(x - c)^3 + m_zp x with a minus, r1 (M2 + b psi)/(x - c), - r1 a lam psi -- to round-off;
    the printed (3.17) (F with (x - c)^2 and a plus, - b psi) is far off."""
    model = gallery.load(NAME)
    p = model.parameter_values
    for x, lam, psi, w, xd in _states(6, 3):
        qdd = evaluate(model, at={"x": x, "lam": lam, "psi": psi, "phi1'": w, "x'": xd}).to_dict()["qddot"]
        wd, xdd = MOD.accelerations(p, x, lam, psi, w, xd)
        assert qdd["phi1"] == pytest.approx(wd, rel=1e-11, abs=1e-12)
        assert qdd["x"] == pytest.approx(xdd, rel=1e-11, abs=1e-12)
        # the rolling relations: phi2' = r1 phi1'/(x - c), lam' = x' - r1 psi phi1'
        assert qdd["phi2"] == pytest.approx(p["r1"] * (wd / (x - p["c"]) - w * xd / (x - p["c"]) ** 2), rel=1e-10)
        printed = MOD.accelerations(p, x, lam, psi, w, xd, printed=True)
        assert abs(printed[0] - wd) > 1e-3 * max(1.0, abs(wd))


def test_F_exponent_and_sign():
    """Each slip of (3.17)'s first equation on its own: with J2 r1^2/(x - c)^2 in F, or with F
    entering with a plus, the library's phi1'' is not reproduced (lam = psi = 0 isolates F)."""
    model = gallery.load(NAME)
    p = model.parameter_values
    x, w, xd = 0.055, 12.0, 0.8
    wd = evaluate(model, at={"x": x, "lam": 0.0, "psi": 0.0, "phi1'": w, "x'": xd}).to_dict()["qddot"]["phi1"]
    base = p["M1"] + p["r1"] * p["M2"] / (x - p["c"])
    assert wd == pytest.approx((base + MOD.F(x, p) * xd * w) / MOD.theta(x, p), rel=1e-12)
    square = (base + MOD.F(x, p, printed=True) * xd * w) / MOD.theta(x, p)
    plus = (base - MOD.F(x, p) * xd * w) / MOD.theta(x, p)
    assert abs(square - wd) > 0.1 * abs(wd) and abs(plus - wd) > 0.1 * abs(wd)


def test_steady_motion_3_18_exists_under_3_19():
    """At (3.18) with (3.19) the rates vanish; the first approximation about it (stability CLI)
    has the derived characteristic polynomial."""
    p = MOD.DEFAULTS
    assert p["M1"] + p["r1"] * p["M2"] / (p["x0"] - p["c"]) == pytest.approx(0, abs=1e-15)
    assert p["mzp"] * p["x0"] * p["omega0"] ** 2 / 2 == pytest.approx(-p["c1"] * p["d1"] + p["c2"] * p["d2"], rel=1e-12)
    ev = evaluate(gallery.load(NAME)).to_dict()["qddot"]
    assert max(abs(v) for v in ev.values()) < 1e-12
    data = cli_json("stability", NAME, "--about", "steady", "--exact", "--at", "phi1'=omega0, x=x0", "--json")
    s = sp.Symbol("s")
    mine = [float(c) for c in sp.Poly(sp.sympify(data["characteristic_polynomial"]), s).all_coeffs()]
    ref = MOD.characteristic_polynomial(p)
    assert mine == pytest.approx(ref, rel=1e-8)


@pytest.mark.parametrize("M1, d2", [(-0.2, 0.028), (-0.25, 0.03), (-0.2, 0.035)])
def test_3_19_violated_the_state_is_refused_with_the_derived_rates(M1, d2):
    """--exact at (3.18) with (3.19) broken: refused (exit 2), naming the residual rates, which
    are (M1 + r1 M2/(x0 - c))/theta(x0) and (c2 d2 - c1 d1 - m_zp x0 omega0^2/2)/m(x0)."""
    p = {**MOD.DEFAULTS, "M1": M1, "d2": d2}
    out = run_cli("stability", NAME, "--about", "steady", "--exact", "--at", "phi1'=omega0, x=x0",
                  "--set", f"M1={M1}", "--set", f"d2={d2}")
    assert out.returncode == 2 and "is not a steady motion" in out.stderr
    w_rate, x_rate = MOD.residual_rates(p)
    text = out.stderr
    for name, value in (("phi1''", w_rate), ("x''", x_rate)):
        if abs(value) > 1e-12:
            shown = float(re.search(re.escape(name) + r" = (-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)", text).group(1))
            assert shown == pytest.approx(value, rel=1e-5)


def test_other_steady_motions_found_by_the_library():
    """x_s = c - r1 M2/M1 and omega_s^2 = 2 (c2 d2 - c1 d1 - (c1 + c2)(x_s - x0))/(m_zp x_s):
    Newton from a guess lands on them; M1 M2 > 0 or omega_s^2 < 0: none."""
    for M1, d2 in ((-0.2, 0.035), (-0.3, 0.03), (-0.22, 0.04)):
        p = {**MOD.DEFAULTS, "M1": M1, "d2": d2}
        st = MOD.steady_motion(p)
        lin = linearize(MOD.build(M1=M1, d2=d2), about="steady", at={"phi1'": 1.2 * st["omega"], "x": st["x"] + 0.003})
        assert lin.q["x"] == pytest.approx(st["x"], rel=1e-9)
        assert lin.qdot["phi1"] == pytest.approx(st["omega"], rel=1e-6)   # Newton's tolerance
        assert lin.qdot["phi2"] == pytest.approx(p["r1"] * st["omega"] / (st["x"] - p["c"]), rel=1e-6)
        assert lin.q["lam"] == pytest.approx(0, abs=1e-12) and lin.q["psi"] == pytest.approx(0, abs=1e-12)
    assert MOD.steady_motion({**MOD.DEFAULTS, "M1": 0.25}) is None
    assert MOD.steady_motion({**MOD.DEFAULTS, "d2": 0.005}) is None      # c2 d2 < c1 d1: omega_s^2 < 0


def test_no_steady_motion_where_newton_runs_off_to_the_singular_radius():
    """With M1 > 0 (M1 M2 > 0) no steady motion exists; Newton from (3.18) runs to the
    singular radius x = c, where phi2' = r1 phi1'/(x - c) grows without bound and the rates
    vanish only in the limit.  It is refused (exit 2) naming what grew -- before, a 'steady
    motion' with phi2' = 2.08e14 was linearized and called unstable."""
    out = run_cli("stability", NAME, "--about", "steady", "--at", "phi1'=omega0, x=x0", "--set", "M1=0.25")
    assert out.returncode == 2
    assert "phi2' = 2.07938e+14 grows without bound" in out.stderr
    assert "no steady motion was found near the guess" in out.stderr
