"""Constraints that become singular along a motion: two holonomic constraints that become
dependent (x^2 + y^2 = 1 and y = -cos t at t = pi) and a nonholonomic constraint whose gradient
vanishes (z'^2 = a^2 (x'^2 + y'^2) where x' = 0).

By default (``[simulation] singular = "smooth"``) the run goes on through the singular instant
on the branch with continuous velocities, recorded as a ``singular`` event; checked against the
closed forms (x = sin t, not |sin t|; the harmonic motion x = sin(w t)/w, z = a x with
w^2 = k/(m (1 + a^2))) and the energy balance.  ``singular = "stop"`` stops the run with exit
code 3, naming the constraints, the time and the state."""

import math
import tomllib

import numpy as np
import pytest

from nonideal.errors import ModelError, SingularMotion
from nonideal.modeling.modelfile import load_model, model_from_dict
from nonideal.simulation import simulate
from tests.helpers import DATA_DIR, run_cli


def with_setting(name, value):
    data = tomllib.loads((DATA_DIR / name).read_text())
    data["simulation"]["singular"] = value
    return model_from_dict(data, name)


def test_dependent_constraints_are_passed_through_on_the_smooth_branch_x_sin_t():
    model = load_model(DATA_DIR / "dependent_in_motion.toml")
    times = np.linspace(0.5, 5.0, 91)  # includes times inside the carried-over interval
    traj = simulate(model, times=times)
    # the smooth branch x = sin t; the other continuation, x = |sin t|, has x' = -cos t > 0
    # after pi, and is 2|sin t| away in x
    assert np.max(np.abs(traj.q[:, 0] - np.sin(times))) < 1e-8
    assert np.max(np.abs(traj.qd[:, 0] - np.cos(times))) < 1e-6
    assert np.max(np.abs(traj.q[:, 1] + np.cos(times))) < 1e-9
    (event,) = traj.events
    assert event["type"] == "singular" and event["branch"] == "smooth"
    assert event["constraint"] == "circle, program"
    assert event["t"] == pytest.approx(math.pi, abs=1e-6)
    lo, hi = event["interval"]
    assert lo < math.pi < hi and hi - lo < 0.1
    assert "multipliers are unbounded" in event["note"]
    # the speed stays 1 (the reactions do no work on the circle with the program's speed)
    assert abs(traj.energy["balance"][-1]) < 1e-5
    # an end time inside the interval carried over: the run ends there, on the branch
    short = simulate(model, t_end=3.15)
    assert short.t[-1] == 3.15 and short.q[-1, 0] == pytest.approx(math.sin(3.15), abs=1e-9)


def test_constraints_that_only_come_close_to_dependent_are_integrated_as_they_are():
    # y = -c cos t with c = 1 - 1e-5: x = sqrt(1 - c^2 cos^2 t) never reaches 0 (its least value
    # 4.5e-3) -- the motion turns back at t = pi, x' going from -1 to +1 within a few ms
    c = 1 - 1e-5
    text = (DATA_DIR / "dependent_in_motion.toml").read_text()
    text = text.replace("y + cos(t)", f"y + {c!r}*cos(t)").replace('y = "-cos(0.5)"', f'y = "-{c!r}*cos(0.5)"')
    text = text.replace('x = "sin(0.5)"', f'x = "sqrt(1 - {c!r}^2*cos(0.5)^2)"')
    times = np.linspace(0.5, 5.0, 46)
    traj = simulate(model_from_dict(tomllib.loads(text), "near.toml"), times=times)
    assert traj.events == []
    assert np.max(np.abs(traj.q[:, 0] - np.sqrt(1 - c * c * np.cos(times) ** 2))) < 1e-9


def test_a_vanishing_gradient_is_passed_through_three_times_on_the_harmonic_motion():
    model = load_model(DATA_DIR / "vanishing_gradient.toml")
    traj = simulate(model)
    a, k, m = 0.5, 1.0, 1.0
    w = math.sqrt(k / (m * (1 + a * a)))  # z' = a x' on the smooth branch: mass m (1 + a^2)
    t = traj.t
    assert np.max(np.abs(traj.q[:, 0] - np.sin(w * t) / w)) < 1e-8
    assert np.max(np.abs(traj.q[:, 2] - a * np.sin(w * t) / w)) < 1e-8   # not a |x'| integral
    assert np.max(np.abs(traj.qd[:, 0] - np.cos(w * t))) < 1e-8
    singular = [ev for ev in traj.events if ev["type"] == "singular"]
    assert [ev["constraint"] for ev in singular] == ["cone"] * 3
    # x' = 0 (the gradient vanishes) at t = (j + 1/2) pi / w
    assert [ev["t"] for ev in singular] == pytest.approx([(j + 0.5) * math.pi / w for j in range(3)],
                                                         abs=1e-6)
    # energy m/2 (x'^2 + z'^2) + k x^2/2 conserved (the reaction is ideal on the smooth branch)
    assert abs(traj.energy["balance"][-1]) < 1e-9
    # with an implicit integrator (its dense output is of lower order than its steps)
    radau = simulate(model, method="Radau", times=np.linspace(0.0, 10.0, 41))
    assert np.max(np.abs(radau.q[:, 0] - np.sin(w * radau.t) / w)) < 1e-8


def test_stop_ends_the_run_at_t_pi_naming_the_constraints():
    for model in (with_setting("dependent_in_motion.toml", "stop"),
                  load_model(DATA_DIR / "dependent_in_motion.toml")):
        options = {} if model.simulation.singular == "stop" else {"singular": "stop"}
        with pytest.raises(SingularMotion) as info:
            simulate(model, **options)
        err = info.value
        assert err.exit_code == 3
        assert err.t == pytest.approx(math.pi, abs=1e-5)
        assert err.details["constraints"] == "circle, program"
        assert abs(err.state["x"]) < 1e-5 and err.state["y"] == pytest.approx(1.0, abs=1e-9)
        assert "became dependent" in str(err)


def test_stop_on_a_vanishing_gradient_names_the_constraint():
    model = with_setting("vanishing_gradient.toml", "stop")
    with pytest.raises(SingularMotion) as info:
        simulate(model)
    err = info.value
    assert err.details["constraint"] == "cone"
    # the gradient (-2 a^2 x', -2 a^2 y', 2 z') vanishes with x' (y' = 0, z' = a |x'|)
    assert abs(err.state["x'"]) < 1e-5 and abs(err.state["z'"]) < 1e-5
    assert "lost its gradient" in str(err)


def test_an_unknown_setting_is_refused():
    with pytest.raises(ModelError, match=r"\[simulation\] singular: must be \"smooth\""):
        with_setting("dependent_in_motion.toml", "maybe")
    with pytest.raises(ModelError, match="singular: must be one of smooth, stop"):
        simulate(load_model(DATA_DIR / "dependent_in_motion.toml"), singular="branch")


def test_cli_stop_exits_3_and_smooth_says_the_branch(tmp_path):
    text = (DATA_DIR / "dependent_in_motion.toml").read_text()
    stop = tmp_path / "stop.toml"
    stop.write_text(text.replace("[simulation]\n", '[simulation]\nsingular = "stop"\n'))
    proc = run_cli("simulate", stop)
    assert proc.returncode == 3, proc.stderr
    assert "'circle', 'program' became dependent" in proc.stderr and "at t = 3.14159" in proc.stderr
    assert "Traceback" not in proc.stderr
    proc = run_cli("simulate", DATA_DIR / "dependent_in_motion.toml")
    assert proc.returncode == 0, proc.stderr
    assert "singular circle, program" in proc.stdout and "smooth branch" in proc.stdout


@pytest.mark.parametrize("method, rtol", [("RK45", 1e-8), ("RK45", 1e-6), ("DOP853", 1e-6)])
def test_stop_stops_at_any_tolerance(method, rtol):
    """At a looser tolerance the integrated motion misses the dependent configuration (RK45 at
    rtol 1e-8: the regularity bottoms out at 3e-6 and the motion turns back on x = |sin t|,
    which ran to the end); the level at which the rows count as singular follows the
    tolerance, so the run stops at t = pi."""
    model = with_setting("dependent_in_motion.toml", "stop")
    with pytest.raises(SingularMotion) as info:
        simulate(model, method=method, rtol=rtol)
    assert info.value.t == pytest.approx(math.pi, abs=1e-2)
    assert info.value.details["constraints"] == "circle, program"
