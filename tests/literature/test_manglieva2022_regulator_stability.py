"""Manglieva & Beknazarov 2022, (3.5)-(3.13): the friction speed regulator's programme against
the quadrature (3.10), its first approximation against (3.13), Persidsky's criterion."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.analysis.stability.program import linearize_program

MOD = gallery.module("regulator-persidsky")


def test_programme_first_approximation_and_persidsky():
    p = dict(MOD.DEFAULTS)
    k, k1, k2 = MOD.constants(p)
    prog = linearize_program(gallery.load("regulator-persidsky"), samples=41)
    rho = prog.q["rho"]
    # (3.10): t(rho) = (k/k2) (rho - rho0 - (k1/k2) ln((k2 rho + k1)/(k2 rho0 + k1)))
    t_closed = k / k2 * (rho - MOD.RHO0 - k1 / k2 * np.log((k2 * rho + k1) / (k2 * MOD.RHO0 + k1)))
    assert np.max(np.abs(t_closed - prog.t)) < 1e-7
    # (3.13): one perturbation variable (the servo-constraint eliminates rho'), A = -k1/(k rho0^2)
    assert prog.variables == ("rho",) and prog.dependent == ("rho'",)
    assert np.allclose(prog.A[:, 0, 0], -k1 / (k * rho ** 2), rtol=1e-8)
    # Persidsky: alpha = k1/(k rho_max^2) > 0 bounds the decay; the library's verdict
    assert -prog.lognorm.max() == pytest.approx(k1 / (k * rho.max() ** 2), rel=1e-6)
    assert prog.verdict == "asymptotically stable" and prog.persidsky_alpha > 0


def test_persidsky_bound_is_uniform_over_every_sub_interval():
    """(3.13) asks |x(t)| <= B exp(-alpha (t - t0)) for EVERY t0: with beta = 0 the largest such
    alpha is k1/(k rho_max^2) = 0.13333, not the average decay from t0 (0.4011 on [0, 2]).  The
    bound reported holds on each sub-interval: over [1.9, 2], int mu = -0.0137 > -0.4011 * 0.1."""
    p = dict(MOD.DEFAULTS)
    k, k1, _ = MOD.constants(p)
    prog = linearize_program(gallery.load("regulator-persidsky"), t_end=2.0, samples=201)
    rho_max = prog.q["rho"].max()
    assert prog.persidsky_beta == 0.0
    assert prog.persidsky_alpha == pytest.approx(k1 / (k * rho_max ** 2), rel=1e-6)
    assert prog.persidsky_alpha == pytest.approx(0.13333, abs=1e-5)
    assert prog.average_decay == pytest.approx(0.401132, rel=1e-5)
    t, mu = prog.t, prog.lognorm
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (mu[1:] + mu[:-1]) * np.diff(t))])
    i0 = int(np.searchsorted(t, 1.9))
    late = cum[-1] - cum[i0]
    assert late == pytest.approx(-0.0137, abs=2e-4)
    assert late <= -prog.persidsky_alpha * (t[-1] - t[i0]) + 1e-12
    # every sub-interval obeys the bound
    diff = cum[None, :] - cum[:, None]
    span = t[None, :] - t[:, None]
    upper = np.triu(np.ones_like(diff, bool))
    assert np.all(diff[upper] <= -prog.persidsky_alpha * span[upper] + prog.persidsky_beta + 1e-12)


def test_persidsky_bound_with_a_transient_growth():
    """mu positive on a stretch, negative on average: alpha is the average decay and beta the
    largest rise of int mu + alpha t over any sub-interval (here the bump's own area)."""
    from nonideal.analysis.stability.program import persidsky_bound

    t = np.linspace(0.0, 10.0, 10001)
    mu = np.where((t > 4) & (t < 5), 1.0, -1.0)
    alpha, beta, average = persidsky_bound(mu, t)
    assert average == pytest.approx(0.8, abs=1e-3) and alpha == average
    # on [4, 5]: int mu = 1, plus alpha * 1
    assert beta == pytest.approx(1.0 + 0.8, abs=5e-3)


def test_negative_moment_makes_the_programme_unstable():
    model = MOD.build(M2=-0.05, M1=0.6)
    prog = linearize_program(model, samples=21)
    assert prog.verdict == "unstable" and np.all(prog.A[:, 0, 0] > 0)
