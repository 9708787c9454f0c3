"""A disk on a rough plane driven by a growing torque: rolling until friction gives out.

Source: the classical rolling problem, read through Kalinin & Novozhilov (Kalinin & Novozhilov:
realizability of nonholonomic constraints by Coulomb friction, and the convergence of the
regularized system to the rolling one, Tikhonov's theorem).  Derived here.

Model.  A homogeneous disk (mass m, radius R, I = m R^2 / 2) upright on the horizontal plane,
centre (x, y), rolling angle phi (clockwise, so that rolling reads x' = R phi'); a torque
``tau = c t`` drives phi:

    T = m (x'^2 + y'^2) / 2 + I phi'^2 / 2,     V = m g y,     Q_phi = c t.

Contact ``plane``: gap ``y - R``, slip = velocity of the contact point ``U = x' - R phi'``,
Coulomb friction mu (kinetic), mu_s (static).  The friction force F (along +x) acts on x with
``Q_x = F`` and on phi with ``Q_phi = -R F``.

Rolling (U = 0 held as a nonholonomic constraint, its multiplier the friction F*):

    m x'' = F*,   I phi'' = c t - R F*,   x'' = R phi''
    =>  phi'' = c t / (I + m R^2),   F* = m R c t / (I + m R^2),
        x' = R c t^2 / (2 (I + m R^2)),   x = R c t^3 / (6 (I + m R^2)),   N = m g.

Realizability (Kalinin & Novozhilov, one slip direction): rolling is realized by friction iff
``|F*| < mu_s N``; F* grows linearly, so rolling is lost at

    t_loss = mu_s m g (I + m R^2) / (m R c)       (default: 1.32435 s),

after which the disk spins faster than it rolls (U < 0) and slides: ``x'' = mu g``,
``I phi'' = c t - mu m g R``.  ``realizability_along`` finds t_loss (the slip event of the
rolling motion) and ``realizability`` at a state gives the needed force F*(t).

Regularization (Kalinin & Novozhilov).  With the epsilon-linear law ``F = -mu N U / eps`` (|U| <= eps) the
slip obeys a LINEAR equation (the constraint is replaced by a stiff restoring friction):

    U' = F (1/m + R^2/I) - R c t / I = -a U - b t,     a = (mu N / eps)(1/m + R^2/I),  b = R c / I,
    U(t) = -(b/a) t + (b/a^2) (1 - exp(-a t))        (U(0) = 0),

and ``x'' - x''_roll = U' I / (I + m R^2)``, so exactly

    x'(t) - x'_roll(t) = I U(t) / (I + m R^2) ~ -I F*(t) eps / ((I + m R^2) mu N)

(|U| <= F* eps / (mu N) < eps as long as F* < mu N: the law stays in its linear range).  The
regularized solution converges to the rolling one with an error proportional to eps
(default at t = 1: 0.25168 eps), as Tikhonov's theorem says for a realizable constraint.  The
regularized system is stiff (time scale 1/a ~ eps/20 s): it is integrated with Radau.
mu = mu_s in the default model: the regularized law saturates at mu N, so with mu < mu_s it
would lose rolling earlier, at ``mu`` instead of ``mu_s``.
"""

from __future__ import annotations

import numpy as np

from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "disk-rolling-torque"
ORDER = 44
TITLE = ("Disk driven by a torque c t: rolling realizable until t_loss = mu_s m g (I + m R^2)/(m R c); "
         "regularized -> rolling as eps -> 0")
FILE = "disk_rolling_torque.toml"

EPSILONS = (1e-2, 1e-3, 1e-4)


def build(m: float = 2.0, R: float = 0.3, g: float = 9.81, mu: float = 0.3, mu_s: float = 0.3,
          c: float = 2.0, t_end: float = 2.0) -> Model:
    """The disk with the Python API (same as the model file for the default values)."""
    return Model(
        name="Disk on a rough plane driven by a growing torque",
        coordinates=["x", "y", "phi"],
        parameters={"m": m, "R": R, "g": g, "mu": mu, "mu_s": mu_s, "c": c},
        kinetic="m/2*(x'^2 + y'^2) + (m*R^2/2)/2*phi'^2",
        potential="m*g*y",
        forces={"phi": "c*t"},
        contacts=[Contact("plane", "y - R", ("x' - R*phi'",), Coulomb("mu", "mu_s"))],
        initial={"x": 0.0, "y": "R", "phi": 0.0, "x'": 0.0, "y'": 0.0, "phi'": 0.0},
        simulation={"t_end": t_end},
    )


def _J(p):
    I = p["m"] * p["R"] ** 2 / 2
    return I, I + p["m"] * p["R"] ** 2


def t_loss(p: dict) -> float:
    """``mu_s m g (I + m R^2) / (m R c)``."""
    _, J = _J(p)
    return p["mu_s"] * p["m"] * p["g"] * J / (p["m"] * p["R"] * p["c"])


def needed_friction(t, p: dict):
    """``F*(t) = m R c t / (I + m R^2)``."""
    _, J = _J(p)
    return p["m"] * p["R"] * p["c"] * np.asarray(t, dtype=float) / J


def motion(t, p: dict):
    """``x, x', phi'`` of the exact motion: rolling until t_loss, then sliding."""
    I, J = _J(p)
    R, c, mu, g = p["R"], p["c"], p["mu"], p["g"]
    t = np.asarray(t, dtype=float)
    tl = t_loss(p)
    tr = np.minimum(t, tl)
    s = np.maximum(t - tl, 0.0)
    x = R * c * tr ** 3 / (6 * J) + (R * c * tl ** 2 / (2 * J)) * s + mu * g * s ** 2 / 2
    xd = R * c * tr ** 2 / (2 * J) + mu * g * s
    phid = c * tr ** 2 / (2 * J) + (c * (t ** 2 - tr ** 2) / 2 - mu * p["m"] * g * R * s) / I
    return x, xd, phid


def regularized_motion(t, p: dict, eps: float):
    """``x'(t)`` and the slip ``U(t)`` of the epsilon-linear regularized system (t < t_loss)."""
    I, J = _J(p)
    m, R, c = p["m"], p["R"], p["c"]
    N = m * p["g"]
    a = p["mu"] * N / eps * (1 / m + R * R / I)
    b = R * c / I
    t = np.asarray(t, dtype=float)
    U = -(b / a) * t + (b / a ** 2) * (-np.expm1(-a * t))
    xd_roll = R * c * t ** 2 / (2 * J)
    return xd_roll + I * U / J, U


def regularization_error(p: dict, eps: float, times) -> dict:
    """Simulate the regularized model (Radau) and compare with the rolling and the exact
    regularized solutions."""
    from ..analysis.contact.realizability import regularized
    from ..simulation.hybrid import simulate

    model = build(**p)
    tr = simulate(regularized(model, eps), times=times, method="Radau")
    _, xd_roll, _ = motion(times, p)
    xd_reg, U = regularized_motion(times, p, eps)
    return {"eps": eps,
            "error_vs_rolling": float(np.max(np.abs(tr.velocity("x") - xd_roll))),
            "error_vs_regularized_closed_form": float(np.max(np.abs(tr.velocity("x") - xd_reg))),
            "slip_error": float(np.max(np.abs(np.array(tr.contacts["plane"]["slip"])[:, 0] - U))),
            "max_slip": float(np.max(np.abs(U))),
            "events": len(tr.events),
            "energy_balance_relative": tr.diagnostics["energy_balance_relative"]}


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..analysis.contact.realizability import realizability, realizability_along
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    I, J = _J(p)
    tl = t_loss(p)
    # exact simulation: rolling, then sliding
    full = simulate(model)
    times = np.union1d(np.linspace(0, model.simulation.t_end, 41), [tl])
    tr = simulate(model, times=times)
    x, xd, phid = motion(times, p)
    err_motion = float(max(np.max(np.abs(tr.coordinate("x") - x)), np.max(np.abs(tr.velocity("x") - xd)),
                           np.max(np.abs(tr.velocity("phi") - phid)) * p["R"]))
    F = np.array(tr.contacts["plane"]["friction"])[:, 0]
    rolling = times < tl
    err_F = float(max(np.max(np.abs(F[rolling] - needed_friction(times[rolling], p))),
                      np.max(np.abs(F[~rolling] - p["mu"] * p["m"] * p["g"]))))
    ev = full.events
    err_t_event = abs(ev[0]["t"] / tl - 1) if ev else np.inf
    # realizability along the rolling motion and at states
    along = realizability_along(model)
    err_along = abs(along.along["lost_at"] / tl - 1)
    at = {}
    for t in (0.5, 1.0, 1.5):
        rep = realizability(model, t=t).contacts["plane"]
        at[t] = {"needed": float(rep.needed[0]), "closed_form": float(needed_friction(t, p)),
                 "available": rep.available, "realizable": rep.realizable}
    err_at = max(abs(v["needed"] / v["closed_form"] - 1) for v in at.values())
    at_ok = at[0.5]["realizable"] and at[1.0]["realizable"] and not at[1.5]["realizable"]
    # regularization
    tr_times = np.linspace(0.0, 1.0, 11)
    reg = [regularization_error(p, eps, tr_times) for eps in EPSILONS]
    coef = I * float(needed_friction(1.0, p)) / (J * p["mu"] * p["m"] * p["g"])
    ratios = [a["error_vs_rolling"] / b["error_vs_rolling"] for a, b in zip(reg[:-1], reg[1:])]
    # leading order coef * eps; the next term is relatively O(1/(a t)) = O(eps)
    reg_ok = (all(abs(r["error_vs_rolling"] / (coef * r["eps"]) - 1) < 0.2 * r["eps"] for r in reg)
              and all(r["error_vs_regularized_closed_form"] < 1e-8 for r in reg)
              and all(r["events"] == 0 for r in reg))
    cross = {state: compare_forms(model, contact_state=state).worst() for state in ("slide", "stick")}
    E = full.energy
    ok = (err_t_event < 1e-9 and [e["mode"] for e in ev] == ["plane:slide-"] and err_motion < 1e-9
          and err_F < 1e-9 and err_along < 1e-9 and err_at < 1e-12 and at_ok and reg_ok
          and np.max(np.diff(E["friction_work"])) <= 1e-12
          and full.diagnostics["energy_balance_relative"] < 1e-8 and max(cross.values()) < 1e-10)
    out = {"ok": bool(ok), "t_loss": tl, "t_loss_event": ev[0]["t"] if ev else None,
           "t_loss_relative_error": err_t_event, "t_loss_realizability_along": along.along["lost_at"],
           "t_loss_along_relative_error": err_along, "max_error_motion": err_motion,
           "max_error_friction": err_F, "realizability_at": at, "regularization": reg,
           "regularization_coefficient": coef, "error_ratios": ratios,
           "energy_balance_relative": full.diagnostics["energy_balance_relative"],
           "forms_disagreement": cross}
    if verbose:
        print(TITLE)
        print(f"rolling needs F* = m R c t/(I + m R^2) = {needed_friction(1.0, p):.10f} t; "
              f"mu_s N = {p['mu_s'] * p['m'] * p['g']:.10f}")
        print(f"t_loss = mu_s m g (I + m R^2)/(m R c) = {tl:.12f}; slip event at {out['t_loss_event']:.12f} "
              f"(rel. error {err_t_event:.1e}); realizability_along: {along.along['lost_at']:.12f} "
              f"(rel. error {err_along:.1e})")
        for t, v in at.items():
            print(f"  realizability at t = {t}: F* = {v['needed']:.12f} (closed form {v['closed_form']:.12f}), "
                  f"mu_s N = {v['available']:.6f}, realizable: {v['realizable']}")
        print(f"exact motion (rolling, then sliding with x'' = mu g): max error {err_motion:.1e}; "
              f"friction force {err_F:.1e}; energy balance {out['energy_balance_relative']:.1e}")
        print("epsilon-linear regularization (Radau), x' on [0, 1] vs rolling:")
        for r in reg:
            print(f"  eps = {r['eps']:.0e}: error {r['error_vs_rolling']:.6e} = "
                  f"{r['error_vs_rolling'] / r['eps']:.6f} eps (closed form {coef:.6f} eps); vs exact "
                  f"regularized solution {r['error_vs_regularized_closed_form']:.1e}")
        print(f"  error ratios between successive eps: {np.round(ratios, 6).tolist()}")
        print(f"all forms vs Lagrange I (sliding, sticking): {cross['slide']:.1e}, {cross['stick']:.1e}")
        print("ok" if ok else "FAILED")
    return out
