"""A ball rolling ideally (mu = inf) off a fixed sphere (classical; closed form derived in
nonideal/gallery/ball_off_sphere.py): lift-off where N = 0 at cos = (10 cos theta0 + 7 rho w0^2/g)/17,
the time against the quadrature, N and F while rolling, free flight after it; the same with a
finite mu = 1e9 through the CLI (it stopped with exit 3, "Painleve indeterminacy", at the very
instant of lift-off)."""

import json

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.gallery.ball_off_sphere import build, check, closed_form
from tests.helpers import run_cli

G = 9.81


def test_closed_form_lift_off():
    p = build().parameter_values
    cf = closed_form(p)
    assert cf["cos_theta"] == pytest.approx(10 * np.cos(0.1) / 17, rel=1e-15)
    # from (nearly) the top: 10/17, not the sliding particle's 2/3
    assert closed_form(dict(p, theta0=1e-6))["cos_theta"] == pytest.approx(10 / 17, rel=1e-11)
    # with a launch rate w0: energy 7/10 m rho^2 theta'^2 and N = 0 (rho = 1.25)
    launched = closed_form(dict(p, theta0=0.05, w0=1.0))
    assert launched["cos_theta"] == pytest.approx((10 * np.cos(0.05) + 7 * 1.25 / G) / 17, rel=1e-15)
    # lift-off state: rolling (U = 0) and N = 0: g cos = rho theta'^2
    assert G * cf["cos_theta"] == pytest.approx(1.25 * cf["theta_rate"] ** 2, rel=1e-12)
    x, y, _ = cf["q"]
    xd, yd, phid = cf["qd"]
    assert (x * yd - y * xd) / np.hypot(x, y) - 0.25 * phid == pytest.approx(0, abs=1e-12)


def test_time_quadrature_against_an_independent_integration():
    """The lift-off time of the quadrature against theta'' = 5/7 g sin(theta)/rho integrated
    as an ODE (scipy) up to cos(theta) = 10 cos(theta0)/17."""
    from scipy.integrate import solve_ivp

    cf = closed_form(build().parameter_values)
    stop = lambda t, s: s[0] - cf["theta"]  # noqa: E731
    stop.terminal = True
    sol = solve_ivp(lambda t, s: [s[1], 5 / 7 * G * np.sin(s[0]) / 1.25], (0, 5), [0.1, 0.0],
                    events=stop, rtol=1e-12, atol=1e-14)
    assert sol.t_events[0][0] == pytest.approx(cf["t"], rel=1e-9)


@pytest.mark.parametrize("params, theta_tol", [
    ({}, 1e-8),                                   # the model file's case: from rest, theta0 = 0.1
    ({"theta0": 0.05, "w0": 1.0}, 1e-8),          # launched
    ({"mu": 1e9}, 1e-6),                           # Coulomb with a huge (finite) coefficient
])
def test_lift_off_forces_and_free_flight(params, theta_tol):
    model = gallery.load("ball-off-sphere") if not params else build(**params)
    r = check(model)
    assert r["theta_error"] < theta_tol
    assert r["t_error"] < 1e-7
    assert r["lift_state_error"] < 1e-6
    assert r["normal_error"] < 1e-8 and r["friction_error"] < 1e-8
    assert [e[1:] for e in r["events"]] == [("lift-off", "sphere:separated")]
    assert r["flight_error"] < 1e-8 and r["min_gap_after"] > 0
    # the rolling reaction does no work: energy conserved, no friction work
    assert r["friction_work"] < 1e-8 and abs(r["energy_balance_relative"]) < 1e-8


def test_rolling_mode_has_no_slip_event_and_friction_grows_past_any_bound():
    """While rolling |F|/N grows without bound as N -> 0 (any finite mu would slip)."""
    model = gallery.load("ball-off-sphere")
    cf = closed_form(model.parameter_values)
    tr = simulate(model, times=np.linspace(0, cf["t"] * (1 - 1e-6), 30))
    ct = tr.contacts["sphere"]
    ratio = np.abs(np.array(ct["friction"])[:, 0]) / np.array(ct["normal"])
    assert set(ct["mode"]) == {"stick"} and not tr.events
    assert ratio[-1] > 1e4 and np.all(np.diff(ratio) > 0)


def test_cli_huge_mu_lifts_off_instead_of_a_paradox(tmp_path):
    text = gallery.model_path("ball-off-sphere").read_text(encoding="utf-8")
    assert 'mu = "inf"' in text
    path = tmp_path / "ball_mu1e9.toml"
    path.write_text(text.replace('mu = "inf"', "mu = 1e9"), encoding="utf-8")
    out = run_cli("simulate", path, "--json")
    assert out.returncode == 0, out.stderr   # was 3: "both [sphere:separated] and [sphere:slide-]"
    d = json.loads(out.stdout)
    assert [(e["type"], e["contact"]) for e in d["events"]] == [("lift-off", "sphere")]
    cf = closed_form(build().parameter_values)
    assert d["events"][0]["t"] == pytest.approx(cf["t"], abs=1e-7)
