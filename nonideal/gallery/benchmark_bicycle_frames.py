"""The benchmark bicycle (Meijaard et al. 2007) written with frames and points.

The Whipple bicycle of :mod:`nonideal.gallery.benchmark_bicycle` -- same bodies, parameters
(Table 1) and axes (x forward, y right, z down) -- declared the way a mechanician draws it:
frames for the heading A (psi), the lean L (phi), the rear frame B (pitch thetaB), the rear
wheel R (thetaR), the steer axis S (B tilted back by lam), the front frame H (steer delta about
S.z) and the front wheel F (thetaF about the axle H.y); points for the rear contact, the wheel
centres, the centres of mass, and the front contact Cf, placed from the front wheel centre
along the projection of the vertical N.z on the wheel plane,

    Cf - Fc = rF (k - (k . a) a) / |k - (k . a) a|,    k = N.z, a = H.y,

as the bicycle of ``sympy.physics.mechanics`` does.  The constraints are written with the
vector functions: the front wheel touches the ground, ``dot(pos(Cf), N.z) = 0`` (holonomic;
it fixes the pitch), and each wheel's material point at its contact has no horizontal
velocity, ``vel(centre) + cross(omega(wheel), pos(contact) - pos(centre))`` along N.x and N.y
(nonholonomic).  8 coordinates (x, y, psi, phi, thetaB, thetaR, delta, thetaF), 1 + 4
constraints: 7 degrees of freedom in configuration, 3 in velocity.  No rotation matrix,
angular velocity or contact velocity is derived by hand.

What is checked (``run``):

1. The library's stability analysis, ``linearize(model, about="steady")`` about upright
   straight running at v = 0..10 m/s, the same path as the hand-derived file: the roll/steer
   eigenvalues against Table 2 (1e-10 relative), the verdict "asymptotically stable" exactly
   at v = 5 and 6 m/s, the cyclic coordinates (x, y, psi, thetaR, thetaF) and the held wheel
   speed named;
2. the weave and capsize speeds (4.29238253634111, 6.02426201538837 m/s) where the
   linearization's weave pair and capsize eigenvalue cross the imaginary axis (1e-10);
3. the nonlinear equations against the hand-derived model file: the roll and steer
   accelerations at leaning, steered states (1e-10), each state completed from its own model's
   constraints;
4. :func:`build` (the Python API, the front frame turned about the steer axis by ``axis`` and
   ``angle`` instead of the body-fixed sequence through S) against the file.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..modeling.bodies import RigidBody, Torque
from ..modeling.frames import Frame
from ..modeling.model import Constraint, Model
from ..modeling.points import Point
from . import benchmark_bicycle as hand

NAME = "benchmark-bicycle-frames"
ORDER = 71
TITLE = ("Benchmark bicycle with frames and points: the published eigenvalues, weave and capsize "
         "speeds from a file with no hand-derived kinematics (Meijaard et al. 2007)")
FILE = "benchmark_bicycle_frames.toml"

COORDINATES = ["x", "y", "psi", "phi", "thetaB", "thetaR", "delta", "thetaF"]
INDEPENDENT = ["x", "y", "psi", "phi", "thetaR", "delta", "thetaF"]
TABLE2 = hand.TABLE2

_DERIVED = {   # the steer-axis geometry of the hand-derived file is not needed here
    k for k in ("d_S", "h_S", "e_F", "s_F", "e_H", "s_H")}


def build(**parameters) -> Model:
    """The bicycle with the Python API: the front frame H is B turned by delta about the steer
    axis (sin(lam), 0, cos(lam)) of B (``axis`` and ``angle``), the rest as in the file."""
    p = {k: v for k, v in hand.PARAMETERS.items() if k not in _DERIVED}
    p.update(parameters)
    frames = [Frame("A", rotation="body Z", angles=["psi"]),
              Frame("L", "A", rotation="body X", angles=["phi"]),
              Frame("B", "L", rotation="body Y", angles=["thetaB"]),
              Frame("R", "L", rotation="body Y", angles=["thetaR"]),
              Frame("H", "B", axis=["sin(lam)", "0", "cos(lam)"], angle="delta"),
              Frame("F", "H", rotation="body Y", angles=["thetaF"])]
    k = "sqrt(dot(N.z, H.x)^2 + dot(N.z, H.z)^2)"
    points = [Point("Cr", ["x", "y", "0"]),
              Point("Rc", ["0", "0", "-rR"], "L", "Cr"),
              Point("Gb", ["xB", "0", "zB + rR"], "B", "Rc"),
              Point("Sp", ["w + c", "0", "rR"], "B", "Rc"),
              Point("Gh", ["xH - w - c", "0", "zH"], "H", "Sp"),
              Point("Fc", ["-c", "0", "-rF"], "H", "Sp"),
              Point("Cf", [f"rF*dot(N.z, H.x)/{k}", "0", f"rF*dot(N.z, H.z)/{k}"], "H", "Fc")]

    def inertia(a, b, c, xz="0"):
        return [[a, "0", xz], ["0", b, "0"], [xz, "0", c]]
    bodies = [RigidBody("rear_wheel", "mR", inertia("IRxx", "IRyy", "IRxx"), frame="R", center="Rc"),
              RigidBody("rear_frame", "mB", inertia("IBxx", "IByy", "IBzz", "IBxz"), frame="B", center="Gb"),
              RigidBody("front_frame", "mH", inertia("IHxx", "IHyy", "IHzz", "IHxz"), frame="H", center="Gh"),
              RigidBody("front_wheel", "mF", inertia("IFxx", "IFyy", "IFxx"), frame="F", center="Fc")]
    steer = [f"Tdelta*(sin(lam)*dot(B.x, N.{a}) + cos(lam)*dot(B.z, N.{a}))" for a in "xyz"]
    loads = [Torque("steer_torque_on_fork", steer, body="front_frame"),
             Torque("steer_torque_on_frame", [f"-({s})" for s in steer], body="rear_frame"),
             Torque("roll_torque", ["Tphi*cos(psi)", "Tphi*sin(psi)", "0"], body="rear_frame")]

    def rolling(centre, wheel, contact, axis):
        return f"dot(vel({centre}) + cross(omega({wheel}), pos({contact}) - pos({centre})), N.{axis})"
    constraints = [Constraint.holonomic("front_contact", "dot(pos(Cf), N.z)")]
    constraints += [Constraint.nonholonomic(f"{side}_rolling_{a}", rolling(c, wh, ct, a))
                    for side, c, wh, ct in (("rear", "Rc", "R", "Cr"), ("front", "Fc", "F", "Cf"))
                    for a in "xy"]
    initial = {n: 0.0 for n in COORDINATES}
    initial.update({"x'": "v", "phi'": 0.0, "delta'": 0.0, "thetaR'": "-v/rR", "thetaF'": "-v/rF"})
    return Model(name="Benchmark bicycle with frames and points (Meijaard et al. 2007)",
                 coordinates=COORDINATES, parameters=p, frames=frames, points=points, bodies=bodies,
                 loads=loads, gravity=["0", "0", "g"], constraints=constraints, initial=initial,
                 independent=INDEPENDENT, simulation={"t_end": 5.0, "rtol": 1e-10, "atol": 1e-12})


def steady_motion(model: Model, v: float) -> dict:
    """Upright straight running at speed *v*: the wheels roll, the rear contact moves at v."""
    p = model.parameter_values
    return {"x'": v, "thetaR'": -v / p["rR"], "thetaF'": -v / p["rF"]}


def linearization(model: Model, v: float, controls=("Tphi", "Tdelta")):
    """``linearize(model, about="steady")`` at upright running at speed *v*."""
    from ..analysis.stability.linearize import linearize

    return linearize(model, about="steady", at=steady_motion(model, v), controls=controls)


def roll_steer_matrix(model: Model, v: float) -> np.ndarray:
    """The linearization's state matrix in (phi, delta, phi', delta')."""
    lin = linearization(model, v)
    i = [lin.variables.index(n) for n in ("phi", "delta", "phi'", "delta'")]
    return lin.A[np.ix_(i, i)]


def speeds(model: Model) -> tuple[float, float]:
    """Weave and capsize speeds: where the weave pair's and the capsize eigenvalue's real
    parts of the linearization cross zero."""
    def weave(v):
        ev = np.linalg.eigvals(roll_steer_matrix(model, v))
        return max(s.real for s in ev if abs(s.imag) > 1.0)

    def capsize(v):
        ev = np.linalg.eigvals(roll_steer_matrix(model, v))
        return max(s.real for s in ev if abs(s.imag) < 1e-9 and abs(s.real) < 1.0)
    return (brentq(weave, 4.0, 4.6, xtol=1e-14, rtol=1e-15),
            brentq(capsize, 5.5, 6.5, xtol=1e-14, rtol=1e-15))


class RollSteerFrames:
    """Roll and steer accelerations of this model at ``z = (phi, delta, phi', delta')`` and
    speed v: the pitch from the front contact (Newton), the dependent velocities from all the
    constraints, ``thetaR' = -v/rR``; Lagrange's equations of the first kind."""

    def __init__(self, model: Model):
        from ..numeric.kernel import kernel_of, parameter_vector

        self.model, self.kernel = model, kernel_of(model)
        self.params = parameter_vector(model, {})
        self.i = [COORDINATES.index("phi"), COORDINATES.index("delta")]

    def __call__(self, z, v: float) -> np.ndarray:
        from ..modes.solver import ModeSolver
        from ..modes.switching import select_mode

        k, n = self.kernel, len(COORDINATES)
        q, qd = np.zeros(n), np.zeros(n)
        q[self.i], qd[self.i] = z[:2], z[2:]
        qd[COORDINATES.index("thetaR")] = -v / self.model.parameter_values["rR"]
        pitch = COORDINATES.index("thetaB")
        for _ in range(30):
            x = k.state_input(0.0, q, qd, self.params)
            res = k.observables(x)["pos"][0]
            step = -res / k.dynamics(x)["G"][0, pitch]
            q[pitch] += step
            if abs(step) < 1e-16:
                break
        dep = [j for j, name in enumerate(COORDINATES) if name not in ("phi", "delta", "thetaR")]
        x = k.state_input(0.0, q, qd, self.params)
        qd[dep] -= np.linalg.solve(k.dynamics(x)["G"][:, dep], k.observables(x)["vel"])
        solver = ModeSolver(k, self.params, "lagrange1")
        return solver.solve(0.0, q, qd, select_mode(solver, 0.0, q, qd)).qdd[self.i]


def _relative(a, b) -> float:
    a, b = np.asarray(a, complex), np.asarray(b, complex)
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))))


def run(verbose: bool = True) -> dict:
    from .. import gallery

    model = gallery.load(NAME)
    err_eigs, verdicts = {}, {}
    for v in TABLE2:
        lin = linearization(model, v)
        i = [lin.variables.index(n) for n in ("phi", "delta", "phi'", "delta'")]
        ev = np.sort_complex(np.linalg.eigvals(lin.A[np.ix_(i, i)]))
        err_eigs[v] = _relative(ev, np.sort_complex(TABLE2[v]))
        verdicts[v] = lin.verdict
    stable = [v for v, verdict in verdicts.items() if verdict == "asymptotically stable"]
    vw, vc = speeds(model)
    ours, theirs = RollSteerFrames(model), hand.RollSteer(gallery.load(hand.NAME))
    states = [(0.05, -0.1, 0.3, -0.5), (-0.2, 0.3, -1.0, 0.8), (0.1, 0.05, 0.0, 0.2)]
    err_hand = max(float(np.max(np.abs(ours(np.array(z), 4.6) - theirs(np.array(z), 4.6)))) for z in states)
    api = RollSteerFrames(build())
    err_api = max(float(np.max(np.abs(ours(np.array(z), 4.6) - api(np.array(z), 4.6)))) for z in states)
    result = {"eigenvalue_error_max": max(err_eigs.values()), "eigenvalue_error_by_speed": err_eigs,
              "self_stable_speeds": stable, "weave_speed": vw, "capsize_speed": vc,
              "weave_speed_error": abs(vw - hand.WEAVE_SPEED) / hand.WEAVE_SPEED,
              "capsize_speed_error": abs(vc - hand.CAPSIZE_SPEED) / hand.CAPSIZE_SPEED,
              "vs_hand_derived_file": err_hand, "file_vs_api": err_api,
              "linearize_ignorable": list(lin.ignorable), "linearize_family": list(lin.family)}
    result["ok"] = bool(result["eigenvalue_error_max"] < 1e-10 and result["weave_speed_error"] < 1e-10
                        and result["capsize_speed_error"] < 1e-10
                        and stable == [v for v in TABLE2 if hand.WEAVE_SPEED < v < hand.CAPSIZE_SPEED]
                        and err_hand < 1e-10 and err_api < 1e-10)
    if verbose:
        print(TITLE)
        print("linearize(model, about='steady') at v = 0..10, eigenvalues against Table 2:")
        for v in TABLE2:
            print(f"  v = {v:2d}: max relative difference {err_eigs[v]:.1e}   {verdicts[v]}")
        print(f"  cyclic {', '.join(lin.ignorable)}; held {', '.join(lin.family)}")
        print(f"weave speed   {vw:.14f}  (published {hand.WEAVE_SPEED}, rel. {result['weave_speed_error']:.1e})")
        print(f"capsize speed {vc:.14f}  (published {hand.CAPSIZE_SPEED}, rel. {result['capsize_speed_error']:.1e})")
        print(f"roll/steer accelerations against the hand-derived file (3 leaning, steered states): {err_hand:.1e}")
        print(f"model file vs Python API (steer by axis and angle): {err_api:.1e}")
        print("ok" if result["ok"] else "FAILED")
    return result
