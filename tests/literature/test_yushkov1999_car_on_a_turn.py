"""Car on a turn (Yushkov 1999, appendix B; model built from mechanics): the kinematic car,
the lateral forces and axle loads it needs (Newton-Euler with load transfer), the skid
onset, oversteer vs understeer, the motion after the skid, all forms, the CLI."""

import json

import numpy as np
import pytest

from nonideal.errors import FormNotApplicable

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.equations.formalisms import FORMS
from nonideal.gallery.car_on_a_turn import (
    RAMP,
    both_sliding,
    circumradius,
    constant_steering_forces,
    drive_crossover,
    first_to_skid,
    onset_speed,
    rear_axle,
    rear_speed,
    skid_onset,
    steering,
    sticking_motion,
)
from nonideal.modes.types import ContactState, Mode
from nonideal.modes.solver import ModeSolver
from nonideal.numeric.kernel import kernel_of, parameter_vector
from nonideal.analysis.contact.realizability import realizability_along
from tests.helpers import run_cli as _cli

FORCE_TIMES = [0.2, 0.5, 1.0, 2.0, 4.0, 6.5]
T_SKID = 6.909262516906938        # rear axle reaches mu_s N (formula, digits of run())
T_SKID_UNDER = 2.1607801737918715  # F0 = 1500 N: the front axle first


@pytest.fixture(scope="module")
def model():
    return gallery.load("car-on-a-turn")


@pytest.fixture(scope="module")
def p(model):
    return model.parameter_values


@pytest.fixture(scope="module")
def traj(model):
    times = np.union1d(np.linspace(0.0, 14.0, 281), FORCE_TIMES)
    return simulate(model, times=times)


def _mg(p):
    return p["m"] * p["g"]


# ----------------------------------------------------------------------------- model


def test_rear_axle_follows_the_circle_L_over_tan_delta(model, p, traj):
    L = p["a"] + p["b"]
    R = L / np.tan(p["delta0"])
    assert R == pytest.approx(17.2031379145, abs=1e-9)
    sel = (traj.t >= RAMP * p["tau"]) & (traj.t < T_SKID - 0.01)
    P = rear_axle(traj, p)[sel]
    assert len(P) > 90
    # circle through first, middle, last point; every other point on it
    idx = [0, len(P) // 2, len(P) - 1]
    radius = circumradius(P[idx])
    assert abs(radius - R) / R < 1e-8
    # centre: rear axle point + R * left normal
    psi = traj.coordinate("psi")[sel]
    centres = P + R * np.column_stack((-np.sin(psi), np.cos(psi)))
    assert np.max(np.abs(centres - centres[0])) / R < 1e-8
    assert np.max(np.abs(np.linalg.norm(P - centres[0], axis=1) - R)) / R < 1e-8
    # centre of mass: radius sqrt(R^2 + b^2)
    G = np.column_stack((traj.coordinate("x")[sel], traj.coordinate("y")[sel]))
    assert np.max(np.abs(np.linalg.norm(G - centres[0], axis=1) - np.hypot(R, p["b"]))) / R < 1e-8
    # contacts closed: z = h, theta = 0
    assert np.max(np.abs(traj.coordinate("z") - p["h"])) < 1e-10
    assert np.max(np.abs(traj.coordinate("theta"))) < 1e-10


def test_curvature_follows_the_steering_during_the_ramp(p, traj):
    sel = traj.t < T_SKID - 0.01
    d, _ = steering(traj.t[sel], p)
    curvature = traj.velocity("psi")[sel] / rear_speed(traj)[sel]
    assert np.max(np.abs(curvature - np.tan(d) / (p["a"] + p["b"]))) < 1e-10


# ----------------------------------------------------------------------------- (2) forces, onset


def test_speed_closed_form(p, traj):
    """d/dt (sqrt(M_e) V) = F0 / sqrt(M_e); after the ramp V' = F0 / M_e."""
    sel = np.flatnonzero(traj.t < T_SKID - 0.01)
    V = rear_speed(traj)
    for i in sel[::20]:
        assert V[i] == pytest.approx(sticking_motion(traj.t[i], p)["V"], rel=1e-10)
    k = np.tan(p["delta0"]) / (p["a"] + p["b"])
    A = p["F0"] / (p["m"] + k * k * (p["Izz"] + p["m"] * p["b"] ** 2))
    assert A == pytest.approx(0.32929798185, abs=1e-10)
    i = np.flatnonzero((traj.t > 3.0) & (traj.t < 6.5))
    c, s = np.cos(traj.q[i, 3]), np.sin(traj.q[i, 3])
    Vdot = (traj.qdd[i, 0] * c + traj.qdd[i, 1] * s
            + traj.qd[i, 3] * (-traj.qd[i, 0] * s + traj.qd[i, 1] * c))
    assert np.max(np.abs(Vdot - A)) < 1e-9


def test_lateral_forces_and_axle_loads_match_newton_euler(p, traj):
    mg = _mg(p)
    for s in FORCE_TIMES:
        i = int(np.flatnonzero(np.isclose(traj.t, s, atol=1e-14))[0])
        f = sticking_motion(s, p)
        assert abs(traj.contacts["rear"]["friction"][i][0] - f["Fr"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["friction"][i][0] - f["Ff"]) / mg < 1e-8
        assert abs(traj.contacts["rear"]["normal"][i] - f["Nr"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["normal"][i] - f["Nf"]) / mg < 1e-8
    # at t = 4 s (constant steering) the closed form of the constant-delta case, numbers
    f = sticking_motion(4.0, p)
    c = constant_steering_forces(f["V"], p)
    for key in ("Fr", "Ff", "Nr", "Nf"):
        assert c[key] == pytest.approx(f[key], rel=1e-12)
    # load transfer: rear gains m h a_x / L over the static m g a / L
    static_r = p["m"] * p["g"] * p["a"] / (p["a"] + p["b"])
    assert f["Nr"] - static_r == pytest.approx(p["m"] * p["h"] * f["ax"] / (p["a"] + p["b"]), rel=1e-12)
    assert f["ax"] < 0   # the centripetal component -b k^2 V^2 outweighs the drive
    assert (f["V"], f["Fr"], f["Ff"], f["Nr"], f["Nf"]) == pytest.approx(
        (11.257169652, 5099.909244, 6057.795253, 6705.809198, 8009.190802), abs=1e-6)


def test_skid_onset_time(model, p, traj):
    on = skid_onset(p)
    assert on["rear"]["root"] == pytest.approx(T_SKID, rel=1e-12)
    assert on["rear"]["quadratic"] == pytest.approx(T_SKID, rel=1e-12)
    assert on["front"]["root"] > on["rear"]["root"] + 0.2      # the rear first (oversteer)
    V_on = onset_speed(p)["rear"]
    assert sticking_motion(T_SKID, p)["V"] == pytest.approx(V_on, rel=1e-12)
    first = traj.events[0]
    assert (first["type"], first["contact"]) == ("slip", "rear")
    assert abs(first["t"] - T_SKID) / T_SKID < 1e-8
    # the needed friction at the onset is mu_s N
    f = sticking_motion(first["t"], p)
    assert abs(f["Fr"]) == pytest.approx(p["mu_s"] * f["Nr"], rel=1e-8)
    along = realizability_along(model, t_end=10.0).along
    assert along["contact"] == "rear"
    assert abs(along["lost_at"] - T_SKID) / T_SKID < 1e-8


# ----------------------------------------------------------------------------- (3) after the skid


def test_mode_timeline_after_the_skid(traj):
    kinds = [(e["type"], e["contact"]) for e in traj.events]
    assert kinds == [("slip", "rear"), ("slip", "front"), ("stick", "front"), ("stick", "rear")]
    times = [e["t"] for e in traj.events]
    assert times == pytest.approx([6.909262517, 7.096766231, 11.895425662, 12.350237899], abs=1e-6)
    assert traj.events[1]["mode"] == "rear:slide-, front:slide-"
    assert traj.contacts["rear"]["mode"][0] == "stick"
    assert traj.contacts["rear"]["mode"][-1] == "stick"


def test_energy_friction_work_and_residuals(traj):
    assert traj.diagnostics["energy_balance_relative"] < 1e-8
    assert traj.diagnostics["constraint_residual_max"] <= 1e-8
    fw = traj.energy["friction_work"]
    assert np.all(np.diff(fw) <= 1e-9 * abs(fw[-1]))
    assert np.max(np.abs(fw[traj.t < T_SKID])) < 1e-6      # sticking friction does no work
    assert fw[-1] == pytest.approx(-113642.36, abs=0.05)


def test_kinetic_energy_is_effective_mass_times_V2_over_2(p, traj):
    """Sticking with constant steering: T = M_e V^2 / 2, M_e = m + k^2 (Izz + m b^2)."""
    k = np.tan(p["delta0"]) / (p["a"] + p["b"])
    Me = p["m"] + k * k * (p["Izz"] + p["m"] * p["b"] ** 2)
    sel = (traj.t > RAMP * p["tau"]) & (traj.t < T_SKID)
    V = rear_speed(traj)[sel]
    assert np.max(np.abs(traj.energy["kinetic"][sel] / (0.5 * Me * V * V) - 1)) < 1e-10
    # and it grows by the work of the drive only (the sticking contacts do no work)
    dT = traj.energy["kinetic"][sel] - traj.energy["kinetic"][0]
    assert np.max(np.abs(dT - traj.energy["active_work"][sel])) / traj.energy["kinetic"][0] < 1e-9


def test_both_axles_sliding_closed_form(p, traj):
    s = both_sliding(p)
    both = [i for i, md in enumerate(traj.modes) if md == "rear:slide-, front:slide-"]
    assert len(both) > 50
    mg = _mg(p)
    for i in both:
        assert abs(traj.contacts["rear"]["normal"][i] - s["Nr"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["normal"][i] - s["Nf"]) / mg < 1e-8
        assert abs(traj.contacts["rear"]["friction"][i][0] - s["Fr"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["friction"][i][0] - s["Ff"]) / mg < 1e-8
        assert abs(traj.qdd[i, 3] - s["psidd"]) < 1e-8
    assert (s["Nr"], s["Nf"], s["psidd"]) == pytest.approx((6668.375418, 8046.624582, 0.076247283),
                                                           abs=1e-6)


def test_kinematic_car_again_after_the_regrip(p, traj):
    sel = np.flatnonzero(traj.t > traj.events[-1]["t"] + 1e-6)
    assert len(sel) > 20
    V = rear_speed(traj)
    assert V[sel[0]] == pytest.approx(5.9647, abs=1e-3)      # 12.21 m/s before the skid
    # V' = A again (kinematic car, constant steering)
    A = constant_steering_forces(V[sel[0]], p)["A"]
    assert np.max(np.abs(np.diff(V[sel]) / np.diff(traj.t[sel]) - A)) < 1e-8
    R = (p["a"] + p["b"]) / np.tan(p["delta0"])
    mg = _mg(p)
    for i in sel[::5]:
        assert traj.velocity("psi")[i] * R == pytest.approx(V[i], rel=1e-9)
        c = constant_steering_forces(V[i], p)
        assert abs(traj.contacts["rear"]["friction"][i][0] - c["Fr"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["friction"][i][0] - c["Ff"]) / mg < 1e-8
        assert abs(traj.contacts["front"]["normal"][i] - c["Nf"]) / mg < 1e-8


# ----------------------------------------------------------------------------- (4) over/understeer


def test_hard_drive_makes_the_front_skid_first(model, p):
    axle, t_on = first_to_skid(dict(p, F0=1500.0))
    assert axle == "front"
    assert t_on == pytest.approx(T_SKID_UNDER, rel=1e-12)
    tr = simulate(model, parameters={"F0": 1500.0}, t_end=4.0, stop_on={"slip"})
    ev = tr.events[0]
    assert (ev["type"], ev["contact"]) == ("slip", "front")
    assert abs(ev["t"] - T_SKID_UNDER) / T_SKID_UNDER < 1e-8


def test_crossover_drive_force(model, p):
    F_star = drive_crossover(p)
    assert F_star == pytest.approx(736.9274, abs=1e-3)
    for F, axle in ((0.9 * F_star, "rear"), (1.1 * F_star, "front")):
        assert first_to_skid(dict(p, F0=F))[0] == axle
        tr = simulate(model, parameters={"F0": F}, t_end=12.0, stop_on={"slip"})
        assert tr.events[0]["contact"] == axle
        assert tr.events[0]["t"] == pytest.approx(first_to_skid(dict(p, F0=F))[1], rel=1e-8)
    # more load transfer (higher centre of mass, centre of mass ahead) -> more oversteer
    assert drive_crossover(dict(p, h=0.7)) == pytest.approx(800.13, abs=0.01)
    assert drive_crossover(dict(p, a=1.0, b=1.6)) == pytest.approx(873.11, abs=0.01)


def test_gentle_drive_criterion_tan_half_delta_vs_mu_h_over_a(p):
    """As A -> 0 the rear skids first iff tan(delta0/2) < mu_s h / a (onset speeds compared)."""
    h_star = np.tan(p["delta0"] / 2) * p["a"] / p["mu_s"]
    for h, first in ((h_star * 1.01, "rear"), (h_star * 0.99, "front")):
        v = onset_speed(dict(p, F0=1e-6, h=h))
        assert min(v, key=v.get) == first
    for a in (1.0, 1.6):
        h_star = np.tan(p["delta0"] / 2) * a / p["mu_s"]
        v = onset_speed(dict(p, F0=1e-6, a=a, h=h_star * 1.01))
        assert v["rear"] < v["front"]


# ----------------------------------------------------------------------------- (5) forms


def _sticking_states(model, count=12, seed=1):
    """Admissible sticking states: contacts closed, both lateral slips zero, t in the ramp."""
    kernel = kernel_of(model)
    params = parameter_vector(model)
    solver = ModeSolver(kernel, params)
    rng = np.random.default_rng(seed)
    h = model.parameter_values["h"]
    out = []
    for _ in range(count):
        t = rng.uniform(0.0, 2.5)
        q = np.array([rng.normal(), rng.normal(), h, rng.uniform(-np.pi, np.pi), 0.0])
        qd = rng.normal(size=5) * np.array([8.0, 8.0, 1.0, 1.0, 1.0])
        cout = solver.ck(solver.input(t, q, qd))
        C = np.vstack([cout["Gn"], cout["W"]])
        qd = qd - np.linalg.pinv(C) @ (C @ qd)
        out.append((t, q, qd))
    return out


def test_all_forms_agree_sliding(model):
    report = compare_forms(model, contact_state="slide")
    assert set(report.accelerations) == set(FORMS) - {"lagrange1"} | {"gauss"}
    assert report.worst() < 1e-10, report


def test_all_forms_agree_sticking(model):
    # compare_forms samples states with U != 0 (it closes only the gaps); Shulgin's form
    # substitutes the dependent velocities and is defined on the sticking manifold only, so
    # it is compared there (below)
    # (so are Voronets' and Chaplygin's, which substitute them too; the car sticking is no
    # Chaplygin system: its rolling coefficients depend on the heading psi eliminated)
    substituting = {"shulgin", "voronets", "chaplygin"}
    report = compare_forms(model, contact_state="stick", forms=[f for f in FORMS if f not in substituting] + ["gauss"])
    assert report.worst() < 1e-10, report
    kernel, params = kernel_of(model), parameter_vector(model)
    mode = Mode(frozenset(), (("rear", ContactState("stick")), ("front", ContactState("stick"))))
    ref = ModeSolver(kernel, params, "lagrange1")
    solvers = {f: ModeSolver(kernel, params, f) for f in list(FORMS) + ["gauss"] if f not in ("lagrange1", "chaplygin")}
    with pytest.raises(FormNotApplicable, match="coordinate 'psi'"):
        ModeSolver(kernel, params, "chaplygin").solve(*_sticking_states(model)[0], mode)
    for t, q, qd in _sticking_states(model):
        r = ref.solve(t, q, qd, mode)
        for f, s in solvers.items():
            sol = s.solve(t, q, qd, mode)
            assert np.max(np.abs(sol.qdd - r.qdd)) / np.max(np.abs(r.qdd)) < 1e-10, f
            for c in ("rear", "front"):
                assert abs(sol.contacts[c].N - r.contacts[c].N) / 1.5e4 < 1e-10, f
                assert abs(sol.contacts[c].F[0] - r.contacts[c].F[0]) / 1.5e4 < 1e-10, f


# ----------------------------------------------------------------------------- (6) CLI


def test_cli_simulate_json_and_plot(tmp_path):
    path = gallery.model_path("car-on-a-turn")
    proc = _cli("simulate", path, "--t-end", "8", "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert set(out["contacts"]) == {"rear", "front"}
    assert {"normal", "friction", "slip", "mode"} <= set(out["contacts"]["rear"])
    assert out["modes"][0] == "rear:stick, front:stick"
    assert [(e["type"], e["contact"]) for e in out["events"]] == [("slip", "rear"), ("slip", "front")]
    assert out["events"][0]["t"] == pytest.approx(T_SKID, rel=1e-8)
    proc = _cli("simulate", path, "--plot", "car.png", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    png = (tmp_path / "car.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
