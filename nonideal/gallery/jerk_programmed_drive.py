"""A drive with a constant-jerk program: a third-order constraint, its force part of the state.

Source: M. P. Yushkov (1999), ch. IV, sec. 5 and 7 (nonholonomic constraints of high order, the
mixed problem of dynamics) and appendix D (equations of motion under third-order constraints
from the generalized Gauss principle).  The system is a textbook-sized one chosen for its
closed form.

Model (``jerk_programmed_drive.toml``).  A mass m on a horizontal table, held by the springs
``kx`` (along x) and ``ky`` (along y); coordinates (x, y).  A drive realizes the program

    x''' = j0                                                                    (jerk-limited profile)

with a force of fixed direction ``(cos alpha, sin alpha)``: ``reaction = [cos(alpha),
sin(alpha)]``, the force's size ``lambda`` is the constraint's multiplier.  The equations

    m x'' + kx x = lambda cos(alpha),       m y'' + ky y = lambda sin(alpha)

contain lambda, so ``x'''`` contains ``lambda'``: the program is a differential equation for the
force, ``lambda' cos(alpha) = m j0 + kx x'``, and ``lambda(t0)`` must be given
(``[initial] lambda_drive = F0``); the state is (x, y, x', y', lambda).

Closed form (derived).  With ``a0 = (F0 cos(alpha) - kx x0)/m``,

    x = x0 + v0 t + a0 t^2/2 + j0 t^3/6,
    lambda = (m x'' + kx x) / cos(alpha)                     (a cubic in t),
    y = P/w^2 - P''/w^4 + A cos(w t) + B sin(w t),   w^2 = ky/m,   P = lambda sin(alpha)/m,

A and B from y(0) = 0, y'(0) = 0 (P is a cubic: ``P/w^2 - P''/w^4`` solves ``y'' + w^2 y = P``
exactly).  ``run`` checks x, y, lambda and the energy balance against these to 1e-8.

Two variants, by ``build``:

* ``ideal=True`` -- the same program without ``reaction``: an ideal third-order constraint.  The
  Gauss principle of third order (appendix D: among the third derivatives the constraint allows,
  the actual one is the closest, in the metric of M, to the one with the reaction held) gives
  ``R' = Lambda (d f/d q''')^T = Lambda (1, 0)``: the reaction's rate is along x, so ``R_y`` keeps
  its initial value and ``R_x = m x'' + kx x``, ``Lambda = m j0 + kx x'``.  The initial reaction
  is the list ``[initial] lambda_drive = [R0x, R0y]``; y is then a free oscillation about
  ``R0y/ky``.
* ``root="smallest"`` -- the program ``x'''^2 = j0^2`` (nonlinear in q''') along the same
  direction: its two roots are ``x''' = +-j0``; ``largest`` gives the profile above, ``smallest``
  the one with ``-j0``.

Misprints: none used (the closed forms are derived here and checked against the simulation).
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import Polynomial

from ..modeling.model import Constraint, Model

NAME = "jerk-programmed-drive"
ORDER = 63
TITLE = ("Drive with a constant-jerk program x''' = j0: a third-order constraint whose force is "
         "part of the state (Yushkov 1999, ch. IV)")
FILE = "jerk_programmed_drive.toml"

DEFAULTS = dict(m=2.0, kx=3.0, ky=5.0, j0=0.7, alpha=0.4, F0=1.5)
X0, V0 = 0.1, 0.2


def build(t_end: float = 2.0, ideal: bool = False, root: str | None = None,
          R0y: float = 0.5, **parameters) -> Model:
    """The drive with the Python API (same as the model file by default).  ``ideal=True``: the
    program without a reaction direction (initial reaction ``(F0, R0y)``); ``root``: the
    program ``x'''^2 = j0^2`` with that root rule."""
    p = dict(DEFAULTS)
    p.update(parameters)
    if ideal:
        drive = Constraint("drive", "x''' - j0", initial=("F0", R0y))
    elif root is not None:
        drive = Constraint.servo("drive", "x'''^2 - j0^2", ["cos(alpha)", "sin(alpha)"], root=root,
                                 initial="F0")
    else:
        drive = Constraint.servo("drive", "x''' - j0", ["cos(alpha)", "sin(alpha)"], initial="F0")
    return Model(
        name="Drive with a constant-jerk program x''' = j0 on a sprung mass",
        coordinates=["x", "y"], parameters=p,
        kinetic="m/2*(x'^2 + y'^2)", potential="kx/2*x^2 + ky/2*y^2",
        constraints=[drive],
        initial={"x": X0, "y": 0, "x'": V0, "y'": 0},
        simulation={"t_end": t_end, "rtol": 1e-12, "atol": 1e-13},
    )


def closed_form(t, p: dict, jerk: float | None = None, ideal: bool = False, R0y: float = 0.5):
    """``(x, y, force)`` at the times *t*: the force is lambda (along the reaction) or R_x
    (ideal); *jerk* defaults to j0."""
    t = np.asarray(t, dtype=float)
    j = p["j0"] if jerk is None else jerk
    m, kx, ky, ca, sa = p["m"], p["kx"], p["ky"], np.cos(p["alpha"]), np.sin(p["alpha"])
    fx0 = p["F0"] if ideal else p["F0"] * ca
    a0 = (fx0 - kx * X0) / m
    x = Polynomial([X0, V0, a0 / 2, j / 6])
    w2 = ky / m
    if ideal:
        force = m * x.deriv(2) + kx * x
        yp = Polynomial([R0y / ky])
    else:
        force = (m * x.deriv(2) + kx * x) / ca
        P = force * (sa / m)
        yp = P / w2 - P.deriv(2) / w2 ** 2
    w = np.sqrt(w2)
    A, B = -yp(0.0), -yp.deriv()(0.0) / w
    y = yp(t) + A * np.cos(w * t) + B * np.sin(w * t)
    return x(t), y, force(t)


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
    for root, sign in (("largest", 1.0), ("smallest", -1.0)):
        tn = simulate(build(root=root), times=times)
        x, y, lam = closed_form(times, p, jerk=sign * p["j0"])
        errors[f"x'''^2 = j0^2, root {root}"] = max(
            np.max(np.abs(tn.q[:, 0] - x)), np.max(np.abs(tn.q[:, 1] - y)),
            np.max(np.abs(tn.multipliers["drive"] - lam)))
    ti = simulate(build(ideal=True), times=times)
    x, y, Rx = closed_form(times, p, ideal=True)
    Lam = p["m"] * p["j0"] + p["kx"] * ti.qd[:, 0]
    errors["ideal (R' along d f/d x''')"] = max(
        np.max(np.abs(ti.q[:, 0] - x)), np.max(np.abs(ti.q[:, 1] - y)),
        np.max(np.abs(ti.controls["drive"]["u_1"] - Rx)),
        np.max(np.abs(ti.controls["drive"]["u_2"] - 0.5)),
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
        print(f"m = {p['m']}, kx = {p['kx']}, ky = {p['ky']}, j0 = {p['j0']}, alpha = {p['alpha']}, "
              f"F0 = {p['F0']}")
        for k, v in errors.items():
            print(f"  max error against the closed form, {k:32s} = {v:.2e}")
        print(f"  drive force {result['force_start']:.6f} -> {result['force_end']:.6f} N, "
              f"its work {result['drive_work']:.9f} J, energy balance {balance:.2e}")
        print("ok" if result["ok"] else "FAILED")
    return result
