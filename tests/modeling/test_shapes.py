"""Contacts from geometry: each shape's closed-form support point, gap and slip against an
independent numeric computation (the minimum of n . x over the surface found with SciPy; the
material point's velocity by central differences of its position with the body point frozen)
at random orientations of the body and of the plane."""

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import minimize, minimize_scalar

from nonideal.modeling.shapes import Disk, Ellipsoid, Paraboloid, Plane, Point, Sphere, contact_geometry, spin_and_rolling

q = sp.symbols("x y z a b c")
qd = sp.symbols("x' y' z' a' b' c'")
t = sp.Symbol("t")


def _rot(axis, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


R_SYM = _rot(2, q[3]) * _rot(0, q[4]) * _rot(1, q[5])
CENTER = (0.02, -0.01, 0.03)


def _surface(n, p0, moving):
    if not moving:
        return Plane(tuple(n), tuple(p0))
    nu = np.asarray(n) / np.linalg.norm(n)
    v = np.cross(nu, [0.3, -0.7, 0.2])            # in the plane
    return Plane(tuple(n), tuple(p0), velocity=tuple(v), omega=tuple(1.7 * nu))


def _numeric_support(shape, n_b):
    """argmin n_b . x over the shape (body axes, relative to its centre), by SciPy."""
    if isinstance(shape, Sphere):
        r = float(shape.radius)
        f = lambda u: r * (n_b @ [np.cos(u[0]) * np.cos(u[1]), np.sin(u[0]) * np.cos(u[1]), np.sin(u[1])])
        best = min((minimize(f, u0, method="Nelder-Mead", options={"xatol": 1e-12, "fatol": 1e-15, "maxiter": 20000})
                    for u0 in ([0.1, 0.2], [2.0, -0.5], [4.0, 1.0])), key=lambda res: res.fun)
        u = best.x
        return r * np.array([np.cos(u[0]) * np.cos(u[1]), np.sin(u[0]) * np.cos(u[1]), np.sin(u[1])])
    if isinstance(shape, Ellipsoid):
        D = np.array([float(s) for s in shape.semi_axes])
        # minimize over the unit sphere of u: x = D u; the minimum of (D n) . u is -D n/|D n|
        # -- not used: an optimizer on the parametrization instead
        g = lambda u: D * np.array([np.cos(u[0]) * np.cos(u[1]), np.sin(u[0]) * np.cos(u[1]), np.sin(u[1])])
        best = min((minimize(lambda u: n_b @ g(u), u0, method="Nelder-Mead",
                             options={"xatol": 1e-12, "fatol": 1e-15, "maxiter": 20000})
                    for u0 in ([0.1, 0.2], [2.0, -0.5], [4.0, 1.0], [5.5, -1.2])), key=lambda res: res.fun)
        return g(best.x)
    if isinstance(shape, Paraboloid):
        a, b = (float(r) for r in shape.curvature_radii)
        h = lambda u: np.array([u[0], u[1], u[0] ** 2 / (2 * a) + u[1] ** 2 / (2 * b)])
        res = minimize(lambda u: n_b @ h(u), [0.0, 0.0], method="BFGS", options={"gtol": 1e-13})
        return h(res.x)
    if isinstance(shape, Disk):
        r = float(shape.radius)
        ax = np.array([float(c) for c in shape.axis]); ax /= np.linalg.norm(ax)
        e1 = np.cross(ax, [1.0, 0.3, -0.2]); e1 /= np.linalg.norm(e1)
        e2 = np.cross(ax, e1)
        p = lambda th: r * (np.cos(th) * e1 + np.sin(th) * e2)
        best = min((minimize_scalar(lambda th: n_b @ p(th), bracket=(s, s + 1.0), tol=1e-14)
                    for s in np.linspace(0, 2 * np.pi, 7)), key=lambda res: res.fun)
        return p(best.x)
    return np.zeros(3)


SHAPES = [Sphere(0.2, CENTER), Ellipsoid((0.2, 0.05, 0.03), CENTER), Paraboloid((0.3, 0.07), CENTER),
          Disk(0.15, (0.3, 1.0, -0.2), CENTER), Point(CENTER)]


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.TYPE)
@pytest.mark.parametrize("moving", [False, True], ids=["fixed", "moving"])
def test_support_gap_slip_against_numerics(shape, moving):
    rng = np.random.default_rng(7)
    checked = 0
    for trial in range(8):
        n = rng.normal(size=3)
        p0 = rng.normal(size=3) * 0.1
        surface = _surface(n, p0, moving)
        g = contact_geometry(shape, surface, R_SYM, q[:3], q, qd, t)
        nu = n / np.linalg.norm(n)
        state = rng.normal(size=6)
        rates = rng.normal(size=6)
        subs = dict(zip(q, state)) | dict(zip(qd, rates)) | {t: 0.4}
        R = np.array(R_SYM.xreplace(subs), dtype=float)
        n_b = R.T @ nu
        if isinstance(shape, Paraboloid) and n_b[2] < 0.3:
            continue              # outside the valid side (checked below)
        checked += 1
        c = np.array(CENTER)
        x_num = c + _numeric_support(shape, n_b)
        x_sym = np.array(g.support_body.xreplace(subs), dtype=float).ravel()
        tol = 1e-6 if isinstance(shape, (Sphere, Ellipsoid)) else 1e-7
        assert np.allclose(x_sym, x_num, atol=tol), (x_sym, x_num)
        P = state[:3] + R @ x_num
        assert float(g.gap.xreplace(subs)) == pytest.approx(nu @ (P - p0), abs=tol)
        assert np.allclose(np.array(g.support.xreplace(subs), dtype=float).ravel(), P, atol=tol)
        # slip: the body's material point at P (x_num frozen in the body) by central differences
        h = 1e-6
        def material(s):
            sub = dict(zip(q, state + s * rates)) | {t: 0.4 + s}
            return state[:3] + s * rates[:3] + np.array(R_SYM.xreplace(sub), dtype=float) @ x_num
        v_body = (material(h) - material(-h)) / (2 * h)
        v_surf = np.array(surface.material_velocity(sp.Matrix(P)).xreplace(subs), dtype=float).ravel()
        t1, t2 = (np.array(e, dtype=float).ravel() for e in surface.tangents())
        U = np.array([float(u.xreplace(subs)) for u in g.slip])
        assert np.allclose(U, [t1 @ (v_body - v_surf), t2 @ (v_body - v_surf)], atol=1e-6)
        assert abs(t1 @ nu) < 1e-14 and abs(t2 @ nu) < 1e-14 and abs(np.cross(t1, t2) @ nu - 1) < 1e-14
        # angular velocity relative to the surface, split into spin and rolling
        dR = (np.array(R_SYM.xreplace(dict(zip(q, state + h * rates))), dtype=float)
              - np.array(R_SYM.xreplace(dict(zip(q, state - h * rates))), dtype=float)) / (2 * h)
        W = dR @ R.T
        w = np.array([W[2, 1], W[0, 2], W[1, 0]]) - np.array(surface.angular_velocity, dtype=float).ravel()
        spin, rolling = spin_and_rolling(g)
        assert float(spin.xreplace(subs)) == pytest.approx(w @ nu, abs=1e-7)
        assert np.allclose(np.array(rolling.xreplace(subs), dtype=float).ravel(), w - (w @ nu) * nu, atol=1e-7)
    assert checked >= 2


def test_tangents_follow_the_rule():
    t1, t2 = Plane((1, 0, 0)).tangents()          # N.x normal: t1 from N.y
    assert list(t1) == [0, 1, 0] and list(t2) == [0, 0, 1]
    t1, t2 = Plane((0, 1, 1)).tangents()
    assert list(t1) == [1, 0, 0]
    assert np.allclose(np.array(t2, dtype=float).ravel(), [0, np.sqrt(0.5), -np.sqrt(0.5)])


def test_validity_of_paraboloid_and_disk():
    n = sp.Matrix([0, 0, 1])
    assert Paraboloid((1, 2)).validity(n)[0] == 1
    assert Paraboloid((1, 2)).validity(-n)[0] == -1
    assert Disk(1, (0, 0, 1)).validity(n)[0] == 0      # lying flat
    assert Disk(1, (0, 1, 0)).validity(n)[0] == 1
    assert Sphere(1).validity(n) is None and Ellipsoid((1, 2, 3)).validity(n) is None
