"""The benchmark bicycle of Meijaard et al. (2007) written with frames and points
(``nonideal/gallery/benchmark_bicycle_frames.toml``): no hand-derived kinematics, the rolling
constraints written with ``vel``, ``cross`` and ``omega`` of the contact points.  Through the
library's stability analysis (``linearize(about="steady")``, the path of the hand-derived
file) it must give the eigenvalues of Table 2 and the weave and capsize speeds, and its
nonlinear roll/steer accelerations must be those of the hand-derived file."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.gallery import benchmark_bicycle as hand
from nonideal.gallery import benchmark_bicycle_frames as bf


@pytest.fixture(scope="module")
def model():
    return gallery.load(bf.NAME)


@pytest.mark.parametrize("v", sorted(bf.TABLE2))
def test_eigenvalues_of_table2(model, v):
    lin = bf.linearization(model, v)
    assert lin.ignorable == ("x", "y", "psi", "thetaR", "thetaF")
    ours = np.sort_complex(np.linalg.eigvals(bf.roll_steer_matrix(model, v)))
    published = np.sort_complex(np.array(bf.TABLE2[v]))
    assert np.max(np.abs(ours - published) / np.maximum(1.0, np.abs(published))) < 1e-10, (ours, published)
    assert (lin.verdict == "asymptotically stable") == (hand.WEAVE_SPEED < v < hand.CAPSIZE_SPEED)


def test_weave_and_capsize_speeds(model):
    vw, vc = bf.speeds(model)
    assert abs(vw - hand.WEAVE_SPEED) / hand.WEAVE_SPEED < 1e-10
    assert abs(vc - hand.CAPSIZE_SPEED) / hand.CAPSIZE_SPEED < 1e-10


def test_the_same_state_matrix_as_the_hand_derived_file(model):
    """The roll/steer state matrix equals the one of the published M, C1, K0, K2 (1e-9)."""
    pub = hand.published()
    for v in (0.0, 4.6, 10.0):
        np.testing.assert_allclose(bf.roll_steer_matrix(model, v), hand.state_matrix(pub, v),
                                   rtol=0, atol=1e-9)


def test_nonlinear_accelerations_equal_the_hand_derived_files(model):
    ours, theirs = bf.RollSteerFrames(model), hand.RollSteer(gallery.load(hand.NAME))
    for z in ((0.05, -0.1, 0.3, -0.5), (-0.2, 0.3, -1.0, 0.8), (0.3, -0.4, 0.5, 0.1)):
        a, b = ours(np.array(z), 4.6), theirs(np.array(z), 4.6)
        assert np.max(np.abs(a - b)) < 1e-10 * (1 + np.max(np.abs(b))), (z, a, b)


def test_upright_running_is_a_steady_motion(model):
    from nonideal import evaluate

    ev = evaluate(model).to_dict()
    assert max(abs(a) for a in ev["qddot"].values()) < 1e-12
    assert ev["qdot"]["y"] == pytest.approx(0.0, abs=1e-14)
    assert ev["qdot"]["thetaB"] == pytest.approx(0.0, abs=1e-14)
