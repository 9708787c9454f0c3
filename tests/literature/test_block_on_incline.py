"""Block thrown up a rough incline (classical closed form): stop time and distance, sticking
vs sliding back (static friction), friction work = -mu N * path, energy balance, all forms,
the CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.evaluation import evaluate
from nonideal.gallery.block_on_incline import build, closed_form, motion
from tests.helpers import run_cli as _cli

G = 9.81
# t1 = v0 / (g (sin a + mu cos a)), v0 = 3, mu = 0.3 (digits from the formula)
T1_A04 = 3.0 / (G * (np.sin(0.4) + 0.3 * np.cos(0.4)))
T1_A06 = 3.0 / (G * (np.sin(0.6) + 0.3 * np.cos(0.6)))


@pytest.fixture(scope="module")
def model():
    return gallery.load("block-on-incline")


def test_closed_form_numbers():
    p = build().parameter_values
    cf = closed_form(p)
    assert cf["t1"] == pytest.approx(0.45935641655455, rel=1e-12)
    assert cf["d"] == pytest.approx(3.0 ** 2 / (2 * G * (np.sin(0.4) + 0.3 * np.cos(0.4))), rel=1e-14)
    assert cf["sticks"] and 0.3 < np.tan(0.4) < 0.5


def test_initial_deceleration(model):
    ev = evaluate(model)
    a_up = G * (np.sin(0.4) + 0.3 * np.cos(0.4))
    assert ev.qdd[0] == pytest.approx(-a_up, rel=1e-13)


@pytest.mark.parametrize("alpha, mu_s, t1, mode", [
    (0.4, 0.5, T1_A04, "plane:stick"),    # mu < tan a <= mu_s: held by static friction
    (0.6, 0.5, T1_A06, "plane:slide-"),   # tan a > mu_s: slides back
    (0.4, 0.3, T1_A04, "plane:slide-"),   # same slope, mu_s = mu: slides back
])
def test_stop_time_regime_and_no_chattering(alpha, mu_s, t1, mode):
    tr = simulate(build(alpha=alpha, mu_s=mu_s), t_end=3.0)
    # exactly one event: the slip velocity reaches zero; then stick or slide down for ever
    kind = "stick" if mode == "plane:stick" else "reverse"
    assert [(e["type"], e["contact"], e["mode"]) for e in tr.events] == [(kind, "plane", mode)]
    assert tr.events[0]["t"] == pytest.approx(t1, rel=1e-9)
    assert tr.modes[-1] == mode
    p = build(alpha=alpha, mu_s=mu_s).parameter_values
    if mode == "plane:stick":
        assert tr.at("x") == pytest.approx(closed_form(p)["d"], rel=1e-10)
        assert abs(tr.at("x'")) < 1e-12
    else:
        a_down = G * (np.sin(alpha) - 0.3 * np.cos(alpha))
        assert tr.qdd[-1, 0] == pytest.approx(-a_down, rel=1e-12)


@pytest.mark.parametrize("alpha", [0.4, 0.6])
def test_motion_forces_and_friction_work_closed_form(alpha):
    m = build(alpha=alpha)
    p = m.parameter_values
    times = np.linspace(0, 1.5, 61)
    tr = simulate(m, times=times)
    x, xd, W = motion(times, p)
    assert np.max(np.abs(tr.coordinate("x") - x)) < 1e-10
    assert np.max(np.abs(tr.velocity("x") - xd)) < 1e-10
    # W_f = -mu N * path length (path = d, or 2 d - x when sliding back)
    assert np.max(np.abs(tr.energy["friction_work"] - W)) < 1e-9
    N = 2.0 * G * np.cos(alpha)
    assert np.allclose(tr.contacts["plane"]["normal"], N, rtol=1e-12)
    F = np.array(tr.contacts["plane"]["friction"])[:, 0]
    sliding = np.array([s.startswith("slide") for s in tr.contacts["plane"]["mode"]])
    assert np.allclose(F[sliding], -0.3 * N * np.sign(tr.velocity("x")[sliding]), rtol=1e-12)
    if alpha == 0.4:   # sticking: friction holds the block, F = m g sin(a) < mu_s N
        assert np.allclose(F[~sliding], 2.0 * G * np.sin(0.4), rtol=1e-12)
        assert sliding.sum() < len(F)


@pytest.mark.parametrize("alpha", [0.4, 0.6])
def test_energy_balance_and_friction_power(alpha):
    tr = simulate(build(alpha=alpha))
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    E = tr.energy["energy"]
    assert np.max(np.abs((E - E[0]) - tr.energy["friction_work"])) < 1e-8 * abs(E[0])
    # fixed support: the friction power is never positive
    assert np.all(np.diff(tr.energy["friction_work"]) <= 1e-12)
    assert tr.diagnostics["constraint_residual_max"] < 1e-10


def test_cli_simulate_json(tmp_path):
    proc = _cli("simulate", gallery.model_path("block-on-incline"), "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
            "diagnostics", "modes"} <= set(d)
    assert {"kinetic", "potential", "friction_work", "reaction_work"} <= set(d["energy"])
    assert {"normal", "friction", "slip", "mode"} <= set(d["contacts"]["plane"])
    assert d["contacts"]["plane"]["mode"][0] == "slide+" and d["contacts"]["plane"]["mode"][-1] == "stick"
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("stick", "plane")]
    assert d["events"][0]["t"] == pytest.approx(T1_A04, rel=1e-9)
    assert np.all(np.diff(d["energy"]["friction_work"]) <= 1e-12)
    assert d["diagnostics"]["energy_balance_relative"] < 1e-8


def test_cli_examples_run(tmp_path):
    proc = _cli("examples", "run", "block-on-incline", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.rstrip().endswith("ok")
