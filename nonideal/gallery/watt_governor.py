"""Watt's centrifugal governor on a steam engine: Vyshnegradsky's condition.

Classic (I. A. Vyshnegradsky 1877; Pontryagin, *Ordinary differential equations*, sec. 27).
The governor's arms (length l, balls of mass m) make the angle phi with the shaft, which
turns at n w (w = theta' the engine's speed, n the gear ratio); the flywheel's moment of
inertia J dominates the governor's own.  With damping b of the sleeve, the engine's torque
k cos(phi) (the valve follows the sleeve) and the load F:

    m l^2 phi'' = m l^2 n^2 w^2 sin(phi) cos(phi) - m g l sin(phi) - b phi',
    J w' = k cos(phi) - F.

Steady motion (theta ignorable, found by the library by Newton from a guess):
cos(phi0) = F/k, w0^2 = g/(l n^2 cos(phi0)).  First approximation in (phi, phi', w)
(derived here):

    s^3 + (b/(m l^2)) s^2 + n^2 w0^2 sin^2(phi0) s + 2 n^2 w0 k sin^2(phi0) cos(phi0)/J = 0,

and the Hurwitz condition a1 a2 > a3 is  b J w0 > 2 m l^2 F,  i.e. Vyshnegradsky's
(b J / (m l^2)) nu > 1 with the non-uniformity nu = |dw0/dF| = w0/(2F): more damping, a
heavier flywheel, lighter balls or more non-uniformity stabilize.  The library finds the same
boundary from the model file with ``--symbolic`` (run() checks the critical J).

    nonideal stability watt-governor --about steady --at "phi=acos(F/k), theta'=sqrt(g*k/(l*n^2*F))" --symbolic J
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Model

NAME = "watt-governor"
ORDER = 201
TITLE = "Watt governor: Vyshnegradsky's condition b J w0 > 2 m l^2 F (Routh-Hurwitz, steady motion)"
FILE = "watt_governor.toml"

DEFAULTS = {"m": 1.0, "l": 0.3, "n": 2.0, "g": 9.81, "b": 0.5, "J": 1.0, "k": 10.0, "F": 5.0}


def build(**overrides) -> Model:
    """The governor with the Python API (same as the model file for the default values)."""
    p = {**DEFAULTS, **overrides}
    return Model(
        name="Watt governor (Vyshnegradsky)", coordinates=["phi", "theta"], parameters=p,
        kinetic="m*l^2*phi'^2/2 + J*theta'^2/2", potential="-m*g*l*cos(phi)",
        forces={"phi": "m*l^2*n^2*theta'^2*sin(phi)*cos(phi) - b*phi'", "theta": "k*cos(phi) - F"},
        initial={"phi": 1.0, "theta": 0.0, "phi'": 0.0, "theta'": 4.0}, simulation={"t_end": 10.0})


def steady(m, l, n, g, b, J, k, F) -> tuple[float, float]:
    """(phi0, w0)."""
    phi0 = np.arccos(F / k)
    return phi0, np.sqrt(g / (l * n * n * np.cos(phi0)))


def polynomial(m, l, n, g, b, J, k, F) -> list[float]:
    """Coefficients of the characteristic polynomial (docstring)."""
    phi0, w0 = steady(m, l, n, g, b, J, k, F)
    s2 = np.sin(phi0) ** 2
    return [1.0, b / (m * l * l), n * n * w0 * w0 * s2, 2 * n * n * w0 * k * s2 * np.cos(phi0) / J]


def critical_J(m, l, n, g, b, J, k, F) -> float:
    """Vyshnegradsky: J_c = 2 m l^2 F / (b w0)."""
    return 2 * m * l * l * F / (b * steady(m, l, n, g, b, J, k, F)[1])


def run(verbose: bool = True) -> dict:
    import sympy as sp

    from ..analysis.stability.linearize import linearize
    from . import load

    model = load(NAME)
    p = dict(DEFAULTS)
    phi0, w0 = steady(**p)
    lin = linearize(model, about="steady", at={"phi": 0.9, "theta'": 3.0})
    state_err = max(abs(lin.q["phi"] - phi0), abs(lin.qdot["theta"] - w0))
    ref = np.roots(polynomial(**p))
    eig_err = max(min(abs(z - r) for r in ref) for z in lin.eigenvalues) / max(1.0, abs(ref).max())
    Jc = critical_J(**p)
    verdicts = {}
    for J in (1.1 * Jc, 0.9 * Jc):
        linJ = linearize(build(J=J), about="steady", at={"phi": phi0, "theta'": w0})
        verdicts[J] = linJ.verdict
    sym = linearize(model, about="steady", at="phi=acos(F/k), theta'=sqrt(g*k/(l*n^2*F))", symbolic=["J"])
    Js = sp.Symbol("J")
    bounds = sorted({float(r) for c in sym.conditions for r in sp.solve(sp.Eq(c.lhs - c.rhs, 0), Js)
                     if r.is_real})
    ok = (state_err < 1e-9 and eig_err < 1e-9 and verdicts[1.1 * Jc] == "asymptotically stable"
          and verdicts[0.9 * Jc] == "unstable" and any(abs(x - Jc) < 1e-8 * Jc for x in bounds)
          and lin.variables == ("phi", "phi'", "theta'") and lin.ignorable == ("theta",))
    out = {"phi0": phi0, "w0": w0, "state_error": state_err, "eigenvalue_error": eig_err,
           "critical_J": Jc, "verdicts": {f"{k:.6g}": v for k, v in verdicts.items()},
           "conditions": [str(c) for c in sym.conditions], "boundaries_J": bounds, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  steady motion found by Newton: phi0 = {lin.q['phi']:.10g} (closed form {phi0:.10g}), "
              f"w0 = {lin.qdot['theta']:.10g} ({w0:.10g})")
        print(f"  polynomial: {lin.characteristic_polynomial}; eigenvalues vs closed form: {eig_err:.2e}")
        print(f"  Vyshnegradsky: J_c = 2 m l^2 F/(b w0) = {Jc:.10g}; library's boundary in J: {bounds}")
        for J, v in verdicts.items():
            print(f"  J = {J:.6g}: {v}")
        print(f"  ok: {ok}")
    return out
