"""The benchmark bicycle of Meijaard, Papadopoulos, Ruina & Schwab (2007), from its model file.

The Whipple bicycle (four rigid bodies, knife-edge wheels rolling on level ground) written
as bodies and constraints in ``nonideal/gallery/benchmark_bicycle.toml``; linearized about
upright straight running from the library's own accelerations, it must reproduce the paper's
matrices M, C1, K0, K2, the eigenvalues of its Table 2 at v = 0..10 m/s and the weave and
capsize speeds, to the published digits (14 decimals).
"""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.gallery import benchmark_bicycle as bb


@pytest.fixture(scope="module")
def model():
    return gallery.load(bb.NAME)


@pytest.fixture(scope="module")
def mats(model):
    return bb.linear_matrices(model)


@pytest.mark.parametrize("name", ["M", "C1", "K0", "K2"])
def test_linear_matrices_are_the_published_ones(mats, name):
    np.testing.assert_allclose(mats[name], bb.PUBLISHED_MATRICES[name], rtol=0, atol=1e-11)


@pytest.mark.parametrize("v", sorted(bb.TABLE2))
def test_eigenvalues_of_table2(mats, v):
    ours = np.sort_complex(bb.eigenvalues(mats, v))
    published = np.sort_complex(np.array(bb.TABLE2[v]))
    scale = np.maximum(1.0, np.abs(published))
    assert np.max(np.abs(ours - published) / scale) < 1e-11, (ours, published)


def test_weave_and_capsize_speeds(mats):
    vw, vc = bb.weave_speed(mats), bb.capsize_speed(mats)
    assert abs(vw - bb.WEAVE_SPEED) / bb.WEAVE_SPEED < 1e-11
    assert abs(vc - bb.CAPSIZE_SPEED) / bb.CAPSIZE_SPEED < 1e-11
    # at the weave speed the weave pair is on the imaginary axis at the published frequency
    pair = [s for s in bb.eigenvalues(mats, vw) if abs(s.imag) > 1.0]
    assert len(pair) == 2
    assert max(abs(s.real) for s in pair) < 1e-10
    assert abs(abs(pair[0].imag) - bb.WEAVE_FREQUENCY) < 1e-11
    # self-stable exactly between them
    for v, stable in ((vw - 0.01, False), (vw + 0.01, True), (vc - 0.01, True), (vc + 0.01, False)):
        assert (np.max(bb.eigenvalues(mats, v).real) < 0) == stable, v


def test_speed_formulas_on_the_published_matrices():
    """The Hurwitz-determinant and det K(v) roots give the paper's speeds from its own matrices
    (checks the two formulas independently of the model)."""
    pub = bb.published()
    assert abs(bb.weave_speed(pub) - bb.WEAVE_SPEED) < 1e-12
    assert abs(bb.capsize_speed(pub) - bb.CAPSIZE_SPEED) < 1e-12


def test_upright_running_is_a_steady_motion(model):
    """At the initial state (upright, straight, v = 4.6 m/s) every acceleration vanishes and
    the dependent velocities follow from the rolling constraints (x' = xF' = v)."""
    from nonideal import evaluate

    ev = evaluate(model).to_dict()
    assert max(abs(a) for a in ev["qddot"].values()) < 1e-12
    v = model.parameter_values["v"]
    assert ev["qdot"]["x"] == pytest.approx(v, rel=1e-14)
    assert ev["qdot"]["xF"] == pytest.approx(v, rel=1e-14)


def test_model_file_is_the_python_api_bicycle(model):
    """The file's steer-axis geometry against :func:`build`, which places the front frame's
    points from the reference configuration: same accelerations at leaning, steered states."""
    ours, api = bb.RollSteer(model), bb.RollSteer(bb.build())
    for z in ((0.05, -0.1, 0.3, -0.5), (-0.2, 0.3, -1.0, 0.8)):
        a, b = ours(np.array(z), 4.6), api(np.array(z), 4.6)
        assert np.max(np.abs(a - b)) < 1e-10 * (1 + np.max(np.abs(b))), (a, b)


@pytest.mark.slow
def test_nonlinear_motion_follows_the_linearization(model, mats):
    """A small roll-rate kick at v = 4.6 m/s (self-stable): the simulated roll and steer follow
    exp(A t) x0.  The bicycle is symmetric left-right (roll and steer change sign together),
    so the roll/steer equations have no quadratic terms: the difference is of third order in
    the kick, and halving the kick quarters the difference relative to it."""
    from nonideal import simulate

    times = np.linspace(0.0, 3.0, 7)
    rel = []
    for eps in (0.02, 0.01):
        traj = simulate(model.replace(initial={**model.initial, "phi'": eps}), t_end=3.0, times=times)
        got = np.column_stack([traj.coordinate("phi"), traj.coordinate("delta")])
        want = bb.linear_response(mats, 4.6, [0.0, 0.0, eps, 0.0], times)[:, :2]
        rel.append(np.max(np.abs(got - want)) / eps)
        assert traj.diagnostics["constraint_residual_max"] < 1e-10
    assert rel[1] < 1e-3
    assert 3.2 < rel[0] / rel[1] < 4.8      # third order: the relative error quarters


@pytest.mark.slow
def test_stability_analysis_of_upright_running(model, mats):
    """``linearize(model, about="steady")`` -- the library's stability analysis -- at upright
    running: roll and steer are the perturbation variables, the cyclic coordinates and the
    held wheel speed are named, A and B equal the differentiated accelerations' state matrix
    and [0; M^-1], the eigenvalues are those of Table 2, and the verdict is "asymptotically
    stable" exactly between the weave and capsize speeds."""
    Minv = np.linalg.inv(mats["M"])
    for v in (0, 3, 5, 6, 7, 10):
        lin = bb.linearization(model, v)
        assert lin.ignorable == ("x", "y", "psi", "thetaR", "thetaF")
        if v:
            assert lin.variables == ("phi", "delta", "phi'", "delta'")
            assert lin.family == ("thetaR'",)    # the rear wheel's rate: the speed v = -rR thetaR'
        i = [lin.variables.index(n) for n in ("phi", "delta", "phi'", "delta'")]
        A4 = lin.A[np.ix_(i, i)]
        np.testing.assert_allclose(A4, bb.state_matrix(mats, v), rtol=0, atol=1e-9)
        np.testing.assert_allclose(lin.B[i[2:]], Minv, rtol=0, atol=1e-11)
        ours = np.sort_complex(np.linalg.eigvals(A4))
        published = np.sort_complex(np.array(bb.TABLE2[v]))
        assert np.max(np.abs(ours - published) / np.maximum(1.0, np.abs(published))) < 1e-11
        stable = bb.WEAVE_SPEED < v < bb.CAPSIZE_SPEED
        assert (lin.verdict == "asymptotically stable") == stable, (v, lin.verdict)
