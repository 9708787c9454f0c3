"""Elastic members as Bubnov-Galerkin coordinates (Yushkov 1999, ch. I §5 and appendix E):
natural frequencies against the closed forms of Timoshenko 1955 and Meirovitch 1967."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from nonideal.analysis.stability.frequencies import natural_frequencies
from nonideal.errors import MechanicsError
from nonideal.modeling.frames import Frame
from nonideal.modeling.members import Member
from nonideal.modeling.model import Constraint, Model
from nonideal.modeling.bodies import Particle


def roots(f, count, upper):
    grid = np.linspace(0.1, upper, 20000)
    v = [f(x) for x in grid]
    return np.array([brentq(f, grid[i], grid[i + 1], xtol=1e-14)
                     for i in range(len(grid) - 1) if v[i] * v[i + 1] < 0][:count])


def beam(n, ends=("clamped", "free"), shape="polynomial", params=None, **kw):
    p = {"L": 1.3, "rho_A": 0.7, "EI": 2.5, **(params or {})}
    return Model("beam", [], p, members=[Member("beam", "beam", "L", "EI", ends, n, mass_per_length="rho_A",
                                                shape=shape, **kw)])


def scale(p):   # omega = (beta L)^2 sqrt(EI / (rho A L^4))
    return np.sqrt(p["EI"] / (p["rho_A"] * p["L"] ** 4))


P = {"L": 1.3, "rho_A": 0.7, "EI": 2.5}
CANTILEVER = roots(lambda b: 1 + np.cos(b) * np.cosh(b), 3, 9.0)


def test_cantilever_roots_are_the_published_ones():
    assert np.allclose(CANTILEVER, [1.8751, 4.6941, 7.8548], atol=5e-5)


def test_cantilever_converges_from_above():
    exact = CANTILEVER ** 2 * scale(P)
    previous = None
    for n in (3, 4, 5, 6, 8):
        w = np.array(natural_frequencies(beam(n), at={}).omega[:3])
        assert np.all(w >= exact * (1 - 1e-12))            # Rayleigh-Ritz upper bounds
        if previous is not None:
            assert np.all(w <= previous * (1 + 1e-12))      # and decreasing with N
        previous = w
    assert np.allclose(previous, exact, rtol=2e-6)
    assert natural_frequencies(beam(2), at={}).omega[0] > exact[0] * (1 + 1e-3)


def test_pinned_pinned_beam_is_exact_with_sine_modes():
    w = natural_frequencies(beam(3, ("pinned", "pinned"), "modes"), at={}).omega
    assert np.allclose(w, [(k * np.pi) ** 2 * scale(P) for k in (1, 2, 3)], rtol=1e-10)


@pytest.mark.parametrize("shape, tol", [("modes", 1e-10), ("polynomial", 2e-5)])
def test_rod_fixed_free(shape, tol):
    p = {"L": 2.0, "rho_A": 3.0, "EA": 50.0}
    m = Model("rod", [], p, members=[Member("rod", "rod", "L", "EA", ("fixed", "free"), 8,
                                            mass_per_length="rho_A", shape=shape)])
    w = natural_frequencies(m, at={}).omega[:3]
    exact = [(2 * k - 1) * np.pi / (2 * p["L"]) * np.sqrt(p["EA"] / p["rho_A"]) for k in (1, 2, 3)]
    assert np.allclose(w, exact, rtol=tol)
    assert np.all(np.array(w) >= np.array(exact) * (1 - 1e-12))


def test_shaft_fixed_fixed_in_torsion():
    p = {"L": 0.8, "rho_J": 0.02, "GJ": 7.0}
    m = Model("shaft", [], p, members=[Member("shaft", "shaft", "L", "GJ", ("fixed", "fixed"), 3,
                                              inertia_per_length="rho_J", shape="modes")])
    w = natural_frequencies(m, at={}).omega
    assert np.allclose(w, [k * np.pi / p["L"] * np.sqrt(p["GJ"] / p["rho_J"]) for k in (1, 2, 3)], rtol=1e-10)


def tip_mass_roots(r):
    """1 + cos bL cosh bL + r bL (cos bL sinh bL - sin bL cosh bL) = 0 (Timoshenko 1955, §62)."""
    return roots(lambda b: 1 + np.cos(b) * np.cosh(b) + r * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b)),
                 2, 8.0)


def test_cantilever_with_a_tip_mass_as_a_particle_at_its_point():
    r = 0.5
    p = {**P, "m_tip": r * P["rho_A"] * P["L"]}
    m = Model("tip", [], p, bodies=[Particle("tip_mass", "m_tip", point="tip")],
              members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), 7, mass_per_length="rho_A",
                              points={"tip": "L"})])
    w = natural_frequencies(m, at={}).omega[:2]
    assert np.allclose(w, tip_mass_roots(r) ** 2 * scale(P), rtol=1e-6)


def test_tip_mass_through_a_constraint_gives_the_same_frequencies():
    """Yushkov's method: the mass is a separate part; the multiplier of the constraint joining
    it to the beam's tip is the force between them."""
    r = 0.5
    p = {**P, "m_tip": r * P["rho_A"] * P["L"]}
    m = Model("joined", ["y"], p, kinetic="m_tip/2*y'^2",
              constraints=[Constraint.holonomic("joint", "y - dot(pos(tip), N.y)")],
              members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), 7, mass_per_length="rho_A",
                              points={"tip": "L"})])
    w = natural_frequencies(m, at={"y": 0}).omega[:2]
    assert np.allclose(w, tip_mass_roots(r) ** 2 * scale(P), rtol=1e-6)


def rotating(deflection, omega, n=6):
    return Model("hub", [], {**P, "Omega": omega}, frames=[Frame("B", axis=["0", "0", "1"], angle="Omega*t")],
                 members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), n, mass_per_length="rho_A",
                                 frame="B", deflection=deflection)])


def test_rotating_beam_stiffens_flapwise_and_softens_chordwise():
    omega = 3.0
    flap = np.array(natural_frequencies(rotating("z", omega), at={}).omega)
    chord = np.array(natural_frequencies(rotating("y", omega), at={}).omega)
    still = np.array(natural_frequencies(rotating("z", 0.0), at={}).omega)
    assert np.all(flap > still)
    assert np.allclose(chord ** 2, flap ** 2 - omega ** 2, rtol=1e-9)   # in-plane: minus Omega^2


def test_southwell_coefficient_of_the_first_flapwise_mode():
    """d(omega^2)/d(Omega^2) at Omega = 0 is the Rayleigh quotient of the centrifugal tension
    rho A (L^2 - x^2)/2 on the exact first cantilever mode (about 1.193, Wright et al. 1982)."""
    b = CANTILEVER[0]
    s = (np.cosh(b) + np.cos(b)) / (np.sinh(b) + np.sin(b))
    phi = lambda x: np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))       # noqa: E731
    dphi = lambda x: b * (np.sinh(b * x) + np.sin(b * x) - s * (np.cosh(b * x) - np.cos(b * x)))  # noqa: E731
    K = quad(lambda x: (1 - x ** 2) / 2 * dphi(x) ** 2, 0, 1)[0] / quad(lambda x: phi(x) ** 2, 0, 1)[0]
    assert K == pytest.approx(1.1933, abs=2e-4)
    w0 = natural_frequencies(rotating("z", 0.0, 8), at={}).omega[0]
    small = 1e-2 * w0
    w = natural_frequencies(rotating("z", small, 8), at={}).omega[0]
    assert (w ** 2 - w0 ** 2) / small ** 2 == pytest.approx(K, rel=1e-4)


def test_unstable_equilibrium_has_no_natural_frequencies():
    """A slender column standing under its own weight above the buckling load (7.837 EI/L^3 for
    rho A g) -- the shortening term gives the geometric softening; the analysis refuses."""
    p = {**P, "g": 7.837 * P["EI"] / (P["rho_A"] * P["L"] ** 3) * 1.2}
    m = Model("column", [], p, gravity=("-g", "0", "0"),
              members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), 6, mass_per_length="rho_A")])
    with pytest.raises(MechanicsError, match="off the imaginary axis"):
        natural_frequencies(m, at={})
    p["g"] = p["g"] / 1.2 * 0.98
    assert natural_frequencies(Model("column", [], p, gravity=("-g", "0", "0"), members=m.elastic_members),
                               at={}).omega[0] > 0


@pytest.mark.parametrize("ends, equation, rigid", [
    (("pinned", "free"), lambda b: np.tan(b) - np.tanh(b), 1),            # 3.9266, 7.0686
    (("free", "free"), lambda b: 1 - np.cos(b) * np.cosh(b), 2),          # 4.7300, 7.8532
    (("clamped", "clamped"), lambda b: 1 - np.cos(b) * np.cosh(b), 0),
])
def test_beams_with_rigid_body_motions(ends, equation, rigid):
    """The polynomials keep the rigid motions the ends allow: zero frequencies, counted."""
    exact = [b for b in roots(lambda b: equation(b) * np.cos(b), 4, 8.5) if abs(np.cos(b)) > 1e-6][:2]
    f = natural_frequencies(beam(10, ends), at={})
    assert f.rigid == rigid
    assert np.allclose(f.omega[:2], np.array(exact) ** 2 * scale(P), rtol=2e-6)
    assert np.all(np.array(f.omega[:2]) >= np.array(exact) ** 2 * scale(P) * (1 - 1e-12))
