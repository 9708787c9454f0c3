"""The heavy symmetric top (Lagrange's top; Goldstein, Classical Mechanics, sec. 5.7) written
with a frame and a point, in Euler angles and in Euler parameters: closed-form kinetic
energy, conserved energy and cyclic momenta, the steady precession rate of Goldstein (5.76),
and the motion in Euler parameters through the gimbal lock of the Euler angles."""

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.gallery import heavy_symmetric_top as hst
from nonideal.gallery import heavy_top_euler_parameters as hep


@pytest.fixture(scope="module")
def top():
    return gallery.load(hst.NAME)


def test_invariants_along_a_nutating_motion(top):
    traj = simulate(top, t_end=2.0, times=np.linspace(0, 2, 41))
    inv = hst.invariants(top.parameter_values, traj.coordinate("theta"), traj.velocity("psi"),
                         traj.velocity("theta"), traj.velocity("phi"))
    for key in ("E", "p_psi", "p_phi"):
        assert np.max(np.abs(inv[key] - inv[key][0])) < 1e-10 * abs(inv[key][0]), key
    assert np.ptp(traj.coordinate("theta")) > 0.01      # it does nutate


@pytest.mark.parametrize("theta0, w3", [(0.6, 60.0), (1.2, 40.0)])
def test_steady_precession_rate(top, theta0, w3):
    p = top.parameter_values
    Omega = hst.precession_rate(p, theta0, w3)
    A_O = p["A"] + p["m"] * p["l"] ** 2       # the root of Goldstein (5.76)
    assert A_O * Omega**2 * np.cos(theta0) - p["C"] * w3 * Omega + p["m"] * p["g"] * p["l"] == pytest.approx(0, abs=1e-12)
    steady = top.replace(initial={"psi": 0.0, "theta": theta0, "phi": 0.0, "psi'": Omega,
                                  "theta'": 0.0, "phi'": w3 - Omega * np.cos(theta0)})
    traj = simulate(steady, t_end=1.0, times=np.linspace(0, 1, 11))
    assert np.max(np.abs(traj.coordinate("theta") - theta0)) < 1e-9
    assert np.max(np.abs(traj.velocity("psi") - Omega)) < 1e-8 * Omega
    # a slightly different rate nutates: the check can fail
    off = top.replace(initial={**steady.initial, "psi'": 1.1 * Omega})
    assert np.max(np.abs(simulate(off, t_end=1.0, times=np.linspace(0, 1, 11)).coordinate("theta") - theta0)) > 1e-4


def test_euler_parameters_through_the_gimbal_lock():
    result = hep.run(verbose=False)
    assert result["theta_min"] == 0.0 and result["lock_passages"] >= 3
    assert result["unit_norm_error"] < 1e-8
    assert max(result["invariant_drift"].values()) < 1e-8
    assert result["axis_vs_euler_angles"] < 1e-8 and result["rate_vs_euler_angles"] < 1e-8


def test_euler_parameters_far_from_unit_norm_are_refused():
    from nonideal.errors import ModelError

    model = gallery.load(hep.NAME)
    with pytest.raises(ModelError) as info:
        model.replace(initial={**model.initial, "e0": 2.0})
    msg = str(info.value)
    assert "norm 2" in msg and "e0 = 1" in msg


def test_no_constraint_and_radial_rates_projected():
    """|e| is kept with no constraint; given rates with a radial part are projected on the
    sphere (e . e' = 0), a missing one is completed from it."""
    model = gallery.load(hep.NAME)
    assert model.constraints == ()
    m = model.replace(initial={**model.initial, "e0'": 0.4})
    assert float(m.initial["e0'"]) == 0.0 and float(m.initial["e3'"]) == 5.0
    start = {k: v for k, v in model.initial.items() if k != "e0'"}
    tilted = model.replace(initial={**start, "e0": 0.6, "e1": 0.8, "e1'": 0.3})
    e = np.array([float(tilted.initial[f"e{i}"]) for i in range(4)])
    ed = np.array([float(tilted.initial[f"e{i}'"]) for i in range(4)])
    assert abs(e @ ed) < 1e-15 and ed[1] == 0.3


def test_euler_parameters_written_with_few_decimals_are_normalized():
    model = gallery.load(hep.NAME)
    m = model.replace(initial={**model.initial, "e0": 0.7071, "e1": 0.7071, "e1'": 0.0})
    e = [float(m.initial[f"e{i}"]) for i in range(4)]
    assert abs(np.linalg.norm(e) - 1) < 1e-15 and e[0] == pytest.approx(np.sqrt(0.5), rel=1e-15)


def test_off_the_unit_sphere_the_motion_is_that_of_e_over_its_norm():
    """The frame turns by the rotation of e/|e|: at a state with |e| = 1.7 and a radial rate,
    Lagrange I gives (e . e')' = 0 along e, and the tangential accelerations of the state
    scaled to the unit sphere (e -> e/|e|, e' -> tangent part / |e|), scaled back -- the
    same rotation and angular velocity; the body angular acceleration agrees."""
    from nonideal.modes.solver import ModeSolver
    from nonideal.modes.types import Mode
    from nonideal.numeric.kernel import kernel_of, parameter_vector

    model = gallery.load(hep.NAME)
    solver = ModeSolver(kernel_of(model), parameter_vector(model), "lagrange1")

    def accelerations(x, xd):
        return solver.solve(0.0, x, xd, Mode()).qdd

    rng = np.random.default_rng(3)
    e = rng.standard_normal(4)
    e *= 1.7 / np.linalg.norm(e)
    ed = rng.standard_normal(4)                      # with a radial part
    edd = accelerations(e, ed)
    assert e @ edd + ed @ ed == pytest.approx(0, abs=1e-12)   # (e . e')' = 0

    k = np.linalg.norm(e)
    u, ud = e / k, (ed - e * (e @ ed) / k**2) / k     # the same rotation and angular velocity
    np.testing.assert_allclose(hep.body_rate(u, ud), 2 * _rate(e, ed) / k**2, rtol=1e-12)
    udd = accelerations(u, ud)
    # body angular acceleration 2 G(u) u'' (G(u) u' = 0 on the sphere's tangent) against the
    # derivative of 2 G(e) e'/|e|^2 along (e', e'')
    h = 1e-6
    def w(x, xd):
        return 2 * _rate(x, xd) / (x @ x)
    wdot = (w(e + h * ed, ed + h * edd) - w(e - h * ed, ed - h * edd)) / (2 * h)
    np.testing.assert_allclose(2 * _rate(u, udd), wdot, rtol=1e-7, atol=1e-7)


def _rate(e, ed):
    """``G(e) e'``: e0 e' - e0' e - e x e' (vector part), the body rate of unit parameters / 2."""
    return e[0] * ed[1:] - ed[0] * e[1:] - np.cross(e[1:], ed[1:])
