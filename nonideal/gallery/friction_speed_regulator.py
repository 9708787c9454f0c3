"""Friction speed regulator: a servo-constraint whose control acts through the dynamics.

Source: N. Manglieva, Kh. Beknazarov, *On the motion of systems with nonholonomic non-ideal
constraints* (2022), ch. 3, sec. 3.1, equations (3.1)--(3.10) and the second regulator of
fig. 3.3.

Model (fig. 3.2, ``friction_speed_regulator.toml``).  Shaft 1 (disc of radius R, inertia J1,
torque M1), the receiving shaft 2 (inertia J2, torque M2) and an intermediate wheel (radius r,
inertia J) that rolls on both; the wheel with its carriage (mass m) is moved along its axle by
the control force u: rho is the distance of its contact from the axis of shaft 2.  Coordinates
``phi1, phi2, phi, rho``; rolling (3.2): ``R phi1' = rho phi2'``, ``r phi' = rho phi2'``
(ideal, nonholonomic); the servo-constraint (3.1) ``phi2' = w0`` is realized by ``u`` along
``rho`` (``reaction = [0, 0, 0, 1]``); the transverse sliding of the wheel meets the Coulomb
force ``F11 + F22 = f (N1 + N2)`` against ``rho'`` (``rho' > 0`` here).

Why it is not an ordinary servo-constraint.  The force on the axle changes ``rho''`` only, and
``phi2''`` depends on ``rho'`` but not on ``rho''``: ``G M^-1 B = 0`` (Béghin's determinant
vanishes).  The library differentiates the program until the control appears (Yushkov 1999,
ch. IV, the mixed problem): ``phi2'' = 0`` with the control switched off is the *condition of
dynamics* (the first equation of (3.3)),

    w0 rho rho' (J1/R^2 + J/r^2) = M2 + rho M1 / R,                                  (3.3)

a condition on the state (it fixes ``rho'(0)``); its derivative contains ``rho''`` and hence u:
the control appears in ``phi2'''`` (order 3, reported by ``nonideal check``).  The second
equation of (3.3), ``m rho'' = -(F11 + F22) + u``, gives the control force.

Closed forms (derived; they agree with the printed (3.4)--(3.8), (3.10)).  With
``k = w0 (J + J1 r^2/R^2)``, ``k1 = r^2 M2``, ``k2 = r^2 M1 / R`` (3.4), (3.3) is the Riccati-type
equation (3.5) ``k rho' = k1/rho + k2``; with ``eps = 1/k`` (3.6) its series (3.7)
``rho = rho0 + eps rho1 + eps^2 rho2 + ...`` has (3.8)

    rho0 rho1' = k1 + k2 rho0,      rho1 rho1' + rho0 rho2' = k2 rho1,

so for constant torques ``rho1 = (k1/rho0 + k2) t``, ``rho2 = -k1 (k1/rho0 + k2) t^2 / (2 rho0^2)``
(the error of the two-term series is O(eps^3): ``run`` checks that it falls 8-fold when w0 is
doubled), and (3.5) integrates to (3.10)

    t = (k/k2) (rho - rho_0 - (k1/k2) ln |(k2 rho + k1)/(k2 rho_0 + k1)|).           (3.10)

The control force (3.9): ``u = m rho'' + (F11 + F22)`` with ``rho'' = (d/dt)(k1/rho + k2)/k``,

    u = (m/k) [(k1' rho - k1 rho')/rho^2 + k2'] + (F11 + F22),    rho' = eps (k1/rho + k2).

Misprints.  (3.9) prints ``- (F11 + F22)`` (the second equation of (3.3) gives ``+``) and, in
its expanded form, ``- k2'`` inside the bracket (``d k2/dt`` enters with ``+``); both are
invisible for constant torques and positive ``rho'`` only in the first case.  The first
equation of (3.3) is printed with ``[rho' w2 rho]`` standing for the product.

The second regulator (fig. 3.3, ``friction_speed_regulator_2.toml``): the wheel rolls on disc 1
at the distance rho and on disc 2 at ``a - rho``: ``r phi' = rho phi1' = (a - rho) phi2'``.  The
paper's own intermediate equations (``J1 w1' = M1 - F1 rho``, ``J w' = r (F1 + F2)``,
``0 = M2 - F2 (a - rho)``, ``w' = -w0 rho'/r``) give

    -(J w0 / r + a r w0 J1 / rho^3) rho' = r (M2/(a - rho) + M1/rho);

the printed result has ``+`` on the left.  The slips are in the line before it,
``(J w0 / r) rho' = r (M2/(a - rho) + M1/rho - w0 a J1 rho'/rho^3)``: the minus of
``J w' = -J w0 rho'/r`` is lost on the left (and ``J w0 / 2`` is printed for ``J w0 / r`` the
line above), and the J1 term inside the bracket has the wrong sign -- ``F1 = M1/rho +
w0 a J1 rho'/rho^3``, printed correctly just above, enters ``r (F1 + F2)`` with ``+``.  The
factor r of the J1 term is there (``a r J1`` in the result, the r outside the bracket before
it); the two sign slips together give the printed result.  With positive torques the wheel moves towards shaft 1 (``rho' < 0``), which the
library's simulation confirms (it derives the condition of dynamics itself); the transverse
friction then acts along ``+rho``: ``m rho'' = u + f (N1 + N2)`` as printed.  ``run`` checks the
simulated rho(t) against an independent integration of this scalar equation and u against
``m rho'' - f (N1 + N2)``.

The stability of the programmed motion (3.11)--(3.13): ``nonideal stability
friction-speed-regulator --about program`` linearizes the closed loop on the program
(variable rho, ``A(t) = -M2/(n w0 rho0^2)``, Persidsky's verdict), the same first
approximation as ``regulator-persidsky``.
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "friction-speed-regulator"
ORDER = 60
TITLE = ("Friction speed regulator: servo-constraint phi2' = w0 held through the dynamics "
         "(Manglieva & Beknazarov 2022, (3.1)-(3.10), fig. 3.3)")
FILE = "friction_speed_regulator.toml"
FILE_2 = "friction_speed_regulator_2.toml"

DEFAULTS = dict(J1=0.02, J2=0.05, J=0.01, m=0.5, R=0.1, r=0.05, M1=0.3, M2=0.2, w0=20.0,
                f=0.2, N1=10.0, N2=10.0, rho0=0.05)


def build(t_end: float = 1.0, **parameters) -> Model:
    """The regulator of fig. 3.2 with the Python API (same as the model file by default)."""
    p = dict(DEFAULTS)
    p.update(parameters)
    return Model(
        name="Friction speed regulator: phi2' = w0 held by a force on the wheel's axle",
        coordinates=["phi1", "phi2", "phi", "rho"],
        parameters=p,
        kinetic="J1/2*phi1'^2 + J2/2*phi2'^2 + J/2*phi'^2 + m/2*rho'^2",
        forces={"phi1": "M1", "phi2": "M2", "rho": "-f*(N1 + N2)"},
        constraints=[Constraint.nonholonomic("roll_1", "R*phi1' - rho*phi2'"),
                     Constraint.nonholonomic("roll_wheel", "r*phi' - rho*phi2'"),
                     Constraint.servo("speed", "phi2' - w0", ["0", "0", "0", "1"])],
        initial={"phi1": 0, "phi2": 0, "phi": 0, "rho": "rho0", "phi2'": "w0"},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-13},
    )


def constants(p: dict) -> tuple[float, float, float]:
    """``k, k1, k2`` of (3.4) for constant torques."""
    k = p["w0"] * (p["J"] + p["J1"] * p["r"] ** 2 / p["R"] ** 2)
    return k, p["r"] ** 2 * p["M2"], p["r"] ** 2 * p["M1"] / p["R"]


def quadrature_time(rho, p: dict):
    """The time (3.10) at which the wheel reaches *rho* (constant torques)."""
    k, k1, k2 = constants(p)
    rho = np.asarray(rho, dtype=float)
    r0 = p["rho0"]
    return k / k2 * (rho - r0 - k1 / k2 * np.log(np.abs((k2 * rho + k1) / (k2 * r0 + k1))))


def riccati_rate(rho, p: dict):
    """``rho'`` from (3.5): ``(k1/rho + k2)/k``."""
    k, k1, k2 = constants(p)
    return (k1 / np.asarray(rho, dtype=float) + k2) / k


def control_force(rho, p: dict):
    """The control force (3.9), corrected: ``u = m rho'' + f (N1 + N2)`` with
    ``rho'' = -k1 rho' / (k rho^2)`` (constant torques)."""
    k, k1, _ = constants(p)
    rho = np.asarray(rho, dtype=float)
    return -p["m"] * k1 * riccati_rate(rho, p) / (k * rho ** 2) + p["f"] * (p["N1"] + p["N2"])


def eps_series(t, p: dict):
    """The two-term series (3.7)-(3.8): ``rho0 + eps rho1 + eps^2 rho2`` (constant torques)."""
    k, k1, k2 = constants(p)
    eps, r0 = 1.0 / k, p["rho0"]
    t = np.asarray(t, dtype=float)
    rho1 = (k1 / r0 + k2) * t
    rho2 = -k1 * (k1 / r0 + k2) * t ** 2 / (2 * r0 ** 2)
    return r0 + eps * rho1 + eps ** 2 * rho2


def second_regulator_rate(rho, p: dict):
    """``rho'`` of the regulator of fig. 3.3 (derived; the printed sign is wrong)."""
    rho = np.asarray(rho, dtype=float)
    lhs = p["w0"] * (p["J"] / p["r"] + p["a"] * p["r"] * p["J1"] / rho ** 3)
    return -p["r"] * (p["M2"] / (p["a"] - rho) + p["M1"] / rho) / lhs


def _series_error(w0: float, t_end: float) -> float:
    """Max error of the two-term series (3.7)-(3.8) against the simulation, at speed *w0*."""
    from ..simulation.hybrid import simulate
    model = build(t_end=t_end, w0=w0)
    times = np.linspace(0.0, t_end, 11)
    tr = simulate(model, times=times)
    return float(np.max(np.abs(tr.coordinate("rho") - eps_series(times, model.parameter_values))))


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..equations.dynamics import dynamics_of
    from ..modeling.modelfile import load_model
    from ..simulation.hybrid import simulate
    from scipy.integrate import solve_ivp

    model = gallery.load(NAME)
    p = model.parameter_values
    t_end = model.simulation.t_end
    times = np.linspace(0.0, t_end, 201)
    tr = simulate(model, times=times)
    rho, rhod = tr.coordinate("rho"), tr.qd[:, 3]
    u = tr.multipliers["speed"]
    order = dynamics_of(model).servo_reach["speed"].order
    err_program = float(np.max(np.abs(tr.qd[:, 1] - p["w0"])))
    k, k1, k2 = constants(p)
    # (3.3), first equation: the condition of dynamics along the motion
    lhs = p["w0"] * rho * rhod * (p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2)
    err_33a = float(np.max(np.abs(lhs - (p["M2"] + rho * p["M1"] / p["R"]))))
    # (3.3), second equation: m rho'' = -(F11 + F22) + u
    err_33b = float(np.max(np.abs(p["m"] * tr.qdd[:, 3] + p["f"] * (p["N1"] + p["N2"]) - u)))
    err_35 = float(np.max(np.abs(rhod - riccati_rate(rho, p))))
    err_310 = float(np.max(np.abs(quadrature_time(rho, p) - times)))
    err_39 = float(np.max(np.abs(u - control_force(rho, p))))
    # (3.6)-(3.8): the error of the two-term series falls as eps^3
    w_big = 2000.0
    e1 = _series_error(w_big, t_end)
    e2 = _series_error(2 * w_big, t_end)
    ratio = e1 / e2 if e2 > 0 else float("inf")
    forms = {f: compare_forms(model, forms=[f], count=8).worst()
             for f in ("lagrange2", "maggi", "appell", "shulgin")}
    # the second regulator (fig. 3.3) against an independent integration of its scalar equation
    model2 = load_model(gallery.HERE / FILE_2)
    p2 = model2.parameter_values
    tr2 = simulate(model2, times=times)
    ref = solve_ivp(lambda t, y: second_regulator_rate(y, p2), (0.0, t_end), [p2["rho0"]],
                    t_eval=times, rtol=1e-12, atol=1e-14, method="DOP853")
    err_2 = float(np.max(np.abs(tr2.coordinate("rho") - ref.y[0])))
    rho_2 = ref.y[0]
    h = 1e-6 * np.maximum(np.abs(rho_2), 1e-3)
    rate = second_regulator_rate(rho_2, p2)
    rho_dd = (second_regulator_rate(rho_2 + h, p2) - second_regulator_rate(rho_2 - h, p2)) / (2 * h) * rate
    u2_ref = p2["m"] * rho_dd - p2["f"] * (p2["N1"] + p2["N2"])
    err_u2 = float(np.max(np.abs(tr2.multipliers["speed"] - u2_ref)))
    E = tr.energy["energy"]
    balance = tr.diagnostics["energy_balance_relative"]
    result = {
        "ok": order == 3 and err_program < 1e-9 and err_33a < 1e-9 and err_33b < 1e-9
        and err_35 < 1e-10 and err_310 < 1e-8 and err_39 < 1e-8 and 6.0 < ratio < 10.0
        and max(forms.values()) < 1e-10 and err_2 < 1e-8 and err_u2 < 1e-6 and balance < 1e-8
        and rhod.min() > 0 and tr2.qd[:, 3].max() < 0,
        "control_order": order,
        "max_error_program": err_program,
        "max_error_3_3_condition_of_dynamics": err_33a,
        "max_error_3_3_wheel_equation": err_33b,
        "max_error_3_5_riccati": err_35,
        "max_error_3_10_quadrature_time": err_310,
        "max_error_3_9_control_force": err_39,
        "series_error_w0": [e1, e2], "series_error_ratio": ratio,
        "rho_end": float(rho[-1]), "u_start": float(u[0]), "u_end": float(u[-1]),
        "control_work": float(tr.energy["reaction_work"][-1]),
        "energy_change": float(E[-1] - E[0]),
        "energy_balance_relative": balance,
        "forms": forms,
        "second_regulator_max_error_rho": err_2,
        "second_regulator_max_error_u": err_u2,
        "second_regulator_rho_end": float(tr2.coordinate("rho")[-1]),
    }
    if verbose:
        print(TITLE)
        print(f"k = {k:.6g}, k1 = {k1:.6g}, k2 = {k2:.6g}; t in [0, {t_end:g}]")
        print(f"  the control appears in derivative order {order} of the coordinates (program phi2' = w0)")
        print(f"  max |phi2' - w0|                        = {err_program:.2e}")
        print(f"  (3.3) condition of dynamics, max error  = {err_33a:.2e}")
        print(f"  (3.3) m rho'' = -(F11+F22) + u          = {err_33b:.2e}")
        print(f"  (3.5) k rho' = k1/rho + k2              = {err_35:.2e}")
        print(f"  (3.10) quadrature t(rho) - t            = {err_310:.2e}   (rho: {rho[0]:.6f} -> {rho[-1]:.9f})")
        print(f"  (3.9) control force u (corrected sign)  = {err_39:.2e}   (u: {u[0]:.9f} -> {u[-1]:.9f} N)")
        print(f"  (3.7)-(3.8) two-term series error, w0 = {w_big:g}, {2 * w_big:g}: {e1:.3e}, {e2:.3e} "
              f"(ratio {ratio:.2f}, eps^3 gives 8)")
        print(f"  work of the control = {result['control_work']:.9f} J, energy change = {result['energy_change']:.9f} J")
        for f, v in forms.items():
            print(f"  form {f:10} vs lagrange1: {v:.2e}")
        print(f"  fig. 3.3 regulator: max |rho - scalar equation| = {err_2:.2e}, max |u - (m rho'' - f(N1+N2))| = {err_u2:.2e}")
        print("ok" if result["ok"] else "FAILED")
    return result
