"""Sphere launched sliding on a rough plane (classical closed form, the friction benchmark):
t* = 2|U0|/(7 mu g), v_f = v0 - (2/7) U0, slip direction constant, energy lost = m|U0|^2/7 =
-(friction work), mode timeline slide -> stick, one- and two-component slip, all forms, CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.gallery.sphere_sliding_on_plane import build, closed_form, motion
from tests.helpers import run_cli as _cli

MU_G = 0.2 * 9.81
U0 = np.array([2.0 + 0.1 * 5.0, 1.0 + 0.1 * 3.0])        # (x' - R b', y' + R a') at t = 0
T_STAR = 2 * np.linalg.norm(U0) / (7 * MU_G)             # 0.41033938557...
V_F = np.array([2.0, 1.0]) - 2.0 / 7.0 * U0              # (9/7, 22/35)


@pytest.fixture(scope="module")
def model():
    return gallery.load("sphere-sliding-on-plane")


@pytest.fixture(scope="module")
def traj(model):
    return simulate(model)


def test_closed_form_numbers(model):
    cf = closed_form(model.parameter_values)
    assert np.allclose(cf["U0"], [2.5, 1.3], rtol=1e-15)
    assert cf["t_star"] == pytest.approx(0.410339385571730, rel=1e-12)
    assert np.allclose(cf["v_f"], [9 / 7, 22 / 35], rtol=1e-14)
    # rolling at the end: v_f - R omega_f,y = 0 and v_f,y + R omega_f,x = 0
    R = 0.1
    assert cf["v_f"][0] - R * cf["omega_f"][1] == pytest.approx(0, abs=1e-14)
    assert cf["v_f"][1] + R * cf["omega_f"][0] == pytest.approx(0, abs=1e-14)


def test_rolling_time_final_velocity_and_timeline(traj):
    assert [(e["type"], e["contact"], e["mode"]) for e in traj.events] == [("stick", "plane", "plane:stick")]
    assert traj.events[0]["t"] == pytest.approx(T_STAR, rel=1e-9)
    assert traj.modes[0] == "plane:slide" and traj.modes[-1] == "plane:stick"
    assert np.allclose(traj.qd[-1, :2], V_F, rtol=1e-9, atol=0)
    # rolling without slipping afterwards, spin about the vertical unchanged, z = R
    assert np.max(np.abs(traj.contacts["plane"]["slip"][-1])) < 1e-12
    assert np.allclose(traj.velocity("c"), 4.0, rtol=1e-14)
    assert np.allclose(traj.coordinate("z"), 0.1, rtol=1e-14)


def test_trajectory_slip_direction_and_angular_momentum(model):
    p = model.parameter_values
    times = np.linspace(0, 1, 41)
    tr = simulate(model, times=times)
    pos, vel, omega, U = motion(times, p)
    assert np.max(np.abs(tr.q[:, :2] - pos)) < 1e-10
    assert np.max(np.abs(tr.qd[:, :2] - vel)) < 1e-10
    assert np.max(np.abs(tr.qd[:, 3:6] - omega)) < 1e-9
    slip = np.array(tr.contacts["plane"]["slip"])
    assert np.max(np.abs(slip - U)) < 1e-10
    # the slip keeps its direction: U x U0 = 0, |U| decreasing at (7/2) mu g
    sliding = times < T_STAR
    assert np.max(np.abs(slip[sliding, 0] * U0[1] - slip[sliding, 1] * U0[0])) < 1e-10
    rate = -np.diff(np.linalg.norm(slip[sliding], axis=1)) / np.diff(times[sliding])
    assert np.allclose(rate, 3.5 * MU_G, rtol=1e-9)
    # friction = -mu N s while sliding, zero while rolling
    F = np.array(tr.contacts["plane"]["friction"])
    assert np.allclose(F[sliding], -MU_G * U0 / np.linalg.norm(U0), rtol=1e-10)
    assert np.max(np.abs(F[~sliding])) < 1e-10
    # angular momentum about the contact point is conserved: I omega + m R e_z x v
    L = 0.4 * 0.01 * tr.qd[:, 3:5] + 0.1 * np.column_stack((-tr.qd[:, 1], tr.qd[:, 0]))
    assert np.max(np.abs(L - L[0])) < 1e-12


def test_friction_work_equals_kinetic_energy_lost(traj):
    loss = np.linalg.norm(U0) ** 2 / 7                     # m |U0|^2 / 7, m = 1
    KE = traj.energy["kinetic"]
    assert KE[0] - KE[-1] == pytest.approx(loss, rel=1e-10)
    assert traj.energy["friction_work"][-1] == pytest.approx(-loss, rel=1e-10)
    assert np.all(np.diff(traj.energy["friction_work"]) <= 1e-12)   # fixed plane: power <= 0
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert traj.diagnostics["constraint_residual_max"] < 1e-10


def test_one_slip_component_launch_along_x_with_backspin():
    # U0 = (2 + 0.1*60, 0) = (8, 0): the ball comes back, v_f = 2 - 16/7 = -2/7
    t_star = 2 * 8.0 / (7 * MU_G)
    tr3 = simulate(build(v0=(2.0, 0.0), omega0=(0.0, -60.0, 0.0)), t_end=2.0)
    tr1 = simulate(build(v0=(2.0,), omega0=(-60.0,), planar=True), t_end=2.0)
    for tr in (tr3, tr1):
        assert len(tr.events) == 1 and tr.events[0]["mode"] == "plane:stick"
        assert tr.events[0]["t"] == pytest.approx(t_star, rel=1e-9)
        assert tr.at("x'") == pytest.approx(-2.0 / 7.0, rel=1e-9)
        assert tr.energy["friction_work"][-1] == pytest.approx(-64.0 / 7.0, rel=1e-10)
        assert np.all(np.diff(tr.energy["friction_work"]) <= 1e-12)
    assert tr3.events[0]["type"] == tr1.events[0]["type"] == "stick"
    assert tr1.modes[0] == "plane:slide+"
    assert np.max(np.abs(tr3.velocity("y"))) < 1e-14


def test_cli_simulate_json_and_plot(tmp_path):
    proc = _cli("simulate", gallery.model_path("sphere-sliding-on-plane"), "--json", "--plot",
                "sphere.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert {"model", "t", "q", "qdot", "multipliers", "contacts", "events", "energy",
            "diagnostics"} <= set(d)
    plane = d["contacts"]["plane"]
    assert {"normal", "friction", "slip", "mode"} <= set(plane)
    assert len(plane["slip"][0]) == 2 and len(plane["friction"][0]) == 2
    assert plane["mode"][0] == "slide" and plane["mode"][-1] == "stick"
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("stick", "plane")]
    assert d["events"][0]["t"] == pytest.approx(T_STAR, rel=1e-9)
    assert d["qdot"]["x"][-1] == pytest.approx(V_F[0], rel=1e-9)
    assert d["energy"]["friction_work"][-1] == pytest.approx(-np.linalg.norm(U0) ** 2 / 7, rel=1e-9)
    png = (tmp_path / "sphere.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
