"""The tippe top with the parameters of Leine & Glocker 2003: Jellett's integral, the inversion
under the smooth Coulomb law against an independent Newton-Euler integration, and the exact
Coulomb law's stick time (derivations in the gallery module's docstring)."""

import math

import pytest

from nonideal import gallery
from nonideal.gallery import tippe_top as example


def test_parameters_inside_the_inversion_condition():
    p = gallery.load(example.NAME).parameter_values
    alpha = p["a"] / p["R"]
    assert 1 - alpha < p["C"] / p["A"] < 1 + alpha
    assert p["W"] > example.spin_threshold(p)
    # E_0 = E_pi at the threshold, both at the same Jellett lambda = C w (a - R) at theta = 0
    w = example.spin_threshold(p)
    lam = p["C"] * w * (p["a"] - p["R"])
    E0 = lam ** 2 / (2 * p["C"] * (p["R"] - p["a"]) ** 2) + p["m"] * p["g"] * (p["R"] - p["a"])
    Epi = lam ** 2 / (2 * p["C"] * (p["R"] + p["a"]) ** 2) + p["m"] * p["g"] * (p["R"] + p["a"])
    assert E0 == pytest.approx(Epi, rel=1e-12)


def test_exact_coulomb_sticks_when_the_independent_slip_vanishes_and_does_not_invert():
    x = example.check_exact(t_end=0.3)
    assert [e[1] for e in x["events"]] == ["stick"]
    assert x["t_stick"] == pytest.approx(x["t_slip_vanishes"], rel=1e-7)
    assert x["U0"] == pytest.approx(180 * 0.015 * math.sin(0.1), rel=1e-12)
    assert x["theta_max"] < 0.11
    assert x["jellett_drift"] < 1e-8 and abs(x["balance"]) < 1e-8


@pytest.mark.slow
def test_inversion_under_the_smooth_law():
    r = example.check()
    assert r["theta"][0] == pytest.approx(0.1, abs=1e-12)
    assert r["theta_end"] > 2.8 and r["rise"] > 1.8          # the centre of mass up by ~2a
    assert 0.5 < r["t_half"] < 1.5
    assert r["jellett_drift"] < 1e-8                         # through the whole sliding motion
    assert r["friction_work_increase"] <= 0.0                # friction never does positive work
    assert r["balance"] < 1e-8 and r["heat"] > 0.3 * r["energy0"]
    assert r["theta_vs_newton_euler"] < 1e-6 and r["compared_until"] == pytest.approx(3.0)
    assert not r["events"]
