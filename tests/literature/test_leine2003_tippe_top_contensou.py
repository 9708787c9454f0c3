"""The tippe top (Leine & Glocker 2003, sec. 5 parameters) with Coulomb friction over a contact
patch (Contensou 1963): the law against a direct two-dimensional integration of Coulomb's
traction over the patch, the inversion against an independent Newton-Euler integration, the
balance of Jellett's integral with the pivoting torque, the energy balance and the refusals."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from nonideal import Contact, CoulombContensou, load_model, simulate
from nonideal.errors import MechanicsError, ModelError
from nonideal.gallery import tippe_top_contensou as example
from nonideal.modeling.shapes import Sphere
from nonideal.numeric.contensou import contensou, contensou_shape

P = example.PARAMETERS


def _patch(v, w, n=400):
    """Force and torque per mu N on a unit patch sliding at v (along x) and pivoting at w:
    Coulomb's traction summed over a polar Gauss grid about the patch's centre."""
    x, wt = np.polynomial.legendre.leggauss(n)
    r, wr = (x + 1) / 2, wt / 2
    th = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    R, T = np.meshgrid(r, th, indexing="ij")
    dA = np.outer(wr * r, np.full(2 * n, np.pi / n))
    px, py = R * np.cos(T), R * np.sin(T)
    ux, uy = v - w * py, w * px
    s = np.hypot(ux, uy)
    s[s == 0] = 1
    return np.sum(dA * ux / s) / np.pi, np.sum(dA * (px * uy - py * ux) / s) / np.pi


@pytest.mark.parametrize("d", [1e-3, 0.3, 0.7, 0.999, 1.5, 4.0, 50.0])
def test_the_law_is_coulombs_traction_summed_over_the_patch(d):
    f, m = contensou(d)
    F, M = _patch(d, 1.0)
    # the grid resolves the pivot point inside the patch (d < 1) to ~1e-5
    assert f == pytest.approx(F, abs=2e-5) and m == pytest.approx(M, abs=2e-5)


def test_the_law_in_its_limits():
    assert contensou(1.0)[0] == pytest.approx(8 / (3 * math.pi), rel=1e-14)   # Contensou's value
    assert contensou(0.0) == (0.0, 2 / 3)                                    # pivoting only
    for d in (1e-6, 1e-3, 1e-3 * (1 + 1e-12)):                             # f ~ d, m ~ 2/3
        f, m = contensou(d)
        assert f == pytest.approx(d, rel=1e-6) and m == pytest.approx(2 / 3, rel=1e-6)
    for d in (1e5, 100.0, 100.0 * (1 + 1e-12)):                              # f ~ 1, m ~ 1/(4 d)
        f, m = contensou(d)
        assert f == pytest.approx(1.0, rel=1e-4) and m == pytest.approx(0.25 / d, rel=1e-4)
    # the series and the quadrature meet without a jump
    for d in (1e-3, 100.0):
        a, b = contensou(d * (1 - 1e-12)), contensou(d * (1 + 1e-12))
        assert a == pytest.approx(b, rel=1e-11)
    # the shape: the force along the slip, the torque against the pivoting; None when both stop
    s = contensou_shape([3e-4, 4e-4, -1e-3])
    f, m = contensou(0.5)
    assert s == pytest.approx([0.6 * f, 0.8 * f, -m], rel=1e-14)
    assert contensou_shape([0.0, 0.0, 2.0]) == pytest.approx([0, 0, 2 / 3])
    assert contensou_shape([0.0, 2.0, 0.0]) == pytest.approx([0, 1, 0])
    assert contensou_shape([0.0, 0.0, 0.0]) is None


def _newton_euler(times):
    """G's motion and Euler's equations in N axes, the normal force from gap'' = 0, the patch's
    force and pivoting torque from the law; SciPy's DOP853 at rtol 1e-11."""
    m, R, a, g, mu, rho = P["m"], P["R"], P["a"], P["g"], P["mu"], P["rho"]
    Ib = np.array([P["A"], P["A"], P["C"]])

    def rot(e):
        e0, e1, e2, e3 = e / np.linalg.norm(e)
        return np.array([[1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                         [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
                         [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)]])

    def rhs(t, y):
        Rm = rot(y[6:10])
        k, w = Rm[:, 2], Rm @ y[10:13]
        d = a * k - np.array([0, 0, R])
        U = y[3:6] + np.cross(w, d)
        s = math.hypot(U[0], U[1])
        f_, m_ = contensou(s / (rho * abs(w[2])))
        f = np.array([-mu * f_ * U[0] / s, -mu * f_ * U[1] / s, 1.0])      # per unit N
        tz = -mu * rho * m_ * math.copysign(1.0, w[2])
        I, Iinv = Rm @ np.diag(Ib) @ Rm.T, Rm @ np.diag(1 / Ib) @ Rm.T
        wd_N = Iinv @ (np.cross(d, f) + [0, 0, tz])
        wd_0 = Iinv @ -np.cross(w, I @ w)
        N = -(-g + a * (np.cross(wd_0, k) + np.cross(w, np.cross(w, k)))[2]) / (f[2] / m + a * np.cross(wd_N, k)[2])
        wd = N * wd_N + wd_0
        e0, e1, e2, e3 = y[6:10]
        wx, wy, wz = y[10:13]
        ed = 0.5 * np.array([-e1 * wx - e2 * wy - e3 * wz, e0 * wx + e2 * wz - e3 * wy,
                             e0 * wy + e3 * wx - e1 * wz, e0 * wz + e1 * wy - e2 * wx])
        return np.concatenate([y[3:6], N * f / m - [0, 0, g], ed, Rm.T @ wd])

    th0 = P["theta0"]
    y0 = np.concatenate([[0, 0, R - a * math.cos(th0), 0, 0, 0], [math.cos(th0 / 2), math.sin(th0 / 2), 0, 0],
                         [0, 0, P["W"]]])
    sol = solve_ivp(rhs, (times[0], times[-1]), y0, method="DOP853", rtol=1e-11, atol=1e-13, t_eval=times)
    return np.array([math.acos(max(-1.0, min(1.0, rot(y[6:10])[2, 2]))) for y in sol.y.T])


@pytest.fixture(scope="module")
def run():
    return example.check()


def test_the_top_turns_over_as_the_independent_integration(run):
    assert run["theta"][-1] > 3.0 and (run["z"][-1] - run["z"][0]) / P["a"] > 1.98
    assert run["slip_min"] > 1e-3 and not run["events"]          # it slides all the way
    t = run["t"][::100]
    assert np.max(np.abs(run["theta"][::100] - _newton_euler(t))) < 1e-8


def test_jellett_changes_only_by_the_pivoting_torque(run):
    assert run["jellett_change"] > 0.1                  # not an integral any more (12.9 %)
    assert run["jellett_balance"] < 1e-7                 # d(lambda)/dt = M (a cos(theta) - R)
    assert np.all(run["pivoting_torque"] * np.asarray(run["trajectory"].contacts["table"]["slip"])[:, 2] <= 0)


def test_energy_balance_and_friction_only_dissipates(run):
    assert run["energy_balance"] < 1e-9
    assert run["friction_work_increase"] <= 0.0


TOP = """
[model]
name = "ball"
format = 1
[parameters]
m = 1.0
r = 0.1
[coordinates]
q = ["x", "y", "z", "e0", "e1", "e2", "e3"]
[[frames]]
name = "B"
quaternion = ["e0", "e1", "e2", "e3"]
[[points]]
name = "G"
position = ["x", "y", "z"]
[[bodies]]
type = "rigid"
name = "ball"
mass = "m"
inertia = [["0.004", "0", "0"], ["0", "0.004", "0"], ["0", "0", "0.004"]]
frame = "B"
center = "G"
[gravity]
vector = ["0", "0", "-9.81"]
[[contacts]]
name = "floor"
body = "ball"
shape = { type = "sphere", radius = "r" }
mu = 0.3
%s
[initial]
x = 0.0
y = 0.0
z = 0.1
e0 = 1.0
e1 = 0.0
e2 = 0.0
e3 = 0.0
"x'" = %s
"y'" = 0.0
"z'" = 0.0
"e0'" = 0.0
"e1'" = 0.0
"e2'" = 0.0
"e3'" = 0.0
[simulation]
t_end = 0.01
"""


@pytest.mark.parametrize("keys, message", [
    ('friction = "contensou"', "needs patch_radius"),
    ('patch_radius = 0.001', "patch_radius applies to friction = \"contensou\" only"),
    ('friction = "contensou"\npatch_radius = -0.001', "patch_radius must be a positive constant"),
    ('friction = "contensou"\npatch_radius = 0.001\neps = 0.01', "remove eps"),
    ('friction = "contensou"\npatch_radius = 0.001\nspin_friction = 0.001', "remove spin_friction"),
])
def test_bad_contensou_keys_are_refused_by_name(tmp_path, keys, message):
    with pytest.raises(ModelError) as err:
        simulate(_load(tmp_path, keys, "0.0"))
    assert "'floor'" in str(err.value) and message in str(err.value)


def _load(tmp_path, keys, speed):
    path = tmp_path / "ball.toml"
    path.write_text(TOP % (keys, speed))
    return load_model(path)


def test_a_contact_at_rest_is_refused_with_the_diagnosis(tmp_path):
    model = _load(tmp_path, 'friction = "contensou"\npatch_radius = 0.001', "0.0")
    with pytest.raises(MechanicsError, match="the slip and the pivoting of its patch vanished together"):
        simulate(model)


def test_a_sliding_ball_slows_down_under_the_full_coulomb_force(tmp_path):
    # no pivoting: the law is Coulomb's at a point; the slip 1 m/s decays at (7/2) mu g
    model = _load(tmp_path, 'friction = "contensou"\npatch_radius = 0.001', "1.0")
    tr = simulate(model, times=np.linspace(0, 0.01, 3))
    U = np.asarray(tr.contacts["floor"]["slip"])
    assert U[-1, 0] == pytest.approx(1.0 - 3.5 * 0.3 * 9.81 * 0.01, rel=1e-9)
    assert np.all(U[:, 2] == 0)


def test_the_python_api_builds_the_same_model():
    m = example.build()
    assert isinstance(m.contacts[0].friction, CoulombContensou)
    assert isinstance(Contact("c", body="top", shape=Sphere("R"), friction=CoulombContensou("mu", "rho")).friction,
                      CoulombContensou)
