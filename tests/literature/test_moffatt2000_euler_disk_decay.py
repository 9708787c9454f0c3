"""Euler's disk decaying with pivoting and rolling friction: the energy lost equals the
torques' integrated power (computed here from the kinematics), and with rolling friction alone
the disk sinks as the quasi-steady equation alpha' = -(2 lr/(3 a)) sqrt(4 g sin(alpha)/a)
predicts (derivations in the gallery module's docstring)."""

import pytest

from nonideal.gallery import euler_disk_decay as example


@pytest.mark.slow
def test_energy_lost_equals_the_torques_power():
    r = example.check()
    assert r["rate_error"] < 2e-5
    assert r["E_end"] - r["E0"] == pytest.approx(r["friction_work"], rel=1e-7)
    assert r["friction_work"] < 0 and abs(r["balance"]) < 1e-8
    assert [e[1:] for e in r["events"]] == [("stick", "table_spin")]


def test_pivoting_torque_power_alone_is_exact():
    r = example.check(example.build(lr=0.0, t_end=0.3), samples=601)
    assert r["rate_error"] < 1e-9 and r["friction_work"] < 0


@pytest.mark.slow
def test_quasi_steady_sinking_with_rolling_friction():
    qs = example.check_quasi_steady()
    assert not qs["events"]
    assert qs["alpha_end"] < 0.25 and qs["trend_error"] < 0.08
    assert qs["Omega_relation_max_dev"] < 0.05
    assert qs["Omega_end"] > 1.07 * 57.6157     # the precession speeds up as the disk sinks


def test_reported_torques_oppose_the_motion_at_every_sample():
    """The rolling torque reported at a sample opposes the rolling velocity it resists (the
    orientation a step keeps to continue the law through a stop belongs to that step, not to
    samples reported after the run: before, the sign flipped with the precession, every
    2 pi / Omega)."""
    import numpy as np

    from nonideal import simulate

    tr = simulate(example.build(ls=0.0, t_end=0.25), times=np.linspace(0.0, 0.25, 251))
    c = tr.contacts["table_rolling"]
    F, U = np.array(c["friction"]), np.array(c["slip"])
    N = np.asarray(c["normal"])
    power = np.einsum("ij,ij->i", F, U)
    assert np.all(power <= 1e-12 * np.abs(U).max() * N.max())
    # and equals -lr N |U| (Coulomb's law for the rolling torque)
    assert np.allclose(power, -1e-4 * N * np.linalg.norm(U, axis=1), rtol=1e-9, atol=0)  # lr = 0.1 mm
