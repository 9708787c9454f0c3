"""The benchmark systems built with ``sympy.physics.mechanics`` (the peer), and its numerics.

The systems are the same as ``nonideal.gallery.nlink_pendulum.build(n)`` and
``nonideal.gallery.knife_chain.build(n)``: same coordinates (absolute angles), parameters
and constraints.  The peer is used the way its documentation shows -- frames, points,
``v2pt_theory``, ``Particle``/``RigidBody``, ``KanesMethod``/``LagrangesMethod`` -- and its
equations reach NumPy through ``lambdify(cse=True)`` (one call for ``M`` and ``F`` together,
so the CSE is shared) and ``numpy.linalg.solve``; PyDy's Cython generator is the fast peer.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me


# ----------------------------------------------------------------------------- n-link pendulum


def _pendulum_symbols(n):
    m = sp.symbols(f"m1:{n + 1}")
    l = sp.symbols(f"l1:{n + 1}")
    return m, l, sp.Symbol("g")


def pendulum_constants(n):
    m, l, g = _pendulum_symbols(n)
    return list(m) + list(l) + [g]


def kane_pendulum(n: int) -> me.KanesMethod:
    """n-link pendulum of point masses, absolute angles from the downward vertical."""
    q = me.dynamicsymbols(f"q1:{n + 1}")
    u = me.dynamicsymbols(f"u1:{n + 1}")
    m, l, g = _pendulum_symbols(n)
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P, particles, loads = O, [], []
    for i in range(n):
        A = N.orientnew(f"A{i + 1}", "Axis", [q[i], N.z])
        A.set_ang_vel(N, u[i] * N.z)
        Pi = P.locatenew(f"P{i + 1}", -l[i] * A.y)  # (l sin q, -l cos q) from the joint
        Pi.v2pt_theory(P, N, A)
        particles.append(me.Particle(f"Pa{i + 1}", Pi, m[i]))
        loads.append((Pi, -m[i] * g * N.y))
        P = Pi
    kd = [qi.diff() - ui for qi, ui in zip(q, u)]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations(particles, loads)
    return km


def lagrange_pendulum(n: int) -> me.LagrangesMethod:
    q = me.dynamicsymbols(f"q1:{n + 1}")
    m, l, g = _pendulum_symbols(n)
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P, particles = O, []
    for i in range(n):
        A = N.orientnew(f"A{i + 1}", "Axis", [q[i], N.z])
        Pi = P.locatenew(f"P{i + 1}", -l[i] * A.y)
        Pi.v2pt_theory(P, N, A)
        pa = me.Particle(f"Pa{i + 1}", Pi, m[i])
        pa.potential_energy = m[i] * g * Pi.pos_from(O).dot(N.y)
        particles.append(pa)
        P = Pi
    L = me.Lagrangian(N, *particles)
    lm = me.LagrangesMethod(L, q)
    lm.form_lagranges_equations()
    return lm


# ----------------------------------------------------------------------------- knife-edge chain


def kane_knife_chain(n: int) -> me.KanesMethod:
    """n links joined by revolute joints, a knife edge at the centre of each link.

    Independent speeds: the velocity (u_x, u_y) of the rear end; dependent: the angular
    velocities w_k.  The velocity constraints are the same expressions as in
    ``nonideal.gallery.knife_chain.constraint_expr`` (already in their short form, which
    favours the peer).
    """
    x, y = me.dynamicsymbols("x y")
    th = me.dynamicsymbols(f"theta1:{n + 1}")
    ux, uy = me.dynamicsymbols("u_x u_y")
    w = me.dynamicsymbols(f"w1:{n + 1}")
    m, l = sp.symbols("m l")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P0", x * N.x + y * N.y)
    P.set_vel(N, ux * N.x + uy * N.y)
    bodies, nh = [], []
    for k in range(n):
        A = N.orientnew(f"A{k + 1}", "Axis", [th[k], N.z])
        A.set_ang_vel(N, w[k] * N.z)
        C = P.locatenew(f"C{k + 1}", l / 2 * A.x)
        C.v2pt_theory(P, N, A)
        bodies.append(me.RigidBody(f"B{k + 1}", C, A, m, (me.inertia(A, 0, 0, m * l ** 2 / 12), C)))
        nh.append(-ux * sp.sin(th[k]) + uy * sp.cos(th[k])
                  + sum((l * w[j] * sp.cos(th[k] - th[j]) for j in range(k)), sp.S.Zero) + l / 2 * w[k])
        Pn = P.locatenew(f"P{k + 1}", l * A.x)
        Pn.v2pt_theory(P, N, A)
        P = Pn
    q = [x, y] + list(th)
    kd = [x.diff() - ux, y.diff() - uy] + [a.diff() - b for a, b in zip(th, w)]
    km = me.KanesMethod(N, q_ind=q, u_ind=[ux, uy], u_dependent=list(w), kd_eqs=kd,
                        velocity_constraints=nh)
    km.kanes_equations(bodies, [])
    return km


def knife_constants():
    return list(sp.symbols("m l"))


# ----------------------------------------------------------------------------- numerics


def lambdify_rhs(km, constants, params):
    """The peer's right-hand side ``y' = [q'; M^-1 F]`` (kinematics q' = u) through
    ``lambdify(cse=True)`` and ``numpy.linalg.solve``.  Returns ``fun(t, y)``."""
    q, u = list(km.q), list(km.u)
    nq = len(q)
    f = sp.lambdify((q, u, constants), [km.mass_matrix, km.forcing], cse=True, modules="numpy")
    p = np.asarray(params, dtype=float)
    # q' = u for every system here (kd_eqs are q' - u = 0, coordinates and speeds in order)

    def fun(t, y):
        qq, uu = y[:nq], y[nq:]
        M, F = f(qq, uu, p)
        return np.concatenate((uu, np.linalg.solve(M, F[:, 0])))
    return fun


def pydy_rhs(km, constants, params):
    """PyDy's Cython right-hand side on the minimal mass matrix (``q' = u`` given as the
    coordinate derivatives), its fastest documented use.  Returns ``fun(t, y)``."""
    from pydy.codegen.ode_function_generators import generate_ode_function

    f = generate_ode_function(km.forcing, list(km.q), list(km.u), constants,
                              mass_matrix=km.mass_matrix, coordinate_derivatives=sp.Matrix(list(km.u)),
                              generator="cython")
    p = np.asarray(params, dtype=float)

    def fun(t, y):
        # PyDy returns the same output buffer on every call; solve_ivp keeps the stages of
        # a Runge-Kutta step, so each call must return a fresh array (cost ~0.3 us)
        return f(y, t, p).copy()
    return fun


def size_of(exprs) -> dict:
    """Operation counts of a list of SymPy/SymEngine expressions: raw tree and after CSE
    (both counted by SymEngine, so that ours and the peer's are measured alike)."""
    import symengine as se

    flat = [se.sympify(e) for e in exprs]
    raw = int(sum(se.count_ops(e) for e in flat))
    reps, reduced = se.cse(flat)
    cse = int(sum(se.count_ops(r) for _, r in reps) + sum(se.count_ops(e) for e in reduced))
    return {"ops": raw, "ops_cse": cse, "cse_temporaries": len(reps)}
