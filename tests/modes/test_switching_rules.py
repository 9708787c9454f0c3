"""Rules of the mode selection and of the reduced forms' coordinate partitioning, found by
the gallery (regressions with numbers)."""

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.modes.types import ContactState, Mode
from nonideal.modes.solver import ModeSolver
from nonideal.numeric.kernel import kernel_of, parameter_vector


def test_reduced_forms_repartition_through_a_singular_choice():
    # the sleigh turned by 90 degrees: with y' dependent, the knife edge cannot be solved for it
    m = gallery.load("chaplygin-sleigh")
    k, p = kernel_of(m), parameter_vector(m)
    q, qd = np.array([0.0, 0.0, np.pi / 2]), np.array([0.0, 1.0, 1.0])
    ref = ModeSolver(k, p, "lagrange1").solve(0, q, qd, Mode()).qdd
    for form in ("maggi", "appell", "shulgin"):
        s = ModeSolver(k, p, form)
        # first at a regular state (the partition is chosen there), then at the singular one
        s.solve(0, np.array([0.0, 0.0, 0.3]), np.array([1.0, np.tan(0.3), 1.0]), Mode())
        assert s.solve(0, q, qd, Mode()).qdd == pytest.approx(ref, rel=1e-12, abs=1e-12), form


def test_the_contact_an_event_concerns_is_the_one_that_changes():
    # mu < mu_s: when the rear axle's needed friction reaches mu_s N, the front needs between
    # mu N and mu_s N -- rigid Coulomb theory admits either axle sliding; the rear slips
    m = gallery.load("car-on-a-turn")
    tr = simulate(m, parameters={"mu": 0.85})
    first = tr.events[0]
    assert first["type"] == "slip" and first["contact"] == "rear"
    assert first["mode"] == "rear:slide-, front:stick"
    assert first["t"] == pytest.approx(6.909262516907, rel=1e-10)


@pytest.mark.parametrize("form", ["maggi", "appell", "shulgin", "lagrange2", "gauss"])
def test_hybrid_car_motion_does_not_depend_on_the_form(form):
    m = gallery.load("car-on-a-turn")
    ref = simulate(m)
    tr = simulate(m, form=form)
    assert [e["type"] for e in tr.events] == [e["type"] for e in ref.events]
    for a, b in zip(tr.events, ref.events):
        assert a["t"] == pytest.approx(b["t"], rel=1e-8)
    assert tr.q[-1] == pytest.approx(ref.q[-1], rel=1e-6, abs=1e-6)


def test_partition_criterion_is_the_exchange_factor():
    from nonideal.modes.partition import REPARTITION_GAIN, better_partition

    # one knife edge -x' sin(psi) + y' cos(psi) = 0 in (x, y, psi): y' = tan(psi) x'
    def row(psi):
        return np.array([[-np.sin(psi), np.cos(psi), 0.0]])

    assert better_partition(row(0.3), [1]) is None  # |tan 0.3| < gain: keep y dependent
    assert better_partition(row(np.arctan(REPARTITION_GAIN) - 1e-3), [1]) is None
    assert better_partition(row(np.arctan(REPARTITION_GAIN) + 1e-3), [1]) == [0]
    assert better_partition(row(np.pi / 2), [1]) == [0]  # singular choice
    # after the switch, switching back needs |cot psi| > gain (hysteresis)
    assert better_partition(row(np.arctan(1 / 2)), [0]) is None


def test_reduced_forms_keep_their_digits_where_the_motion_leaves_a_coordinate():
    # the kinematic car turning through psi ~ pi/2: with x independent, the dependent
    # velocities are large multiples of x' (the centre of mass moves almost along y), and a
    # reduced form lost 1e-11 to cancellation before the exchange-factor criterion (the
    # Hadamard ratio of the dependent block did not see it); DOP853 at rtol 1e-11 then took
    # 40x more steps
    m = gallery.load("car-on-a-turn")
    times = list(np.linspace(2.0, 3.0, 9))
    ref = simulate(m, t_end=3.0, times=times)
    k, p = kernel_of(m), parameter_vector(m)
    l1 = ModeSolver(k, p, "lagrange1")
    stick = Mode(contacts=(("rear", ContactState("stick")), ("front", ContactState("stick"))))
    for form in ("maggi", "appell", "shulgin"):
        s = ModeSolver(k, p, form)
        for t, q, qd in zip(ref.t, ref.q, ref.qd):
            q, qd = np.array(q), np.array(qd)
            a = s.solve(t, q, qd, stick).qdd
            b = l1.solve(t, q, qd, stick).qdd
            assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b)), (form, t)
