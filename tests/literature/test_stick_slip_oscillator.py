"""Stick-slip oscillator on a moving belt (classical closed form): slip at k x = mu_s m g,
harmonic slip about mu m g / k, limit cycle period and amplitude, stick/slip event times,
friction work of a moving support (heat only while slipping, the belt's work while sticking), energy balance,
all forms, CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.gallery.stick_slip_oscillator import build, closed_form, schedule
from tests.helpers import run_cli as _cli

# m = 1, k = 10, g = 9.81, mu = 0.25, mu_s = 0.4, v_b = 0.5
W = np.sqrt(10.0)
D = (0.4 - 0.25) * 9.81 / 10.0                      # x_s - x_k
T_SLIP = (np.pi + 2 * np.arctan(0.5 * W / ((0.4 - 0.25) * 9.81))) / W
T_STICK = 2 * D / 0.5
T = T_SLIP + T_STICK
T1 = 0.4 * 9.81 / 10.0 / 0.5                         # first slip: x = x_s reached at v_b


@pytest.fixture(scope="module")
def model():
    return gallery.load("stick-slip-oscillator")


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model)


def test_closed_form_numbers(model):
    cf = closed_form(model.parameter_values)
    assert cf["T_slip"] == pytest.approx(1.512893805582, rel=1e-11)
    assert cf["T_stick"] == pytest.approx(0.5886, rel=1e-14)
    assert cf["T"] == pytest.approx(T, rel=1e-14)
    assert cf["A"] == pytest.approx(np.hypot(D, 0.5 / W), rel=1e-14)
    # slip ends at x_k - d with x' = v_b: on the energy ellipse of the slip oscillation
    assert (cf["x_k"] - cf["d"] - cf["x_k"]) ** 2 + (0.5 / W) ** 2 == pytest.approx(cf["A"] ** 2, rel=1e-14)


def test_stick_slip_event_times_and_no_chattering(traj):
    expected = [(T1, "slip"), (T1 + T_SLIP, "stick"), (T1 + T, "slip"), (T1 + T + T_SLIP, "stick"),
                (T1 + 2 * T, "slip"), (T1 + 2 * T + T_SLIP, "stick")]
    assert [(e["type"], e["contact"]) for e in traj.events] == [(k, "belt") for _, k in expected]
    for e, (t, _) in zip(traj.events, expected):
        assert e["t"] == pytest.approx(t, rel=1e-8)
    assert [e["mode"] for e in traj.events[:2]] == ["belt:slide-", "belt:stick"]


def test_limit_cycle_period_and_amplitude(model, traj):
    slips = np.array([e["t"] for e in traj.events if e["type"] == "slip"])
    sticks = np.array([e["t"] for e in traj.events if e["type"] == "stick"])
    assert np.allclose(np.diff(slips), T, rtol=1e-8)
    assert np.allclose(sticks - slips[:len(sticks)], T_SLIP, rtol=1e-8)
    cf = closed_form(model.parameter_values)
    times = np.sort([slips[1] + cf["tau_max"], slips[1] + cf["tau_min"]])
    tr = simulate(model, times=np.concatenate(([0.0], times)))
    x_max, x_min = tr.coordinate("x")[1], tr.coordinate("x")[2]
    assert x_max == pytest.approx(cf["x_k"] + cf["A"], abs=1e-9)
    assert x_min == pytest.approx(cf["x_k"] - cf["A"], abs=1e-9)
    assert abs(tr.velocity("x")[1]) < 1e-9 and abs(tr.velocity("x")[2]) < 1e-9


def test_start_from_rest_joins_the_same_cycle():
    m = build(xd0=0.0)
    tr = simulate(m)
    p = m.parameter_values
    expected = schedule(p, 7.0, 0.0, 0.0)
    t_catch = np.arcsin(0.5 / (W * 0.25 * 9.81 / 10.0)) / W   # sliding from rest catches the belt
    assert expected[0] == (pytest.approx(t_catch, rel=1e-14), "stick")
    assert [e["type"] for e in tr.events] == [k for _, k in expected]
    for e, (t, _) in zip(tr.events, expected):
        assert e["t"] == pytest.approx(t, rel=1e-8)
    slips = np.array([e["t"] for e in tr.events if e["type"] == "slip"])
    assert np.allclose(np.diff(slips), T, rtol=1e-8)


def test_forces_and_friction_work_of_the_moving_support(model):
    p = model.parameter_values
    cf = closed_form(p)
    tr = simulate(model, times=np.linspace(0, 7, 141))
    belt = tr.contacts["belt"]
    F = np.array(belt["friction"])[:, 0]
    stick = np.array(belt["mode"]) == "stick"
    assert np.allclose(F[stick], 10.0 * tr.coordinate("x")[stick], rtol=1e-10, atol=1e-12)
    assert np.allclose(F[~stick], 0.25 * 9.81, rtol=1e-12)          # slower than the belt: +mu N
    assert np.all(np.abs(F[stick]) <= 0.4 * 9.81 + 1e-12)
    assert np.allclose(belt["normal"], 9.81, rtol=1e-12)
    # at the event times: the work of friction on the block, +2 d mu m g per full stick phase and
    # -2 d mu m g per slip, splits into the heat F U (friction_work: only while slipping, never
    # positive) and what the belt puts in, F v_b (reaction_work)
    full = simulate(model)
    te = [e["t"] for e in full.events]
    tr = simulate(model, times=[0.0] + te)
    Wf, WR = tr.energy["friction_work"], tr.energy["reaction_work"]
    assert Wf[1] == pytest.approx(0.0, abs=1e-12)                        # first stick: no heat
    assert WR[1] == pytest.approx(10.0 * cf["x_s"] ** 2 / 2, rel=1e-9)   # ... the belt's work
    dW, dWf = np.diff((Wf + WR)[1:]), np.diff(Wf[1:])
    assert np.allclose(dW[0::2], cf["work_slip"], rtol=1e-9)
    assert np.allclose(dW[1::2], cf["work_stick"], rtol=1e-9)
    assert cf["work_stick"] == pytest.approx(2 * D * 0.25 * 9.81, rel=1e-14)
    assert np.allclose(dWf[0::2], -cf["heat_per_cycle"], rtol=1e-9)
    assert np.allclose(dWf[1::2], 0.0, atol=1e-11)
    # the heat never decreases, although the support makes the friction's work on the block
    # positive while the block is carried along; the energy T + V is periodic
    assert np.max(np.diff(full.energy["friction_work"])) <= 1e-12
    assert np.max(np.diff(full.energy["friction_work"] + full.energy["reaction_work"])) > 1e-3
    E = tr.energy["energy"]
    assert np.allclose(E[1::2], E[1], rtol=1e-9)


def test_energy_balance(traj):
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    E = traj.energy
    assert np.max(np.abs((E["energy"] - E["energy"][0]) - E["friction_work"] - E["reaction_work"])) < 1e-8
    assert traj.diagnostics["constraint_residual_max"] < 1e-10


def test_cli_simulate_json(tmp_path):
    proc = _cli("simulate", gallery.model_path("stick-slip-oscillator"), "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
            "diagnostics"} <= set(d)
    belt = d["contacts"]["belt"]
    assert {"normal", "friction", "slip", "mode"} <= set(belt)
    assert belt["mode"][0] == "stick" and "slide-" in belt["mode"]
    assert [e["type"] for e in d["events"]] == ["slip", "stick"] * 3
    assert d["events"][2]["t"] - d["events"][0]["t"] == pytest.approx(T, rel=1e-8)
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8
