"""The benchmark bicycle: Whipple's bicycle with the parameters of Meijaard et al. (2007).

Source: J. P. Meijaard, J. M. Papadopoulos, A. Ruina, A. L. Schwab, *Linearized dynamics
equations for the balance and steer of a bicycle: a benchmark and review*, Proc. R. Soc. A
463 (2007) 1955-1982.  Their Table 1 gives the parameters; for these they give the
linearized equations about upright straight running at speed v,

    M q'' + v C1 q' + (g K0 + v^2 K2) q = f,      q = (phi, delta),  f = (T_phi, T_delta),

with M, C1, K0, K2 to 14 decimals, and Table 2 the eigenvalues for v = 0, 1, ..., 10 m/s, the
weave speed v_w = 4.29238253634111 m/s (a complex pair crosses the imaginary axis) and the
capsize speed v_c = 6.02426201538837 m/s (a real eigenvalue crosses zero): between them the
uncontrolled bicycle is self-stable.  Every multibody code is measured by these numbers
(``sympy.physics.mechanics`` reproduces the linear matrices in its own tests).

Model (``benchmark_bicycle.toml``).  Four rigid bodies -- rear wheel R, rear frame B with the
rider, front frame H (fork and handlebar), front wheel F -- in the paper's axes (x forward,
y right, z down, origin at the rear contact).  Coordinates: the rear contact (x, y), yaw psi,
roll phi, pitch thetaB and rear wheel rotation thetaR; the steer angle delta about the steer
axis (tilted back by lam); the front wheel's own contact point (xF, yF), heading psiF, lean
phiF and rotation thetaF.  Rotations are Rz(psi) Rx(phi) Ry(.) for the wheels and the rear
frame and R_S Rz(delta) Ry(-lam) for the front frame, R_S = Rz(psi) Rx(phi) Ry(thetaB + lam).
The constraints:

* holonomic (5): the front wheel centre computed along the frame chain equals the one above
  the front contact, and the front axle lies along the fork's axle (its vertical component
  is sin(phiF), its horizontal part is perpendicular to the heading psiF).  They make the
  front wheel touch the ground and fix the pitch thetaB;
* nonholonomic (4): rolling without slipping.  For a knife-edge wheel of radius r whose
  rotation theta is measured in its heading/lean frame, the velocity of the material point at
  the contact, v_centre + omega x (contact - centre), vanishes iff the contact point moves as
  (x', y') = -r theta' (cos heading, sin heading): with n the unit vector from the contact to
  the centre and a the axle, v_centre = (contact)' + r n', n' = Omega x n and
  omega = Omega + theta' a, so the material velocity is (contact)' - r theta' a x n and
  a x n = -(cos heading, sin heading, 0).

12 coordinates, 9 constraints: 7 degrees of freedom in configuration, 3 in velocity (roll,
steer, forward speed v = -rR thetaR').  In the steady motion (upright, straight, speed v) the
cyclic coordinates (x, y, psi, thetaR, thetaF, xF, yF) drift and the speed is held.

What is checked (``run``):

1. The linear matrices.  ``linear_matrices`` differentiates the library's accelerations
   (Lagrange's equations of the first kind from the model file, ``evaluate``'s machinery) at
   consistent states near upright running: M from the response to the input torques
   (q'' = M^-1 f at q = q' = 0), then K(v) = -M dq''/dq and v C1 = -M dq''/dq' at v = 0 and
   1 m/s (fourth-order central differences, step 1e-4): K0 = K(0)/g, K2 = K(1) - K(0).
   They agree with the published matrices to ~2e-13 (the published 14 decimals).
2. The eigenvalues of the first-order system at v = 0..10 against Table 2 (1e-11 relative),
   the weave speed (root of the Hurwitz determinant a1 a2 a3 - a0 a3^2 - a1^2 a4 of the
   characteristic polynomial det(M s^2 + v C1 s + g K0 + v^2 K2)) and the capsize speed
   (det(g K0 + v^2 K2) = 0, a quadratic in v^2) against the published ones (1e-11 relative).
3. The library's stability analysis: ``linearize(model, about="steady")`` at v = 0..10
   (:func:`linearization`; the model file's ``[forms] independent`` keeps roll and steer
   independent, so x, y, psi, thetaR, thetaF are recognized as cyclic and the held wheel
   speed is named) gives the roll/steer state matrix and the input matrix B = [0; M^-1] of
   item 1 (1e-9) and the eigenvalues of Table 2 (1e-11 relative); its verdict is
   "asymptotically stable" exactly at v = 5 and 6 m/s of the eleven speeds.
4. The model file against :func:`build` (the same bicycle written with the Python API, the
   front frame rotated as R_B Ry(lam) Rz(delta) Ry(-lam) and its points placed from the
   reference configuration, independently of the file's steer-axis parameters): the
   accelerations agree at perturbed states.
5. The nonlinear motion: a simulation at v = 4.6 m/s (self-stable) started with a small roll
   rate follows the linear solution exp(A t) x0; the bicycle is symmetric left-right, so the
   difference is of third order in the perturbation (1.6e-5 of a roll-rate kick of 0.01 rad/s
   over 3 s).

No misprint to report: the model reproduces the published matrices and eigenvalues.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.linalg import expm
from scipy.optimize import brentq

from ..modeling.bodies import RigidBody, Torque
from ..modeling.model import Constraint, Model

NAME = "benchmark-bicycle"
ORDER = 70
TITLE = ("Benchmark bicycle (Whipple model): linearized roll/steer matrices, eigenvalues, weave "
         "and capsize speeds (Meijaard et al. 2007)")
FILE = "benchmark_bicycle.toml"

#: Meijaard et al. 2007, Table 1.
PARAMETERS = {
    "w": 1.02, "c": 0.08, "lam": "pi/10", "g": 9.81, "v": 4.6,
    "rR": 0.3, "mR": 2.0, "IRxx": 0.0603, "IRyy": 0.12,
    "xB": 0.3, "zB": -0.9, "mB": 85.0, "IBxx": 9.2, "IByy": 11.0, "IBzz": 2.8, "IBxz": 2.4,
    "xH": 0.9, "zH": -0.7, "mH": 4.0, "IHxx": 0.05892, "IHyy": 0.06, "IHzz": 0.00708,
    "IHxz": -0.00756,
    "rF": 0.35, "mF": 3.0, "IFxx": 0.1405, "IFyy": 0.28,
    "Tphi": 0.0, "Tdelta": 0.0,
}

#: Meijaard et al. 2007, the benchmark's coefficient matrices (q = (phi, delta)).
PUBLISHED_MATRICES = {
    "M": [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]],
    "C1": [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]],
    "K0": [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]],
    "K2": [[0.0, 76.59734589573222], [0.0, 2.65431523794604]],
}

#: Meijaard et al. 2007, Table 2: weave and capsize speeds, the weave frequency at v_w.
WEAVE_SPEED = 4.29238253634111
CAPSIZE_SPEED = 6.02426201538837
WEAVE_FREQUENCY = 3.43503384866144

#: Meijaard et al. 2007, Table 2: the eigenvalues at v = 0..10 m/s.
TABLE2 = {
    0: [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    1: [-7.11008014637442, -3.13423125066578, 3.52696170990070 + 0.80774027519930j,
        3.52696170990070 - 0.80774027519930j],
    2: [-8.67387984831735, -3.07158645641514, 2.68234517512745 + 1.68066296590675j,
        2.68234517512745 - 1.68066296590675j],
    3: [-10.35101467245920, -2.63366137253667, 1.70675605663975 + 2.31582447384325j,
        1.70675605663975 - 2.31582447384325j],
    4: [-12.15861426576450, -1.42944427361326, 0.41325331521125 + 3.07910818603206j,
        0.41325331521125 - 3.07910818603206j],
    5: [-14.07838969279820, -0.32286642900409, -0.77534188219585 + 4.46486771378823j,
        -0.77534188219585 - 4.46486771378823j],
    6: [-16.08537123098030, -0.00406690076970, -1.52644486584142 + 5.87673060598709j,
        -1.52644486584142 - 5.87673060598709j],
    7: [-18.15788466125262, 0.10268170574766, -2.13875644258362 + 7.19525913329805j,
        -2.13875644258362 - 7.19525913329805j],
    8: [-20.27940894394569, 0.14327879765713, -2.69348683581097 + 8.46037971396931j,
        -2.69348683581097 - 8.46037971396931j],
    9: [-22.43788559040858, 0.15790184030917, -3.21675402252485 + 9.69377351531791j,
        -3.21675402252485 - 9.69377351531791j],
    10: [-24.62459635017404, 0.16105338653172, -3.72016840437287 + 10.90681139476287j,
         -3.72016840437287 - 10.90681139476287j],
}

COORDINATES = ["x", "y", "psi", "phi", "thetaB", "thetaR", "delta", "thetaF", "xF", "yF",
               "psiF", "phiF"]
#: coordinates kept independent (reduced forms, linearization): roll and steer, the cyclic rest
INDEPENDENT = ["x", "y", "psi", "phi", "thetaR", "delta", "thetaF"]
#: start values of the dependent coordinates near upright running
_GUESS = {"thetaB": 0.0, "xF": 1.02, "yF": 0.0, "psiF": 0.0, "phiF": 0.0}


# ----------------------------------------------------------------------------- Python API


def _Rz(a):
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def _Rx(a):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])


def _Ry(a):
    return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])


def build(**parameters) -> Model:
    """The benchmark bicycle with the Python API.

    The front frame is rotated as ``R_B Ry(lam) Rz(delta) Ry(-lam)`` about the point where
    the steer axis meets the ground in the reference configuration, ``(w + c, 0, 0)``, and
    its points are placed from their reference positions -- a construction independent of
    the steer-axis parameters (d_S, h_S, e_F, s_F, e_H, s_H) of the model file.
    """
    p = dict(PARAMETERS)
    unknown = set(parameters) - set(p)
    if unknown:
        raise TypeError(f"build: unknown parameter(s) {sorted(unknown)}; known: {sorted(p)}")
    p.update(parameters)
    x, y, psi, phi, thB, thR, de, thF, xF, yF, psiF, phiF = sp.symbols(COORDINATES)
    qd = {n: sp.Symbol(n + "'") for n in COORDINATES}
    w, c, lam, rR, rF, xB, zB, xH, zH = sp.symbols("w c lam rR rF xB zB xH zH")
    Td, Tp = sp.symbols("Tdelta Tphi")
    Y = _Rz(psi) * _Rx(phi)                      # heading and lean of the rear frame
    RB = Y * _Ry(thB)
    RH = RB * _Ry(lam) * _Rz(de) * _Ry(-lam)
    CR = sp.Matrix([x, y, 0]) + Y * sp.Matrix([0, 0, -rR])     # rear wheel centre

    def rear_point(p_ref):                       # a point of B from its reference position
        return CR + RB * (sp.Matrix(p_ref) - sp.Matrix([0, 0, -rR]))
    S_ref = sp.Matrix([w + c, 0, 0])

    def front_point(p_ref):                      # a point of H from its reference position
        return rear_point(S_ref) + RH * (sp.Matrix(p_ref) - S_ref)
    Bcom = rear_point([xB, 0, zB])
    Hcom = front_point([xH, 0, zH])
    CF_chain = front_point([w, 0, -rF])
    CF = sp.Matrix([xF, yF, 0]) + _Rz(psiF) * _Rx(phiF) * sp.Matrix([0, 0, -rF])
    axle = RH * sp.Matrix([0, 1, 0])
    steer_axis = RB * _Ry(lam) * sp.Matrix([0, 0, 1])

    def inertia(a, b, cc, xz=0):
        return [[a, 0, xz], [0, b, 0], [xz, 0, cc]]
    bodies = [
        RigidBody("rear_wheel", "mR", inertia("IRxx", "IRyy", "IRxx"), list(CR),
                  (Y * _Ry(thR)).tolist()),
        RigidBody("rear_frame", "mB", inertia("IBxx", "IByy", "IBzz", "IBxz"), list(Bcom),
                  RB.tolist()),
        RigidBody("front_frame", "mH", inertia("IHxx", "IHyy", "IHzz", "IHxz"), list(Hcom),
                  RH.tolist()),
        RigidBody("front_wheel", "mF", inertia("IFxx", "IFyy", "IFxx"), list(CF),
                  (_Rz(psiF) * _Rx(phiF) * _Ry(thF)).tolist()),
    ]
    loads = [Torque("steer_torque_on_fork", list(Td * steer_axis), body="front_frame"),
             Torque("steer_torque_on_frame", list(-Td * steer_axis), body="rear_frame"),
             Torque("roll_torque", [Tp * sp.cos(psi), Tp * sp.sin(psi), 0], body="rear_frame")]
    constraints = [
        Constraint.holonomic("fork_x", CF_chain[0] - CF[0]),
        Constraint.holonomic("fork_y", CF_chain[1] - CF[1]),
        Constraint.holonomic("fork_z", CF_chain[2] - CF[2]),
        Constraint.holonomic("axle_tilt", axle[2] - sp.sin(phiF)),
        Constraint.holonomic("axle_heading", axle[0] * sp.cos(psiF) + axle[1] * sp.sin(psiF)),
        Constraint.nonholonomic("rear_rolling_x", qd["x"] + rR * qd["thetaR"] * sp.cos(psi)),
        Constraint.nonholonomic("rear_rolling_y", qd["y"] + rR * qd["thetaR"] * sp.sin(psi)),
        Constraint.nonholonomic("front_rolling_x", qd["xF"] + rF * qd["thetaF"] * sp.cos(psiF)),
        Constraint.nonholonomic("front_rolling_y", qd["yF"] + rF * qd["thetaF"] * sp.sin(psiF)),
    ]
    initial = {n: 0.0 for n in COORDINATES}
    initial.update({"xF": "w", "x'": "v", "phi'": 0.0, "delta'": 0.0, "thetaR'": "-v/rR",
                    "thetaF'": "-v/rF", "xF'": "v"})
    return Model(name="Benchmark bicycle (Whipple model, Meijaard et al. 2007)",
                 coordinates=COORDINATES, parameters=p, bodies=bodies, loads=loads,
                 gravity=["0", "0", "g"], constraints=constraints, initial=initial,
                 independent=INDEPENDENT, simulation={"t_end": 5.0, "rtol": 1e-10, "atol": 1e-12})


# ----------------------------------------------------------------------------- linearization


class RollSteer:
    """Roll and steer accelerations of the nonlinear model near upright straight running.

    ``RollSteer(model)(z, v, torques)`` with ``z = (phi, delta, phi', delta')``: the state is
    completed from the constraints (pitch and front wheel coordinates from the holonomic
    ones, the dependent velocities from all of them, ``thetaR' = -v / rR``) and the library
    solves Lagrange's equations of the first kind there; returns ``(phi'', delta'')``.
    """

    def __init__(self, model: Model):
        from ..numeric.kernel import kernel_of

        self.model = model
        self.kernel = kernel_of(model)
        self.rR = model.parameter_values["rR"]
        self.i = [COORDINATES.index("phi"), COORDINATES.index("delta")]

    def state(self, z, v: float, params):
        """The consistent state at ``z = (phi, delta, phi', delta')`` and speed *v*.

        Newton's method on the holonomic rows for the pitch and the front wheel coordinates
        (to the last bit: the finite differences divide its residual by their step), then the
        dependent velocities from all constraint rows (linear).
        """
        k = self.kernel
        q = np.zeros(len(COORDINATES))
        q[self.i] = z[:2]
        for name, value in _GUESS.items():
            q[COORDINATES.index(name)] = value
        qd = np.zeros(len(COORDINATES))
        qd[self.i] = z[2:]
        qd[COORDINATES.index("thetaR")] = -v / self.rR
        hol = [j for j, r in enumerate(k.rows) if r.position is not None]
        dep_q = [COORDINATES.index(n) for n in _GUESS]
        dep_v = [j for j, n in enumerate(COORDINATES) if n not in ("phi", "delta", "thetaR")]
        for _ in range(20):
            x = k.state_input(0.0, q, qd, params)
            res = k.observables(x)["pos"][hol]
            step = np.linalg.solve(k.dynamics(x)["G"][hol][:, dep_q], -res)
            q[dep_q] += step
            if np.max(np.abs(step)) < 1e-15:
                break
        else:
            raise RuntimeError(f"no upright-running state at phi = {z[0]}, delta = {z[1]}")
        x = k.state_input(0.0, q, qd, params)
        qd[dep_v] -= np.linalg.solve(k.dynamics(x)["G"][:, dep_v], k.observables(x)["vel"])
        return q, qd

    def __call__(self, z, v: float, torques=(0.0, 0.0)) -> np.ndarray:
        from ..modes.solver import ModeSolver
        from ..modes.switching import select_mode
        from ..numeric.kernel import parameter_vector

        params = parameter_vector(self.model, {"Tphi": torques[0], "Tdelta": torques[1]})
        q, qd = self.state(z, v, params)
        solver = ModeSolver(self.kernel, params, "lagrange1")
        qdd = solver.solve(0.0, q, qd, select_mode(solver, 0.0, q, qd)).qdd
        return qdd[self.i]


def _derivative(f, n: int, h: float) -> np.ndarray:
    """Jacobian of f at 0 by fourth-order central differences (columns: the n inputs)."""
    cols = []
    for k in range(n):
        e = np.zeros(n)
        e[k] = h
        cols.append((8 * (f(e) - f(-e)) - (f(2 * e) - f(-2 * e))) / (12 * h))
    return np.column_stack(cols)


def linear_matrices(model: Model | None = None, h: float = 1e-4) -> dict[str, np.ndarray]:
    """M, C1, K0, K2 of the linearized roll/steer equations, from the library's accelerations.

    ``M`` from the inputs (``q'' = M^-1 f`` at rest, exact: the accelerations are linear in the
    torques); ``K(v) = -M dq''/dq`` and ``v C1 = -M dq''/dq'`` by fourth-order central
    differences (step *h*) at v = 0 and 1 m/s; ``K0 = K(0)/g``, ``K2 = K(1) - K(0)``,
    ``C1 = C(1)``.  Truncation error ~ h^4, rounding ~ 1e-16/h: ~1e-13 at h = 1e-4.

    Returns
    -------
    dict with ``"M", "C1", "K0", "K2"`` (ndarray, shape (2, 2)) and ``"g"``.
    """
    from .. import gallery

    model = gallery.load(NAME) if model is None else model
    acc = RollSteer(model)
    g = model.parameter_values["g"]
    M = np.linalg.inv(_derivative(lambda T: acc(np.zeros(4), 0.0, T), 2, 1.0))
    out = {"M": M, "g": g}
    K = {}
    for v in (0.0, 1.0):
        J = _derivative(lambda z, v=v: acc(z, v), 4, h)
        K[v] = -M @ J[:, :2]
        if v:
            out["C1"] = -M @ J[:, 2:] / v
    out["K0"] = K[0.0] / g
    out["K2"] = K[1.0] - K[0.0]
    return out


def steady_motion(model: Model, v: float) -> dict:
    """The velocities of upright straight running at speed *v* (the ``at`` of the stability
    analysis): the rear and front contacts move forward at v, the wheels roll."""
    p = model.parameter_values
    return {"x'": v, "xF'": v, "thetaR'": -v / p["rR"], "thetaF'": -v / p["rF"]}


def linearization(model: Model, v: float, controls=("Tphi", "Tdelta")):
    """The library's first approximation about upright running at speed *v*
    (:func:`nonideal.analysis.stability.linearize.linearize`, ``about="steady"``): perturbation variables
    (phi, delta, phi', delta'), the cyclic coordinates and the held speed named; with the
    torques as controls, ``B = [0; M^-1]``."""
    from ..analysis.stability.linearize import linearize

    return linearize(model, about="steady", at=steady_motion(model, v), controls=controls)


def state_matrix(mats: dict, v: float) -> np.ndarray:
    """A of x' = A x, x = (phi, delta, phi', delta')."""
    M, C1, K0, K2, g = (mats[k] for k in ("M", "C1", "K0", "K2", "g"))
    Minv = np.linalg.inv(M)
    return np.block([[np.zeros((2, 2)), np.eye(2)],
                     [-Minv @ (g * K0 + v * v * K2), -v * Minv @ C1]])


def eigenvalues(mats: dict, v: float) -> np.ndarray:
    """The four eigenvalues at speed v, sorted by real part, then imaginary part."""
    return np.sort_complex(np.linalg.eigvals(state_matrix(mats, v)))


def characteristic_polynomial(mats: dict, v: float) -> np.ndarray:
    """Coefficients a0..a4 of det(M s^2 + v C1 s + g K0 + v^2 K2) (highest power first)."""
    M, C1, K0, K2, g = (mats[k] for k in ("M", "C1", "K0", "K2", "g"))
    P = [[np.array([M[i, j], v * C1[i, j], g * K0[i, j] + v * v * K2[i, j]]) for j in range(2)]
         for i in range(2)]
    return np.polysub(np.polymul(P[0][0], P[1][1]), np.polymul(P[0][1], P[1][0]))


def hurwitz_determinant(mats: dict, v: float) -> float:
    """Delta_3 = a1 a2 a3 - a0 a3^2 - a1^2 a4: zero where a complex pair crosses the axis."""
    a0, a1, a2, a3, a4 = characteristic_polynomial(mats, v)
    return a1 * a2 * a3 - a0 * a3 * a3 - a1 * a1 * a4


def weave_speed(mats: dict, bracket=(3.0, 5.0)) -> float:
    """Speed where the weave pair becomes stable: root of the Hurwitz determinant."""
    return brentq(lambda v: hurwitz_determinant(mats, v), *bracket, xtol=1e-15, rtol=8.9e-16)


def capsize_speed(mats: dict) -> float:
    """Speed where the capsize eigenvalue crosses zero: det(g K0 + v^2 K2) = 0.

    The determinant is a quadratic in u = v^2, ``a u^2 + b u + c``; the capsize speed is
    the square root of its positive root above the weave speed.
    """
    K0, K2, g = mats["K0"] * mats["g"], mats["K2"], mats["g"]
    a = K2[0, 0] * K2[1, 1] - K2[0, 1] * K2[1, 0]
    b = K0[0, 0] * K2[1, 1] + K2[0, 0] * K0[1, 1] - K0[0, 1] * K2[1, 0] - K2[0, 1] * K0[1, 0]
    c = K0[0, 0] * K0[1, 1] - K0[0, 1] * K0[1, 0]
    roots = [-c / b] if abs(a) < 1e-300 else list(np.roots([a, b, c]).real)
    u = max(r for r in roots if r > 0)
    return float(np.sqrt(u))


def published() -> dict:
    """The published matrices as arrays (with g), in the form :func:`eigenvalues` takes."""
    out = {k: np.array(v, dtype=float) for k, v in PUBLISHED_MATRICES.items()}
    out["g"] = 9.81
    return out


def linear_response(mats: dict, v: float, x0, times) -> np.ndarray:
    """exp(A t) x0 at the given times, rows (phi, delta, phi', delta')."""
    A = state_matrix(mats, v)
    return np.array([expm(A * t) @ np.asarray(x0, float) for t in times])


# ----------------------------------------------------------------------------- run


def _relative(a, b) -> float:
    a, b = np.asarray(a, complex), np.asarray(b, complex)
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))))


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..simulation import simulate

    model = gallery.load(NAME)
    mats = linear_matrices(model)
    pub = published()
    err_mats = {k: float(np.max(np.abs(mats[k] - pub[k]))) for k in ("M", "C1", "K0", "K2")}
    err_eigs = {v: _relative(eigenvalues(mats, v), np.sort_complex(TABLE2[v])) for v in TABLE2}
    vw, vc = weave_speed(mats), capsize_speed(mats)
    at_weave = eigenvalues(mats, vw)
    weave_freq = float(np.max(np.abs(at_weave.imag)))

    # the library's stability analysis (linearize about the steady motion) at v = 0..10
    roll_steer = ["phi", "delta", "phi'", "delta'"]
    err_lin, err_A, verdicts = {}, 0.0, {}
    for vv in TABLE2:
        lin = linearization(model, vv)
        i = [lin.variables.index(n) for n in roll_steer]
        rest = [j for j in range(len(lin.variables)) if j not in i]
        A4 = lin.A[np.ix_(i, i)]
        err_lin[vv] = _relative(np.sort_complex(np.linalg.eigvals(A4)), np.sort_complex(TABLE2[vv]))
        err_A = max(err_A, float(np.max(np.abs(A4 - state_matrix(mats, vv)))),
                    float(np.max(np.abs(lin.A[rest]), initial=0.0)),
                    float(np.max(np.abs(lin.B[i[2:]] - np.linalg.inv(mats["M"])))))
        verdicts[vv] = lin.verdict
    stable = [vv for vv, verdict in verdicts.items() if verdict == "asymptotically stable"]

    # the model file against the Python API: accelerations at perturbed states
    api = RollSteer(build())
    ours = RollSteer(model)
    states = [(0.05, -0.1, 0.3, -0.5), (-0.2, 0.3, -1.0, 0.8), (0.1, 0.05, 0.0, 0.2)]
    err_api = max(float(np.max(np.abs(ours(np.array(z), 4.6) - api(np.array(z), 4.6))))
                  for z in states)

    # the nonlinear motion follows the linear one (small roll rate at v = 4.6 m/s)
    v, eps = model.parameter_values["v"], 0.01
    times = np.linspace(0.0, 3.0, 13)
    traj = simulate(model.replace(initial={**model.initial, "phi'": eps}), t_end=3.0, times=times)
    nonlinear = np.column_stack([traj.coordinate("phi"), traj.coordinate("delta")])
    linear = linear_response(mats, v, [0.0, 0.0, eps, 0.0], times)[:, :2]
    err_sim = float(np.max(np.abs(nonlinear - linear)) / eps)

    result = {
        "matrices": {k: mats[k].tolist() for k in ("M", "C1", "K0", "K2")},
        "matrix_error_max": err_mats,
        "eigenvalue_error_max": max(err_eigs.values()),
        "eigenvalue_error_by_speed": err_eigs,
        "weave_speed": vw, "weave_speed_error": abs(vw - WEAVE_SPEED) / WEAVE_SPEED,
        "capsize_speed": vc, "capsize_speed_error": abs(vc - CAPSIZE_SPEED) / CAPSIZE_SPEED,
        "weave_frequency": weave_freq,
        "weave_frequency_error": abs(weave_freq - WEAVE_FREQUENCY) / WEAVE_FREQUENCY,
        "linearize_eigenvalue_error_max": max(err_lin.values()),
        "linearize_vs_differences_max": err_A,
        "linearize_variables": list(lin.variables), "linearize_ignorable": list(lin.ignorable),
        "linearize_family": list(lin.family), "self_stable_speeds": stable,
        "file_vs_api_max": err_api,
        "nonlinear_vs_linear_relative": err_sim,
        "constraint_residual_max": traj.diagnostics["constraint_residual_max"],
    }
    result["ok"] = bool(max(err_mats.values()) < 1e-11 and result["eigenvalue_error_max"] < 1e-11
                        and result["weave_speed_error"] < 1e-11
                        and result["capsize_speed_error"] < 1e-11
                        and result["weave_frequency_error"] < 1e-11
                        and max(err_lin.values()) < 1e-11 and err_A < 1e-9
                        and stable == [vv for vv in TABLE2 if WEAVE_SPEED < vv < CAPSIZE_SPEED]
                        and err_api < 1e-10 and err_sim < eps / 10)
    if verbose:
        np.set_printoptions(precision=14, suppress=False, linewidth=120)
        print(TITLE)
        print("linearized equations M q'' + v C1 q' + (g K0 + v^2 K2) q = f, q = (phi, delta),")
        print("from the library's accelerations (the published values in brackets):")
        for k in ("M", "C1", "K0", "K2"):
            for i in range(2):
                row = "  ".join(f"{mats[k][i, j]:20.14f} [{pub[k][i, j]:18.14f}]" for j in range(2))
                print(f"  {k if i == 0 else '':3s} {row}")
            print(f"      max |difference| = {err_mats[k]:.1e}")
        print("eigenvalues (Table 2), max relative difference per speed:")
        for vv in TABLE2:
            ev = ", ".join(f"{s.real:.14f}{s.imag:+.14f}j" if abs(s.imag) > 0 else f"{s.real:.14f}"
                           for s in eigenvalues(mats, vv))
            print(f"  v = {vv:2d}: {ev}   ({err_eigs[vv]:.1e})")
        print(f"weave speed   {vw:.14f}  (published {WEAVE_SPEED}, rel. {result['weave_speed_error']:.1e})")
        print(f"capsize speed {vc:.14f}  (published {CAPSIZE_SPEED}, rel. {result['capsize_speed_error']:.1e})")
        print(f"weave frequency at v_w: {weave_freq:.14f} (published {WEAVE_FREQUENCY})")
        print("the stability analysis, linearize(model, about='steady') at v = 0..10:")
        print(f"  variables {', '.join(lin.variables)}; cyclic {', '.join(lin.ignorable)}; "
              f"held {', '.join(lin.family)}")
        print(f"  eigenvalues vs Table 2: max relative difference {max(err_lin.values()):.1e}")
        print(f"  A, B vs the differentiated accelerations: max |difference| {err_A:.1e}")
        print(f"  asymptotically stable at v = {stable} (published: between {WEAVE_SPEED} and "
              f"{CAPSIZE_SPEED})")
        print(f"model file vs Python API (accelerations): {err_api:.1e}")
        print(f"nonlinear simulation vs linear solution (v = {v}, phi'(0) = {eps}): "
              f"{err_sim:.1e} of the perturbation")
        print("ok" if result["ok"] else "FAILED")
    return result
