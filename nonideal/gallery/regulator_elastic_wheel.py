"""Manglieva & Beknazarov 2022, sec. 3.1, (3.20)-(3.22): the regulator with an elastic
intermediate wheel (M. V. Keldysh's rolling model) -- determinant (3.22), its expansion and the
Hurwitz conditions.

Model.  The first approximation about the steady motion (3.18) (omega1 = omega0, x = x0,
lambda = psi = 0) in the perturbations w = omega1 - omega0, x, lambda, psi:

    theta0 w' + Phi1 x' + Phi2 x - b psi = 0,          m0 x'' + Phi3 w + Phi4 x - a lambda = 0,
    x' - lambda' = V0 psi,                              psi' = V0 (alpha lambda - beta psi),

Phi1 = F(x0) omega0, Phi2 = r1 M2/rho0^2, Phi3 = m_zp x0 omega0, Phi4 = m_zp omega0^2/2 + c1 + c2,
V0 = r1 omega0: exactly the rows of the determinant (3.22).  The model file writes it as a
mechanical system (shaft angle phi1 with phi1' = omega0 + w, the massless periphery
coordinates lambda, psi tied by two nonholonomic rolling relations); the library linearizes it
about the steady motion phi1' = omega0 (phi1 ignorable, lambda', psi' eliminated) and finds a
fifth-degree polynomial.  The printed text is inconsistent about this linear system: (3.20)
writes x' where the determinant has x (Phi2 x) and 2 x0 omega0 w' where it has Phi3 w, and the
sign of b psi differs between (3.17) and (3.20); the determinant (3.22) is taken as the
statement.

Checks (run()): the library's characteristic polynomial equals det (3.22) divided by
theta0 m0 (expanded independently with SymPy); the library's Hurwitz minors equal those of
that polynomial and are all positive for the parameters of the model file (asymptotically
stable; the eigenvalues agree); with beta < 0 the coefficient of s^4, V0 beta, is negative and
the steady motion is unstable.  Misprints: the expanded polynomial printed after (3.22),
compared term by term with the determinant (SymPy; the test repeats it), has the wrong sign in
the s^4 term (-theta m0 beta1), in Phi3 Phi1 and Phi4 theta of the s^3 term, in Phi3 Phi1
beta1, Phi4 theta beta1 and Phi3 Phi2 of the s^2 term and in beta1 Phi3 Phi2 of the s term (the
s^5 and constant terms are right); its coefficient list writes a0 = theta m_zp (it is
theta m0), so the printed Hurwitz minors inherit these signs.

More misprints (derived here; :func:`hurwitz_coefficients` and ``run`` give the numbers).

* (3.21) prints the last equation ``psi' - r1 omega0 alpha lambda' + r1 omega0 beta psi = 0``;
  the linearization of (3.17), ``psi' = (alpha lambda - beta psi) R omega1``, has ``lambda``,
  not ``lambda'`` -- as the determinant's last row ``(0, 0, -V0 alpha, mu + V0 beta)`` has.
* The Hurwitz coefficients printed after (3.22), with ``Z = -Phi3 Phi1 + Phi4 theta +
  a theta``: the determinant (3.22) divided by its sign gives, with
  ``Z~ = -Phi3 Phi1 + Phi4 theta - a theta`` (the sign of ``a theta`` reversed),

      a0 = theta m0,  a1 = theta m0 beta1,  a2 = Z~ + theta m0 alpha1 V0,
      a3 = beta1 Z~ - Phi3 Phi2,  a4 = Phi3 (b alpha1 - beta1 Phi2) + alpha1 V0 (Z~ + a theta),
      a5 = -alpha1 V0 Phi3 Phi2,

  where the paper prints ``a2 = Z - theta m_zp alpha1 V0`` (the sign of the alpha1 term and
  Z for Z~), ``a3 = beta1 Z - Phi3 Phi2`` (Z for Z~), ``a4 = ... + alpha1 V0 (a theta - Z)``
  (the sign of the bracket: ``Z~ + a theta = Z - a theta``) and ``a5 = +alpha1 V0 Phi3 Phi2``
  (its own expansion ends with ``- alpha1 V0 Phi3 Phi2``).
* The minors: ``Delta1 = a1 = theta m0 beta1`` (printed ``theta m0``, beta1 dropped);
  ``Delta2 = a1 a2 - a0 a3 = theta m0 (Phi3 Phi2 + theta m0 alpha1 V0 beta1)`` (printed
  ``theta m0 (Phi3 Phi2 - theta m0 alpha1 V0 beta1 V0)``: the sign and an extra V0);
  ``Delta3`` is not printed at all (the list goes Delta1, Delta2, Delta4, Delta5), though the
  criterion needs it; ``Delta5 = a5 Delta4`` reduces to ``a5 > 0``, i.e. to
  ``alpha1 V0 Phi3 Phi2 < 0`` with the sign corrected (alpha < 0 for the model file's numbers).
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "regulator-elastic-wheel"
ORDER = 207
TITLE = "Regulator with an elastic intermediate wheel (Keldysh): determinant (3.22) and Hurwitz conditions"
FILE = "regulator_elastic_wheel.toml"

DEFAULTS = {"theta0": 0.05, "m0": 0.4, "F0": 0.02, "omega0": 10.0, "r1": 0.05, "M2": 0.2, "rho0": 0.04,
            "mzp": 0.3, "x0": 0.06, "c1": 50.0, "c2": 50.0, "a": 9.0, "b": -20.0, "alpha": -20.0, "beta": 4.0}
DERIVED = {"V0": "r1*omega0", "Phi1": "F0*omega0", "Phi2": "r1*M2/rho0^2", "Phi3": "mzp*x0*omega0",
           "Phi4": "mzp*omega0^2/2 + c1 + c2"}


def build(**overrides) -> Model:
    """The linear regulator with the Python API (same as the model file for the defaults)."""
    return Model(
        name="regulator with an elastic intermediate wheel (Manglieva & Beknazarov 2022, (3.22))",
        coordinates=["phi1", "x", "lam", "psi"], parameters={**DEFAULTS, **overrides, **DERIVED},
        kinetic="theta0*phi1'^2/2 + m0*x'^2/2",
        forces={"phi1": "-Phi1*x' - Phi2*x + b*psi", "x": "-Phi3*(phi1' - omega0) - Phi4*x + a*lam"},
        constraints=[Constraint.nonholonomic("roll", "x' - lam' - V0*psi"),
                     Constraint.nonholonomic("keldysh", "psi' - V0*(alpha*lam - beta*psi)")],
        initial={"phi1": 0.0, "x": 0.0, "lam": 0.0, "psi": 0.0, "phi1'": "omega0", "x'": 0.0},
        independent=["phi1", "x"], simulation={"t_end": 2.0})


def determinant_coefficients(p: dict) -> list[float]:
    """Coefficients (highest first) of det (3.22) / (theta0 m0), expanded with SymPy."""
    import sympy as sp

    mu = sp.Symbol("mu")
    V0 = p["r1"] * p["omega0"]
    P1, P2 = p["F0"] * p["omega0"], p["r1"] * p["M2"] / p["rho0"] ** 2
    P3, P4 = p["mzp"] * p["x0"] * p["omega0"], p["mzp"] * p["omega0"] ** 2 / 2 + p["c1"] + p["c2"]
    D = sp.Matrix([[p["theta0"] * mu, P1 * mu + P2, 0, -p["b"]],
                   [P3, p["m0"] * mu ** 2 + P4, -p["a"], 0],
                   [0, mu, -mu, -V0],
                   [0, 0, -V0 * p["alpha"], mu + V0 * p["beta"]]])
    coeffs = [float(c) for c in sp.Poly(sp.expand(D.det(method="berkowitz")), mu).all_coeffs()]
    return [c / coeffs[0] for c in coeffs]


def hurwitz_coefficients(p: dict, printed: bool = False) -> list[float]:
    """a0 .. a5 of the characteristic polynomial in the paper's notation (module docstring):
    derived from the determinant (3.22), or (*printed*) as the paper prints them after it."""
    V0 = p["r1"] * p["omega0"]
    th, m0, a, b = p["theta0"], p["m0"], p["a"], p["b"]
    P1, P2 = p["F0"] * p["omega0"], p["r1"] * p["M2"] / p["rho0"] ** 2
    P3, P4 = p["mzp"] * p["x0"] * p["omega0"], p["mzp"] * p["omega0"] ** 2 / 2 + p["c1"] + p["c2"]
    al1, be1 = V0 * p["alpha"], V0 * p["beta"]
    if printed:
        Z = -P3 * P1 + P4 * th + a * th
        return [th * p["mzp"], th * p["mzp"] * be1, Z - th * p["mzp"] * al1 * V0, be1 * Z - P3 * P2,
                P3 * (b * al1 - be1 * P2) + al1 * V0 * (a * th - Z), al1 * V0 * P3 * P2]
    Zt = -P3 * P1 + P4 * th - a * th
    return [th * m0, th * m0 * be1, Zt + th * m0 * al1 * V0, be1 * Zt - P3 * P2,
            P3 * (b * al1 - be1 * P2) + al1 * V0 * (Zt + a * th), -al1 * V0 * P3 * P2]


def printed_minors(p: dict) -> list[float]:
    """Delta1, Delta2 as printed after (3.22) (Delta3 is not printed)."""
    V0 = p["r1"] * p["omega0"]
    th, m0 = p["theta0"], p["m0"]
    P2, P3 = p["r1"] * p["M2"] / p["rho0"] ** 2, p["mzp"] * p["x0"] * p["omega0"]
    al1, be1 = V0 * p["alpha"], V0 * p["beta"]
    return [th * m0, th * m0 * (P3 * P2 - th * m0 * al1 * V0 * be1 * V0)]


def hurwitz(coeffs) -> list[float]:
    """Hurwitz minors of a polynomial (independent of the library's routh module)."""
    n = len(coeffs) - 1
    H = np.array([[coeffs[2 * j - i] if 0 <= 2 * j - i <= n else 0.0 for j in range(1, n + 1)]
                  for i in range(1, n + 1)])
    return [float(np.linalg.det(H[:k, :k])) for k in range(1, n + 1)]


def run(verbose: bool = True) -> dict:
    import sympy as sp

    from ..analysis.stability.linearize import linearize
    from . import load

    lin = linearize(load(NAME), about="steady", at={"phi1'": DEFAULTS["omega0"]})
    ref = determinant_coefficients(DEFAULTS)
    mine = [float(c) for c in sp.Poly(lin.characteristic_polynomial, sp.Symbol("s")).all_coeffs()]
    poly_err = max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(mine, ref))
    H_ref = hurwitz(ref)
    H_err = max(abs(float(a) - b) / max(1.0, abs(b)) for a, b in zip(lin.hurwitz, H_ref))
    eig_err = max(min(abs(z - r) for r in np.roots(ref)) for z in lin.eigenvalues)
    unstable = linearize(build(beta=-4.0), about="steady", at={"phi1'": DEFAULTS["omega0"]})
    # the Hurwitz coefficients and minors in the paper's notation: derived vs printed
    a_true = hurwitz_coefficients(DEFAULTS)
    a_printed = hurwitz_coefficients(DEFAULTS, printed=True)
    coef_err = max(abs(a_true[0] * c - t) / max(1.0, abs(t)) for c, t in zip(mine, a_true))
    minors = hurwitz(a_true)
    printed_D = printed_minors(DEFAULTS)
    ok = (len(mine) == 6 and poly_err < 1e-8 and H_err < 1e-6 and all(h > 0 for h in H_ref)
          and lin.verdict == "asymptotically stable" and eig_err < 1e-7 and unstable.verdict == "unstable"
          and lin.variables == ("x", "lam", "psi", "phi1'", "x'") and coef_err < 1e-9)
    out = {"polynomial": str(lin.characteristic_polynomial), "determinant": ref, "polynomial_error": poly_err,
           "hurwitz": [float(h) for h in lin.hurwitz], "hurwitz_error": H_err, "verdict": lin.verdict,
           "verdict_beta_negative": unstable.verdict, "hurwitz_coefficients": a_true,
           "hurwitz_coefficients_printed": a_printed, "coefficient_error": coef_err,
           "minors_paper_notation": minors, "minors_printed": printed_D, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  library: {lin.characteristic_polynomial}")
        print(f"  det (3.22)/(theta0 m0): {np.array2string(np.array(ref), precision=6)}  (difference {poly_err:.1e})")
        print("  Hurwitz minors: " + ", ".join(f"{float(h):.6g}" for h in lin.hurwitz) + f" (vs independent {H_err:.1e})")
        print(f"  verdict: {lin.verdict}; with beta = -4: {unstable.verdict}")
        print("  a0..a5 derived from (3.22): " + ", ".join(f"{x:.6g}" for x in a_true)
              + f" (theta0 m0 x the library's, difference {coef_err:.1e})")
        print("  a0..a5 as printed:          " + ", ".join(f"{x:.6g}" for x in a_printed))
        print(f"  Delta1, Delta2, Delta3: {minors[0]:.6g}, {minors[1]:.6g}, {minors[2]:.6g}; printed "
              f"Delta1, Delta2: {printed_D[0]:.6g}, {printed_D[1]:.6g} (Delta3 not printed)")
        print(f"  ok: {ok}")
    return out
