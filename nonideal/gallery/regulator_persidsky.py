"""Manglieva & Beknazarov 2022, ch. 3, (3.5)-(3.13): the programme of the friction speed
regulator and its stability by Persidsky's criterion.

Model.  Under the servo-constraint omega2 = omega0 (shaft 2 turns at the programmed speed) the
regulator's Appell equation for shaft 2 (Manglieva & Beknazarov 2022, (3.26)-(3.27) with
zeta = 0; n = J1/R^2 + J/r^2 the reduced inertia of wheel 1 and of the intermediate wheel)

    n omega0 rho rho' = M2 + rho M1 / R,     i.e.   k rho' = k1/rho + k2   (3.5),

k = n omega0, k1 = M2, k2 = M1/R, is a first-order relation for the position rho of the
intermediate wheel: the programme.  Here it is a servo-constraint on rho realized by the
control force u along rho (its multiplier, (3.9): u = m rho'').

Checks (run()):

* the programme followed by the library against the quadrature (3.10),
  t = (k/k2) (rho - rho0 - (k1/k2) ln((k2 rho + k1)/(k2 rho0 + k1)));
* the first approximation along it: the library's A(t) (one variable: the servo-constraint
  eliminates rho') against (3.13), rho'_dot = -(k1/(k rho0(t)^2)) rho';
* Persidsky's criterion: with M2 > 0 and rho bounded by rho_max,
  exp(int A) <= exp(-alpha (t - t0)), alpha = k1/(k rho_max^2) > 0 -- the library finds the
  logarithmic-norm bound with this alpha (its largest mu(A(t)) is -alpha) and the verdict
  "asymptotically stable"; with M2 < 0 the same programme is unstable;
* the control force: the multiplier against m rho0'' from the closed form of rho0'.

Notation.  The paper's constants (3.4) carry a factor r^2: k = omega0 (J + J1 r^2/R^2) =
r^2 n omega0, k1 = r^2 M2, k2 = r^2 M1/R -- the same relation (3.5); (3.12)-(3.13) write
k1' = k1/k.  Misprint: the estimate after (3.13) is printed with exp(-int k1(tau)/rho0^2) (the
prime dropped); with k1' it gives alpha = k1'/rho_max^2 = r^2 M2/(k rho_max^2), as printed.

    nonideal stability regulator-persidsky --about program --t-end 2
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "regulator-persidsky"
ORDER = 205
TITLE = "Friction speed regulator: programme (3.10) and Persidsky's criterion (3.13) (Manglieva & Beknazarov 2022)"
FILE = "regulator_persidsky.toml"

DEFAULTS = {"m": 0.5, "J1": 0.02, "J": 0.01, "R": 0.1, "r": 0.05, "omega0": 20.0, "M1": 0.3, "M2": 0.5}
RHO0 = 0.05


def build(**overrides) -> Model:
    """The programme with the Python API (same as the model file for the default values)."""
    p = {**DEFAULTS, **overrides}
    p["n"] = "J1/R^2 + J/r^2"
    return Model(
        name="friction speed regulator: programme rho(t) (Manglieva & Beknazarov 2022, (3.5))",
        coordinates=["rho"], parameters=p, kinetic="m*rho'^2/2",
        constraints=[Constraint.servo("programme", "n*omega0*rho*rho' - M2 - rho*M1/R", reaction=["1"])],
        initial={"rho": RHO0}, simulation={"t_end": 2.0})


def constants(p: dict) -> tuple[float, float, float]:
    """(k, k1, k2) of (3.5)."""
    n = p["J1"] / p["R"] ** 2 + p["J"] / p["r"] ** 2
    return n * p["omega0"], p["M2"], p["M1"] / p["R"]


def time_of(rho, p: dict, rho0: float = RHO0):
    """(3.10): the time at which the programme reaches rho."""
    k, k1, k2 = constants(p)
    return k / k2 * (rho - rho0 - k1 / k2 * np.log((k2 * rho + k1) / (k2 * rho0 + k1)))


def run(verbose: bool = True) -> dict:
    from ..analysis.stability.program import linearize_program
    from ..simulation import simulate
    from . import load

    model = load(NAME)
    p = dict(DEFAULTS)
    k, k1, k2 = constants(p)
    prog = linearize_program(model, samples=81)
    rho = prog.q["rho"]
    t_err = float(np.max(np.abs(time_of(rho, p) - prog.t)))
    A_ref = -k1 / (k * rho ** 2)
    A_err = float(np.max(np.abs(prog.A[:, 0, 0] - A_ref) / np.abs(A_ref)))
    alpha = k1 / (k * rho.max() ** 2)
    bound_ok = abs(prog.persidsky_alpha - alpha) < 1e-6 * alpha and prog.persidsky_beta == 0
    traj = simulate(model, times=prog.t[::10])
    rd = traj.qd[:, 0]
    rdd = -(k1 / (k * traj.q[:, 0] ** 2)) * rd            # d/dt (k1/(k rho) + k2/k)
    u = np.asarray(traj.multipliers["programme"])
    u_err = float(np.max(np.abs(u - p["m"] * rdd)) / np.max(np.abs(p["m"] * rdd)))
    unstable = linearize_program(load(NAME).replace(parameters={**model.parameters, "M2": -0.05,
                                                                 "M1": 0.6}), samples=41)
    ok = (t_err < 1e-7 and A_err < 1e-7 and bound_ok and prog.verdict == "asymptotically stable"
          and prog.variables == ("rho",) and u_err < 1e-6 and unstable.verdict == "unstable")
    out = {"programme_time_error": t_err, "A_relative_error": A_err, "alpha": alpha,
           "library_alpha_bound": prog.persidsky_alpha, "verdict": prog.verdict,
           "control_force_error": u_err, "verdict_M2_negative": unstable.verdict, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  programme vs quadrature (3.10): max |t_library - t(rho)| = {t_err:.2e} s")
        print(f"  A(t) vs (3.13) -k1/(k rho0^2): {A_err:.2e} (relative)")
        print(f"  Persidsky: alpha = k1/(k rho_max^2) = {alpha:.6g}; library: alpha = {prog.persidsky_alpha:.6g}, "
              f"beta = {prog.persidsky_beta:g} (uniform over every sub-interval) -> {prog.verdict}")
        print(f"  control force u = m rho'' (3.9): {u_err:.2e} (relative)")
        print(f"  with M2 < 0: {unstable.verdict}")
        print(f"  ok: {ok}")
    return out
