"""A ball rolling without slipping off a fixed sphere: ideal rolling while in contact, lift-off
where the normal force vanishes, then free flight.

Source: the classical problem of a body leaving a sphere (for a sliding particle the answer is
cos = 2/3); for a rolling ball the closed form is derived here.

Model.  A homogeneous ball (mass m, radius r, I = 2/5 m r^2) on top of a fixed sphere of radius
R, in the vertical plane.  Coordinates: the ball's centre (x, y) (origin at the centre of the
fixed sphere, y up) and its rotation angle phi (counter-clockwise):

    T = m (x'^2 + y'^2)/2 + I phi'^2/2,        V = m g y.

Contact ``sphere``: gap ``g = sqrt(x^2 + y^2) - (R + r) >= 0`` (its multiplier is the normal
force N), slip = the tangential velocity of the ball's point in contact,
``U = (x y' - y x')/sqrt(x^2 + y^2) - r phi'``, and ``mu = "inf"``: ideal rolling while the gap
is closed -- ``U = 0`` is an ideal nonholonomic constraint whose multiplier, the friction force,
is whatever rolling needs (no friction limit, no sliding, no friction work); the contact
releases with the gap, when N reaches 0.

Closed form.  Let theta be the angle of the line of centres from the vertical,
``rho = R + r``.  While rolling the centre moves on the circle of radius rho and the ball turns
at ``omega = rho theta'/r`` (absolute), so

    T = m rho^2 theta'^2/2 + (2/5 m r^2)(rho theta'/r)^2/2 = 7/10 m rho^2 theta'^2,

and energy conservation (the rolling reaction does no work) from ``theta0``, ``theta'(0) = w0``:

    rho theta'^2 = rho w0^2 + (10/7) g (cos theta0 - cos theta).

The radial equation ``m g cos theta - N = m rho theta'^2`` gives the normal force
``N = m ((17/7) g cos theta - (10/7) g cos theta0 - rho w0^2)`` and the tangential one with the
moment equation the friction force ``F = (2/7) m g sin theta`` (the ball's angular acceleration
``theta'' = (5/7) g sin theta / rho``).  The ball lifts off at N = 0:

    cos theta* = (10 cos theta0 + 7 rho w0^2 / g) / 17        (= 10/17 from rest at the top),

at the time ``t* = integral from theta0 to theta* of d theta / theta'`` (a quadrature; the
substitution ``theta = theta0 + u^2`` removes the 1/sqrt singularity of a start from rest).
Then the ball flies freely: the centre on the parabola from the lift-off point with the velocity
``rho theta'*`` along the tangent, the spin ``phi' = -rho theta'*/r`` constant.  Note that
``F/N`` grows without bound as N -> 0: rolling to the very end needs an unbounded friction
coefficient -- with a finite mu the ball slips just before it leaves (at ``N = F/mu``); with
mu = 1e9 the difference is below 1e-9 and the simulation lifts off at the same angle.

Checks (``run``): the lift-off angle against the closed form to 1e-8 and the lift-off time
against the quadrature; N and F along the rolling phase; the free flight after it (state at
t_end from the closed-form lift-off state); energy conserved and no friction work; the same
with an initial speed w0; and with a finite mu = 1e9 (Coulomb's law) the same lift-off, without
a Painleve diagnosis at the instant the normal force vanishes.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad

from ..modeling.contacts import Contact, Coulomb, IdealRolling
from ..modeling.model import Model

NAME = "ball-off-sphere"
ORDER = 46
TITLE = ("Ball rolling off a fixed sphere (mu = inf: ideal rolling while in contact): lifts off at "
         "cos = 10/17, then free flight")
FILE = "ball_off_sphere.toml"


def build(m: float = 1.0, g: float = 9.81, R: float = 1.0, r: float = 0.25, theta0: float = 0.1,
          w0: float = 0.0, mu: float | None = None, t_end: float = 2.0) -> Model:
    """The ball with the Python API (same as the model file for the default values); *mu*
    (a number) replaces ideal rolling by Coulomb's law with that coefficient."""
    friction = IdealRolling() if mu is None else Coulomb(mu)
    return Model(
        name="Ball rolling off a fixed sphere (ideal rolling, lift-off at cos = 10/17)",
        coordinates=["x", "y", "phi"],
        parameters={"m": m, "g": g, "R": R, "r": r, "theta0": theta0, "w0": w0},
        kinetic="m/2*(x'^2 + y'^2) + (2*m*r^2/5)/2*phi'^2",
        potential="m*g*y",
        contacts=[Contact("sphere", "sqrt(x^2 + y^2) - (R + r)",
                          ("(x*y' - y*x')/sqrt(x^2 + y^2) - r*phi'",), friction)],
        initial={"x": "(R + r)*sin(theta0)", "y": "(R + r)*cos(theta0)", "phi": 0.0,
                 "x'": "(R + r)*w0*cos(theta0)", "y'": "-(R + r)*w0*sin(theta0)",
                 "phi'": "-(R + r)*w0/r"},
        simulation={"t_end": t_end},
    )


def closed_form(p: dict) -> dict:
    """Lift-off angle, time and state for parameters *p* (see the docstring)."""
    g, rho, r, th0, w0 = p["g"], p["R"] + p["r"], p["r"], p["theta0"], p.get("w0", 0.0)
    k = 10.0 * g / (7.0 * rho)
    cos_star = (10.0 * np.cos(th0) + 7.0 * rho * w0 * w0 / g) / 17.0
    th_star = float(np.arccos(cos_star))

    def rate(th):  # cos a - cos b written as a product: no cancellation near the start
        return np.sqrt(w0 * w0 + 2.0 * k * np.sin((th0 + th) / 2) * np.sin((th - th0) / 2))

    def integrand(u):  # theta = theta0 + u^2, d theta = 2 u du
        if u == 0.0:
            return 0.0 if w0 else 2.0 / np.sqrt(k * np.sin(th0))
        return 2.0 * u / rate(th0 + u * u)

    t_star, _ = quad(integrand, 0.0, np.sqrt(th_star - th0), epsabs=1e-14, epsrel=1e-13, limit=200)
    w = float(rate(th_star))
    s, c = np.sin(th_star), np.cos(th_star)
    return {"cos_theta": float(cos_star), "theta": th_star, "t": float(t_star), "theta_rate": w,
            "q": np.array([rho * s, rho * c, -rho * (th_star - th0) / r]),
            "qd": np.array([rho * w * c, -rho * w * s, -rho * w / r])}


def forces(theta, p: dict) -> tuple[np.ndarray, np.ndarray]:
    """Normal force N and friction magnitude |F| while rolling, at the angles *theta*."""
    m, g, rho, th0, w0 = p["m"], p["g"], p["R"] + p["r"], p["theta0"], p.get("w0", 0.0)
    theta = np.asarray(theta, dtype=float)
    N = m * (17.0 / 7.0 * g * np.cos(theta) - 10.0 / 7.0 * g * np.cos(th0) - rho * w0 * w0)
    return N, 2.0 / 7.0 * m * g * np.abs(np.sin(theta))


def flight(t: float, cf: dict, p: dict) -> tuple[np.ndarray, np.ndarray]:
    """State ``(q, q')`` at time *t* after the lift-off *cf* (free flight)."""
    s = t - cf["t"]
    q = cf["q"] + cf["qd"] * s + np.array([0.0, -p["g"] * s * s / 2, 0.0])
    qd = cf["qd"] + np.array([0.0, -p["g"] * s, 0.0])
    return q, qd


def check(model: Model) -> dict:
    """Simulate *model* and compare with the closed form."""
    from ..simulation.hybrid import simulate

    p = dict(model.parameter_values)
    cf = closed_form(p)
    at_lift = simulate(model, stop_on={"lift-off"})
    q1, qd1 = at_lift.q[-1], at_lift.qd[-1]
    theta1 = float(np.arctan2(q1[0], q1[1]))
    rolling_times = np.linspace(model.t0, 0.95 * cf["t"], 20)
    sampled = simulate(model, times=rolling_times)
    x, y = sampled.coordinate("x"), sampled.coordinate("y")
    N_cf, F_cf = forces(np.arctan2(x, y), p)
    ct = sampled.contacts["sphere"]
    N_sim = np.array(ct["normal"], dtype=float)
    F_sim = np.linalg.norm(np.array(ct["friction"], dtype=float), axis=1)
    full = simulate(model)
    q_end, qd_end = flight(full.t[-1], cf, p)
    scale = 1.0 + np.max(np.abs(q_end)) + np.max(np.abs(qd_end))
    return {
        "theta_lift": theta1, "theta_closed_form": cf["theta"],
        "theta_error": abs(theta1 - cf["theta"]),
        "cos_lift": float(q1[1] / (p["R"] + p["r"])), "cos_closed_form": cf["cos_theta"],
        "t_lift": float(at_lift.t[-1]), "t_closed_form": cf["t"],
        "t_error": abs(float(at_lift.t[-1]) - cf["t"]),
        "lift_state_error": float(max(np.max(np.abs(q1 - cf["q"])), np.max(np.abs(qd1 - cf["qd"])))),
        "normal_error": float(np.max(np.abs(N_sim - N_cf)) / (p["m"] * p["g"])),
        "friction_error": float(np.max(np.abs(F_sim - F_cf)) / (p["m"] * p["g"])),
        "events": [(e["t"], e["type"], e["mode"]) for e in full.events],
        "flight_error": float(max(np.max(np.abs(full.q[-1] - q_end)),
                                  np.max(np.abs(full.qd[-1] - qd_end))) / scale),
        "min_gap_after": float(np.min(np.array(full.contacts["sphere"]["gap"])[full.t > cf["t"] + 1e-6])),
        "friction_work": float(np.max(np.abs(full.energy["friction_work"]))),
        "energy_balance_relative": full.diagnostics["energy_balance_relative"],
        "constraint_residual_max": full.diagnostics["constraint_residual_max"],
    }


def _ok(r: dict, theta_tol: float) -> bool:
    return (r["theta_error"] < theta_tol and r["t_error"] < 1e-7 and r["lift_state_error"] < 1e-6
            and r["normal_error"] < 1e-8 and r["friction_error"] < 1e-8 and r["flight_error"] < 1e-8
            and [e[1] for e in r["events"]] == ["lift-off"] and r["min_gap_after"] > 0
            and r["friction_work"] < 1e-8 and abs(r["energy_balance_relative"]) < 1e-8)


def run(verbose: bool = True) -> dict:
    from .. import gallery

    cases = {
        "from rest, theta0 = 0.1 (mu = inf)": (gallery.load(NAME), 1e-8),
        "launched, theta0 = 0.05, w0 = 1 rad/s (mu = inf)": (build(theta0=0.05, w0=1.0), 1e-8),
        "from rest, Coulomb with mu = 1e9": (build(mu=1e9), 1e-6),
    }
    results = {}
    ok = True
    for label, (model, tol) in cases.items():
        r = check(model)
        r["ok"] = _ok(r, tol)
        ok &= r["ok"]
        results[label] = r
    out = {"ok": bool(ok), "cases": results}
    if verbose:
        print(TITLE)
        for label, r in results.items():
            print(f"{label}:")
            print(f"  lift-off: cos(theta) = {r['cos_lift']:.12f} (closed form "
                  f"(10 cos theta0 + 7 rho w0^2/g)/17 = {r['cos_closed_form']:.12f}), angle error "
                  f"{r['theta_error']:.1e} rad")
            print(f"  lift-off time t = {r['t_lift']:.12f} (quadrature {r['t_closed_form']:.12f}, "
                  f"error {r['t_error']:.1e} s); events {[(round(e[0], 9), e[1], e[2]) for e in r['events']]}")
            print(f"  while rolling: N and |F| vs closed form {r['normal_error']:.1e}, "
                  f"{r['friction_error']:.1e} (of m g); free flight at t_end {r['flight_error']:.1e}; "
                  f"friction work {r['friction_work']:.1e}; energy balance {r['energy_balance_relative']:.1e}")
        print("ok" if ok else "FAILED")
    return out
