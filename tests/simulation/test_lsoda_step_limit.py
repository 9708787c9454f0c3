"""LSODA honours the step limit of the force guards within a phase.

A block held by static friction (mu_s = mu) under ``F = a t^2 sin(w t)``: at the start the
guard's rates vanish (no limit), later its dips come every half period, and every one that
crosses the friction cone is a slip.  LSODA fixes its largest step when it starts, so without
a restart it stepped over most of them (3 of 7 switches in 0.06 s).

Closed form (m x'' = F(t) + friction, at rest at t = 0): the block slips where |F| reaches
mu m g, in the direction s = sign F, with

    x'(t) = (P(t) - P(t_s))/m - s mu g (t - t_s),    P(t) = a (2 cos(w t)/w^3 + 2 t sin(w t)/w^2 - t^2 cos(w t)/w)

(P' = F), and sticks again where x' returns to zero (|F| < mu m g there).
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from nonideal.modeling.modelfile import model_from_dict
from nonideal.simulation import simulate

M, G, MU, W, T_END = 1.0, 9.81, 0.5, 1000.0, 0.06
A = 1.2 * MU * M * G / 0.05 ** 2


def F(t):
    return A * t * t * math.sin(W * t)


def P(t):
    return A * (2 * math.cos(W * t) / W ** 3 + 2 * t * math.sin(W * t) / W ** 2 - t * t * math.cos(W * t) / W)


def closed_form():
    """The switches ``[(t, "slip" | "stick")]`` and ``x(T_END)``."""
    limit, dt = MU * M * G, 1e-3 / W
    t, x, switches = 0.0, 0.0, []
    while True:
        s = t
        while abs(F(s + dt)) <= limit and s < T_END:
            s += dt
        if s >= T_END:
            return switches, x
        ts = brentq(lambda u: abs(F(u)) - limit, s, s + dt, xtol=1e-17, rtol=8.9e-16)
        sign = math.copysign(1.0, F(ts))
        v = lambda u: (P(u) - P(ts)) / M - sign * MU * G * (u - ts)
        switches.append((ts, "slip"))
        u = ts + dt
        while sign * v(u + dt) > 0 and u < T_END:
            u += dt
        if u >= T_END:
            return switches, x + quad(v, ts, T_END, epsabs=1e-16, epsrel=1e-13, limit=200)[0]
        te = brentq(v, u, u + dt, xtol=1e-17, rtol=8.9e-16)
        assert abs(F(te)) < limit  # it sticks: static friction holds there
        x += quad(v, ts, te, epsabs=1e-16, epsrel=1e-13, limit=200)[0]
        switches.append((te, "stick"))
        t = te


def block():
    return model_from_dict({
        "model": {"name": "Block under a growing fast force", "format": 1},
        "parameters": {"m": M, "g": G, "mu": MU, "a": A, "w": W},
        "coordinates": {"q": ["x", "y"]},
        "energy": {"kinetic": "m/2*(x'^2+y'^2)", "potential": "m*g*y"},
        "forces": {"x": "a*t^2*sin(w*t)"},
        "contacts": [{"name": "floor", "gap": "y", "slip": ["x'"], "mu": "mu"}],
        "initial": {"x": 0.0, "y": 0.0, "x'": 0.0, "y'": 0.0},
        "simulation": {"t_end": T_END},
    }, "<test>")


def test_the_closed_form_numbers():
    switches, x = closed_form()
    assert [k for _, k in switches] == ["slip", "stick"] * 3 + ["slip"]
    assert switches[0][0] > 0.048 and x > 0


@pytest.mark.parametrize("method", ["LSODA", "DOP853", "RK45"])
def test_every_switch_of_a_late_fast_guard(method):
    switches, x_end = closed_form()
    traj = simulate(block(), method=method)
    found = [(e["t"], e["type"]) for e in traj.events]
    assert [k for _, k in found] == [k for _, k in switches]
    assert np.max(np.abs(np.array([t for t, _ in found]) - [t for t, _ in switches])) < 1e-8
    assert traj.coordinate("x")[-1] == pytest.approx(x_end, rel=1e-6, abs=1e-12)
