"""Free motion of the Chaplygin sleigh.

Source: M. P. Yushkov, *Equations of motion of nonholonomic systems and variational
principles of mechanics* (1999), appendix A, sec. 2 "free motion of the Chaplygin sleigh".
The appendix text is not in the paper (only its table of contents), so the closed form below
is derived here and checked against the simulation and against every form of the equations.

Model.  A planar rigid body (mass m, central moment of inertia I) with a knife edge at the
point C = (x, y); the centre of mass G is at distance a ahead of C on the body axis, which
makes the angle theta with Ox.  The knife edge is the nonholonomic constraint

    phi = -x' sin(theta) + y' cos(theta) = 0       (no velocity of C across the axis).

Equations.  With v = x' cos(theta) + y' sin(theta) (speed of C along the axis),
omega = theta' and J = I + m a^2, the Maggi equations reduce to

    m (v' - a omega^2) = 0,        J omega' = -m a v omega,

and the reaction of the knife edge (force on C across the axis) is
N = lambda = m (v omega + a omega') = m I v omega / J.

Closed form (derived).  The energy E = m v^2/2 + J omega^2/2 is conserved; with
V = sqrt(2E/m), k = m a V / J and c0 = artanh(v0/V):

    v(t) = V tanh(k t + c0),
    omega(t) = omega0 cosh(c0) / cosh(k t + c0),
    theta(t) = theta0 + (omega0 cosh(c0)/k) (gd(k t + c0) - gd(c0)),   gd = Gudermann function,

so the sleigh turns by a finite total angle and ends moving straight at speed V.  x(t), y(t)
follow by quadrature of v cos(theta), v sin(theta).

Free motion with zero reaction (appendix A's question).  N = m I v omega / J vanishes along a
curved motion only if I = 0: all the mass at G.  Then G moves uniformly in a straight line and
the knife edge C trails behind it (a tractrix); the multiplier is identically zero.  ``run``
checks both cases.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad

from ..modeling.bodies import PlanarBody
from ..modeling.model import Constraint, Model

NAME = "chaplygin-sleigh"
ORDER = 10
TITLE = "Chaplygin sleigh, free motion: closed form v = V tanh(kt + c0) (Yushkov 1999, app. A)"
FILE = "chaplygin_sleigh.toml"


def build(m: float = 2.0, I: float = 0.3, a: float = 0.4, v0: float = 1.0, omega0: float = 1.5,
          t_end: float = 5.0) -> Model:
    """The sleigh with the Python API (same as the model file for the default values)."""
    return Model(
        name="Chaplygin sleigh, free motion",
        coordinates=["x", "y", "theta"],
        parameters={"m": m, "I": I, "a": a},
        bodies=[PlanarBody("sleigh", "m", "I", ["x + a*cos(theta)", "y + a*sin(theta)"], "theta")],
        constraints=[Constraint.nonholonomic("knife", "-x'*sin(theta) + y'*cos(theta)")],
        initial={"x": 0.0, "y": 0.0, "theta": 0.0, "x'": v0, "theta'": omega0},
        simulation={"t_end": t_end},
    )


def closed_form(t, m, I, a, v0, omega0, theta0=0.0):
    """``v(t), omega(t), theta(t)`` of the free motion (see the module docstring)."""
    t = np.asarray(t, dtype=float)
    J = I + m * a * a
    E = 0.5 * m * v0 ** 2 + 0.5 * J * omega0 ** 2
    V = np.sqrt(2 * E / m)
    k = m * a * V / J
    c0 = np.arctanh(v0 / V)

    def gd(u):
        return 2 * np.arctan(np.tanh(u / 2))
    v = V * np.tanh(k * t + c0)
    omega = omega0 * np.cosh(c0) / np.cosh(k * t + c0)
    theta = theta0 + omega0 * np.cosh(c0) / k * (gd(k * t + c0) - gd(c0))
    return v, omega, theta


def position(t, m, I, a, v0, omega0):
    """``x(t), y(t)`` of the knife edge by quadrature of the closed form."""
    def vx(s):
        v, _, th = closed_form(s, m, I, a, v0, omega0)
        return float(v * np.cos(th))

    def vy(s):
        v, _, th = closed_form(s, m, I, a, v0, omega0)
        return float(v * np.sin(th))
    return (quad(vx, 0, t, epsabs=1e-13, epsrel=1e-13, limit=200)[0],
            quad(vy, 0, t, epsabs=1e-13, epsrel=1e-13, limit=200)[0])


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..equations.formalisms import FORMS, derive
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    m, I, a = p["m"], p["I"], p["a"]
    v0, omega0 = 1.0, 1.5
    times = np.linspace(0.0, model.simulation.t_end, 11)
    traj = simulate(model, times=times)
    th = traj.coordinate("theta")
    v = traj.velocity("x") * np.cos(th) + traj.velocity("y") * np.sin(th)
    v_cf, w_cf, th_cf = closed_form(times, m, I, a, v0, omega0)
    err_v = float(np.max(np.abs(v - v_cf)))
    err_w = float(np.max(np.abs(traj.velocity("theta") - w_cf)))
    err_th = float(np.max(np.abs(th - th_cf)))
    x_end, y_end = position(times[-1], m, I, a, v0, omega0)
    err_xy = float(np.hypot(traj.coordinate("x")[-1] - x_end, traj.coordinate("y")[-1] - y_end))
    N_cf = m * I * v_cf * w_cf / (I + m * a * a)
    err_N = float(np.max(np.abs(traj.multipliers["knife"] - N_cf)))
    forms = {f: derive(model, f) for f in FORMS}

    # appendix A: all the mass at G -> zero reaction, G in uniform straight motion
    free = build(I=0.0)
    tr0 = simulate(free, times=np.linspace(0, 3, 7))
    lam0 = float(np.max(np.abs(tr0.multipliers["knife"])))
    xg = tr0.coordinate("x") + a * np.cos(tr0.coordinate("theta"))
    yg = tr0.coordinate("y") + a * np.sin(tr0.coordinate("theta"))
    vg = np.array([xg[-1] - xg[0], yg[-1] - yg[0]]) / 3.0
    vg0 = np.array([v0, a * omega0])
    uniform = float(np.max(np.abs(np.diff(xg) / 0.5 - vg[0])) + np.max(np.abs(np.diff(yg) / 0.5 - vg[1])))

    result = {
        "ok": max(err_v, err_w, err_th, err_xy, err_N) < 1e-8 and lam0 < 1e-9 and uniform < 1e-8
        and np.allclose(vg, vg0, atol=1e-8),
        "max_error_v": err_v, "max_error_omega": err_w, "max_error_theta": err_th,
        "error_position_end": err_xy, "max_error_reaction": err_N,
        "theta_end": float(th[-1]), "v_end": float(v[-1]),
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
        "constraint_residual_max": traj.diagnostics["constraint_residual_max"],
        "zero_reaction_max_lambda": lam0, "zero_reaction_G_velocity": vg.tolist(),
        "forms": list(forms),
    }
    if verbose:
        print(TITLE)
        print(forms["maggi"].as_text())
        print(f"simulation vs closed form over t in [0, {times[-1]:g}]:")
        print(f"  max |v - V tanh(kt+c0)|          = {err_v:.2e}")
        print(f"  max |omega - closed form|        = {err_w:.2e}")
        print(f"  max |theta - closed form|        = {err_th:.2e}   theta(t_end) = {th[-1]:.12f}")
        print(f"  |(x, y)(t_end) - quadrature|     = {err_xy:.2e}")
        print(f"  max |lambda - m I v omega / J|   = {err_N:.2e}")
        print(f"  energy balance (relative)        = {result['energy_balance_relative']:.2e}")
        print(f"  constraint residual              = {result['constraint_residual_max']:.2e}")
        print(f"I = 0 (mass at G): max |lambda| = {lam0:.2e}; G velocity = {vg} (expected {vg0})")
        print("ok" if result["ok"] else "FAILED")
    return result
