"""Realizability of nonholonomic (no-slip) constraints by Coulomb friction (Kalinin & Novozhilov).

Kalinin & Novozhilov: for ``V' = g + sum_s b_s f_s`` with Coulomb forces ``f_s = -f_s0 sign U_s``
the sticking motion ``U_s = 0`` is realized by friction -- and the regularized system (the
discontinuity replaced by a steep monotone law in ``|U_s| <= eps``) converges to it as
``eps -> 0`` (Tikhonov) -- if and only if the roots ``f*_s`` of ``g_l + sum_s b_ls f_s = 0``
satisfy ``|f*_s| < f_s0`` (one slip direction) or ``f*_1^2 + f*_2^2 < f_s0^2`` (isotropic
friction in a contact plane).  The roots are exactly the reactions of the no-slip constraints
(the friction needed to stick), so necessary and sufficient conditions coincide.

* :func:`realizability` -- at one state: the friction force needed to keep each touching
  contact sticking, compared with ``mu_s N``, with the margin;
* :func:`realizability_along` -- along the rolling motion, the first time rolling stops being
  realizable (the needed friction reaches ``mu_s N``) or the contact lifts off;
* :func:`regularized` -- the model with the epsilon-linear (or smooth) friction law of
  Kalinin & Novozhilov, whose solutions tend to the sticking one as ``eps -> 0``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ...numeric.consistency import complete_state
from ...modeling.contacts import Coulomb, CoulombContensou, IdealRolling, LinearizedCoulomb, RegularizedCoulomb
from ...errors import ModelError, did_you_mean
from ...modeling.model import Model
from ...modes.types import SEPARATED, SMOOTH, STICK, ContactState, Mode
from ...modes.solver import ModeSolver
from ...numeric.kernel import kernel_of, parameter_vector

__all__ = ["ContactRealizability", "RealizabilityReport", "realizability", "realizability_along",
           "regularized"]


@dataclass
class ContactRealizability:
    """The friction needed to stick at one contact, and what Coulomb friction can give."""

    name: str
    components: int
    needed: np.ndarray       # F*, the reaction of the no-slip constraint(s)
    normal: float            # N
    mu_static: float
    available: float         # mu_s N
    margin: float            # available - |F*|
    ratio: float             # |F*| / available
    realizable: bool
    note: str = ""
    slip: np.ndarray | None = None   # U at the state: nonzero when the contact slides there
    ideal_rolling: bool = False      # mu = inf: f0 unbounded, any rolling is realized while N >= 0

    @property
    def sticking(self) -> bool:
        """Whether the contact sticks at the state (its slip is zero)."""
        return self.slip is None or not np.any(self.slip)

    def to_dict(self) -> dict[str, Any]:
        def value(v: float):  # JSON has no infinity: an unbounded value is written "inf"
            return "inf" if v == float("inf") else v

        out = {"contact": self.name, "components": self.components, "sticking": self.sticking,
               "slip": [float(v) for v in self.slip] if self.slip is not None else None,
               "friction_needed": [float(v) for v in self.needed],
               "friction_needed_magnitude": float(np.linalg.norm(self.needed)),
               "normal": self.normal, "mu_static": value(self.mu_static),
               "friction_available": value(self.available), "margin": value(self.margin),
               "ratio": self.ratio, "realizable": self.realizable,
               "condition": ("|f*| < f0" if self.components == 1 else "f1*^2 + f2*^2 < f0^2"),
               "note": self.note}
        if self.ideal_rolling:
            out["ideal_rolling"] = True
        return out


@dataclass
class RealizabilityReport:
    model: str
    t: float
    state: dict[str, float]
    contacts: dict[str, ContactRealizability]
    along: dict[str, Any] = field(default_factory=dict)
    others: dict[str, str] = field(default_factory=dict)

    @property
    def realizable(self) -> bool:
        return all(c.realizable for c in self.contacts.values())

    def to_dict(self) -> dict[str, Any]:
        out = {"model": self.model, "t": self.t, "state": self.state, "realizable": self.realizable,
               "contacts": {k: v.to_dict() for k, v in self.contacts.items()}}
        if self.along:
            out["along"] = self.along
        if self.others:
            out["other_contacts"] = self.others
        return out

    def as_text(self) -> str:
        lines = [f"{self.model}: realizability of rolling/sticking by Coulomb friction "
                 f"(Kalinin & Novozhilov) at t = {self.t:g}"]
        for c in self.contacts.values():
            cond = "|f*| < f0" if c.components == 1 else "f1*^2 + f2*^2 < f0^2"
            if c.ideal_rolling:
                lines.append(f"  {c.name}: needed friction f* = {_numbers(c.needed)} "
                             f"(|f*| = {np.linalg.norm(c.needed):.8g}), normal N = {c.normal:.8g}; "
                             "ideal rolling (mu = inf): f0 unbounded")
                lines.append(f"    {cond}: {'yes' if c.realizable else 'NO'} -- an infinite mu "
                             "realizes any rolling while N >= 0; only lift-off (N reaching 0) ends it"
                             + (f"  ({c.note})" if c.note else ""))
                continue
            lines.append(
                f"  {c.name}: needed friction f* = {_numbers(c.needed)} "
                f"(|f*| = {np.linalg.norm(c.needed):.8g}), normal N = {c.normal:.8g}, "
                f"f0 = mu_s N = {c.available:.8g}")
            lines.append(f"    {cond}: {'yes' if c.realizable else 'NO'}; margin f0 - |f*| = "
                         f"{c.margin:.8g}, ratio |f*|/f0 = {c.ratio:.6g}" + (f"  ({c.note})" if c.note else ""))
            if not c.sticking:
                lines.append(f"    but the contact is NOT sticking at this state: it slides (slip U = "
                             f"{_numbers(c.slip)}); f* is the friction sticking would need if the slip "
                             "were stopped here")
        if self.others:
            lines.append("  other contacts, as in the motion: "
                         + ", ".join(f"{k} {v}" for k, v in self.others.items()))
        if self.along:
            a = self.along
            if a.get("lost_at") is not None:
                lines.append(f"  along the rolling motion: rolling stops being realizable at t = "
                             f"{a['lost_at']:.12g} ({a['reason']} at contact '{a['contact']}')")
            else:
                how = ("located between the samples" if a.get("min_margin_located")
                       else "the smallest sampled")
                lines.append(f"  along the rolling motion: realizable up to t = {a['t_end']:g} "
                             f"(minimum margin {a['min_margin']:.10g} at t = {a['min_margin_t']:.10g}, "
                             f"{how})")
        return "\n".join(lines)


def _stick_mode(solver: ModeSolver, t, q, qd, names=None) -> Mode:
    """The touching contacts sticking (only *names*, when given; a frictionless one is
    smooth).  The other touching contacts keep the state the motion has there
    (:func:`~nonideal.modes.switching.select_mode`: sliding, smooth, separating), so that their
    forces still act; when that selection has no answer they stick too."""
    held = frozenset(solver.kernel.rows[i].name for i in solver.unilateral)
    cout = solver.ck(solver.input(t, q, qd))
    scale = 1 + np.max(np.abs(q))
    natural = {}
    if names is not None:
        from ...errors import MechanicsError
        from ...modes.switching import select_mode

        try:
            natural = dict(select_mode(solver, t, q, qd).contacts)
        except MechanicsError:
            natural = {}
    states = []
    for c, name in enumerate(solver.ck.names):
        closed = solver.ck.data[c].bilateral or abs(cout["gap"][c]) <= 1e-8 * scale
        touching = SMOOTH if c in solver.frictionless else STICK  # no friction: nothing to realize
        if not closed:
            states.append((name, ContactState(SEPARATED)))
        elif names is None or name in names or name not in natural:
            states.append((name, ContactState(touching)))
        else:
            states.append((name, natural[name]))
    return Mode(held, tuple(states))


def _numbers(values, scale: float | None = None) -> str:
    """``[a, b]`` with 8 significant digits; rounding noise (below 1e-12 of the scale) as 0."""
    values = np.atleast_1d(np.asarray(values, dtype=float))
    scale = float(np.max(np.abs(values))) if scale is None and values.size else (scale or 0.0)
    tol = 1e-12 * max(scale, 1.0)
    return "[" + ", ".join("0" if abs(v) <= tol else f"{v:.8g}" for v in values) + "]"


def _assess(solver, sol, mode, t=None, q=None, qd=None) -> dict[str, ContactRealizability]:
    out = {}
    slips = {}
    if q is not None:
        cout = solver.ck(solver.input(t, q, qd))
        scale = 1.0 + float(np.max(np.abs(qd))) if len(qd) else 1.0
        for c, name in enumerate(solver.ck.names):
            U = np.atleast_1d(np.asarray(solver.ck.slip(cout, c), dtype=float))
            slips[name] = np.where(np.abs(U) <= 1e-9 * scale, 0.0, U)
    for c, (name, cs) in enumerate(mode.contacts):
        if cs.state != STICK:
            continue
        cf = sol.contacts[name]
        bil = solver.ck.data[c].bilateral
        N = abs(cf.N) if bil else cf.N
        available = cf.mu_s * max(N, 0.0)
        need = float(np.linalg.norm(cf.F))
        note = ""
        if not bil and cf.N < 0:
            note = "the normal force is negative: the contact would separate"
        rolling = c in solver.rolling
        if rolling:  # mu = inf: every friction force is available while N >= 0
            available = float("inf")
            ratio = 0.0
            ok = bil or cf.N >= 0
        else:
            ratio = need / available if available > 0 else float("inf")
            ok = need < available and (bil or cf.N >= 0)
        out[name] = ContactRealizability(name, len(cf.F), cf.F.copy(), float(cf.N), float(cf.mu_s), available,
                                         available - need, ratio, bool(ok), note, slips.get(name), rolling)
    return out


def _refuse_patches(model: Model) -> None:
    """Coulomb-Contensou contacts stick inside a set of force and pivoting torque together, not
    inside the friction circle tested here: refused rather than answered with the circle."""
    for c in model.contacts:
        if isinstance(c.friction, CoulombContensou):
            raise ModelError(f"realizability: contact '{c.name}' uses the Coulomb-Contensou law; its "
                             "sticking set couples the friction force with the pivoting torque and is "
                             "not the friction circle this analysis tests -- use friction = \"coulomb\" "
                             "(with spin_friction for the pivoting) to assess sticking",
                             None if model.source == "<api>" else model.source)


def realizability(model: Model, at: Mapping[str, float] | None = None, t: float | None = None,
                  contacts=None, parameters: Mapping[str, float] | None = None) -> RealizabilityReport:
    """Friction needed to keep the touching contacts sticking at a state, vs ``mu_s N``.

    Parameters
    ----------
    model : Model
    at : mapping, optional
        State overrides (missing dependent values are completed).
    contacts : list of str, optional
        Contacts to keep sticking (default: every touching contact).
    """
    if not model.contacts:
        raise ModelError("realizability: the model has no [[contacts]]",
                         None if model.source == "<api>" else model.source)
    _refuse_patches(model)
    if contacts is not None:
        names = [c.name for c in model.contacts]
        for c in contacts:
            if c not in names:
                raise ModelError(f"realizability: no contact '{c}'{did_you_mean(c, names)}")
    kernel = kernel_of(model)
    params = parameter_vector(model, parameters)
    t = model.t0 if t is None else float(t)
    given = dict(model.numeric_initial())
    given.update(at or {})
    q, qd, _ = complete_state(kernel, given, params, t)
    solver = ModeSolver(kernel, params)
    mode = _stick_mode(solver, t, q, qd, contacts)
    sol = solver.solve(t, q, qd, mode)
    state = dict(zip(model.coordinates, map(float, q)))
    state.update({c + "'": float(v) for c, v in zip(model.coordinates, qd)})
    others = {name: cs.label() for name, cs in mode.contacts
              if contacts is not None and name not in contacts}
    return RealizabilityReport(model.name, t, state, _assess(solver, sol, mode, t, q, qd), others=others)


def realizability_along(model: Model, t_end: float | None = None, samples: int = 201,
                        parameters: Mapping[str, float] | None = None) -> RealizabilityReport:
    """Follow the sticking (rolling) motion and find when rolling stops being realizable.

    The hybrid simulation starts with the touching contacts sticking and stops at the first
    slip or lift-off event, whose time is located exactly (root of the margin
    ``mu_s N - |F*|``, or of ``N``).  Until then the motion is the nonholonomic one.  The margin
    of an ideally rolling contact (``mu = inf``) is its normal force ``N``: only lift-off
    ends rolling there.  The smallest margin is located between the samples (Brent's method
    on the dense output of the phase around the sampled minimum, the exact margin evaluated
    at each candidate state): ``along["min_margin"]``, ``along["min_margin_t"]``; the sampled
    one stays in ``min_margin_sampled`` / ``min_margin_sampled_t``.
    """
    from ...simulation.hybrid import Simulation

    report = realizability(model, parameters=parameters)
    sim = Simulation(model, parameters=parameters)
    t_end = t_end if t_end is not None else model.simulation.t_end
    if t_end is None:
        raise ModelError("realizability --along needs an end time ([simulation] t_end or --t-end)")
    traj = sim.run(t_end=t_end, times=np.linspace(model.t0, t_end, samples),
                   stop_on={"slip", "lift-off"})
    margins = {}
    for c, (name, rec) in enumerate(traj.contacts.items()):
        if c in sim.solver.frictionless:
            continue
        if c in sim.solver.rolling:  # ideal rolling: only the normal force can end it
            margins[name] = np.array(rec["normal"], dtype=float)
            continue
        F = np.array(rec["friction"], dtype=float)
        margins[name] = np.array(rec["mu_static"]) * np.abs(rec["normal"]) - np.linalg.norm(F, axis=1)
    first = next((e for e in traj.events if e["type"] in ("slip", "lift-off")), None)
    allm = np.min(np.vstack(list(margins.values())), axis=0) if margins else np.zeros(len(traj.t))
    k = int(np.argmin(allm)) if allm.size else 0
    located = _locate_minimum(sim, traj, allm, k, list(margins)) if margins else None
    t_min, m_min = located if located is not None else \
        ((float(traj.t[k]), float(allm[k])) if allm.size else (None, None))
    report.along = {
        "t_end": float(traj.t[-1]),
        "lost_at": float(first["t"]) if first else None,
        "reason": {"slip": "needed friction reached mu_s N", "lift-off": "normal force reached zero"}
        .get(first["type"]) if first else None,
        "contact": first.get("contact") if first else None,
        "min_margin": m_min,
        "min_margin_t": t_min,
        "min_margin_located": located is not None,
        "min_margin_sampled": float(allm[k]) if allm.size else None,
        "min_margin_sampled_t": float(traj.t[k]) if allm.size else None,
        "t": [float(v) for v in traj.t],
        "margin": {k_: [float(v) for v in m] for k_, m in margins.items()},
    }
    return report


def _locate_minimum(sim, traj, allm: np.ndarray, k: int, names: list[str]):
    """The smallest margin between the samples around the sampled minimum *k*.

    The phase is integrated again from the sample before *k* to the sample after it (same
    mode, the simulation's method and tolerances, with its dense output), and the exact margin
    -- the mode solved again at each candidate state -- is minimized over that bracket by
    Brent's bounded method.  Returns ``(t, margin)``, or ``None`` when the bracket holds an
    event or a change of mode (the sampled minimum is then reported as it is) or when the
    sampled minimum is at an end of the motion (an event there is located exactly already).
    """
    from scipy.integrate import solve_ivp
    from scipy.optimize import minimize_scalar

    from ...modes.switching import select_mode
    from ...simulation.hybrid import N_WORK

    t = traj.t
    if len(t) < 3 or not 0 < k < len(t) - 1:
        return None
    lo, hi = k - 1, k + 1
    if len({traj.modes[i] for i in (lo, k, hi)}) != 1 or \
            any(t[lo] < e["t"] <= t[hi] for e in traj.events):
        return None
    solver, n = sim.solver, sim.n
    y0 = np.concatenate((traj.q[lo], traj.qd[lo]))
    mode = select_mode(solver, float(t[lo]), traj.q[lo], traj.qd[lo])
    if mode.label() != traj.modes[lo]:
        return None
    fun = sim.rhs(mode)
    y0 = np.concatenate((y0, np.zeros(N_WORK + len(sim.control_rows) if sim.track else 0)))  # works from 0
    atol = sim.work_tolerances() if sim.track else sim.atol
    ode = solve_ivp(fun, (float(t[lo]), float(t[hi])), y0, method=sim.method, rtol=sim.rtol,
                    atol=atol, dense_output=True)
    if not ode.success:
        return None
    index = {name: c for c, name in enumerate(solver.ck.names)}

    def margin(s: float) -> float:
        y = ode.sol(s)
        motion = solver.motion(s, y, mode)
        values = []
        for name in names:
            c = index[name]
            _, N, F, _, _, mu_s = motion.contact_record(c)
            values.append(N if c in solver.rolling else mu_s * abs(N) - float(np.linalg.norm(F)))
        return float(min(values))

    span = float(t[hi] - t[lo])
    best = minimize_scalar(margin, bounds=(float(t[lo]), float(t[hi])), method="bounded",
                           options={"xatol": 1e-12 * max(span, 1e-300) + 1e-15 * abs(float(t[k]))})
    candidates = [(float(t[k]), margin(float(t[k])))]
    if best.success:
        candidates.append((float(best.x), float(best.fun)))
    return min(candidates, key=lambda c: c[1])


def regularized(model: Model, eps: float, law: str = "linearized") -> Model:
    """The model with every Coulomb contact replaced by the epsilon-linear law of Kalinin & Novozhilov
    (``law="linearized"``: ``F = -mu N U/eps`` for ``|U| <= eps``) or the smooth law
    (``law="smooth"``: ``F = -mu N U/sqrt(|U|^2 + eps^2)``).  An ideally rolling contact
    (``mu = inf``) is kept as it is."""
    cls = {"linearized": LinearizedCoulomb, "smooth": RegularizedCoulomb}.get(law)
    if cls is None:
        raise ModelError(f"regularized: law must be 'linearized' or 'smooth' (got {law!r})")
    contacts = []
    for c in model.contacts:
        fr = c.friction
        if isinstance(fr, IdealRolling):  # mu = inf has no regularization: it keeps rolling
            contacts.append(c)
            continue
        mu = fr.mu if isinstance(fr, Coulomb) else fr.mu
        contacts.append(replace(c, friction=cls(mu, eps)))
    return model.replace(contacts=tuple(contacts), name=f"{model.name} (regularized, eps = {eps:g})")
