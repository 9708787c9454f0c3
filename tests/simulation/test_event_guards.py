"""Event guards that a long step cannot skip: an event function that goes through zero and
back within one accepted step is found on the dense output (the stiff stick-slip oscillator,
whose sticking lasts microseconds inside steps of a tenth of a millisecond; a ball's whole
flight inside one step of an integrator that is exact on parabolas)."""

import math

import numpy as np
import pytest

from nonideal.gallery import stick_slip_oscillator
from nonideal.simulation import simulate
from nonideal.simulation.guards import StepScan


def test_stiff_stick_slip_cycle_every_event_against_the_closed_form_period():
    k, m, g, mu, mu_s, v_b = 1e6, 1.0, 9.81, 0.25, 0.4, 0.5
    omega = math.sqrt(k / m)
    T_stick = 2 * (mu_s - mu) * m * g / (k * v_b)
    T_slip = (math.pi + 2 * math.atan(v_b * omega / ((mu_s - mu) * g))) / omega
    period = T_stick + T_slip  # 6.28 ms, of which 5.9 us sticking
    t_end = 0.1
    traj = simulate(stick_slip_oscillator.build(k=k, t_end=t_end), t_end=t_end)
    slips = np.array([e["t"] for e in traj.events if e["type"] == "slip"])
    sticks = np.array([e["t"] for e in traj.events if e["type"] == "stick"])
    first = mu_s * m * g / (k * v_b)  # the first slip: the spring reaches mu_s m g
    assert slips[0] == pytest.approx(first, rel=1e-9)
    assert len(slips) == math.floor((t_end - first) / period) + 1
    assert len(sticks) == len(slips) - (1 if t_end - slips[-1] < T_slip else 0)
    assert np.diff(slips) == pytest.approx(period, rel=1e-8)
    # each stick lasts T_stick (to the event location, ~2e-10 s of a 6 ms cycle)
    assert slips[1:] - sticks[:len(slips) - 1] == pytest.approx(T_stick, abs=5e-10)


def test_a_dip_below_zero_inside_a_step_is_found():
    # g = (s - 0.5)^2 - 1e-6: positive at both ends and at the probes, negative for 2 ms
    scan = StepScan(lambda k, s: (s - 0.5) ** 2 - 1e-6, 0.0, 1.0, [(0.25 - 1e-6, 0.25 - 1e-6)])
    te, armed = scan.first_root(0, True, 0.0)
    assert te == pytest.approx(0.5 - 1e-3, abs=1e-12) and armed


def test_a_function_that_stays_positive_gives_no_event():
    scan = StepScan(lambda k, s: (s - 0.5) ** 2 + 1e-6, 0.0, 1.0, [(0.25 + 1e-6, 0.25 + 1e-6)])
    assert scan.first_root(0, True, 0.0) == (None, True)


def test_an_unarmed_event_is_armed_by_a_bounce_inside_the_step():
    # a gap just closed by an impact (-5e-11) opening and closing again within the step
    def gap(k, s):
        return -5e-11 + 1e-3 * s - 1e-3 * s * s
    scan = StepScan(gap, 0.0, 2.0, [(gap(0, 0.0), gap(0, 2.0))])
    te, armed = scan.first_root(0, False, 1e-10)
    assert armed and te == pytest.approx(1.0, abs=1e-6)
