"""Steady rolling of a disk: stability of the upright motion, W^2 > g/(3 r).

Classic (Neimark & Fufaev, *Dynamics of nonholonomic systems*, ch. III; Appell 1900).  A
uniform disk (radius r, central moments A = m r^2/4 about a diameter, C = m r^2/2 about its
axis) rolls without slipping on a horizontal plane: two nonholonomic constraints (the contact
point has zero velocity).  Coordinates x, y (centre), heading psi, lean theta, spin phi.

Steady motion: upright rolling along a line, theta = 0, phi' = W.  The library eliminates the
dependent velocities x', y' (the constraints), drops the ignorable x, y, psi, phi and names
the held spin phi' (a family: its zero eigenvalue).  In (theta, psi', theta') the first
approximation has the characteristic polynomial (derived here from the Euler equations with
the rolling constraint; the lean equation is (A + m r^2) theta'' + (C (C + m r^2) W^2 / A -
m g r) theta = 0 once psi' is eliminated)

    s (s^2 + (C (C + m r^2) W^2 / A - m g r) / (A + m r^2)) = s (s^2 + (4/5)(3 W^2 - g/r)),

the last for the uniform disk: stable in the first approximation iff W^2 > g/(3 r); the
remaining zero eigenvalue is the family of steady circular motions (psi' perturbed).  run() also checks the linearization against a simulation of the nonlinear
motion: a small lean-rate perturbation follows the linear solution.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.model import Constraint, Model

NAME = "rolling-disk"
ORDER = 202
TITLE = "Rolling disk: upright rolling is stable iff W^2 > g/(3 r) (nonholonomic linearization)"
FILE = "rolling_disk.toml"

ROTATION = [
    ["-sin(phi)*sin(psi)*sin(theta) + cos(phi)*cos(psi)", "-sin(psi)*cos(theta)",
     "sin(phi)*cos(psi) + sin(psi)*sin(theta)*cos(phi)"],
    ["sin(phi)*sin(theta)*cos(psi) + sin(psi)*cos(phi)", "cos(psi)*cos(theta)",
     "sin(phi)*sin(psi) - sin(theta)*cos(phi)*cos(psi)"],
    ["-sin(phi)*cos(theta)", "sin(theta)", "cos(phi)*cos(theta)"],
]


def build(m: float = 1.0, r: float = 0.5, g: float = 9.81, W: float = 5.0) -> Model:
    """The disk with the Python API (same as the model file for the default values)."""
    return Model(
        name="rolling disk", coordinates=["x", "y", "psi", "theta", "phi"],
        parameters={"m": m, "r": r, "g": g},
        bodies=[RigidBody("disk", "m", [["m*r^2/4", 0, 0], [0, "m*r^2/2", 0], [0, 0, "m*r^2/4"]],
                          ["x", "y", "r*cos(theta)"], ROTATION)],
        gravity=["0", "0", "-g"],
        constraints=[
            Constraint.nonholonomic("roll_x", "x' - r*phi'*cos(psi) - r*psi'*sin(theta)*cos(psi) "
                                    "- r*theta'*sin(psi)*cos(theta)"),
            Constraint.nonholonomic("roll_y", "y' - r*phi'*sin(psi) - r*psi'*sin(psi)*sin(theta) "
                                    "+ r*theta'*cos(psi)*cos(theta)")],
        initial={"x": 0.0, "y": 0.0, "psi": 0.0, "theta": 0.0, "phi": 0.0,
                 "psi'": 0.0, "theta'": 0.0, "phi'": W},
        independent=["psi", "theta", "phi"], simulation={"t_end": 3.0})


def lean_frequency_squared(W: float, r: float = 0.5, g: float = 9.81) -> float:
    """-lambda^2 = (4/5)(3 W^2 - g/r) for the uniform disk."""
    return 0.8 * (3 * W * W - g / r)


def linear_vs_nonlinear(model, lin, W: float, eps: float = 1e-5, t_end: float = 1.0) -> float:
    """Largest difference (relative to eps) between the nonlinear lean and the linear solution
    after a lean-rate perturbation eps."""
    from scipy.linalg import expm

    from ..simulation import simulate

    times = np.linspace(0.0, t_end, 6)
    init = {"x": 0.0, "y": 0.0, "psi": 0.0, "theta": 0.0, "phi": 0.0, "psi'": 0.0, "theta'": eps, "phi'": W}
    traj = simulate(model.replace(initial=init), times=times)
    x0 = np.zeros(len(lin.variables))
    x0[lin.variables.index("theta'")] = eps
    k = lin.variables.index("theta")
    lean = np.array([(expm(lin.A * t) @ x0)[k] for t in times])
    return float(np.max(np.abs(traj.q[:, model.coordinates.index("theta")] - lean)) / eps)


def run(verbose: bool = True) -> dict:
    from ..analysis.stability.linearize import linearize
    from . import load

    model = load(NAME)
    Wc = np.sqrt(9.81 / (3 * 0.5))
    out = {"critical_W": Wc, "cases": []}
    ok = True
    for W in (0.9 * Wc, 1.1 * Wc, 5.0):
        lin = linearize(model, about="steady", at={"phi'": W})
        w2 = lean_frequency_squared(W)
        ref = np.array([0.0, np.sqrt(complex(-w2)), -np.sqrt(complex(-w2))])
        err = max(min(abs(z - r) for r in ref) for z in lin.eigenvalues)
        expected = "critical" if W > Wc else "unstable"
        case_ok = (err < 1e-9 * max(1, abs(w2)) and lin.verdict == expected and lin.family == ("phi'",)
                   and lin.variables == ("theta", "psi'", "theta'") and lin.dependent == ("x'", "y'"))
        ok &= case_ok
        out["cases"].append({"W": W, "verdict": lin.verdict, "eigenvalue_error": err, "ok": case_ok})
    lin = linearize(model, about="steady", at={"phi'": 5.0})
    dev = linear_vs_nonlinear(model, lin, 5.0)
    ok &= dev < 1e-3
    out.update({"linear_vs_nonlinear": dev, "ok": bool(ok)})
    if verbose:
        print(TITLE)
        print(f"  critical spin W_c = sqrt(g/(3 r)) = {Wc:.10g} rad/s")
        for c in out["cases"]:
            print(f"  W = {c['W']:.6g}: {c['verdict']} (eigenvalues vs closed form: {c['eigenvalue_error']:.2e})")
        print(f"  lean after theta' = 1e-5: nonlinear vs linear, max difference {dev:.2e} of the perturbation")
        print(f"  ok: {out['ok']}")
    return out
