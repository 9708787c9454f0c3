"""Chaplygin's ball (Chaplygin 1903): a balanced, dynamically asymmetric sphere rolling on a
plane keeps its energy and its angular momentum about the contact point, computed here from
the angles and rates independently of the library's contact geometry."""

from nonideal import gallery
from nonideal.gallery import chaplygin_ball as example


def test_energy_and_angular_momentum_about_the_contact_point():
    r = example.check(gallery.load(example.NAME))
    assert r["energy_drift"] < 1e-9 and r["K_drift"] < 1e-9
    assert r["slip_max"] < 1e-9 and not r["events"]
    assert r["wandered"] > 0.05          # it does move (not a trivial spin in place)


def test_other_inertia_and_spin():
    r = example.check(example.build(A=0.004, B=0.0025, C=0.003, omega0=(1.0, 0.5, -4.0), t_end=2.0))
    assert r["energy_drift"] < 1e-9 and r["K_drift"] < 1e-9
