"""Models built from ``sympy.physics.mechanics`` objects (issue 2: Particle, RigidBody,
ReferenceFrame, dynamicsymbols) give the accelerations of sympy's own ``KanesMethod`` on the
same objects, at random states."""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

from nonideal import Constraint, ModelError
from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.mechanics import coordinate_name, model_from_mechanics

RNG = np.random.default_rng(7)


def _kane_accelerations(frame, q, u, kd, bodies, loads, values, state, constraints=None):
    """q'' from sympy's KanesMethod (u = q'), at *state*."""
    if constraints is None:
        km = me.KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kd)
        u_all = u
    else:
        km = me.KanesMethod(frame, q_ind=q, u_ind=constraints["u_ind"], kd_eqs=kd,
                            u_dependent=constraints["u_dep"], velocity_constraints=constraints["eqs"])
        u_all = constraints["u_ind"] + constraints["u_dep"]
    km.kanes_equations(bodies, loads)
    subs = dict(values)
    subs.update({qi: state[coordinate_name(qi)] for qi in q})
    subs.update({ui: state[coordinate_name(qi) + "'"] for qi, ui in zip(q, u)})
    M = np.array(km.mass_matrix_full.xreplace(subs).evalf(), dtype=float)
    F = np.array(km.forcing_full.xreplace(subs).evalf(), dtype=float).ravel()
    x = np.linalg.solve(M, F)
    n = len(q)
    return {coordinate_name(qi): x[n + u_all.index(ui)] for qi, ui in zip(q, u)}


def assert_matches_kane(model, frame, q, u, bodies, loads, values, constraints=None, states=5, seed_state=None):
    kd = [qi.diff() - ui for qi, ui in zip(q, u)]
    for _ in range(states):
        state = seed_state(RNG) if seed_state else {
            **{coordinate_name(qi): RNG.uniform(-1, 1) for qi in q},
            **{coordinate_name(qi) + "'": RNG.uniform(-1, 1) for qi in q},
        }
        ours = evaluate(model, at=state).to_dict()["qddot"]
        ref = _kane_accelerations(frame, q, u, kd, bodies, loads, values, state, constraints)
        for name, a in ref.items():
            assert ours[name] == pytest.approx(a, rel=1e-10, abs=1e-10), name


def test_double_pendulum_of_rigid_links_matches_kane():
    q1, q2 = me.dynamicsymbols("q1 q2")
    u1, u2 = me.dynamicsymbols("u1 u2")
    m, l, g = sp.symbols("m l g")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = N.orientnew("B", "Axis", [q2, N.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(N, u2 * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    Ao = O.locatenew("Ao", l / 2 * A.x)
    P = O.locatenew("P", l * A.x)
    Bo = P.locatenew("Bo", l / 2 * B.x)
    Ao.v2pt_theory(O, N, A)
    P.v2pt_theory(O, N, A)
    Bo.v2pt_theory(P, N, B)
    I = me.inertia(A, 0, 0, m * l ** 2 / 12)
    IB = me.inertia(B, 0, 0, m * l ** 2 / 12)
    links = [me.RigidBody("A", Ao, A, m, (I, Ao)), me.RigidBody("B", Bo, B, m, (IB, Bo))]
    loads = [(Ao, -m * g * N.y), (Bo, -m * g * N.y), (B, 0.3 * sp.sin(q1) * N.z)]
    values = {m: 1.3, l: 0.7, g: 9.81}
    model = model_from_mechanics(
        "double pendulum (sympy.physics.mechanics)", [q1, q2], N, O, links, loads,
        parameters={"m": 1.3, "l": 0.7, "g": 9.81}, initial={q1: 0.2, q2: -0.1, q1.diff(): 0, q2.diff(): 0})
    assert model.coordinates == ("q1", "q2")
    assert_matches_kane(model, N, [q1, q2], [u1, u2], links, loads, values)


def test_inertia_about_another_point_is_made_central():
    # a rod (length 2l) pivoted at its end O, inertia declared about O: m l^2 + m l^2/3
    q = me.dynamicsymbols("q")
    m, l, g = sp.symbols("m l g")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q, N.z])
    O = me.Point("O")
    G = O.locatenew("G", l * A.x)
    about_O = me.inertia(A, 0, m * l ** 2 * 4 / 3, m * l ** 2 * 4 / 3)
    rod = me.RigidBody("rod", G, A, m, (about_O, O))
    values = {"m": 2.0, "l": 0.5, "g": 9.81}
    model = model_from_mechanics("rod", [q], N, O, [rod], loads=[(G, -m * g * N.y)],
                                 parameters=values, initial={"q": 0.4, "q'": 1.0})
    central = sp.Matrix(model.bodies[0].inertia)[2, 2]
    assert float(central.subs({sp.Symbol(k): v for k, v in values.items()})) == pytest.approx(2.0 * 0.25 / 3)
    # physical pendulum: q'' = -m g l cos(q) / (4/3 m l^2)
    assert evaluate(model).to_dict()["qddot"]["q"] == pytest.approx(-9.81 * np.cos(0.4) / (4 / 3 * 0.5), rel=1e-12)


def test_spinning_top_euler_angles_matches_kane():
    # a heavy symmetric top on a fixed point, ZXZ body angles, with a torque about its axis
    psi, th, phi = me.dynamicsymbols("psi theta phi")
    u = me.dynamicsymbols("u1:4")
    m, g, h, Ia, It, c = sp.symbols("m g h I_a I_t c")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", [psi, th, phi], "ZXZ")
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", h * B.z)
    top = me.RigidBody("top", G, B, m, (me.inertia(B, It, It, Ia), G))
    loads = [(G, -m * g * N.z), (B, c * B.z)]
    values = {m: 0.8, g: 9.81, h: 0.1, Ia: 2e-3, It: 3e-3, c: 0.01}
    model = model_from_mechanics(
        "top", [psi, th, phi], N, O, [top], loads,
        parameters={str(k): v for k, v in values.items()},
        initial={psi: 0, th: 0.4, phi: 0, psi.diff(): 0, th.diff(): 0, phi.diff(): 30})
    assert_matches_kane(model, N, [psi, th, phi], list(u), [top], loads, values,
             seed_state=lambda r: {"psi": r.uniform(-1, 1), "theta": r.uniform(0.3, 1.2),
                                   "phi": r.uniform(-1, 1), "psi'": r.uniform(-2, 2),
                                   "theta'": r.uniform(-2, 2), "phi'": r.uniform(-30, 30)})


def test_knife_edge_with_a_dynamicsymbols_constraint_matches_kane():
    # Chaplygin-type knife edge on an inclined plane: y' cos(theta) - x' sin(theta) = 0
    x, y, th = me.dynamicsymbols("x y theta")
    ux, uy, ut = me.dynamicsymbols("u_x u_y u_t")
    m, Izz, g, a, alpha = sp.symbols("m I_zz g a alpha")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [th, N.z])
    O = me.Point("O")
    O.set_vel(N, 0)
    C = O.locatenew("C", x * N.x + y * N.y)
    G = C.locatenew("G", a * B.x)
    body = me.RigidBody("sleigh", G, B, m, (me.inertia(B, 0, 0, Izz), G))
    loads = [(G, -m * g * sp.sin(alpha) * N.x)]
    knife = Constraint.nonholonomic("knife", y.diff() * sp.cos(th) - x.diff() * sp.sin(th))
    values = {m: 1.0, Izz: 0.05, g: 9.81, a: 0.2, alpha: 0.3}
    model = model_from_mechanics(
        "knife edge", [x, y, th], N, O, [body], loads, constraints=[knife],
        parameters={str(k): v for k, v in values.items()},
        initial={x: 0, y: 0, th: 0.3, x.diff(): 1.0, th.diff(): 0.5})
    # Kane with dependent speed u_y (the knife edge solved for it)
    B.set_ang_vel(N, ut * N.z)
    C.set_vel(N, ux * N.x + uy * N.y)
    G.v2pt_theory(C, N, B)
    cons = {"u_ind": [ux, ut], "u_dep": [uy], "eqs": [uy * sp.cos(th) - ux * sp.sin(th)]}

    def state(r):
        t = r.uniform(-1, 1)
        vx, w = r.uniform(-1, 1), r.uniform(-2, 2)
        return {"x": r.uniform(-1, 1), "y": r.uniform(-1, 1), "theta": t,
                "x'": vx, "y'": vx * np.tan(t), "theta'": w}

    assert_matches_kane(model, N, [x, y, th], [ux, uy, ut], [body], loads, values, constraints=cons,
             seed_state=state)


def test_errors_name_the_object_and_the_fix():
    q = me.dynamicsymbols("q")
    N, O = me.ReferenceFrame("N"), me.Point("O")
    lost = me.Point("lost")
    with pytest.raises(ModelError, match="point 'lost' has no position relative to the origin 'O'.*locatenew"):
        model_from_mechanics("x", [q], N, O, [me.Particle("p", lost, 1)], initial={q: 0, q.diff(): 0})
    A = N.orientnew("A", "Axis", [q, N.z])
    P = O.locatenew("P", A.x)
    with pytest.raises(ModelError, match="frame 'A', which is not the frame of a RigidBody"):
        model_from_mechanics("x", [q], N, O, [me.Particle("p", P, 1)], loads=[(A, N.z)],
                             initial={q: 0, q.diff(): 0})
    with pytest.raises(ModelError, match="not a sympy.physics.mechanics Particle or RigidBody"):
        model_from_mechanics("x", [q], N, O, ["bob"], initial={q: 0, q.diff(): 0})


def test_frames_and_points_of_the_bodies_are_declared():
    """The SymPy frames and points become the model's: vector functions in expressions give
    SymPy's own angular velocities and point velocities."""
    import numpy as np
    import sympy as sp
    import sympy.physics.mechanics as me

    from nonideal import model_from_mechanics

    q1, q2 = me.dynamicsymbols("q1 q2")
    l, m = sp.symbols("l m")
    N, O = me.ReferenceFrame("N"), me.Point("O")
    O.set_vel(N, 0)
    A = N.orientnew("A", "Axis", (q1, N.z))
    B = A.orientnew("B", "Axis", (q2, A.x))
    G = O.locatenew("G", l * A.x + l / 2 * B.y)
    G.set_vel(N, G.pos_from(O).dt(N))
    P = O.locatenew("P", l * A.x)
    body = me.RigidBody("link", G, B, m, (me.inertia(B, 1, 2, 3), G))
    model = model_from_mechanics("two axes", [q1, q2], N, O, [body], points=[P],
                                 parameters={"l": 0.7, "m": 1.0})
    assert [f.name for f in model.frames] == ["B"] and [p.name for p in model.points] == ["G", "P"]
    vals = {q1: 0.3, q2: -0.8, q1.diff(): 1.1, q2.diff(): 0.4, l: 0.7}
    ours_vals = {sp.Symbol("q1"): 0.3, sp.Symbol("q2"): -0.8, sp.Symbol("q1'"): 1.1,
                 sp.Symbol("q2'"): 0.4, l: 0.7}
    for text, theirs in (("dot(omega(B), N.x)", B.ang_vel_in(N).dot(N.x)),
                         ("dot(vel(G), N.y)", G.vel(N).dot(N.y)),
                         ("dot(vel(P), N.x)", P.vel(N).dot(N.x)),
                         ("dot(B.y, N.z)", B.y.dot(N.z))):
        ours = float(model.parse(text, "test").xreplace(ours_vals))
        want = float(me.msubs(theirs, vals))
        assert np.isclose(ours, want, atol=1e-12), text
