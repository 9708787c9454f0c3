"""A block held by static friction under a force that oscillates faster than anything the
sticking state shows: the margin of the friction cone dips below zero for a fraction of every
period, and every such slip must be found (the integrator alone would step over whole periods
of a sticking mode, whose state is constant).

Closed form (m x'' = F(t) + friction, mu_s = mu, the block at rest at t = 0): while it sticks
the friction is -F(t), and it slips where |F(t)| reaches mu m g; sliding in the direction
s = sign F, m x'' = F(t) - s mu m g, so from the slip at t_s

    x'(t) = (F0/m - s mu g)(t - t_s) + (A/(m w))(cos w t_s - cos w t),
    x(t) - x(t_s) = (F0/m - s mu g)(t - t_s)^2/2 + (A/(m w))(cos w t_s (t - t_s) - (sin w t - sin w t_s)/w),

for F = F0 + A sin w t, and it sticks again where x' returns to zero (|F| < mu m g there).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from nonideal.modeling.modelfile import model_from_dict
from nonideal.simulation import simulate

M, G, MU = 1.0, 9.81, 0.5


def block(F0, A, w):
    return model_from_dict({
        "model": {"name": "Block under a fast force", "format": 1},
        "parameters": {"m": M, "g": G, "mu": MU, "F0": F0, "A": A, "w": w},
        "coordinates": {"q": ["x", "y"]},
        "energy": {"kinetic": "m/2*(x'^2+y'^2)", "potential": "m*g*y"},
        "forces": {"x": "F0 + A*sin(w*t)"},
        "contacts": [{"name": "floor", "gap": "y", "slip": ["x'"], "mu": "mu"}],
        "initial": {"x": 0.0, "y": 0.0, "x'": 0.0, "y'": 0.0},
        "simulation": {"t_end": 0.05},
    }, "<test>")


def closed_form(F0, A, w, t_end):
    """The switches ``[(t, "slip" | "stick")]`` and ``x(t_end)`` (module docstring)."""
    F = lambda t: F0 + A * math.sin(w * t)
    limit, dt = MU * M * G, 1e-3 / w
    t, x, switches = 0.0, 0.0, []
    while True:
        s = t
        while abs(F(s + dt)) <= limit and s < t_end:
            s += dt
        if s >= t_end:
            return switches, x
        ts = brentq(lambda u: abs(F(u)) - limit, s, s + dt, xtol=1e-17, rtol=8.9e-16)
        sign = math.copysign(1.0, F(ts))
        a0 = F0 / M - sign * MU * G
        v = lambda u: a0 * (u - ts) + A / (M * w) * (math.cos(w * ts) - math.cos(w * u))
        X = lambda u: a0 * (u - ts) ** 2 / 2 + A / (M * w) * (
            math.cos(w * ts) * (u - ts) - (math.sin(w * u) - math.sin(w * ts)) / w)
        switches.append((ts, "slip"))
        u = ts + dt
        while sign * v(u + dt) > 0:
            u += dt
        te = brentq(v, u, u + dt, xtol=1e-17, rtol=8.9e-16)
        if te > t_end:
            return switches, x + X(t_end)
        assert abs(F(te)) < limit  # it sticks: static friction holds there
        x += X(te)
        switches.append((te, "stick"))
        t = te


def test_the_closed_form_numbers():
    switches, x = closed_form(0.0, 1.05 * MU * M * G, 1000.0, 0.05)
    assert len(switches) == 32  # two slips and two sticks in each of 7.96 periods
    assert switches[0][0] == pytest.approx(math.asin(1 / 1.05) / 1000.0, rel=1e-14)
    _, x = closed_form(0.8 * MU * M * G, 0.3 * MU * M * G, 1000.0, 0.05)
    assert x == pytest.approx(6.3369e-6, rel=1e-4)


@pytest.mark.parametrize("F0, A, w", [(0.0, 1.05, 1000.0), (0.8, 0.3, 1000.0), (0.8, 0.3, 3000.0)],
                         ids=["alternating", "ratchet-1000", "ratchet-3000"])
def test_every_short_slip_against_the_closed_form(F0, A, w):
    F0, A = F0 * MU * M * G, A * MU * M * G
    switches, x_end = closed_form(F0, A, w, 0.05)
    traj = simulate(block(F0, A, w), times=np.linspace(0.0, 0.05, 11))
    found = [(e["t"], e["type"]) for e in traj.events]
    assert [k for _, k in found] == [k for _, k in switches]
    assert np.max(np.abs(np.array([t for t, _ in found]) - [t for t, _ in switches])) < 1e-8
    # the creep: each slip integrated, however short (a ratchet only moves forward)
    assert traj.coordinate("x")[-1] == pytest.approx(x_end, rel=1e-6, abs=1e-12)


def test_a_dip_of_the_cone_margin_that_does_not_reach_zero_stays_native():
    """|F| peaks at 99.9 % of mu m g twice a period: the margin dips as the scan minimizes
    (its samples' parabola reaches zero), and the native loop finds the dip's minimum itself
    (positive: no event) instead of handing the step back to the hybrid loop for it (16
    hand-backs in 0.05 s before)."""
    pytest.importorskip("numba")
    from nonideal.simulation.hybrid import Simulation

    sim = Simulation(block(0.0, 0.999 * MU * M * G, 1000.0), native=True)
    tr = sim.run()
    assert tr.events == [] and tr.t[-1] == 0.05
    assert sim.fast_contacts.native_steps >= 50
    assert sim.fast_contacts.handbacks == 0
