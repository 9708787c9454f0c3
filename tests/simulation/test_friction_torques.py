"""Friction torques at a contact: pivoting (``spin_friction``) and rolling resistance
(``rolling_friction``), Coulomb's law on the angular velocity with the contact's normal force,
against closed forms.

* a disk lying flat and spinning on a plane: ``psi' = w0 - (l m g/I) t``, stops exactly at
  ``t* = I w0/(l m g)`` and stays stopped; the heat is the initial spin energy;
* a ball rolling on a plane (``mu = inf``) with rolling resistance:
  ``x'' = -l m g r/(I + m r^2)`` (with ``I = 2/5 m r^2``: ``-(5/7) l g/r``), stops at ``v0/|x''|``;
* a stuck spin under a torque below ``l N`` stays stuck; above it, it starts at once with
  ``psi'' = (T - l m g)/I``; under a torque growing as ``k t`` it starts exactly at
  ``t = l m g/k``;
* the energy balances, the friction torques' work is reported with the friction work and is
  never positive.
"""

import numpy as np
import pytest

from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

SPIN = DATA_DIR / "torques" / "spinning_disk.toml"
BALL = DATA_DIR / "torques" / "ball_rolling_resistance.toml"


@pytest.fixture(scope="module")
def spin_run():
    model = load_model(SPIN)
    return model, simulate(model, times=np.linspace(0, 0.5, 101))


def test_spin_decays_linearly_and_stops_exactly(spin_run):
    model, tr = spin_run
    p = model.parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    rate = p["l"] * p["m"] * p["g"] / I
    w0 = 10.0
    t_star = w0 / rate
    (event,) = tr.events
    assert event["type"] == "stick" and event["contact"] == "floor_spin"
    assert abs(event["t"] - t_star) < 1e-8
    w = tr.velocity("psi")
    expected = np.where(tr.t < t_star, w0 - rate * tr.t, 0.0)
    assert np.max(np.abs(w - expected)) < 1e-8
    torque = np.array(tr.contacts["floor_spin"]["friction"])[:, 0]
    moving = tr.t < t_star - 1e-6
    assert np.allclose(torque[moving], -p["l"] * p["m"] * p["g"], rtol=1e-10)
    assert np.max(np.abs(torque[tr.t > t_star + 1e-6])) < 1e-9      # stopped: no torque needed
    assert set(tr.contacts["floor_spin"]["mode"]) == {"slide+", "stick"}
    assert np.allclose(tr.contacts["floor_spin"]["normal"], p["m"] * p["g"], rtol=1e-12)


def test_spin_heat_is_the_spin_energy(spin_run):
    model, tr = spin_run
    p = model.parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    W_f = tr.energy["friction_work"]
    assert W_f[-1] == pytest.approx(-0.5 * I * 10.0 ** 2, rel=1e-9)
    assert np.all(np.diff(W_f) <= 1e-15)                    # never positive
    assert tr.diagnostics["energy_balance_max"] < 1e-10


def test_rolling_resistance_decelerates_the_ball():
    model = load_model(BALL)
    p = model.parameter_values
    m, r, g, l = p["m"], p["r"], p["g"], p["l"]
    I = 2 / 5 * m * r ** 2
    a = l * m * g * r / (I + m * r ** 2)
    assert a == pytest.approx(5 / 7 * l * g / r, rel=1e-14)
    v0 = 0.5
    t_star = v0 / a
    tr = simulate(model, times=np.linspace(0, 5.0, 201))
    (event,) = tr.events
    assert event["type"] == "stick" and event["contact"] == "floor_rolling"
    assert abs(event["t"] - t_star) < 1e-8
    v = tr.velocity("x")
    assert np.max(np.abs(v - np.where(tr.t < t_star, v0 - a * tr.t, 0.0))) < 1e-8
    assert tr.coordinate("x")[-1] == pytest.approx(v0 ** 2 / (2 * a), rel=1e-9)
    E0 = 0.5 * m * v0 ** 2 + 0.5 * I * (v0 / r) ** 2
    assert tr.energy["friction_work"][-1] == pytest.approx(-E0, rel=1e-9)
    assert tr.diagnostics["energy_balance_max"] < 1e-12


def _with_torque(expr, w0=0.0):
    model = load_model(SPIN)
    return model.replace(forces={"psi": expr}, initial={**model.initial, "psi'": w0})


@pytest.mark.parametrize("fraction", [0.5, 0.999])
def test_stuck_spin_below_the_bound_stays_stuck(fraction):
    p = load_model(SPIN).parameter_values
    T = fraction * p["l"] * p["m"] * p["g"]
    tr = simulate(_with_torque(str(T)), t_end=0.2)
    assert tr.events == []
    assert np.max(np.abs(tr.velocity("psi"))) < 1e-12
    torque = np.array(tr.contacts["floor_spin"]["friction"])[:, 0]
    assert np.allclose(torque, -T, rtol=1e-10)


def test_stuck_spin_above_the_bound_starts_at_once():
    p = load_model(SPIN).parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    bound = p["l"] * p["m"] * p["g"]
    T = 1.5 * bound
    tr = simulate(_with_torque(str(T)), times=np.linspace(0, 0.2, 21))
    assert tr.contacts["floor_spin"]["mode"][0] == "slide+"
    assert np.allclose(tr.velocity("psi"), (T - bound) / I * tr.t, rtol=1e-9, atol=1e-12)


def test_growing_torque_starts_the_spin_exactly_at_the_bound():
    p = load_model(SPIN).parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    bound = p["l"] * p["m"] * p["g"]
    k = 2.0
    tr = simulate(_with_torque(f"{k}*t"), times=np.linspace(0, 0.5, 51))
    (event,) = tr.events
    t1 = bound / k
    assert event["type"] == "slip" and event["contact"] == "floor_spin"
    assert abs(event["t"] - t1) < 1e-8
    after = tr.t > t1
    # psi'' = (k t - l m g)/I after t1: psi' = k (t - t1)^2 / (2 I)
    assert np.allclose(tr.velocity("psi")[after], k * (tr.t[after] - t1) ** 2 / (2 * I), rtol=1e-8, atol=1e-12)
    assert tr.diagnostics["energy_balance_max"] < 1e-10


def test_sliding_and_spinning_decay_independently():
    """The uncoupled law: the sliding friction -mu N U/|U| and the pivoting torque -l N sign(w)
    each with its own bound (no Contensou coupling): x' = v0 - mu g t, psi' = w0 - (l m g/I) t."""
    model = load_model(SPIN)
    p = model.parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    v0, w0 = 0.5, 10.0
    model = model.replace(initial={**model.initial, "x'": v0})
    tr = simulate(model, times=np.linspace(0, 0.3, 61))
    t_slide, t_spin = v0 / (p["mu"] * p["g"]), w0 * I / (p["l"] * p["m"] * p["g"])
    events = {e["contact"]: e for e in tr.events}
    assert abs(events["floor"]["t"] - t_slide) < 1e-8 and abs(events["floor_spin"]["t"] - t_spin) < 1e-8
    assert np.allclose(tr.velocity("x"), np.maximum(v0 - p["mu"] * p["g"] * tr.t, 0), atol=1e-9)
    assert np.allclose(tr.velocity("psi"), np.maximum(w0 - p["l"] * p["m"] * p["g"] / I * tr.t, 0), atol=1e-8)
    heat = 0.5 * p["m"] * v0 ** 2 + 0.5 * I * w0 ** 2
    assert tr.energy["friction_work"][-1] == pytest.approx(-heat, rel=1e-9)
