"""Lagrange II along a motion that leaves its chart (nonideal/charts.py).

Lagrange II eliminates the holonomic constraints on a chart chosen at t0 (the kept
coordinates and the branch of each root).  A pendulum in Cartesian coordinates going over the
top, or the double pendulum of ``tests/data/double_pendulum_cartesian.toml`` (rod 1 passes the
vertical, rod 2 the horizontal), pass the singular points of every chart: the simulation must
change charts and give Lagrange I's motion.  The hybrid motions with contacts and unilateral
constraints, which keep their chart, must not change.
"""

from dataclasses import replace

import numpy as np
import pytest

from nonideal import Constraint, FormNotApplicable, Model, gallery
from nonideal.analysis.crosscheck import compare_forms
from nonideal.errors import IntegrationFailed
from nonideal.modeling.modelfile import load_model
from nonideal.modes.types import Mode
from nonideal.modes.solver import ModeSolver
from nonideal.numeric.kernel import kernel_of, parameter_vector
from nonideal.simulation.hybrid import Simulation, simulate
from tests.helpers import DATA_DIR

DATA = DATA_DIR


def double_pendulum(independent=None):
    model = load_model(DATA / "double_pendulum_cartesian.toml")
    return replace(model, independent=independent) if independent else model


def pendulum(independent=None, x0=0.0, y0=-1.0, v0=8.0):
    """A pendulum in (x, y) with speed enough to go over the top (v0^2 > 4 g l)."""
    return Model(name="pendulum over the top", coordinates=["x", "y"],
                 parameters={"m": 1.0, "l": 1.0, "g": 9.81},
                 kinetic="m*(x'^2 + y'^2)/2", potential="m*g*y",
                 constraints=[Constraint.holonomic("rod", "x^2 + y^2 - l^2")],
                 initial={"x": x0, "y": y0, "x'": v0 * -y0, "y'": v0 * x0},
                 independent=independent)


def sign_changes(values):
    return int(np.count_nonzero(np.diff(np.sign(values))))


def assert_matches_lagrange1(model, tol=1e-8, **options):
    ref = simulate(model, form="lagrange1", **options)
    traj = simulate(model, form="lagrange2", **options)
    assert traj.events == ref.events == []
    assert np.max(np.abs(traj.q[-1] - ref.q[-1])) < tol
    assert np.max(np.abs(traj.qd[-1] - ref.qd[-1])) < tol
    d = traj.diagnostics
    assert d["energy_balance_relative"] < 1e-8
    assert d["constraint_residual_max"] < 1e-8
    return traj


@pytest.mark.parametrize("independent", [None, ("x1", "x2")])
def test_double_pendulum_passes_the_singular_points_of_its_charts(independent):
    # the default chart (y1, x2 kept) is singular where rod 1 is vertical (x1 = 0), the chart
    # keeping x1, x2 where rod 2 is horizontal (y2 = y1); the motion passes both, repeatedly
    traj = assert_matches_lagrange1(double_pendulum(independent))
    assert sign_changes(traj.q[:, 0]) >= 2
    assert sign_changes(traj.q[:, 1] - traj.q[:, 3]) >= 2
    assert traj.diagnostics["chart_changes"] >= 2


@pytest.mark.parametrize("independent", [("x",), ("y",)])
def test_pendulum_over_the_top_from_either_chart(independent):
    # kept x: y = -sqrt(l^2 - x^2), singular where the rod is horizontal; kept y: x = -sqrt(...)
    # (the root through x = 0 at the bottom), singular at once.  Over the top x and y change
    # sign again and again; both charts and both branches of each are needed
    sim = Simulation(pendulum(independent), form="lagrange2", rtol=1e-10, atol=1e-12)
    traj = sim.run(t_end=3.0)
    ref = simulate(pendulum(independent), form="lagrange1", t_end=3.0, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(traj.q[-1] - ref.q[-1])) < 1e-8
    assert np.max(np.abs(traj.qd[-1] - ref.qd[-1])) < 1e-8
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert sign_changes(traj.q[:, 0]) >= 4 and sign_changes(traj.q[:, 1]) >= 4
    changes = traj.diagnostics["chart_changes"]
    assert changes >= 8
    # the cached charts are reused: two kept coordinates, two branches each
    charts = [fs for listed in sim.solver.charts.cache.values() for fs in listed]
    assert len(charts) == 4 < changes
    assert sorted(fs.eom.independent for fs in charts) == [("x",), ("x",), ("y",), ("y",)]


def test_a_chart_is_never_used_off_its_branch():
    # the first chart is derived through the model's initial state, x = +0.6: a run from the
    # mirror state x = -0.6 (and an evaluation there) must change to the branch x = -sqrt(...)
    model = pendulum(("y",), x0=0.6, y0=-0.8, v0=1.0)
    mirror = {"x": -0.6, "y": -0.8, "x'": 0.8, "y'": -0.6}
    ref = simulate(model, form="lagrange1", t_end=1.0, initial=mirror)
    traj = simulate(model, form="lagrange2", t_end=1.0, initial=mirror)
    assert np.max(np.abs(traj.q[-1] - ref.q[-1])) < 1e-8
    kernel, params = kernel_of(model), parameter_vector(model)
    solver = ModeSolver(kernel, params, "lagrange2", model.independent)
    q, qd = np.array([-0.6, -0.8]), np.array([0.8, -0.6])
    first = solver.form_system(Mode())
    assert str(first.eom.extras_["chart"][0]) == "x - sqrt(l**2 - y**2)"
    sol = solver.solve(0.0, q, qd, Mode())
    expected = ModeSolver(kernel, params, "lagrange1").solve(0.0, q, qd, Mode()).qdd
    assert np.allclose(sol.qdd, expected, rtol=1e-12, atol=1e-12)
    assert solver.charts.changes == 1


@pytest.mark.parametrize("make", [double_pendulum, pendulum])
def test_compare_forms_evaluates_lagrange2_on_every_branch(make):
    report = compare_forms(make(), forms=["lagrange2"], count=20, spread=1.0)
    assert report.states == 20
    assert report.off_chart == {}
    assert report.worst() < 1e-10, report


@pytest.mark.parametrize("name", ["appell-ladder", "painleve-rod"])
def test_hybrid_motion_with_unilateral_constraints_and_contacts_is_unchanged(name):
    model = gallery.load(name)
    ref = simulate(model, form="lagrange1")
    times = np.linspace(model.t0, ref.t[-1], 41)
    ref = simulate(model, form="lagrange1", times=times)
    traj = simulate(model, form="lagrange2", times=times)
    assert [e["type"] for e in traj.events] == [e["type"] for e in ref.events]
    assert np.allclose([e["t"] for e in traj.events], [e["t"] for e in ref.events], atol=1e-9)
    assert np.max(np.abs(traj.q - ref.q)) < 1e-9
    assert traj.diagnostics["chart_changes"] == 0


def folded_curve():
    """A bead on x + sin(x) = k sin(y): Lagrange II keeps x (y = asin(...)), singular where
    y = pi/2; there the bead goes on with x turning back, and the chart keeping y does not
    exist (x + sin(x) = u has no closed-form solution)."""
    return Model(name="bead on a folded curve", coordinates=["x", "y"], parameters={"k": 2.0},
                 kinetic="(x'^2 + y'^2)/2",
                 constraints=[Constraint.holonomic("curve", "x + sin(x) - k*sin(y)")],
                 initial={"x": 0.0, "y": 0.0, "x'": 1.0, "y'": 1.0})


def test_a_singular_chart_without_alternative_is_named():
    model = folded_curve()
    ref = simulate(model, form="lagrange1", t_end=3.0)
    assert ref.q[-1, 1] > 3.0  # Lagrange I goes through y = pi/2
    with pytest.raises(FormNotApplicable) as info:
        simulate(model, form="lagrange2", t_end=3.0)
    text = str(info.value)
    for part in ["singular", "eliminates y by y = asin((x + sin(x))/k)", "'curve'",
                 "no component along y", "x = 1.106", "keeping y", "no closed-form solution",
                 "--form lagrange1 or --form maggi"]:
        assert part in text, text


def test_explain_names_the_chart_when_the_integration_stalls():
    # the reason the simulation gives when the step size collapses on a singular chart
    model = folded_curve()
    ref = simulate(model, form="lagrange1", t_end=3.0)
    sim = Simulation(model, form="lagrange2")
    solver = sim.solver
    fold = int(np.argmin(np.abs(ref.q[:, 1] - np.pi / 2)))
    for i in range(fold - 20, fold):  # as the simulation approaches: the chart keeping y is refused
        solver.accelerations(ref.t[i], ref.q[i], ref.qd[i], Mode())
        solver.charts.settle(Mode(), ref.t[i], ref.q[i], ref.qd[i])
    reason = solver.charts.explain(Mode(), ref.t[fold], ref.q[fold], ref.qd[fold])
    assert "eliminates y by y = asin((x + sin(x))/k)" in reason and "keeping y" in reason
    message = str(IntegrationFailed(ref.t[fold], "free", reason))
    assert "Fix: use --form lagrange1 or --form maggi" in message
    # far from the fold the chart is not the cause of a failure
    assert solver.charts.explain(Mode(), 0.0, np.zeros(2), np.ones(2)) is None
