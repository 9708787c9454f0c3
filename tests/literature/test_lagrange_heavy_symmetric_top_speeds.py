"""The heavy symmetric top in body speeds (Kane & Levinson 1985, ch. 6): with Euler parameters
and with Euler angles the quasi-velocity forms print Euler's equations with the gravity torque;
energy and the two momenta are conserved; Euler parameters and Euler angles give one motion."""

import numpy as np
import pytest

from nonideal import derive, gallery, simulate
from nonideal.gallery.heavy_symmetric_top_speeds import euler_angles

EULER = ["(A + l**2*m)*w1' + (-A + C - l**2*m)*w2*w3 = {m1}",
         "(A + l**2*m)*w2' + (A - C + l**2*m)*w1*w3 = {m2}",
         "C*w3' = 0"]


@pytest.fixture(scope="module")
def model():
    return gallery.load("heavy-symmetric-top-speeds")


@pytest.mark.parametrize("form", ["kane", "boltzmann_hamel", "poincare_chetaev", "appell"])
def test_eulers_equations_in_euler_parameters(model, form):
    eom = derive(model, form)
    assert eom.unknowns == ("w1'", "w2'", "w3'")
    assert eom.readable() == [EULER[0].format(m1="2*g*l*m*(e0*e1 + e2*e3)"),
                              EULER[1].format(m2="2*g*l*m*(e0*e2 - e1*e3)"), EULER[2]]


def test_eulers_equations_in_euler_angles():
    eom = derive(euler_angles(), "kane")
    assert eom.readable() == [EULER[0].format(m1="g*l*m*sin(theta)*cos(phi)"),
                              EULER[1].format(m2="-g*l*m*sin(theta)*sin(phi)"), EULER[2]]


def test_invariants_and_same_motion_as_euler_angles(model):
    times = np.linspace(0.0, 2.0, 21)
    tq = simulate(model, times=times, form="kane")
    te = simulate(euler_angles(), times=times)
    for k in ("E", "H_vertical", "H_axis"):
        scale = 1.0 + abs(tq.outputs[k][0])
        assert np.ptp(tq.outputs[k]) < 1e-9 * scale, k
    assert np.max(np.abs(tq.outputs["nutation"] - te.outputs["nutation"])) < 1e-8
    for k in ("w1", "w2", "w3"):
        assert np.max(np.abs(tq.speeds[k] - te.speeds[k])) < 1e-7
    # the spin about the symmetry axis: C w3 = H_axis, constant
    assert np.allclose(tq.outputs["H_axis"], 0.03 * tq.speeds["w3"], rtol=1e-10)


def test_run_is_ok():
    assert gallery.run("heavy-symmetric-top-speeds", verbose=False)["ok"]


def test_a_vector_output_gives_its_components_in_N():
    from nonideal import evaluate
    from nonideal.gallery.heavy_symmetric_top_speeds import build

    m = build().replace(outputs={"H": "angular_momentum(top, O)", "Hz": "dot(angular_momentum(top, O), N.z)"})
    assert list(m.outputs) == ["H.x", "H.y", "H.z", "Hz"]
    out = evaluate(m).outputs
    assert out["H.z"] == pytest.approx(out["Hz"], rel=1e-14)
    # tilted by th0 about N.x, spinning w3 about B.z and w2 about B.y: H_O = J_O omega in B, turned
    th0, A, C, m_, l = 0.5, 0.02, 0.03, 1.0, 0.1
    hb = np.array([0.0, (A + m_ * l * l) * 2.0, C * 40.0])
    R = np.array([[1, 0, 0], [0, np.cos(th0), -np.sin(th0)], [0, np.sin(th0), np.cos(th0)]])
    assert [out["H.x"], out["H.y"], out["H.z"]] == pytest.approx(list(R @ hb), abs=1e-12)


def test_no_constraint_the_radial_rate_completes_the_speeds(model):
    """No constraint is added for the Euler parameters: the three angular speeds determine
    the four rates with e . e' = 0 (the initial rates from the speeds are tangent), and the
    quasi-velocity forms hold the radial rate at zero themselves (their note says so)."""
    assert model.constraints == ()
    eom = derive(model, "kane")
    assert any("radial rate of frame B" in n for n in eom.notes)
    from nonideal import evaluate

    ev = evaluate(model)
    e = np.array([ev.q[i] for i in range(4)])
    ed = np.array([ev.qd[i] for i in range(4)])
    assert abs(e @ ed) < 1e-14 and np.linalg.norm(ed) > 1.0
    # the speeds given at t0 are the body components of the angular velocity of e'
    w = 2 * (e[0] * ed[1:] - ed[0] * e[1:] - np.cross(e[1:], ed[1:]))
    np.testing.assert_allclose(w, [0.0, 2.0, 40.0], atol=1e-12)
    # the speeds are blind to the radial rate: a fourth angular speed is dependent, it
    # cannot stand for e . e'
    from nonideal.errors import ModelError

    with pytest.raises(ModelError, match="w1, w2, w3, w4 are linearly dependent"):
        model.replace(speeds={"w1": "dot(omega(B), B.x)", "w2": "dot(omega(B), B.y)",
                              "w3": "dot(omega(B), B.z)", "w4": "dot(omega(B), N.z)"})
