"""Manglieva & Beknazarov 2022, sec. 3.1, (3.14)-(3.19): the nonlinear friction speed regulator
with an elastic intermediate wheel (M. V. Keldysh's rolling model), its steady motion and the
conditions for it to exist.

Model (fig. 3.1).  Shaft 1 (angle phi1, inertia J1, torque M1) carries the centrifugal governor
(mass m_zp, arms l; its muff at x); the intermediate wheel (angle phi, radius r, inertia J) rolls
on the disc of shaft 1 at the radius r1 and on the disc of shaft 2 (phi2, J2, torque M2) at
``rho = x - c`` (3.15), so ``r1 phi1' = rho phi2'`` and ``r phi' = r1 phi1'`` (nonholonomic).  The
periphery of the wheel is massless; its lateral displacement lam and the turn psi of the contact
patch obey Keldysh's relations ((3.16), as (3.17) writes them)

    x' - lam' = r1 psi phi1',        psi' = r1 (alpha lam - beta psi) phi1',

and carry the elastic forces of the printed elementary work: ``a lam`` on lam, ``b psi`` on phi2
and on psi.  Springs (c1, c2, pretensions delta1, delta2) act on x.  The kinetic energy is
``T = theta(x) phi1'^2/2 + m(x) x'^2/2`` once the rolling relations are used, with (3.17)'s

    theta(x) = J2 r1^2/(x - c)^2 + J1 + J r1^2/r^2 + m_zp (4 l^2 - x^2)/2,
    m(x) = m_zp + 2 m_zp l^2/(4 l^2 - x^2);

the model file keeps all six coordinates (phi2, phi, lam, psi with their relations) and lets the
library eliminate them.

Equations of motion (derived by Appell's method; :func:`accelerations`).  With ``rho = x - c``,
phi2'' = r1 phi1''/rho - r1 phi1' x'/rho^2 from the rolling relation, and the massless periphery
(its two relations carry the reactions ``a lam`` and ``-b psi``):

    theta(x) phi1'' - F(x) x' phi1' = M1 + r1 (M2 + b psi)/rho - r1 a lam psi + r1 b psi (alpha lam - beta psi),
    m(x) x'' + m_zp x phi1'^2/2 + m'(x) x'^2/2 = -(c1 + c2)(x - x0) - c1 delta1 + c2 delta2 + a lam,

    F(x) = J2 r1^2/(x - c)^3 + m_zp x,      m'(x)/2 = 2 m_zp l^2 x/(4 l^2 - x^2)^2.

Steady motion (3.18) ``phi1' = omega0, x = x0, lam = psi = 0``: the residual rates there are
``phi1'' = (M1 + r1 M2/(x0 - c))/theta(x0)`` and ``x'' = (-c1 delta1 + c2 delta2 -
m_zp x0 omega0^2/2)/m(x0)``, so it exists iff (3.19)

    M1 + r1 M2/(x0 - c) = 0,         m_zp x0 omega0^2/2 = -c1 delta1 + c2 delta2     (as printed).

More generally (x0 the springs' reference): the steady motions are ``x_s = c - r1 M2/M1``,
``omega_s^2 = 2 (c2 delta2 - c1 delta1 - (c1 + c2)(x_s - x0))/(m_zp x_s)`` -- they exist iff
``M1 M2 < 0`` (``x_s > c``: shaft 1 receives the power shaft 2 brings, ``M1 omega1 < 0``), ``x_s < 2 l``
and the bracket is positive (:func:`steady_motion`).  The library finds them (``nonideal
stability ... --about steady``) and refuses the state (3.18) with ``--exact`` when (3.19) fails,
printing these residual rates.

Misprints (each derived above; the test of this example checks the equations against the
library at random states, which the printed forms fail):

* (3.14), the energy of accelerations: ``1/2 omega1' [theta]`` is ``1/2 omega1'^2 theta``;
  ``- omega1' omega1 x (J2 r1^2/(x - c)^3 + m_zp x)`` has x for x' (the cube is right: the
  derivative of phi2'' = r1 phi1''/rho - r1 phi1' x'/rho^2 gives J2 r1^2 phi1' x'/rho^3);
  ``1/2 x'^2 (m_zp + ...)`` is ``1/2 x''^2 m(x)``; and the governor's term
  ``m_zp x'' x' (omega^2/2 + 2 l^2 x^2/(4 l^2 - x^2)^2)`` has x and x' exchanged: it is
  ``m_zp x'' x (omega1^2/2 + 2 l^2 x'^2/(4 l^2 - x^2)^2)`` (its x''-derivative is the x-equation's
  ``m_zp x omega1^2/2 + m'(x) x'^2/2``, which (3.17) prints correctly).
* (3.17) prints ``theta(x) omega1' + F(x) x' omega1`` with ``F(x) = J2 r1^2/(x - c)^2 + m_zp x``:
  the exponent is 3, as in (3.14) (with 2 the term is not a torque: J2 r1^2/rho^2 x' omega1 has
  units kg m^3/s^2), and the sign is minus (both parts of F come from d/dt of a coefficient that
  decreases with x).  Lagrange's equations with phi2' = r1 phi1'/rho put into T -- not allowed
  for the nonholonomic rolling -- would give 2 J2 r1^2/rho^3 and a term J2 r1^2 phi1'^2/rho^3 in
  the x-equation, which (3.17) rightly does not have.
* The elementary work: its first line has ``+ b psi delta phi2`` = ``+ b psi r1/(x - c) delta
  phi1``, its second line ``- b psi R/(x - c)``, and (3.17) ``- b psi`` (R/(x - c) dropped); it is
  ``+ r1 b psi/(x - c)``.  ``a lam delta lam = a lam delta x`` drops ``delta lam = delta x - r1 psi
  delta phi1`` (the lateral relation): the phi1-equation lacks ``- r1 a lam psi`` (second order,
  no effect on (3.18)-(3.22)).
* (3.16) prints the third relation as ``psi1' = (alpha lam' - beta psi') R phi1'``; (3.17) and
  (3.21)'s determinant use ``(alpha lam - beta psi) R omega1`` (R = r1 throughout, V0 = r1 omega0).

Linearized about (3.18), the equations give the determinant (3.22) with ``-F(x0) omega0`` for its
``+F(x0) omega0`` and ``r1 b/(x0 - c)`` for its b (:func:`characteristic_polynomial`; the library's
linearization of this nonlinear model agrees with it; ``regulator-elastic-wheel`` studies the
printed determinant itself).

    nonideal stability regulator-elastic-wheel-nonlinear --about steady --at "phi1'=omega0, x=x0"
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "regulator-elastic-wheel-nonlinear"
ORDER = 208
TITLE = ("Regulator with an elastic intermediate wheel, nonlinear (3.14)-(3.19): the steady motion "
         "and the conditions for it to exist")
FILE = "regulator_elastic_wheel_nonlinear.toml"

DEFAULTS = {"J1": 0.02, "J2": 0.05, "J": 0.01, "r1": 0.05, "r": 0.05, "c": 0.02, "l": 0.1, "mzp": 0.3,
            "x0": 0.06, "omega0": 10.0, "M2": 0.2, "M1": -0.25, "c1": 50.0, "c2": 50.0, "d1": 0.01,
            "d2": 0.028, "a": 9.0, "b": -0.5, "alpha": -20.0, "beta": 4.0}


def build(**overrides) -> Model:
    """The nonlinear regulator with the Python API (same as the model file for the defaults)."""
    return Model(
        name="regulator with an elastic intermediate wheel, nonlinear (Manglieva & Beknazarov 2022, (3.14)-(3.19))",
        coordinates=["phi1", "phi2", "phi", "x", "lam", "psi"], parameters={**DEFAULTS, **overrides},
        kinetic=("J1/2*phi1'^2 + J2/2*phi2'^2 + J/2*phi'^2 + mzp/4*(4*l^2 - x^2)*phi1'^2"
                 " + (mzp + 2*mzp*l^2/(4*l^2 - x^2))/2*x'^2"),
        forces={"phi1": "M1", "phi2": "M2 + b*psi", "psi": "b*psi",
                "x": "-(c1 + c2)*(x - x0) - c1*d1 + c2*d2", "lam": "a*lam"},
        constraints=[Constraint.nonholonomic("roll_2", "r1*phi1' - (x - c)*phi2'"),
                     Constraint.nonholonomic("roll_wheel", "r*phi' - r1*phi1'"),
                     Constraint.nonholonomic("lateral", "x' - lam' - r1*psi*phi1'"),
                     Constraint.nonholonomic("keldysh", "psi' - r1*(alpha*lam - beta*psi)*phi1'")],
        initial={"phi1": 0.0, "phi2": 0.0, "phi": 0.0, "x": "x0", "lam": 0.0, "psi": 0.0,
                 "phi1'": "omega0", "x'": 0.0},
        independent=["phi1", "x"], simulation={"t_end": 2.0})


def theta(x, p):
    """theta(x) of (3.17)."""
    return (p["J2"] * p["r1"] ** 2 / (x - p["c"]) ** 2 + p["J1"] + p["J"] * p["r1"] ** 2 / p["r"] ** 2
            + p["mzp"] * (4 * p["l"] ** 2 - x ** 2) / 2)


def mass(x, p):
    """m(x) of (3.17)."""
    return p["mzp"] + 2 * p["mzp"] * p["l"] ** 2 / (4 * p["l"] ** 2 - x ** 2)


def F(x, p, printed: bool = False):
    """F(x) of the phi1-equation: derived ``J2 r1^2/(x - c)^3 + m_zp x`` (entering with a minus),
    or as (3.17) prints it, ``J2 r1^2/(x - c)^2 + m_zp x`` (entering with a plus)."""
    return p["J2"] * p["r1"] ** 2 / (x - p["c"]) ** (2 if printed else 3) + p["mzp"] * x


def accelerations(p, x, lam, psi, w, xd, printed: bool = False) -> tuple[float, float]:
    """``(phi1'', x'')`` at the state (derived equations of the module docstring), or by the
    printed (3.17) (*printed*: F with (x - c)^2 and +, ``b psi (r1 (alpha lam - beta psi) - 1)``)."""
    rho = x - p["c"]
    if printed:
        rhs = p["M1"] + p["r1"] * p["M2"] / rho + p["b"] * psi * (p["r1"] * (p["alpha"] * lam - p["beta"] * psi) - 1)
        wd = (rhs - F(x, p, True) * xd * w) / theta(x, p)
    else:
        rhs = (p["M1"] + p["r1"] * (p["M2"] + p["b"] * psi) / rho - p["r1"] * p["a"] * lam * psi
               + p["r1"] * p["b"] * psi * (p["alpha"] * lam - p["beta"] * psi))
        wd = (rhs + F(x, p) * xd * w) / theta(x, p)
    l2 = 4 * p["l"] ** 2 - x ** 2
    Qx = -(p["c1"] + p["c2"]) * (x - p["x0"]) - p["c1"] * p["d1"] + p["c2"] * p["d2"] + p["a"] * lam
    xdd = (Qx - p["mzp"] * x * w ** 2 / 2 - 2 * p["mzp"] * p["l"] ** 2 * x / l2 ** 2 * xd ** 2) / mass(x, p)
    return float(wd), float(xdd)


def residual_rates(p) -> tuple[float, float]:
    """``(phi1'', x'')`` at the state (3.18): both zero iff (3.19)."""
    x0, w0 = p["x0"], p["omega0"]
    return ((p["M1"] + p["r1"] * p["M2"] / (x0 - p["c"])) / theta(x0, p),
            (-p["c1"] * p["d1"] + p["c2"] * p["d2"] - p["mzp"] * x0 * w0 ** 2 / 2) / mass(x0, p))


def steady_motion(p) -> dict | None:
    """The steady motion ``phi1' = omega_s, x = x_s, lam = psi = 0`` (module docstring), or
    None where it does not exist (``M1 M2 >= 0``, ``x_s >= 2 l`` or ``omega_s^2 <= 0``)."""
    if p["M1"] * p["M2"] >= 0:
        return None
    xs = p["c"] - p["r1"] * p["M2"] / p["M1"]
    w2 = 2 * (p["c2"] * p["d2"] - p["c1"] * p["d1"] - (p["c1"] + p["c2"]) * (xs - p["x0"])) / (p["mzp"] * xs)
    if xs >= 2 * p["l"] or w2 <= 0:
        return None
    return {"x": xs, "omega": float(np.sqrt(w2))}


def characteristic_polynomial(p, x0: float | None = None, omega0: float | None = None) -> list[float]:
    """Monic coefficients (highest first) of the first approximation about a steady motion: the
    determinant of the linearized equations of the module docstring (SymPy)."""
    import sympy as sp

    s = sp.Symbol("s")
    x0 = p["x0"] if x0 is None else x0
    w0 = p["omega0"] if omega0 is None else omega0
    rho0, V0 = x0 - p["c"], p["r1"] * w0
    P1, P2 = F(x0, p) * w0, p["r1"] * p["M2"] / rho0 ** 2
    P3 = p["mzp"] * x0 * w0
    P4 = p["mzp"] * w0 ** 2 / 2 + p["c1"] + p["c2"]
    D = sp.Matrix([[theta(x0, p) * s, -P1 * s + P2, 0, -p["r1"] * p["b"] / rho0],
                   [P3, mass(x0, p) * s ** 2 + P4, -p["a"], 0],
                   [0, s, -s, -V0],
                   [0, 0, -V0 * p["alpha"], s + V0 * p["beta"]]])
    coeffs = [float(c) for c in sp.Poly(sp.expand(D.det(method="berkowitz")), s).all_coeffs()]
    return [c / coeffs[0] for c in coeffs]


def run(verbose: bool = True) -> dict:
    import sympy as sp

    from ..analysis.evaluation import evaluate
    from ..analysis.stability.linearize import linearize
    from . import load

    model = load(NAME)
    p = dict(model.parameter_values)
    rng = np.random.default_rng(7)
    worst, worst_printed = 0.0, 0.0
    for _ in range(8):
        x, lam, psi = p["x0"] + rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), rng.uniform(-0.05, 0.05)
        w, xd = rng.uniform(5, 15), rng.uniform(-0.5, 0.5)
        at = {"x": x, "lam": lam, "psi": psi, "phi1'": w, "x'": xd}
        ev = evaluate(model, at=at).to_dict()["qddot"]
        mine = accelerations(p, x, lam, psi, w, xd)
        printed = accelerations(p, x, lam, psi, w, xd, printed=True)
        worst = max(worst, abs(ev["phi1"] - mine[0]) / max(1.0, abs(mine[0])), abs(ev["x"] - mine[1]) / max(1.0, abs(mine[1])))
        worst_printed = max(worst_printed, abs(ev["phi1"] - printed[0]) / max(1.0, abs(mine[0])))
    at_steady = evaluate(model).to_dict()["qddot"]
    steady_ok = max(abs(at_steady[c]) for c in ("phi1", "x")) < 1e-12 and max(abs(r) for r in residual_rates(p)) < 1e-12
    # another steady motion: M1 = -0.2, delta2 = 0.035 (x_s = 0.07 from (3.19), omega_s from its second part)
    q = {**p, "M1": -0.2, "d2": 0.035}
    found = steady_motion(q)
    lin = linearize(build(M1=-0.2, d2=0.035), about="steady", at={"phi1'": 5.0, "x": 0.07})
    xs, ws = float(lin.q["x"]), float(lin.qdot["phi1"])
    other_err = max(abs(xs - found["x"]), abs(ws - found["omega"]) / found["omega"])
    ref = characteristic_polynomial(p)
    lin0 = linearize(model, about="steady", at={"phi1'": p["omega0"], "x": p["x0"]})
    mine = [float(c) for c in sp.Poly(lin0.characteristic_polynomial, sp.Symbol("s")).all_coeffs()]
    poly_err = max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(mine, ref))
    ok = (worst < 1e-10 and worst_printed > 1e-3 and steady_ok and other_err < 1e-6 and len(mine) == 6
          and poly_err < 1e-8 and steady_motion({**p, "M1": 0.25}) is None)
    out = {"equations_error": worst, "printed_equations_error": worst_printed, "steady_3_18": steady_ok,
           "other_steady": found, "other_steady_error": other_err, "polynomial": str(lin0.characteristic_polynomial),
           "polynomial_error": poly_err, "verdict": lin0.verdict, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  phi1'', x'' of the library vs the derived equations at 8 random states: {worst:.1e}; "
              f"vs the printed (3.17): {worst_printed:.3g}")
        print(f"  (3.18) with (3.19): rates {at_steady['phi1']:.1e}, {at_steady['x']:.1e}")
        print(f"  M1 = -0.2, delta2 = 0.035: steady x_s = {found['x']:.6g}, omega_s = {found['omega']:.8g} "
              f"(library {xs:.6g}, {ws:.8g})")
        print(f"  first approximation about (3.18): {lin0.characteristic_polynomial} (vs derived "
              f"{poly_err:.1e}); {lin0.verdict}")
        print(f"  ok: {ok}")
    return out
