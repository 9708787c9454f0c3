"""Points: positions, velocities (two-point theorem) and accelerations (one-point theorem)
of declared points against ``sympy.physics.vector.Point`` at random states."""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

from nonideal import Model
from nonideal.errors import ModelError
from nonideal.modeling.points import Point

from .test_frames import _chain_model, _sympy_chain, ours, random_state, theirs

POINTS = [
    Point("P1", ["q1", "2", "q3*q2"], frame="A"),                 # moving in a moving frame
    Point("P2", ["l", "0", "q4"], frame="D", origin="P1"),
    Point("P3", ["0.3", "-l", "0.1"], frame="E", origin="P2"),    # fixed in E
    Point("P4", ["q5", "sin(q6)", "t"], origin="P3"),             # in N axes, time-dependent
    Point("P5", ["1", "2", "3"], frame="G", origin="P4"),
]


@pytest.fixture(scope="module")
def chain():
    model = _chain_model(POINTS)
    q, N, frames = _sympy_chain()
    O = me.Point("O")
    O.set_vel(N, 0)
    l = sp.Symbol("l")
    A, D, E, G = frames["A"], frames["D"], frames["E"], frames["G"]
    P1 = O.locatenew("P1", q["q1"] * A.x + 2 * A.y + q["q3"] * q["q2"] * A.z)
    P2 = P1.locatenew("P2", l * D.x + q["q4"] * D.z)
    P3 = P2.locatenew("P3", 0.3 * E.x - l * E.y + 0.1 * E.z)
    P4 = P3.locatenew("P4", q["q5"] * N.x + sp.sin(q["q6"]) * N.y + me.dynamicsymbols._t * N.z)
    P5 = P4.locatenew("P5", G.x + 2 * G.y + 3 * G.z)
    return model, q, N, O, dict(P1=P1, P2=P2, P3=P3, P4=P4, P5=P5)


@pytest.mark.parametrize("seed", [4])
def test_positions_velocities_accelerations_agree_with_sympy(chain, seed):
    model, q, N, O, points = chain
    kin = model.kinematics
    state = random_state(np.random.default_rng(seed))
    for name, P in points.items():
        for ours_v, theirs_v in ((kin.pos(name), P.pos_from(O)), (kin.vel(name), P.vel(N)),
                                 (kin.acc(name), P.acc(N))):
            a = np.array([ours(x, state) for x in ours_v])
            b = np.array([theirs(x, q, state) for x in theirs_v.to_matrix(N)])
            np.testing.assert_allclose(a, b, atol=1e-10, err_msg=name)


def test_point_from_loop_is_refused():
    with pytest.raises(ModelError) as info:
        Model("loop", coordinates=["a"], points=[Point("P", ["a", 0, 0], origin="Q"),
                                                 Point("Q", [0, 1, 0], origin="P")])
    msg = str(info.value)
    assert "P -> Q -> P" in msg and 'from = "O"' in msg


def test_unknown_frame_and_origin_suggest():
    with pytest.raises(ModelError) as info:
        Model("u", coordinates=["a"], points=[Point("Pivot", ["a", 0, 0]),
                                              Point("Q", [0, 1, 0], origin="Pivto"),
                                              Point("R", [0, 1, 0], frame="Nn")])
    msg = str(info.value)
    assert "from 'Pivto' is not declared (did you mean 'Pivot'?)" in msg
    assert "frame 'Nn' is not declared (did you mean 'N'?)" in msg


def test_position_needs_three_components():
    with pytest.raises(ModelError, match="expected 3 components"):
        Model("u", coordinates=["a"], points=[Point("P", ["a", 0])])
