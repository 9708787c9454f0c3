"""Spherical pendulum of variable length: the multiplier is the thread tension.

Source: M. P. Yushkov, *Equations of motion of nonholonomic systems and variational
principles of mechanics* (1999), ch. I, sec. 1, eq. (1.11): the length of a spherical
pendulum is changed by a prescribed law, ``y1^2 + y2^2 + y3^2 - l^2(t) = 0``; when the
constraint is realized by pulling the thread in, its reaction is the tension N, normal to the
sphere of the moment, and the constraint is ideal (``T0 = 0`` in Yushkov's notation).

Model.  A point of mass m at r = (x, y, z) (z up, suspension point at the origin) under
gravity -g e_z, on a thread of prescribed length

    l(t) = l0 (1 - eps sin(w t)).

The constraint is written ``f = l(t) - |r| = 0`` (not Yushkov's squared form): then
``grad f = -r/|r| = -e_r`` and the reaction ``lambda grad f = -lambda e_r`` points from the
bob to the suspension point, so **lambda = N, the tension**, with no normalization factor
(Yushkov's ``|r|^2 - l^2`` would give N = 2 l lambda, with the opposite sign).

Closed form of the tension (derived).  With spherical angles (theta from the downward
vertical, phi the azimuth), r = l (sin(theta) cos(phi), sin(theta) sin(phi), -cos(theta)), the
radial component of m r'' = -N e_r - m g e_z is

    m (l'' - l (theta'^2 + sin^2(theta) phi'^2)) = -N + m g cos(theta),

    N = m (l (theta'^2 + sin^2(theta) phi'^2) - l'') + m g cos(theta),          (*)

with l'' = l0 eps w^2 sin(w t).  ``run`` computes theta, phi, theta', phi' from the simulated
Cartesian state and checks (*) against the multiplier.

Energy.  The constraint is rheonomic, so the ideal reaction does work on the real motion
(not on virtual displacements): ``d(T + V)/dt = -N l'``.  The simulation integrates this
power as ``energy["reaction_work"]``; ``run`` checks it against a Simpson quadrature of
``-N l'`` built from (*) and checks the balance ``E - E0 = W_R``.

Independent check.  The same pendulum in the minimal coordinates (theta, phi), with the
rheonomic kinetic energy ``T = m/2 (l'^2 + l^2 theta'^2 + l^2 sin^2(theta) phi'^2)`` and
``V = -m g l cos(theta)`` (``build_spherical``), must give the same motion.

Misprints.  None in (1.11) itself (the printed equation is garbled by the scan; its content is
``y1^2 + y2^2 + y3^2 - l^2(t) = 0``).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import simpson

from ..modeling.bodies import Particle
from ..modeling.model import Constraint, Model

NAME = "spherical-pendulum-variable-length"
ORDER = 20
TITLE = "Spherical pendulum of variable length: multiplier = thread tension (Yushkov 1999, (1.11))"
FILE = "spherical_pendulum_variable_length.toml"

LENGTH = "l0*(1 - eps*sin(w*t))"
LENGTH_RATE = "(-l0*eps*w*cos(w*t))"


def _parameters(m, g, l0, eps, w, theta0, phi0d):
    return {"m": m, "g": g, "l0": l0, "eps": eps, "w": w, "theta0": theta0, "phi0d": phi0d}


def build(m: float = 1.0, g: float = 9.81, l0: float = 1.0, eps: float = 0.1, w: float = 3.0,
          theta0: float = 0.6, phi0d: float = 2.0, t_end: float = 5.0) -> Model:
    """The pendulum in Cartesian coordinates (same as the model file for the default values)."""
    return Model(
        name="Spherical pendulum of variable length",
        coordinates=["x", "y", "z"],
        parameters=_parameters(m, g, l0, eps, w, theta0, phi0d),
        bodies=[Particle("bob", "m", ["x", "y", "z"])],
        gravity=["0", "0", "-g"],
        constraints=[Constraint.holonomic("thread", f"{LENGTH} - sqrt(x^2 + y^2 + z^2)")],
        initial={"x": "l0*sin(theta0)", "y": 0.0, "z": "-l0*cos(theta0)",
                 "x'": "-eps*w*l0*sin(theta0)", "y'": "l0*sin(theta0)*phi0d",
                 "z'": "eps*w*l0*cos(theta0)"},
        simulation={"t_end": t_end},
    )


def build_spherical(m: float = 1.0, g: float = 9.81, l0: float = 1.0, eps: float = 0.1,
                    w: float = 3.0, theta0: float = 0.6, phi0d: float = 2.0,
                    t_end: float = 5.0) -> Model:
    """The same pendulum in the minimal coordinates (theta, phi): an independent model."""
    L, Ld = LENGTH, LENGTH_RATE
    return Model(
        name="Spherical pendulum of variable length (theta, phi)",
        coordinates=["theta", "phi"],
        parameters=_parameters(m, g, l0, eps, w, theta0, phi0d),
        kinetic=f"m/2*({Ld}^2 + ({L})^2*theta'^2 + ({L})^2*sin(theta)^2*phi'^2)",
        potential=f"-m*g*({L})*cos(theta)",
        initial={"theta": "theta0", "phi": 0.0, "theta'": 0.0, "phi'": "phi0d"},
        simulation={"t_end": t_end},
    )


def length(t, l0, eps, w):
    """``l, l', l''`` of the thread at times *t*."""
    t = np.asarray(t, dtype=float)
    return (l0 * (1 - eps * np.sin(w * t)), -l0 * eps * w * np.cos(w * t),
            l0 * eps * w * w * np.sin(w * t))


def spherical_state(q, qd):
    """``theta, phi, theta', phi'`` from Cartesian positions/velocities (arrays (N, 3))."""
    x, y, z = q.T
    xd, yd, zd = qd.T
    rho2 = x * x + y * y
    r2 = rho2 + z * z
    rho = np.sqrt(rho2)
    theta = np.arctan2(rho, -z)
    phi = np.arctan2(y, x)
    rhod = (x * xd + y * yd) / rho
    thetad = (-z * rhod + rho * zd) / r2
    phid = (x * yd - y * xd) / rho2
    return theta, phi, thetad, phid


def tension(t, q, qd, m, g, l0, eps, w):
    """The tension (*) of the module docstring at simulated Cartesian states."""
    theta, _, thetad, phid = spherical_state(q, qd)
    ell, _, elldd = length(t, l0, eps, w)
    return m * (ell * (thetad ** 2 + np.sin(theta) ** 2 * phid ** 2) - elldd) + m * g * np.cos(theta)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..errors import FormNotApplicable
    from ..equations.formalisms import FORMS
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    m, g, l0, eps, w = p["m"], p["g"], p["l0"], p["eps"], p["w"]
    t_end = model.simulation.t_end
    times = np.linspace(0.0, t_end, 2001)
    traj = simulate(model, times=times)
    N_cf = tension(times, traj.q, traj.qd, m, g, l0, eps, w)
    N = traj.multipliers["thread"]
    err_N = float(np.max(np.abs(N - N_cf)) / np.max(np.abs(N_cf)))
    _, ld, _ = length(times, l0, eps, w)
    W_quad = simpson(-N_cf * ld, x=times)
    W_R = traj.energy["reaction_work"]
    err_W = abs(W_R[-1] - W_quad)
    E = traj.energy["energy"]
    err_balance = float(np.max(np.abs(E - E[0] - W_R)))
    ell = np.linalg.norm(traj.q, axis=1)
    err_len = float(np.max(np.abs(ell - length(times, l0, eps, w)[0])))

    sph = simulate(build_spherical(**{k: p[k] for k in ("m", "g", "l0", "eps", "w", "theta0", "phi0d")},
                                   t_end=t_end), times=times[::100])
    th, ph, _, _ = spherical_state(traj.q[::100], traj.qd[::100])
    err_sph = float(max(np.max(np.abs(th - sph.coordinate("theta"))),
                        np.max(np.abs(np.unwrap(ph) - sph.coordinate("phi")))))

    forms = {}
    for f in list(FORMS) + ["gauss"]:
        if f == "lagrange1":
            continue
        try:
            forms[f] = compare_forms(model, forms=[f], count=10).worst()
        except FormNotApplicable as exc:
            forms[f] = f"not applicable: {exc}"
    worst_form = max([v for v in forms.values() if isinstance(v, float)] + [0.0])

    result = {
        "ok": err_N < 1e-9 and err_W < 1e-8 and err_balance < 1e-8 and err_len < 1e-8
        and err_sph < 1e-8 and worst_form < 1e-10
        and traj.diagnostics["energy_balance_relative"] < 1e-8
        and traj.diagnostics["constraint_residual_max"] < 1e-8,
        "max_relative_error_tension": err_N,
        "tension_min": float(N.min()), "tension_max": float(N.max()),
        "reaction_work_end": float(W_R[-1]), "reaction_work_quadrature": float(W_quad),
        "energy_change_end": float(E[-1] - E[0]),
        "max_error_energy_balance": err_balance,
        "max_error_length": err_len,
        "max_error_vs_spherical_model": err_sph,
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
        "constraint_residual_max": traj.diagnostics["constraint_residual_max"],
        "forms": forms,
    }
    if verbose:
        print(TITLE)
        print(f"l(t) = l0 (1 - eps sin(w t)), l0 = {l0}, eps = {eps}, w = {w}; t in [0, {t_end:g}]")
        print(f"  max |lambda - N(*)| / max N            = {err_N:.2e}   (N in [{N.min():.6f}, {N.max():.6f}])")
        print(f"  work of the tension W_R(t_end)          = {W_R[-1]:.12f}")
        print(f"  Simpson quadrature of -N l'              = {W_quad:.12f}   (diff {err_W:.2e})")
        print(f"  max |E - E0 - W_R|                       = {err_balance:.2e}")
        print(f"  max | |r| - l(t) |                       = {err_len:.2e}")
        print(f"  max |(theta, phi) - minimal-coordinate model| = {err_sph:.2e}")
        print(f"  energy balance (relative)                = {result['energy_balance_relative']:.2e}")
        print(f"  constraint residual                      = {result['constraint_residual_max']:.2e}")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v if isinstance(v, str) else f'{v:.2e}'}")
        print("ok" if result["ok"] else "FAILED")
    return result
