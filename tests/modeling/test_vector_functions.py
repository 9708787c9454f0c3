"""Vector functions in expressions: omega, vel, pos, acc, dot, cross, norm, unit vectors,
momentum and angular momentum -- their values, and every misuse refused with the key named."""

import numpy as np
import pytest
import sympy as sp

from nonideal import Constraint, Model
from nonideal.errors import ModelError
from nonideal.modeling.bodies import Particle, RigidBody
from nonideal.modeling.frames import Frame
from nonideal.modeling.points import Point


def _pendulum(**fields):
    """A rigid rod swinging about the y axis of N, its frame B by the angle th."""
    base = dict(
        name="rod", coordinates=["th", "x"], parameters={"m": 2.0, "l": 0.5, "g": 9.81, "J": 0.1},
        frames=[Frame("B", rotation="body Y", angles=["th"])],
        points=[Point("G", ["0", "0", "-l"], frame="B", origin="S"), Point("S", ["x", 0, 0])],
        bodies=[RigidBody("rod", "m", [["J", 0, 0], [0, "J", 0], [0, 0, "J"]], frame="B", center="G")],
        gravity=["0", "0", "-g"])
    base.update(fields)
    return Model(**base)


def test_vector_expressions_evaluate():
    m = _pendulum()
    th, x, thd, xd = sp.symbols("th x th' x'")
    l = sp.Symbol("l")
    e = m.parse("dot(vel(G), N.x)", "test")
    assert sp.simplify(e - (xd - l * sp.cos(th) * thd)) == 0
    assert sp.simplify(m.parse("norm(omega(B))^2", "test") - thd**2) == 0
    assert sp.simplify(m.parse("dot(cross(B.x, B.y), B.z)", "test") - 1) == 0
    assert sp.simplify(m.parse("dot(pos(G) - pos(S), 2*B.z/2 - 0*N.x)", "test") + l) == 0
    assert m.parse("dot(-N.x, N.x)", "test") == -1
    acc = m.parse("dot(acc(G), N.z)", "test", order=2)
    assert acc.has(sp.Symbol("th''"))


def test_kinetic_energy_from_vector_functions_equals_the_bodies():
    """T written with vel() and omega() by hand equals the body's T: the two models move alike."""
    a = _pendulum()
    b = _pendulum(bodies=[], kinetic="m/2*dot(vel(G), vel(G)) + J/2*dot(omega(B), omega(B))",
                  potential="m*g*dot(pos(G), N.z)")
    from nonideal.equations.dynamics import dynamics_of
    da, db = dynamics_of(a), dynamics_of(b)
    import symengine as se
    for i in range(2):
        for j in range(2):
            assert se.expand(da.M[i, j] - db.M[i, j]) == 0
        assert abs(float((da.F[i] - db.F[i]).subs({se.Symbol(n): v for n, v in
                   {"th": 0.3, "x": 0.1, "th'": 0.7, "x'": -0.2, "m": 2.0, "l": 0.5, "g": 9.81, "J": 0.1}.items()}))) < 1e-12


def test_momentum_and_angular_momentum():
    m = _pendulum()
    th, thd, xd = sp.symbols("th th' x'")
    l, mass, J = sp.symbols("l m J")
    p = m.parse("dot(momentum(rod), N.x)", "out")
    assert sp.simplify(p - mass * (xd - l * sp.cos(th) * thd)) == 0
    # about the pivot S when it is at rest: J th' + m l^2 th' along y
    H = m.parse("dot(angular_momentum(rod, S), N.y)", "out").subs(xd, 0)
    assert sp.simplify(H - (J + mass * l**2) * thd) == 0
    # a particle has no spin: its angular momentum about O is r x m v
    q = Model("p", coordinates=["x", "y"], parameters={"m": 1.0},
              points=[Point("P", ["x", "y", 0])], bodies=[Particle("bob", "m", point="P")])
    Hz = q.parse("dot(angular_momentum(bob, O), N.z)", "out")
    x, y, xd, yd = sp.symbols("x y x' y'")
    assert sp.expand(Hz - mass * (x * yd - y * xd)) == 0


@pytest.mark.parametrize("text, fragment", [
    ("vel(G)", "is a vector (3 components in N) but a scalar is expected"),
    ("vel(G) + 1", "'+' between a vector and a scalar"),
    ("vel(G)*omega(B)", "product of two vectors; write dot(a, b) or cross(a, b)"),
    ("1/N.x", "division by a vector"),
    ("N.x^2", "a power of a vector"),
    ("sin(N.x)", "sin of a vector"),
    ("dot(1, N.x)", "dot takes vectors; argument 1 is a scalar"),
    ("vel(Gg)", "unknown point 'Gg' (did you mean 'G'?)"),
    ("omega(b)", "unknown frame 'b' (did you mean 'B'?)"),
    ("B.w", "a frame's unit vectors are B.x, B.y, B.z"),
    ("Bb.x", "unknown frame 'Bb' (did you mean 'B'?)"),
    ("vel(2)", "vel takes the name of a point as argument 1"),
    ("dot(N.x)", "dot takes 2 argument(s)"),
    ("vel(G, S)", "vel takes 1 argument(s)"),
    ("momentum(rdo)", "unknown body 'rdo' (did you mean 'rod'?)"),
    ("x.__class__", "unknown frame 'x'"),
])
def test_misuse_is_refused_naming_the_key(text, fragment):
    with pytest.raises(ModelError) as info:
        _pendulum(forces={"x": text})
    msg = str(info.value)
    assert "[forces] x" in msg and fragment in msg, msg


def test_velocities_are_refused_where_only_coordinates_may_appear():
    with pytest.raises(ModelError) as info:
        _pendulum(potential="m*g*dot(vel(G), N.z)")
    msg = str(info.value)
    assert "[energy] potential" in msg and "contains velocities (th', x')" in msg


def test_constraint_with_vector_functions_is_nonholonomic():
    m = _pendulum(constraints=[Constraint.nonholonomic("no_slip", "dot(vel(G), N.x)")])
    assert m.constraints[0].order == 1


def test_loads_may_use_vector_functions():
    m = _pendulum(forces={"x": "-dot(vel(S), N.x)"})
    assert m.forces[1] == -sp.Symbol("x'")


def test_parameters_cannot_use_vector_functions():
    with pytest.raises(ModelError, match="not available here"):
        Model("p", coordinates=["x"], parameters={"a": 1.0, "b": "norm(pos(O))"})


def test_vector_functions_values_numerically():
    """vel() of the rod's end agrees with a finite difference of pos() along a motion."""
    m = _pendulum()
    length = {sp.Symbol("l"): 0.5}
    pos = sp.lambdify(sp.symbols("th x"), [c.xreplace(length) for c in m.kinematics.pos("G")])
    vel = sp.lambdify(sp.symbols("th x th' x'"), [c.xreplace(length) for c in m.kinematics.vel("G")])
    th0, x0, thd, xd, h = 0.4, 0.2, 1.3, -0.7, 1e-6
    fd = (np.array(pos(th0 + h * thd, x0 + h * xd)) - np.array(pos(th0 - h * thd, x0 - h * xd))) / (2 * h)
    np.testing.assert_allclose(vel(th0, x0, thd, xd), fd, atol=1e-8)
