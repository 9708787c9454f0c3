"""Frames: rotations, angular velocities and accelerations of declared frames against
``sympy.physics.vector`` (``orient_body_fixed``, ``orient_space_fixed``, ``orient_axis``,
``orient_quaternion``) at random states, over chains of every kind of rotation."""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

from nonideal import Model
from nonideal.errors import ModelError
from nonideal.modeling.frames import Frame, elementary
from nonideal.modeling.points import Point

Q = ["q1", "q2", "q3", "q4", "q5", "q6", "q7", "e0", "e1", "e2", "e3"]


def _chain_model(points=()):
    c = sp.cos(sp.Symbol("q7"))
    s = sp.sin(sp.Symbol("q7"))
    matrix = [[1, 0, 0], [0, c, -s], [0, s, c]]      # Rx(q7) written out
    frames = [
        Frame("A", rotation="body ZXZ", angles=["q1", "q2", "q3"]),
        Frame("B", parent="A", rotation="space XY", angles=["q4", "q5 + k*t"]),
        Frame("C", parent="B", axis=["1", "2", "2"], angle="q6"),
        Frame("D", parent="C", quaternion=["e0", "e1", "e2", "e3"]),
        Frame("E", parent="D", matrix=matrix),
        Frame("F", parent="A", rotation="body Y", angles=["q7"]),
        Frame("G", parent="F", rotation="space ZYX", angles=["q2", "q3", "q1"]),
    ]
    return Model("chain", coordinates=Q, parameters={"k": 0.7, "l": 0.4}, frames=frames,
                 points=points)


def _sympy_chain():
    q = dict(zip(Q, me.dynamicsymbols(" ".join(Q))))
    k, t = sp.Symbol("k"), me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    A, B, C, D, E, F, G = (me.ReferenceFrame(n) for n in "ABCDEFG")
    A.orient_body_fixed(N, (q["q1"], q["q2"], q["q3"]), "ZXZ")
    B.orient_space_fixed(A, (q["q4"], q["q5"] + k * t, 0), "XYZ")
    C.orient_axis(B, (B.x + 2 * B.y + 2 * B.z) / 3, q["q6"])
    D.orient_quaternion(C, (q["e0"], q["e1"], q["e2"], q["e3"]))
    E.orient_axis(D, D.x, q["q7"])
    F.orient_axis(A, A.y, q["q7"])
    G.orient_space_fixed(F, (q["q2"], q["q3"], q["q1"]), "ZYX")
    return q, N, dict(zip("ABCDEFG", (A, B, C, D, E, F, G)))


def random_state(rng):
    """Values of q, q', q'' with unit Euler parameters moving on their sphere."""
    vals = {n: rng.uniform(-2, 2) for n in Q}
    e = rng.normal(size=4)
    e /= np.linalg.norm(e)
    ed = rng.normal(size=4)
    ed -= e * (e @ ed)
    edd = rng.normal(size=4)
    edd -= e * (e @ edd + ed @ ed)           # e.e'' + e'.e' = 0
    for i in range(4):
        vals[f"e{i}"] = e[i]
    out = dict(vals)
    for n in Q:
        out[n + "'"] = rng.uniform(-2, 2)
        out[n + "''"] = rng.uniform(-2, 2)
    for i in range(4):
        out[f"e{i}'"], out[f"e{i}''"] = ed[i], edd[i]
    out.update(k=0.7, l=0.4, t=0.3)
    return out


def ours(expr, state):
    expr = sp.sympify(expr)
    return float(expr.xreplace({s: state[s.name] for s in expr.free_symbols}))


def theirs(expr, q, state):
    subs = {}
    for n, f in q.items():
        subs[f.diff(me.dynamicsymbols._t, 2)] = state[n + "''"]
    for n, f in q.items():
        subs[f.diff(me.dynamicsymbols._t)] = state[n + "'"]
    for n, f in q.items():
        subs[f] = state[n]
    subs[sp.Symbol("k")] = state["k"]
    subs[sp.Symbol("l")] = state["l"]
    e = me.msubs(sp.sympify(expr), subs)
    return float(e.subs(me.dynamicsymbols._t, state["t"]))


@pytest.fixture(scope="module")
def chain():
    return _chain_model(), _sympy_chain()


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_rotations_and_angular_velocities_agree_with_sympy(chain, seed):
    model, (q, N, frames) = chain
    kin = model.kinematics
    state = random_state(np.random.default_rng(seed))
    for name, frame in frames.items():
        R = np.array([[ours(x, state) for x in row] for row in kin.rotation(name).tolist()])
        R_sp = np.array([[theirs(x, q, state) for x in row] for row in N.dcm(frame).tolist()])
        np.testing.assert_allclose(R, R_sp, atol=1e-12, err_msg=name)
        w = np.array([ours(x, state) for x in kin.omega(name)])
        w_sp = np.array([theirs(x, q, state) for x in frame.ang_vel_in(N).to_matrix(N)])
        np.testing.assert_allclose(w, w_sp, atol=1e-11, err_msg=name)
        w_own = np.array([ours(x, state) for x in kin.omega_own(name)])
        np.testing.assert_allclose(w_own, R.T @ w_sp, atol=1e-11, err_msg=name)
        a = np.array([ours(x, state) for x in kin.alpha(name)])
        a_sp = np.array([theirs(x, q, state) for x in frame.ang_acc_in(N).to_matrix(N)])
        np.testing.assert_allclose(a, a_sp, atol=1e-10, err_msg=name)


def test_body_and_space_sequences_are_products_of_elementary_rotations():
    """body XYZ = Rx Ry Rz, space XYZ = Rz Ry Rx (columns: the frame's axes in the parent's)."""
    model = Model("seq", coordinates=["a", "b", "c"], frames=[
        Frame("P", rotation="body XYZ", angles=["a", "b", "c"]),
        Frame("S", rotation="space XYZ", angles=["a", "b", "c"])])
    a, b, c = sp.symbols("a b c")
    body = elementary(0, a) * elementary(1, b) * elementary(2, c)
    space = elementary(2, c) * elementary(1, b) * elementary(0, a)
    assert sp.simplify(model.kinematics.rotation("P") - body) == sp.zeros(3, 3)
    assert sp.simplify(model.kinematics.rotation("S") - space) == sp.zeros(3, 3)


def test_angular_velocity_of_a_body_sequence_is_short():
    """Composed from the elementary rates: omega of ZXZ Euler angles in body axes is the
    textbook (psi' sin(theta) sin(phi) + theta' cos(phi), ...), no R' R^T."""
    model = Model("euler", coordinates=["psi", "theta", "phi"], frames=[
        Frame("B", rotation="body ZXZ", angles=["psi", "theta", "phi"])])
    psi, th, ph = sp.symbols("psi theta phi")
    pd, td, fd = sp.symbols("psi' theta' phi'")
    w = model.kinematics.omega_own("B")
    want = [pd * sp.sin(th) * sp.sin(ph) + td * sp.cos(ph),
            pd * sp.sin(th) * sp.cos(ph) - td * sp.sin(ph),
            pd * sp.cos(th) + fd]
    assert [sp.expand(x - y) for x, y in zip(w, want)] == [0, 0, 0]


def _problems(**frame):
    with pytest.raises(ModelError) as info:
        Model("bad", coordinates=["a", "b", "c"], frames=[Frame("B", **frame)])
    return str(info.value)


def test_unknown_axis_letter_is_refused():
    msg = _problems(rotation="body ZQZ", angles=["a", "b", "c"])
    assert "'B'" in msg and "unknown axis 'Q'" in msg and "X, Y, Z" in msg


def test_unknown_sequence_kind_suggests():
    msg = _problems(rotation="bodi ZXZ", angles=["a", "b", "c"])
    assert "did you mean 'body'" in msg


def test_angle_count_must_match_axes():
    assert "give 3 angles" in _problems(rotation="body ZXZ", angles=["a", "b"])


def test_frame_parent_loop_is_refused():
    with pytest.raises(ModelError) as info:
        Model("loop", coordinates=["a"], frames=[
            Frame("A", parent="B", rotation="body Z", angles=["a"]),
            Frame("B", parent="A", rotation="body X", angles=["a"])])
    msg = str(info.value)
    assert "A -> B -> A" in msg and "loop" in msg and 'parent = "N"' in msg


def test_unknown_parent_suggests():
    with pytest.raises(ModelError) as info:
        Model("p", coordinates=["a"], frames=[
            Frame("Arm", rotation="body Z", angles=["a"]),
            Frame("B", parent="Amr", rotation="body X", angles=["a"])])
    assert "parent 'Amr' is not declared (did you mean 'Arm'?)" in str(info.value)


def test_matrix_must_be_a_rotation():
    msg = _problems(matrix=[["cos(a)", "sin(a)", 0], ["sin(a)", "cos(a)", 0], [0, 0, 1]])
    assert "not a rotation" in msg


def test_two_rotations_or_none_are_refused():
    assert "give one rotation" in _problems()
    assert "got rotation and axis" in _problems(rotation="body Z", angles=["a"], axis=[0, 0, 1], angle="b")


def test_reserved_and_duplicate_names():
    with pytest.raises(ModelError) as info:
        Model("r", coordinates=["a"], frames=[Frame("N", rotation="body Z", angles=["a"]),
                                              Frame("A", rotation="body Z", angles=["a"])],
              points=[Point("A", [0, 0, 1])])
    msg = str(info.value)
    assert "'N' is reserved" in msg and "already used by frame 'A'" in msg


def test_quaternion_must_name_coordinates():
    msg = _problems(quaternion=["a", "b", "c", "1"])
    assert "four different coordinates" in msg


# ---------------------------------------------------------------- model files

def _file(**tables):
    data = {"coordinates": {"q": ["a", "b"]}, "parameters": {"m": 1.0, "l": 0.5}}
    data.update(tables)
    return data


def _file_problems(data):
    from nonideal.modeling.modelfile import model_from_dict

    with pytest.raises(ModelError) as info:
        model_from_dict(data, "m.toml")
    return str(info.value)


def test_model_file_frames_points_and_bodies():
    from nonideal.modeling.modelfile import model_from_dict

    model = model_from_dict(_file(
        frames=[{"name": "B", "rotation": "space ZX", "angles": ["a", "b"]}],
        points=[{"name": "G", "frame": "B", "position": ["0", "0", "l"]},
                {"name": "P", "from": "G", "position": ["l", 0, 0]}],
        bodies=[{"type": "rigid", "name": "body", "mass": "m", "frame": "B", "center": "G",
                 "inertia": [["1", 0, 0], [0, "1", 0], [0, 0, "2"]]},
                {"type": "particle", "name": "bob", "mass": "m", "point": "P"}],
        energy={"potential": "m*9.81*dot(pos(P), N.z)"}), "m.toml")
    body, bob = model.bodies
    assert body.frame == "B" and body.omega is not None and len(body.position) == 3
    assert bob.position == tuple(model.kinematics.pos("P"))


@pytest.mark.parametrize("tables, fragment", [
    ({"frames": [{"name": "B", "rotation": "body ZQ", "angles": ["a", "b"]}]},
     "[[frames]] 'B': rotation 'body ZQ': unknown axis 'Q'"),
    ({"frames": [{"name": "B", "rotation": "body Z", "angles": ["a"], "parnt": "N"}]},
     "unknown key 'parnt' (did you mean 'parent'?)"),
    ({"frames": [{"name": "A", "parent": "C", "axis": [0, 0, 1], "angle": "a"},
                 {"name": "C", "parent": "A", "axis": [1, 0, 0], "angle": "b"}]},
     "its parent chain A -> C -> A is a loop"),
    ({"points": [{"name": "P", "position": ["a", 0, 0], "from": "Q"},
                 {"name": "Q", "position": ["b", 0, 0], "from": "P"}]},
     "its from chain P -> Q -> P is a loop"),
    ({"bodies": [{"type": "rigid", "name": "b", "mass": "m", "frame": "B", "center": "G",
                  "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}]},
     "frame 'B' is not declared"),
    ({"bodies": [{"type": "rigid", "name": "b", "mass": "m", "frame": "B", "position": [0, 0, 0],
                  "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}]},
     "give either position and rotation or center and frame, not both"),
    ({"bodies": [{"type": "particle", "name": "b", "mass": "m", "point": "Q"}]},
     "point 'Q' is not declared"),
    ({"points": [{"name": "P", "frame": "N"}]}, "missing position"),
    ({"energy": {"kinetic": "dot(vel(P), vel(P))"}}, "unknown point 'P'; the points are O"),
])
def test_model_file_problems_name_the_key(tables, fragment):
    msg = _file_problems(_file(**tables))
    assert fragment in msg, msg
    assert msg.startswith("m.toml: ")
