"""The heavy symmetric top (Lagrange's top), written with a frame and a point.

Classic (Lagrange 1788; Goldstein, *Classical Mechanics*, sec. 5.7).  A symmetric rigid body
turns about a fixed point O; central moments A (transverse) and C (axial), centre of mass G on
the symmetry axis at distance l from O, gravity -g along N.z.  The model file declares the
top's frame by the Euler angles (``rotation = "body ZXZ"``, ``angles = [psi, theta, phi]``)
and G as the point (0, 0, l) of that frame: the library derives the rotation, the angular
velocity (composed from the elementary rates) and the velocity of G.

Closed forms, with A_O = A + m l^2 and the axial spin w3 = phi' + psi' cos(theta):

    T = A_O/2 (theta'^2 + psi'^2 sin^2 theta) + C/2 w3^2,      V = m g l cos(theta),
    p_phi = C w3,   p_psi = A_O psi' sin^2 theta + C w3 cos(theta)   (psi, phi cyclic),

and the steady precession at theta0 (theta' = 0 for all t) has the rate Omega = psi' of

    A_O Omega^2 cos(theta0) - C w3 Omega + m g l = 0

(Goldstein (5.76)); the slow root is Omega = (C w3 - sqrt(C^2 w3^2 - 4 A_O m g l cos(theta0)))
/ (2 A_O cos(theta0)).

What is checked (``run``): the library's kinetic energy against the closed form at random
states; along a nutating motion the energy, p_psi and p_phi stay constant (relative drift
< 1e-9); started at the slow steady precession, theta stays at theta0 and psi' at Omega.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.frames import Frame
from ..modeling.model import Model
from ..modeling.points import Point

NAME = "heavy-symmetric-top"
ORDER = 205
TITLE = "Heavy symmetric top with frames and points: energy, p_psi, p_phi and steady precession"
FILE = "heavy_symmetric_top.toml"

PARAMETERS = {"m": 0.5, "A": 0.0025, "C": 0.004, "l": 0.08, "g": 9.81}


def build(**parameters) -> Model:
    """The top with the Python API (same as the model file)."""
    p = {**PARAMETERS, **parameters}
    return Model(
        name="Heavy symmetric top (frames and points)", coordinates=["psi", "theta", "phi"],
        parameters=p,
        frames=[Frame("B", rotation="body ZXZ", angles=["psi", "theta", "phi"])],
        points=[Point("G", ["0", "0", "l"], frame="B")],
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G")],
        gravity=["0", "0", "-g"],
        initial={"psi": 0.0, "theta": 0.6, "phi": 0.0, "psi'": 1.0, "theta'": 0.5, "phi'": 60.0},
        simulation={"t_end": 3.0})


def invariants(p: dict, theta, psid, thetad, phid) -> dict[str, np.ndarray]:
    """Energy, p_psi and p_phi from the closed forms (arrays along a motion)."""
    A_O = p["A"] + p["m"] * p["l"] ** 2
    w3 = phid + psid * np.cos(theta)
    T = A_O / 2 * (thetad ** 2 + psid ** 2 * np.sin(theta) ** 2) + p["C"] / 2 * w3 ** 2
    return {"E": T + p["m"] * p["g"] * p["l"] * np.cos(theta), "p_phi": p["C"] * w3,
            "p_psi": A_O * psid * np.sin(theta) ** 2 + p["C"] * w3 * np.cos(theta), "T": T}


def precession_rate(p: dict, theta0: float, w3: float) -> float:
    """The slow steady-precession rate Omega at theta0 and axial spin w3 (Goldstein (5.76))."""
    A_O = p["A"] + p["m"] * p["l"] ** 2
    c, Cw = np.cos(theta0), p["C"] * w3
    return float((Cw - np.sqrt(Cw * Cw - 4 * A_O * p["m"] * p["g"] * p["l"] * c)) / (2 * A_O * c))


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..equations.dynamics import dynamics_of
    from ..simulation import simulate
    import symengine as se

    model = gallery.load(NAME)
    p = model.parameter_values
    # the library's kinetic energy against the closed form at random states
    T = dynamics_of(model).T
    rng = np.random.default_rng(1)
    err_T = 0.0
    for _ in range(5):
        th, ps, ph, psd, thd, phd = rng.uniform(-2, 2, 6)
        vals = {"psi": ps, "theta": th, "phi": ph, "psi'": psd, "theta'": thd, "phi'": phd, **p}
        ours = float(T.xreplace({se.Symbol(k): se.Float(v) for k, v in vals.items()}))
        want = float(invariants(p, th, psd, thd, phd)["T"])
        err_T = max(err_T, abs(ours - want) / abs(want))
    # a nutating motion: the invariants stay constant
    traj = simulate(model, t_end=3.0, times=np.linspace(0, 3, 61))
    inv = invariants(p, traj.coordinate("theta"), traj.velocity("psi"), traj.velocity("theta"),
                     traj.velocity("phi"))
    drift = {k: float(np.max(np.abs(v - v[0])) / abs(v[0])) for k, v in inv.items() if k != "T"}
    # steady precession at theta0
    theta0, w3 = 0.6, 60.0
    Omega = precession_rate(p, theta0, w3)
    steady = model.replace(initial={"psi": 0.0, "theta": theta0, "phi": 0.0, "psi'": Omega,
                                    "theta'": 0.0, "phi'": w3 - Omega * np.cos(theta0)})
    times = np.linspace(0, 2, 21)
    st = simulate(steady, t_end=2.0, times=times)
    err_theta = float(np.max(np.abs(st.coordinate("theta") - theta0)))
    err_rate = float(np.max(np.abs(st.velocity("psi") - Omega)) / Omega)
    result = {"kinetic_energy_error": err_T, "invariant_drift": drift, "precession_rate": Omega,
              "steady_theta_error": err_theta, "steady_rate_error": err_rate,
              "constraint_residual_max": traj.diagnostics["constraint_residual_max"]}
    result["ok"] = bool(err_T < 1e-12 and max(drift.values()) < 1e-9 and err_theta < 1e-9
                        and err_rate < 1e-8)
    if verbose:
        print(TITLE)
        print(f"kinetic energy vs the closed form (5 random states): {err_T:.1e}")
        print("along a nutating motion (theta0 = 0.6, theta'(0) = 0.5, phi' = 60): relative drift "
              + ", ".join(f"{k} {v:.1e}" for k, v in drift.items()))
        print(f"steady precession at theta0 = {theta0}, w3 = {w3}: Omega = {Omega:.10f} rad/s; "
              f"theta stays within {err_theta:.1e}, psi' within {err_rate:.1e} (relative)")
        print("ok" if result["ok"] else "FAILED")
    return result
