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


def test_negative_moment_makes_the_programme_unstable():
    model = MOD.build(M2=-0.05, M1=0.6)
    prog = linearize_program(model, samples=21)
    assert prog.verdict == "unstable" and np.all(prog.A[:, 0, 0] > 0)
