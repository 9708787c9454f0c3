"""A point driven along a circle by a quasi-ideal constraint: a Riccati equation, four regimes.

Source: Briskin, Pavlovsky, Pavlovsky & Smirnaya 2021, sec. 3.2, (3.11)-(3.18), Table 1,
figs. 6-8.

Model.  A point of mass m in polar coordinates (r, phi), kept on the circle ``f = r - r0 = 0``
by a quasi-ideal constraint with the transform ``A = [[1, alpha], [beta, 1]]``: the generalized
reactions are (3.12) ``R_r = lambda/(1 - alpha beta)``, ``R_phi = -beta lambda/(1 - alpha
beta)`` (``[alpha] = 1/m``, ``[beta] = m``; ``R_phi`` is a moment).  A force F pushes the point
at the angle gamma to the tangent, forward and inward: generalized forces ``Q_r = -F sin(gamma)``,
``Q_phi = F r cos(gamma)``.

Derivation.  On the circle the radial equation gives ``R_r = F sin(gamma) - m r0 omega^2``
(3.18), hence ``R_phi = -beta R_r`` and ``m r0^2 omega' = F r0 cos(gamma) + R_phi``:

    omega' - A omega^2 = B,   A = beta / r0,
    B = F cos(gamma) / (m r0) - beta F sin(gamma) / (m r0^2)                   (3.13)-(3.14)

a Riccati equation with constant coefficients whose regime -- blow-up in finite time, a limit
angular velocity, linear growth -- is what :func:`nonideal.analysis.stability.riccati.riccati_regime`
reports (case numbers of the paper: 1 tan (3.15), 2 ``B = 0`` (3.16), 3 tanh (3.17),
4 ``A = 0``), with the exact ``omega(t)`` and the blow-up time.  The reactions' work is
``int R_phi omega dt = m r0^2 omega^2/2 - F r0 cos(gamma) phi`` (energy balance; ``R_r`` does
no work on the circle), the drives' heat ``W = int (mu_r R_r^2 + mu_phi R_phi^2) dt``.

**Misprints (the signs of sec. 3.2 are inconsistent).**  Table 1 gives, for m = 1, F = 2,
r0 = 2, gamma = pi/4, ``B = (1 - A)/sqrt(2)``; this is the B above (the force drives the point
forward).  The printed (3.11) has ``-F r cos(gamma)`` (the force braking it) and the printed
(3.14) ``+ beta F sin(gamma)/(m r0^2)``: from (3.11) as printed one derives
``B = -(F cos(gamma)/(m r0) + beta F sin(gamma)/(m r0^2)) = -(1 + A)/sqrt(2)``, and (3.14) as
printed is ``(1 + A)/sqrt(2)``; neither matches Table 1, whose regimes the paper discusses and
plots.  The library follows Table 1 (derived with the SymPy check in the tests).  Also: Table
1's ``B/A`` for beta = -1 is -2.12 (printed -2.18); the closed forms (3.15) and (3.17) hold for
``A > 0`` only -- for ``A < 0`` the argument is ``A c t`` (``c = sqrt(|B/A|)``), so for
beta = -1 omega tends to ``+c``, not to ``-c`` as (3.17) would give; the text cites (3.15) for
the tanh limit of case 3, meaning (3.17); (3.18)'s ``R_phi = m r0 phi'' - F cos(gamma)`` is
the tangential force ``R_phi / r0`` (the generalized reaction is ``m r0^2 phi'' - F r0
cos(gamma)``).
"""

from __future__ import annotations

import math

import numpy as np

from ..modeling.model import Constraint, Model

NAME = "briskin-point-on-circle"
ORDER = 71
TITLE = ("Point on a circle, quasi-ideal constraint (Briskin et al. 2021, 3.2): the Riccati "
         "equation (3.13) and its regimes (Table 1, signs corrected)")
FILE = "briskin_point_on_circle.toml"

#: Table 1: beta -> (A, B, B/A as printed, case)
TABLE_1 = {-1.0: (-0.5, 1.5 / math.sqrt(2), -2.18, 3), 0.0: (0.0, 1 / math.sqrt(2), None, 4),
           1.0: (0.5, 0.5 / math.sqrt(2), 0.7, 1), 2.0: (1.0, 0.0, 0.0, 2),
           3.0: (1.5, -0.5 / math.sqrt(2), -0.236, 3)}


def build(m: float = 1.0, F: float = 2.0, gamma: float = math.pi / 4, r0: float = 2.0,
          alpha: float = 0.0, beta: float = 1.0, omega0: float = 0.0, t_end: float = 2.0) -> Model:
    """The point on the circle with the Python API (same as the model file)."""
    return Model(
        name="Briskin et al. 2021, 3.2: point on a circle with a quasi-ideal constraint",
        coordinates=["r", "phi"],
        parameters={"m": m, "F": F, "gamma": gamma, "r0": r0, "alpha": alpha, "beta": beta,
                    "mu_r": 1.0, "mu_phi": 1.0, "omega0": omega0},
        kinetic="m/2*(r'^2 + r^2*phi'^2)",
        forces={"r": "-F*sin(gamma)", "phi": "F*r*cos(gamma)"},
        constraints=[Constraint("circle", "r - r0", "holonomic",
                                transform=(("1", "alpha"), ("beta", "1")),
                                losses=("mu_r", "mu_phi"))],
        initial={"r": "r0", "phi": 0.0, "phi'": "omega0"}, simulation={"t_end": t_end})


def riccati_coefficients(p: dict) -> tuple[float, float]:
    """``(A, B)`` of (3.13)-(3.14), signs as in Table 1."""
    A = p["beta"] / p["r0"]
    B = (p["F"] * math.cos(p["gamma"]) / (p["m"] * p["r0"])
         - p["beta"] * p["F"] * math.sin(p["gamma"]) / (p["m"] * p["r0"] ** 2))
    return A, B


def regime(model: Model):
    """The library's classification of the motion of *model* (a :class:`RiccatiRegime`)."""
    from ..analysis.stability.riccati import riccati_regime

    p = model.parameter_values
    return riccati_regime(*riccati_coefficients(p), p["omega0"])


def check(model: Model) -> dict:
    """Simulate *model* (to 0.9 of the blow-up time, if any) against the exact omega(t), the
    reactions (3.12)/(3.18) and the reactions' work; the regime of the motion."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    reg = regime(model)
    t_end = min(4.0, 0.9 * reg.blowup_time) if reg.blowup_time else 4.0
    times = np.linspace(0.0, t_end, 81)
    traj = simulate(model, times=times)
    w, phi = traj.velocity("phi"), traj.coordinate("phi")
    exact = reg.omega(times)
    mu = traj.multipliers["circle"]      # R = adj(A) grad f mu = (1, -beta) mu
    Rr = mu
    Rphi = -p["beta"] * Rr
    Rr_318 = p["F"] * math.sin(p["gamma"]) - p["m"] * p["r0"] * w ** 2
    wdot = traj.qdd[:, 1]
    Rphi_318 = p["m"] * p["r0"] ** 2 * wdot - p["F"] * p["r0"] * math.cos(p["gamma"])
    work = p["m"] * p["r0"] ** 2 * w ** 2 / 2 - p["F"] * p["r0"] * math.cos(p["gamma"]) * phi
    scale = max(1.0, float(np.max(np.abs(exact))))
    return {"regime": reg.to_dict(), "t_end": t_end,
            "omega_error": float(np.max(np.abs(w - exact))) / scale,
            "R_r_error": float(np.max(np.abs(Rr - Rr_318))) / max(1.0, float(np.max(np.abs(Rr_318)))),
            "R_phi_error": float(np.max(np.abs(Rphi - Rphi_318))) / max(1.0, float(np.max(np.abs(Rphi_318)))),
            "work_error": float(np.max(np.abs(traj.energy["reaction_work"] - work))) / max(1.0, float(np.max(np.abs(work)))),
            "omega_end": float(w[-1])}


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..modeling.modelfile import load_model

    path = gallery.model_path(NAME)
    rows = {}
    ok = True
    for beta, (A_t, B_t, ratio_t, case_t) in TABLE_1.items():
        model = load_model(path, parameters={"beta": beta})
        A, B = riccati_coefficients(model.parameter_values)
        r = check(model)
        r["table"] = {"A": A_t, "B": B_t, "B/A": ratio_t, "case": case_t}
        r["A"], r["B"] = A, B
        ok &= (abs(A - A_t) < 1e-12 and abs(B - B_t) < 1e-12 and r["regime"]["case"] == case_t
               and max(r["omega_error"], r["R_r_error"], r["R_phi_error"], r["work_error"]) < 1e-8)
        rows[beta] = r
    out = {"ok": bool(ok), "table_1": rows}
    if verbose:
        print(TITLE)
        print("beta      A          B       case  behaviour        limit / blow-up time   "
              "max error omega, R_r, R_phi, work")
        for beta, r in rows.items():
            g = r["regime"]
            what = (f"omega -> {g['limit']:.6g}" if g["behaviour"] == "limit" else
                    f"t* = {g['blowup_time']:.6g}" if g["behaviour"] == "blow-up" else g["behaviour"])
            print(f"{beta:4g}  {r['A']:8.4g}  {r['B']:9.4g}   {g['case']}    {g['behaviour']:15} "
                  f"{what:22} {r['omega_error']:.1e} {r['R_r_error']:.1e} {r['R_phi_error']:.1e} "
                  f"{r['work_error']:.1e}")
        print("ok" if ok else "FAILED")
    return out
