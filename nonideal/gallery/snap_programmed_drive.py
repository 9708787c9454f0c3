"""A drive with a constant-snap program: a constraint of order four, its force and the force's
rate part of the state.

Source: M. P. Yushkov (1999), ch. IV, secs. 5 and 7 (ideal nonholonomic constraints of order n,
the mixed problem of dynamics; linear constraints of order n >= 3, whose multipliers are unknown
functions of time governed by differential equations of their own).  The system is a
textbook-sized one chosen for its closed form; it continues ``jerk-programmed-drive`` one order
up.

Model (``snap_programmed_drive.toml``).  A mass m on a horizontal table, held by the springs
``kx`` (along x) and ``ky`` (along y); coordinates (x, y).  A drive realizes the program

    x'''' = s0                                                              (constant snap)

with a force of fixed direction ``(cos alpha, sin alpha)``: ``reaction = [cos(alpha),
sin(alpha)]``, the force's size ``lambda`` is the constraint's multiplier.  The equations

    m x'' + kx x = lambda cos(alpha),       m y'' + ky y = lambda sin(alpha)

contain lambda, so ``x'''`` contains ``lambda'`` and ``x''''`` contains ``lambda''``: the program
is a second-order differential equation for the force, ``lambda'' cos(alpha) = m s0 + kx x''``,
and ``lambda(t0)``, ``lambda'(t0)`` must be given (``[initial] lambda_drive = F0``,
``"lambda_drive'" = F1``); the state is (x, y, x', y', lambda, lambda').

Closed form (derived).  With ``a0 = (F0 cos(alpha) - kx x0)/m`` and ``j0 = (F1 cos(alpha) - kx
v0)/m`` (the acceleration and the jerk at t0),

    x = x0 + v0 t + a0 t^2/2 + j0 t^3/6 + s0 t^4/24,
    lambda = (m x'' + kx x) / cos(alpha)                      (a quartic in t),
    y = P/w^2 - P''/w^4 + P''''/w^6 + A cos(w t) + B sin(w t),   w^2 = ky/m,   P = lambda sin(alpha)/m,

A and B from y(0) = 0, y'(0) = 0 (P is a quartic, so the three terms solve ``y'' + w^2 y = P``
exactly).  The same motion is the jerk program ``x''' = j0 + s0 t`` of order three started with
``lambda(t0) = F0``: ``run`` checks both.

Variant, by ``build``: ``ideal=True`` -- the program without ``reaction``: an ideal constraint of
order four.  The generalized Gauss principle of order four (among the fourth derivatives the
constraint allows, the actual one is the closest, in the metric of M, to the one with the
reaction's second derivative held at zero) gives ``R'' = Lambda (d f/d q'''')^T = Lambda (1,
0)``: the reaction's second derivative is along x, so ``R_y = R0y + R1y t`` keeps its initial
rate, ``R_x = m x'' + kx x``, ``Lambda = m s0 + kx x''``.  The initial reaction and its rate are
lists, ``lambda_drive = [F0, R0y]``, ``"lambda_drive'" = [F1, R1y]``; y is then driven by the
linear force ``R_y``: ``y = R_y/ky + A cos(w t) + B sin(w t)``.

Misprints: none used (the closed forms are derived here and checked against the simulation).
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import Polynomial

from ..modeling.model import Constraint, Model

NAME = "snap-programmed-drive"
ORDER = 63.5
TITLE = ("Drive with a constant-snap program x'''' = s0: a constraint of order four whose force "
         "and its rate are part of the state (Yushkov 1999, ch. IV)")
FILE = "snap_programmed_drive.toml"

DEFAULTS = dict(m=2.0, kx=3.0, ky=5.0, s0=0.6, alpha=0.4, F0=1.5, F1=0.5)
X0, V0 = 0.1, 0.2
R0Y, R1Y = 0.5, -0.3


def build(t_end: float = 2.0, ideal: bool = False, **parameters) -> Model:
    """The drive with the Python API (same as the model file by default).  ``ideal=True``: the
    program without a reaction direction (initial reaction ``(F0, R0Y)``, its rate ``(F1,
    R1Y)``)."""
    p = dict(DEFAULTS)
    p.update(parameters)
    if ideal:
        drive = Constraint("drive", "x'''' - s0", initial=(("F0", R0Y), ("F1", R1Y)))
    else:
        drive = Constraint.servo("drive", "x'''' - s0", ["cos(alpha)", "sin(alpha)"], initial=("F0", "F1"))
    return Model(
        name="Drive with a constant-snap program x'''' = s0 on a sprung mass",
        coordinates=["x", "y"], parameters=p,
        kinetic="m/2*(x'^2 + y'^2)", potential="kx/2*x^2 + ky/2*y^2",
        constraints=[drive],
        initial={"x": X0, "y": 0, "x'": V0, "y'": 0},
        simulation={"t_end": t_end, "rtol": 1e-12, "atol": 1e-13},
    )


def closed_form(t, p: dict, ideal: bool = False):
    """``(x, y, force)`` at the times *t*: the force is lambda (along the reaction) or R_x
    (ideal)."""
    t = np.asarray(t, dtype=float)
    m, kx, ky, ca, sa = p["m"], p["kx"], p["ky"], np.cos(p["alpha"]), np.sin(p["alpha"])
    fx0, fx1 = (p["F0"], p["F1"]) if ideal else (p["F0"] * ca, p["F1"] * ca)
    a0, j0 = (fx0 - kx * X0) / m, (fx1 - kx * V0) / m
    x = Polynomial([X0, V0, a0 / 2, j0 / 6, p["s0"] / 24])
    w2 = ky / m
    if ideal:
        force = m * x.deriv(2) + kx * x
        P = Polynomial([R0Y, R1Y]) / m
    else:
        force = (m * x.deriv(2) + kx * x) / ca
        P = force * (sa / m)
    yp = P / w2 - P.deriv(2) / w2 ** 2 + P.deriv(4) / w2 ** 3
    w = np.sqrt(w2)
    A, B = -yp(0.0), -yp.deriv()(0.0) / w
    y = yp(t) + A * np.cos(w * t) + B * np.sin(w * t)
    return x(t), y, force(t)


def jerk_program(p: dict) -> Model:
    """The same drive as a program of order three, ``x''' = j0 + s0 t``, started with the force
    ``F0``: the motion of the snap program, one order lower."""
    j0 = (p["F1"] * np.cos(p["alpha"]) - p["kx"] * V0) / p["m"]
    drive = Constraint.servo("drive", f"x''' - ({float(j0)!r}) - s0*t", ["cos(alpha)", "sin(alpha)"], initial="F0")
    return build().replace(parameters=p, constraints=[drive])


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    times = np.linspace(0.0, model.simulation.t_end, 21)
    errors = {}
    tr = simulate(model, times=times)
    x, y, lam = closed_form(times, p)
    errors["along the reaction"] = max(np.max(np.abs(tr.q[:, 0] - x)), np.max(np.abs(tr.q[:, 1] - y)),
                                       np.max(np.abs(tr.multipliers["drive"] - lam)))
    tj = simulate(jerk_program(p), times=times)
    errors["the jerk program x''' = j0 + s0 t"] = max(np.max(np.abs(tj.q - tr.q)),
                                                     np.max(np.abs(tj.multipliers["drive"] - lam)))
    ti = simulate(build(ideal=True), times=times)
    x, y, Rx = closed_form(times, p, ideal=True)
    Lam = p["m"] * p["s0"] + p["kx"] * ti.qdd[:, 0]
    errors["ideal (R'' along d f/d x'''')"] = max(
        np.max(np.abs(ti.q[:, 0] - x)), np.max(np.abs(ti.q[:, 1] - y)),
        np.max(np.abs(ti.controls["drive"]["u_1"] - Rx)),
        np.max(np.abs(ti.controls["drive"]["u_2"] - (R0Y + R1Y * times))),
        np.max(np.abs(ti.multipliers["drive"] - Lam)))
    balance = max(t.diagnostics["energy_balance_relative"] for t in (tr, ti))
    worst = max(errors.values())
    result = {"ok": bool(worst < 1e-8 and balance < 1e-8),
              "max_errors": {k: float(v) for k, v in errors.items()},
              "force_start": float(tr.multipliers["drive"][0]),
              "force_end": float(tr.multipliers["drive"][-1]),
              "drive_work": float(tr.controls["drive"]["work"][-1]),
              "energy_balance_relative": float(balance)}
    if verbose:
        print(TITLE)
        print(f"m = {p['m']}, kx = {p['kx']}, ky = {p['ky']}, s0 = {p['s0']}, alpha = {p['alpha']}, "
              f"F0 = {p['F0']}, F1 = {p['F1']}")
        for k, v in errors.items():
            print(f"  max error against the closed form, {k:36s} = {v:.2e}")
        print(f"  drive force {result['force_start']:.6f} -> {result['force_end']:.6f} N, "
              f"its work {result['drive_work']:.9f} J, energy balance {balance:.2e}")
        print("ok" if result["ok"] else "FAILED")
    return result
