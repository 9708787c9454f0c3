"""A rocket whose acceleration has a constant magnitude: a constraint nonlinear in q''.

Source: M. P. Yushkov (1999), ch. IV, sec. 5-6 and appendix D: the motion of an Earth
satellite whose acceleration, from some instant on, keeps a constant magnitude -- a second-order
nonholonomic constraint nonlinear in the accelerations, realized by a thrust of given direction
(the mixed problem of dynamics).  Here the field is uniform (a rocket near the ground), so that
the motion has a closed form up to one quadrature.

Model (``rocket_constant_acceleration.toml``).  A point of mass m in gravity g, coordinates
(x, y); the constraint ``x''^2 + y''^2 - w^2 = 0`` with ``reaction = v/|v|`` (the thrust T
along the velocity is its multiplier) and ``root = "largest"``.  With ``q'' = -g e_y + T e_v/m``
the constraint is the quadratic ``(T/m)^2 - 2 g sin(theta) T/m + g^2 - w^2 = 0`` (theta: the
angle of the velocity above the horizontal), whose largest root is the forward thrust

    T = m (g sin(theta) + sqrt(w^2 - g^2 cos^2(theta))).

Closed form (derived).  Along the velocity and across it,

    v' = sqrt(w^2 - g^2 cos^2(theta)),        v theta' = -g cos(theta),

so ``dv/dtheta = -v sqrt(w^2 - g^2 cos^2)/(g cos)`` and

    v(theta) = v0 exp(-I(theta)),   I(theta) = int_theta0^theta sqrt(w^2 - g^2 cos^2 s)/(g cos s) ds,
    t(theta) = int_theta^theta0 v(s) / (g cos s) ds.

``run`` checks the simulated speed and time against these quadratures at every sample, the
thrust against T(theta), and |r''| = w.  Without gravity (``g = 0``) the motion is a straight
line with ``v = v0 + w t``, ``T = m w`` (checked too).  With ``w < g`` the two roots meet where
``cos(theta) = w/g`` and no thrust along the velocity can keep |r''| = w: the run stops there
(exit code 3) -- ``run`` checks that the stop happens at that angle.

Misprints: none used (the source gives the satellite's equations; this uniform-field case is
derived here and checked by quadrature).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad

from ..modeling.model import Constraint, Model

NAME = "rocket-constant-acceleration"
ORDER = 62
TITLE = ("Rocket with |r''| = w, thrust along the velocity: a second-order constraint nonlinear "
         "in the accelerations (Yushkov 1999, ch. IV)")
FILE = "rocket_constant_acceleration.toml"

DEFAULTS = dict(m=2.0, g=9.81, w=15.0, v0=10.0, theta0=1.0)


def build(t_end: float = 2.0, root: str = "largest", **parameters) -> Model:
    """The rocket with the Python API (same as the model file by default)."""
    p = dict(DEFAULTS)
    p.update(parameters)
    return Model(
        name="Rocket with a constant-magnitude acceleration, thrust along the velocity",
        coordinates=["x", "y"], parameters=p,
        kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y",
        constraints=[Constraint.servo("thrust", "x''^2 + y''^2 - w^2",
                                      ["x'/sqrt(x'^2 + y'^2)", "y'/sqrt(x'^2 + y'^2)"], root=root)],
        initial={"x": 0, "y": 0, "x'": "v0*cos(theta0)", "y'": "v0*sin(theta0)"},
        simulation={"t_end": t_end, "rtol": 1e-12, "atol": 1e-13},
    )


def _I(theta, p):
    g, w = p["g"], p["w"]
    return quad(lambda s: np.sqrt(w * w - (g * np.cos(s)) ** 2) / (g * np.cos(s)), p["theta0"], theta,
                epsabs=1e-14, epsrel=1e-13)[0]


def speed(theta, p: dict) -> float:
    """``v(theta) = v0 exp(-I(theta))``."""
    return p["v0"] * np.exp(-_I(theta, p))


def time(theta, p: dict) -> float:
    """``t(theta) = int_theta^theta0 v(s)/(g cos s) ds``."""
    return quad(lambda s: speed(s, p) / (p["g"] * np.cos(s)), theta, p["theta0"],
                epsabs=1e-14, epsrel=1e-13)[0]


def thrust(theta, p: dict):
    """The forward thrust ``T = m (g sin(theta) + sqrt(w^2 - g^2 cos^2(theta)))``."""
    theta = np.asarray(theta, dtype=float)
    return p["m"] * (p["g"] * np.sin(theta) + np.sqrt(p["w"] ** 2 - (p["g"] * np.cos(theta)) ** 2))


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..errors import MechanicsError
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    times = np.linspace(0.0, model.simulation.t_end, 21)
    tr = simulate(model, times=times)
    xd, yd = tr.qd[:, 0], tr.qd[:, 1]
    theta, v = np.arctan2(yd, xd), np.hypot(xd, yd)
    err_v = max(abs(v[k] - speed(theta[k], p)) for k in range(len(times)))
    err_t = max(abs(times[k] - time(theta[k], p)) for k in range(len(times)))
    T = tr.multipliers["thrust"]
    err_T = float(np.max(np.abs(T - thrust(theta, p))))
    err_a = float(np.max(np.abs(np.hypot(tr.qdd[:, 0], tr.qdd[:, 1]) - p["w"])))
    # no gravity: a straight line, v = v0 + w t, T = m w
    free = simulate(build(g=0.0), times=times)
    v_free = np.hypot(free.qd[:, 0], free.qd[:, 1])
    err_free = float(max(np.max(np.abs(v_free - (p["v0"] + p["w"] * times))),
                         np.max(np.abs(free.multipliers["thrust"] - p["m"] * p["w"])),
                         np.max(np.abs(np.arctan2(free.qd[:, 1], free.qd[:, 0]) - p["theta0"]))))
    # w < g: the two roots meet where cos(theta) = w/g and the run stops there
    weak = dict(p, w=9.0)
    try:
        simulate(build(t_end=5.0, w=9.0))
        stop_angle = None
    except MechanicsError as exc:
        stop_angle = float(np.arctan2(exc.state["y'"], exc.state["x'"]))
    err_stop = abs(stop_angle - np.arccos(weak["w"] / weak["g"])) if stop_angle is not None else np.inf
    balance = tr.diagnostics["energy_balance_relative"]
    result = {
        "ok": err_v < 1e-8 and err_t < 1e-8 and err_T < 1e-8 and err_a < 1e-9 and err_free < 1e-8
        and err_stop < 1e-4 and balance < 1e-8,
        "max_error_speed": float(err_v), "max_error_time": float(err_t),
        "max_error_thrust": err_T, "max_error_acceleration_magnitude": err_a,
        "max_error_free_space": err_free,
        "weak_thrust_stop_angle": stop_angle, "error_stop_angle": float(err_stop),
        "thrust_start": float(T[0]), "thrust_end": float(T[-1]),
        "thrust_work": float(tr.controls["thrust"]["work"][-1]),
        "energy_balance_relative": balance,
    }
    if verbose:
        print(TITLE)
        print(f"m = {p['m']}, g = {p['g']}, w = {p['w']}, v0 = {p['v0']}, theta0 = {p['theta0']}")
        print(f"  max |v - v0 exp(-I(theta))|          = {err_v:.2e}")
        print(f"  max |t - t(theta)| (quadrature)      = {err_t:.2e}")
        print(f"  max |T - m(g sin + sqrt(w^2 - g^2 cos^2))| = {err_T:.2e}   (T: {T[0]:.6f} -> {T[-1]:.6f} N)")
        print(f"  max ||r''| - w|                      = {err_a:.2e}")
        print(f"  no gravity: v = v0 + w t, T = m w     : {err_free:.2e}")
        print(f"  w = 9 < g: stops at theta = {stop_angle:.6f}, acos(w/g) = {np.arccos(9.0 / p['g']):.6f}")
        print(f"  work of the thrust = {result['thrust_work']:.9f} J, energy balance {balance:.2e}")
        print("ok" if result["ok"] else "FAILED")
    return result
