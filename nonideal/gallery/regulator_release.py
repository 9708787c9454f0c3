"""Manglieva & Beknazarov 2022, sec. 3.2, (3.23)-(3.37): Chetaev's parametric release of the
friction speed regulator, the controllability matrix W(t) and optimal stabilization.

Model.  Releasing the servo-constraint omega2 = omega0 (Chetaev's parametric release, (3.23)):
shaft 2 turns freely, omega2 = omega0 + zeta (3.24); the intermediate wheel (mass m, position
rho) is driven by the programmed force u(t) and a stabilizing control u1; the wheels roll
without slipping (R phi1' = rho phi2', r phi' = rho phi2', nonholonomic).  Appell's equation of
shaft 2 from the acceleration energy (3.25), with n = J1/R^2 + J/r^2 and D = n rho^2 + J2:

    D zeta' + n rho rho' (omega0 + zeta) = M2 + rho M1/R,      m rho'' = u + u1      (3.26)

(printed without the factor rho in the second term of (3.26); (3.27) has it).  With M1 = 0
the programme zeta = 0 is explicit: rho0 rho0' = a = M2/(n omega0), rho0(t) =
sqrt(rho_i^2 + 2 a t), u(t) = m rho0'' = -m a^2/rho0^3.  First approximation in
(rho', zeta, z = rho'_dot) (derived; (3.28)-(3.29), where J3 is a misprint for J2):

    rho'_dot = z,   D zeta_dot = -n rho0 rho0' zeta - n rho0 omega0 z - n omega0 rho0' rho',
    m z_dot = u1.

Controllability (Krasovskii; (3.30)-(3.31)): W = [L1, L2, L3], L1 = B = (0, 0, 1/m),
L(i+1) = dLi/dt - A Li, gives (derived)

    W = [[0, -1/m, 0], [0, n rho0 omega0/(m D), -n^2 omega0 rho0^2 rho0'/(m D^2)], [1/m, 0, 0]],

full rank exactly while rho0' != 0 (M2 != 0) -- the structure of the printed (3.32), whose
entries are normalized differently.  With M1 != 0 (derived; the programme is then the implicit
(3.10), n omega0 rho0 rho0' = M2 + rho0 M1/R, and the model file, whose programmed force is
explicit in t, covers M1 = 0 only) the same recursion gives W[phi2', L3] =
(M1 D/R - n^2 omega0 rho0^2 rho0')/(m D^2) and

    det W = (M2 R n rho0 - J2 M1)/(R m^3 D^2),

which vanishes at rho0 = J2 M1/(M2 R n) (0.125 m for M1 = 0.75 N m with the numbers below):
the paper's "w = rho0^2 rho0' omega0 != 0, so rank W = 3" fails there -- the first
approximation loses controllability at the instant the programme passes that radius.
:func:`det_W` gives the formula.

M1 != 0 (``regulator_release_m1.toml``, the numbers of fig. 3.2: M1 = 0.3, M2 = 0.2, so
again rho0* = 0.125 m).  With g(rho) = (M2 + rho M1/R)/(n omega0 rho) the programme is
rho0' = g(rho0) and (3.10) integrates it: with y = M2 + rho M1/R and b = M1/R,

    t = (n omega0/b^2) (y - y_i - M2 ln(y/y_i)),
    rho0(t) = (M2/b) (-W_{-1}(-exp(-C(t)/M2)) - 1),   C(t) = y_i - M2 ln y_i + b^2 t/(n omega0) + M2 ln M2

(:func:`programme_m1`; the branch W_{-1} because y > M2 for M1 > 0); the programmed force is
u(t) = m rho0'' = m g(rho0) g'(rho0) = -m M2 (M2 R + M1 rho0)/(n^2 omega0^2 R rho0^3).  The model
file writes this u through rho (the expression language has no Lambert W): along the
programme it is u(t); its first approximation adds u'(rho0) rho'/m to z' (absent from (3.29)
with an open-loop u(t)), which enters only the z component of L3 and leaves det W as above
(:func:`closed_forms_m1` has W with it).  The wheel passes rho0* at t* = 1.676 s (:func:`t_of_rho`):
``nonideal stability regulator_release_m1.toml --about program --controls u1 --t-end 2.5``
stops there with exit code 3 naming the instant and the state (rho = 0.125); on [0, 1] it
runs (rank 3 throughout).  The test of this example checks the library's W(t) and det W
against these formulas at M1 = 0 and M1 = 0.3, and the instant it reports against t*.  Optimal stabilization (3.33)-(3.37): the cost
int (zeta^2 + rho'^2 + z^2 + u1^2) dt, V = x^T P(t) x with P from the differential Riccati
equation, u1 = -B^T P x.  The printed (3.35) omits the cross term zeta rho' whose coefficient
C13 appears in (3.36), and (3.36) has further index and sign misprints; the library integrates
the Riccati equation itself (``program_lqr``).

Misprints (derived here; the test of this example checks the numbers):

* (3.26) prints ``m rho'' = F1 + F2 + u + u1``; the generalized force written just above it,
  ``Q_rho = -(F11 + F22) + u + u1``, and (3.27) have the transverse friction against the
  motion, ``-(F11 + F22)`` (as in (3.3)).
* (3.34) divides by ``n rho_c^2 + J^2``: it is ``D = n rho0^2 + J2`` (the coefficient of
  zeta' in (3.29); (3.28)-(3.29) write J3).  ``n1`` is then defined twice, after (3.34) as
  ``n/(omega rho0^2 + J^2)`` and after (3.36) as ``n/(n rho0^2 + J2)``; dividing (3.29) by D
  gives the second, ``n1 = n/D``.  (3.34) also writes ``n rho0 n rho0'`` (n once) and
  ``S1' = (M1 - n omega0 rho0')/D`` for ``(M1/R - n omega0 rho0')/D`` of (3.29).
* (3.37) prints ``u1 = -(c33 z + c13 xi + c23 rho')``.  With V labelled as in (3.35) -- C22 the
  coefficient of z^2, C33 that of rho'^2 -- the minimum of the Bellman function,
  ``dB/du1 = 2 u1 + 2 C22 z + 2 C13 xi + 2 C23 rho' = 0`` (printed just before), gives
  ``u1 = -(C22 z + C13 xi + C23 rho')``: the feedback on z is the coefficient of z^2 in V
  (``u1 = -B^T P x``: the row of P of the controlled variable), not of rho'^2.

run() checks the programme against the closed form, A(t) and W(t) against the formulas above,
and that the optimal feedback turns the growing perturbations of the open loop into decaying
ones (the characteristic exponents of the fundamental matrices).

    nonideal stability regulator-release --about program --controls u1
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "regulator-release"
ORDER = 206
TITLE = "Friction speed regulator, parametric release: W(t) (3.30)-(3.32) and optimal stabilization (3.33)-(3.37)"
FILE = "regulator_release.toml"
FILE_M1 = "regulator_release_m1.toml"

DEFAULTS = {"m": 0.5, "J1": 0.02, "J": 0.01, "J2": 0.05, "R": 0.1, "r": 0.05, "omega0": 20.0, "M2": 0.5,
            "rho_i": 0.05, "u1": 0.0}


def build(**overrides) -> Model:
    """The released regulator with the Python API (same as the model file for the defaults)."""
    p = {**DEFAULTS, **overrides, "n": "J1/R^2 + J/r^2", "a": "M2/(n*omega0)"}
    return Model(
        name="friction speed regulator, parametric release (Manglieva & Beknazarov 2022, sec. 3.2)",
        coordinates=["phi1", "phi", "phi2", "rho"], parameters=p,
        kinetic="J1*phi1'^2/2 + J*phi'^2/2 + J2*phi2'^2/2 + m*rho'^2/2",
        forces={"phi2": "M2", "rho": "-m*a^2/(rho_i^2 + 2*a*t)^(3/2) + u1"},
        constraints=[Constraint.nonholonomic("roll_1", "R*phi1' - rho*phi2'"),
                     Constraint.nonholonomic("roll_wheel", "r*phi' - rho*phi2'")],
        initial={"phi1": 0.0, "phi": 0.0, "phi2": 0.0, "rho": "rho_i", "phi2'": "omega0", "rho'": "a/rho_i"},
        independent=["phi2", "rho"], simulation={"t_end": 1.0})


def closed_forms(t, p=DEFAULTS):
    """rho0, rho0', A(t), W(t) of the docstring at the times *t*."""
    n = p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2
    a = p["M2"] / (n * p["omega0"])
    w, m = p["omega0"], p["m"]
    rho = np.sqrt(p["rho_i"] ** 2 + 2 * a * np.asarray(t))
    rd = a / rho
    D = n * rho ** 2 + p["J2"]
    A = np.zeros((len(rho), 3, 3))
    A[:, 0, 2] = 1.0
    A[:, 1, 0], A[:, 1, 1], A[:, 1, 2] = -n * w * rd / D, -n * rho * rd / D, -n * rho * w / D
    W = np.zeros((len(rho), 3, 3))
    W[:, 2, 0], W[:, 0, 1], W[:, 1, 1] = 1 / m, -1 / m, n * rho * w / (m * D)
    W[:, 1, 2] = -n ** 2 * w * rho ** 2 * rd / (m * D ** 2)
    return rho, rd, A, W


def det_W(rho0, p=DEFAULTS, M1: float = 0.0):
    """``det W = (M2 R n rho0 - J2 M1)/(R m^3 D^2)`` along the programme (module docstring)."""
    n = p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2
    rho0 = np.asarray(rho0, dtype=float)
    D = n * rho0 ** 2 + p["J2"]
    return (p["M2"] * p["R"] * n * rho0 - p["J2"] * M1) / (p["R"] * p["m"] ** 3 * D ** 2)


def _n(p) -> float:
    return p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2


def t_of_rho(rho, p) -> np.ndarray:
    """(3.10): the time at which the programme (M1 != 0, constant torques) reaches *rho*."""
    n, b = _n(p), p["M1"] / p["R"]
    y, yi = p["M2"] + b * np.asarray(rho, dtype=float), p["M2"] + b * p["rho_i"]
    return n * p["omega0"] / b ** 2 * (y - yi - p["M2"] * np.log(y / yi))


def programme_m1(t, p) -> tuple[np.ndarray, np.ndarray]:
    """rho0(t), rho0'(t) of the implicit programme (3.10) with M1 > 0: the Lambert-W time law
    of the module docstring (scipy's ``lambertw``, branch -1)."""
    from scipy.special import lambertw

    n, b, M2 = _n(p), p["M1"] / p["R"], p["M2"]
    yi = M2 + b * p["rho_i"]
    C = yi - M2 * np.log(yi) + b ** 2 * np.asarray(t, dtype=float) / (n * p["omega0"]) + M2 * np.log(M2)
    s = -np.real(lambertw(-np.exp(-C / M2), -1))
    rho = (M2 * s - M2) / b
    return rho, (M2 + b * rho) / (n * p["omega0"] * rho)


def closed_forms_m1(rho, p) -> np.ndarray:
    """W(t) = [L1, L2, L3] at the programme's positions *rho* (M1 != 0, the programmed force
    written through rho as in the model file), in the library's order (rho, phi2', rho')."""
    n, w, m, M1, M2, R = _n(p), p["omega0"], p["m"], p["M1"], p["M2"], p["R"]
    rho = np.asarray(rho, dtype=float)
    rd = (M2 + rho * M1 / R) / (n * w * rho)
    D = n * rho ** 2 + p["J2"]
    du = m * M2 * (2 * M1 * rho + 3 * M2 * R) / (n ** 2 * w ** 2 * R * rho ** 4)    # u'(rho)
    W = np.zeros((len(rho), 3, 3))
    W[:, 2, 0], W[:, 0, 1], W[:, 1, 1] = 1 / m, -1 / m, n * rho * w / (m * D)
    W[:, 1, 2] = (M1 / (R * D) - n ** 2 * w * rho ** 2 * rd / D ** 2) / m
    W[:, 2, 2] = du / m ** 2
    return W


def run(verbose: bool = True) -> dict:
    from ..analysis.stability.control import program_lqr
    from ..analysis.stability.program import linearize_program
    from . import load

    prog = linearize_program(load(NAME), controls=["u1"], samples=161)
    rho, rd, A_ref, W_ref = closed_forms(prog.t)
    prog_err = max(float(np.max(np.abs(prog.q["rho"] - rho))), float(np.max(np.abs(prog.qdot["phi2"] - 20.0))))
    A_err = float(np.max(np.abs(prog.A - A_ref)) / np.max(np.abs(A_ref)))
    inner = slice(10, -10)           # W from splines: their derivatives are least accurate at the ends
    W_err = float(np.max(np.abs(prog.W[inner] - W_ref[inner]) / np.max(np.abs(W_ref[inner]), axis=(1, 2))[:, None, None]))
    reg = program_lqr(prog)
    P_pd = bool(all(np.linalg.eigvalsh(P).min() > 0 for P in reg.P[:-1]))
    ok = (prog_err < 1e-8 and A_err < 1e-8 and W_err < 1e-3 and np.all(prog.controllability_rank == 3)
          and prog.variables == ("rho", "phi2'", "rho'") and reg.exponent_open > 0 > reg.exponent_closed and P_pd)
    out = {"programme_error": prog_err, "A_relative_error": A_err, "W_relative_error": W_err,
           "controllability_rank": int(prog.controllability_rank.min()), "exponent_open": reg.exponent_open,
           "exponent_closed": reg.exponent_closed, "K_t0": reg.K[0].tolist(), "P_positive_definite": P_pd,
           "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  programme rho0 = sqrt(rho_i^2 + 2 a t), zeta = 0: max error {prog_err:.1e}")
        print(f"  A(t) vs the corrected (3.29): {A_err:.1e}; W(t) vs the derived (3.32): {W_err:.1e}; "
              f"rank W = {out['controllability_rank']}")
        print(f"  optimal stabilization: K(t0) = {np.array2string(reg.K[0], precision=4)}; exponents "
              f"open {reg.exponent_open:.4g}, closed {reg.exponent_closed:.4g}; P(t) > 0: {P_pd}")
        print(f"  ok: {ok}")
    return out
