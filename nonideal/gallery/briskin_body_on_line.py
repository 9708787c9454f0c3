"""Briskin et al. 2021, sec. 3.3: stability of phi = 0 for a planar body with a quasi-ideal
constraint -- the library's condition, and where the printed one is incomplete.

Model (Briskin et al. 2021, (3.19)--(3.22)).  A planar body (mass M, central moment of inertia
J), coordinates x_C, y_C, phi; a follower force F along CA applied at C; the point A (CA = l)
is held on the line y = 0: f = y_C + l sin(phi) = 0 (3.20).  The constraint is quasi-ideal:
its reactions satisfy A R = lambda grad f with A = [[1, alpha, 0], [beta, 1, 0], [0, 0, 1]]
(3.21), so R = A^-1 grad f lambda: R_x = -alpha lambda/(1 - alpha beta),
R_y = lambda/(1 - alpha beta), R_phi = lambda l cos(phi).

Derivation (checked by the library from the model file).  With c = 1 - alpha beta, the twice
differentiated constraint (3.23) gives

    lambda = c J (M l phi'^2 - F) sin(phi) / (J + M c l^2 cos^2(phi)),
    J phi'' = lambda l cos(phi),

and about phi = 0 (x_C ignorable, x_C' drifting: the body is accelerated along the line)

    delta phi'' + k delta phi = 0,      k = c F l / (J + M c l^2).

Misprints of the printed formulas: (3.22) prints the y-equation as
``M y_C'' = F sin(phi) - lambda/(1 - alpha beta)``; by (3.21) ``R_y = lambda/(1 - alpha beta)``
(``R_x = -alpha lambda/(1 - alpha beta)``, which the x-equation adds correctly), so it is
``M y_C'' = F sin(phi) + lambda/(1 - alpha beta)`` -- the sign the printed (3.24) itself follows
from (with the minus, (3.23) would give the denominator ``-J + M c l^2 cos^2(phi)``).  In (3.24) the denominator is printed with
``cos(phi) sin(phi)`` (it is cos^2(phi)), the numerator with ``phi'^2 cos(phi) sin(phi)``
(it is phi'^2 sin(phi)) and the second equation without the factor l cos(phi); the variational
equation (3.25) is printed as ``J delta phi'' + (1 - alpha beta) F l delta phi = 0``, without
the factor J/(J + M c l^2).  That factor changes the answer: the first approximation is stable
(critical: the motion is conservative, a pair of imaginary roots) iff k > 0, i.e.

    c F > 0 when c > -J/(M l^2),        c F < 0 when c < -J/(M l^2).

The printed condition (3.26) -- pulling (F < 0) is stable when 1 - alpha beta < 0 -- is
therefore incomplete: it holds only for -J/(M l^2) < 1 - alpha beta < 0; beyond,
1 - alpha beta < -J/(M l^2), pushing is stable again and pulling unstable; and at
1 - alpha beta = -J/(M l^2) the constraint cannot be realized (G M^-1 B = 0: the multiplier is
undetermined; the library stops with exit code 3).  Checked: the library's eigenvalues against
+-sqrt(-k), its condition in (alpha, beta, F) against the sign of k at random points, and a
simulation of the nonlinear motion after a small perturbation against the linear solution.

    nonideal stability briskin-body-on-line --about steady --at "phi=0" --symbolic alpha,beta,F
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "briskin-body-on-line"
ORDER = 204
TITLE = "Briskin et al. 2021, sec. 3.3: stability of phi = 0 under a quasi-ideal constraint (3.25) corrected"
FILE = "briskin_body_on_line.toml"

DEFAULTS = {"M": 2.0, "J": 0.5, "l": 0.4, "F": 3.0, "alpha": 0.5, "beta": 0.5}


def build(**overrides) -> Model:
    """The body with the Python API (same as the model file for the default values)."""
    p = {**DEFAULTS, **overrides}
    return Model(
        name="Briskin et al. 2021: planar body with a quasi-ideal constraint", coordinates=["xc", "yc", "phi"],
        parameters=p, kinetic="M*(xc'^2 + yc'^2)/2 + J*phi'^2/2",
        forces={"xc": "F*cos(phi)", "yc": "F*sin(phi)"},
        constraints=[Constraint.holonomic("line", "yc + l*sin(phi)",
                                          transform=[["1", "alpha", "0"], ["beta", "1", "0"], ["0", "0", "1"]])],
        initial={"xc": 0.0, "yc": 0.0, "phi": 0.0, "xc'": 1.0, "phi'": 0.0}, simulation={"t_end": 2.0})


def stiffness(M, J, l, F, alpha, beta) -> float:
    """k of delta phi'' + k delta phi = 0 (the corrected (3.25))."""
    c = 1 - alpha * beta
    return c * F * l / (J + M * c * l * l)


def run(verbose: bool = True) -> dict:
    import sympy as sp
    from scipy.linalg import expm

    from ..analysis.stability.linearize import linearize
    from ..errors import LinearizationUndefined
    from ..simulation import simulate

    cases, ok = [], True
    Jc = DEFAULTS["J"] / (DEFAULTS["M"] * DEFAULTS["l"] ** 2)        # J/(M l^2)
    for F in (3.0, -3.0):
        for ab in (0.25, 1.0 + 0.5 * Jc, 1.0 + 2.0 * Jc):          # c > 0, -J/(Ml^2) < c < 0, c < -J/(Ml^2)
            p = {**DEFAULTS, "F": F, "alpha": 1.0, "beta": ab}
            lin = linearize(build(**p), about="steady", at={"phi": 0.0})
            k = stiffness(**p)
            ref = np.sqrt(complex(-k)) * np.array([1, -1])
            err = max(min(abs(z - r) for r in ref) for z in lin.eigenvalues)
            expected = "critical" if k > 0 else "unstable"
            printed = (1 - ab) * F > 0                    # (3.25)-(3.26) as printed
            good = err < 1e-9 and lin.verdict == expected and lin.variables == ("phi", "phi'")
            ok &= good
            cases.append({"F": F, "1-alpha*beta": 1 - ab, "k": k, "verdict": lin.verdict,
                          "printed_says_stable": printed, "ok": good})
    try:
        linearize(build(alpha=1.0, beta=1.0 + Jc), about="steady", at={"phi": 0.0})
        singular_ok = False
    except LinearizationUndefined:
        singular_ok = True
    ok &= singular_ok
    sym = linearize(build(), about="steady", at={"phi": 0.0}, symbolic=["alpha", "beta", "F"])
    a, b, F = sp.symbols("alpha beta F")
    rng = np.random.default_rng(5)
    agree = True
    for _ in range(30):
        vals = {a: rng.uniform(-3, 3), b: rng.uniform(-3, 3), F: rng.uniform(-3, 3)}
        k = stiffness(DEFAULTS["M"], DEFAULTS["J"], DEFAULTS["l"], float(vals[F]), float(vals[a]), float(vals[b]))
        agree &= all(bool(c.subs(vals)) for c in sym.conditions) == (k > 0)
    ok &= agree
    model = build()
    lin = linearize(model, about="steady", at={"phi": 0.0})
    eps, times = 1e-5, np.linspace(0.0, 1.0, 5)
    traj = simulate(model.replace(initial={"xc": 0.0, "phi": 0.0, "xc'": 1.0, "phi'": eps}), times=times)
    lin_phi = [(expm(lin.A * t) @ np.array([0.0, eps]))[0] for t in times]
    follow = float(np.max(np.abs(traj.q[:, 2] - lin_phi)) / eps)
    ok &= follow < 1e-3
    out = {"cases": cases, "singular_at_1-alpha*beta=-J/(Ml^2)": singular_ok,
           "conditions": [str(c) for c in sym.conditions], "conditions_agree_with_k": agree,
           "linear_vs_nonlinear": follow, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print(f"  k = (1 - alpha beta) F l / (J + M (1 - alpha beta) l^2); -J/(M l^2) = {-Jc:.6g}")
        for c in cases:
            print(f"  F = {c['F']:+g}, 1 - alpha beta = {c['1-alpha*beta']:+.4g}: k = {c['k']:+.5g} -> "
                  f"{c['verdict']} (printed (3.26) says {'stable' if c['printed_says_stable'] else 'unstable'})")
        print(f"  1 - alpha beta = -J/(M l^2): linearization undefined (exit 3): {singular_ok}")
        print(f"  library's condition in alpha, beta, F: {'; '.join(out['conditions'])} "
              f"(agrees with k > 0: {agree})")
        print(f"  perturbed nonlinear motion vs linear solution: {follow:.1e} of the perturbation")
        print(f"  ok: {ok}")
    return out
