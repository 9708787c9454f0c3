"""Mode selection and impacts: the small complementarity problems solved at every switch.

:func:`select_mode` enumerates, for the closed unilateral constraints and the closed contacts,
every combination of states (held/released; separated/sticking/sliding in each admissible
direction) and keeps the consistent ones:

* held unilateral constraint: multiplier ``>= 0``; released closed one: ``f'' >= 0``;
* separated closed contact: ``g'' >= 0``;
* sticking contact: ``N >= 0`` and ``|F| <= mu_s N`` (Kalinin--Novozhilov: one component
  ``|F| <= f0``, two components ``F1^2 + F2^2 <= f0^2``);
* sliding contact: ``N >= 0`` and, at the onset (``U ~ 0``), slip acceleration along the
  assumed direction (``U' = kappa s, kappa >= 0``; for two components the direction is found
  by a one-dimensional root search);
* "smooth" contact (a regularized law, or no friction): ``N >= 0``;
* ideally rolling contact (``mu = inf``): closed, it is either separated or rolling
  (``N >= 0``, any friction force) -- never sliding.

Static friction is preferred (a consistent sticking state wins over sliding).  If the
consistent combinations still give different motions, or none is consistent, the problem has
no unique or no consistent continuation: with a sliding contact this is Painleve's paradox,
reported with the contact, the state and the critical friction coefficient.
"""

from __future__ import annotations

from collections.abc import Sequence
import itertools
import math

import numpy as np

from ..errors import MechanicsError, PainleveParadox, SetValuedFriction, SingularSystem
from .onset import onset_directions
from .system import compliance_of
from .types import SEPARATED, SLIDE, SMOOTH, STICK, ContactState, Mode
from .solver import ModeSolver
from ..numeric.kernel import SingularMatrix, max_abs, solve_saddle

__all__ = ["select_mode", "impact", "effective_compliance", "critical_friction", "MAX_COMBINATIONS"]

MAX_COMBINATIONS = 4096


def _scales(q, qd):
    return 1.0 + max_abs(q), 1.0 + max_abs(qd)


def contact_options(solver: ModeSolver, kin: np.ndarray, scales, tol_pos=1e-9, tol_vel=1e-9):
    """Admissible states of every contact at a state (closed contacts get several); *kin*: the
    contact kernel's flat outputs there, *scales*: ``1 + max |q|``, ``1 + max |q'|``."""
    ck = solver.ck
    if not ck:
        return []
    sq, sv = scales
    at = ck.at
    options = []
    for c, data in enumerate(ck.data):
        gap, rate = kin[at["gap"] + c], kin[at["gap_rate"] + c]
        closed = data.bilateral or (abs(gap) <= tol_pos * sq and rate <= tol_vel * sv)
        if not closed:
            options.append([ContactState(SEPARATED)])
            continue
        opts = [] if data.bilateral else [ContactState(SEPARATED)]
        sigmas = (1, -1) if data.bilateral else (1,)
        U = kin[at["U"] + ck.offsets[c]:at["U"] + ck.offsets[c] + ck.dims[c]]
        if not solver.laws[c].exact or c in solver.frictionless:
            opts += [ContactState(SMOOTH, (), s) for s in sigmas]
        elif c in solver.rolling:  # ideal rolling: touching means rolling (after any impact)
            opts.append(ContactState(STICK))
        elif np.sqrt(U @ U) <= tol_vel * sv:
            opts.append(ContactState(STICK))
            for sg in sigmas:
                if len(U) == 1:
                    opts += [ContactState(SLIDE, (1.0,), sg), ContactState(SLIDE, (-1.0,), sg)]
                else:
                    opts.append(ContactState(SLIDE, ("onset",), sg))
        else:
            direction = (float(np.sign(U[0])),) if len(U) == 1 else ()
            opts += [ContactState(SLIDE, direction, sg) for sg in sigmas]
        options.append(opts)
    return options


def _linked(parents, combo) -> bool:
    """Whether every friction torque of *combo* touches exactly when its contact does."""
    return all(p is None or (cs.state == SEPARATED) == (combo[p].state == SEPARATED)
               for p, cs in zip(parents, combo))


def _consistent(solver, motion, mode, closed_uni, scales, onset_check=True):
    """Sign conditions of a candidate mode (see the module docstring) on its
    :class:`~nonideal.modes.motion.Motion`; *scales*: ``1 + max |q|``, ``1 + max |q'|`` and
    ``1 + max |F|`` at the state."""
    kernel = solver.kernel
    sq, sv, sf = scales
    qdd, values = motion.qdd, motion.values
    tol_f = 1e-9 * (sf + max_abs(values))
    tol_a = 1e-9 * (1.0 + max_abs(qdd))
    for i in closed_uni:
        name = kernel.rows[i].name
        if name in mode.held:
            if motion.multiplier(i) < -tol_f:
                return False
        elif motion.constraint_acc(i) < -tol_a:
            return False
    for c, (name, cs) in enumerate(mode.contacts):
        if cs.state == SEPARATED:
            closed = abs(motion.gap(c)) <= 1e-8 * sq and motion.gap_rate(c) <= 1e-8 * sv
            if closed and motion.gap_acc(c) < -tol_a:
                return False
            continue
        N, F = motion.normal(c), motion.friction(c)
        cone = cs.state == STICK and c not in solver.rolling  # ideal rolling: no friction limit
        if solver.ck.data[c].bilateral:
            if cs.state in (SLIDE, SMOOTH) and cs.sigma * N < -tol_f:
                return False
            if cone and np.sqrt(F @ F) > motion.mu_s(c) * abs(N) + tol_f:
                return False
        else:
            if N < -tol_f:
                return False
            if cone and np.sqrt(F @ F) > motion.mu_s(c) * N + tol_f:
                return False
        U = motion.slip(c)
        if cs.state == SLIDE and onset_check and np.sqrt(U @ U) <= 1e-9 * sv:
            s = solver.friction_shape(c, cs, U, motion.qd)
            if motion.slip_acc(c) @ s < -tol_a:
                return False
    return True


def _state(solver, q, qd) -> dict:
    """The state named for an error message."""
    state = dict(zip(solver.model.coordinates, q))
    state.update({c + "'": v for c, v in zip(solver.model.coordinates, qd)})
    return state


def _stickiness(mode: Mode) -> tuple:
    stick = sum(1 for _, cs in mode.contacts if cs.state == STICK)
    touching = sum(1 for _, cs in mode.contacts if cs.state != SEPARATED)
    return (stick, len(mode.held), touching)


def _same(a: Mode, b: Mode) -> bool:
    if a.held != b.held:
        return False
    for (_, x), (_, y) in zip(a.contacts, b.contacts):
        if x.state != y.state or x.sigma != y.sigma:
            return False
        if x.state == SLIDE and len(x.direction) == 1 and x.direction != y.direction:
            return False
    return True


def _differing(choices: list):
    """The first ``(mode, motion)`` of *choices* and those whose accelerations differ from it."""
    m0, s0 = choices[0]
    scale = 1e-7 * (1.0 + max_abs(s0.qdd))
    return m0, s0, [(m, s) for m, s in choices[1:] if not np.allclose(s.qdd, s0.qdd, rtol=1e-7, atol=scale)]


def _lifting(solver, choices: list, sf: float) -> list:
    """*choices* (consistent ``(mode, motion)`` pairs) without those that keep a contact
    touching with a normal force at the noise level when the same choice with that contact
    separated is consistent too: the contact is lifting off at this instant.

    With a large friction coefficient (``mu = 1e9``) a sticking contact starts to slide at
    ``N = |F|/mu``, a normal force far below the tolerance of the sign tests, where separation
    is consistent as well; sliding and separation then differ by the friction ``mu N = |F|``,
    finite, and looked like Painleve's indeterminacy.  A genuine indeterminacy keeps a normal
    force well above the noise."""
    def lifts(touching, motion, separated) -> bool:
        if touching.held != separated.held:
            return False
        tol = 1e-9 * (sf + max_abs(motion.values))
        differ = False
        for c, ((_, a), (_, b)) in enumerate(zip(touching.contacts, separated.contacts)):
            if a == b:
                continue
            if b.state != SEPARATED or a.state == SEPARATED or abs(motion.normal(c)) > tol:
                return False
            differ = True
        return differ

    kept = [(m, s) for m, s in choices if not any(lifts(m, s, o) for o, _ in choices if o is not m)]
    return kept or choices


def select_mode(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray,
                tol_pos: float = 1e-9, tol_vel: float = 1e-9, exclude: Mode | Sequence[Mode] | None = None,
                previous: Mode | None = None, concerned: str | None = None) -> Mode:
    """Choose held unilateral constraints and contact states at a state.

    *exclude* is the mode that an event has just ended (a multiplier or a friction margin
    reached zero), or the modes a chain of events has ended at the same instant: at the
    switching point they are still (marginally) consistent, so they are dropped whenever
    another consistent choice exists.  *previous* is the mode before the
    event and *concerned* the contact the event is about: among equally sticky choices with
    the same contacts touching, the one that changes the fewest other contacts is taken.

    Raises
    ------
    PainleveParadox
        A sliding contact admits no consistent continuation, or several.
    MechanicsError
        No consistent choice (or several) without a sliding contact involved.
    """
    sq, sv = _scales(q, qd)
    outer, solver.selecting = solver.selecting, tol_vel * sv  # a slip within the tolerance is zero:
    try:                                                       # each candidate slides its own way
        return _select(solver, t, q, qd, tol_pos, tol_vel, exclude, previous, concerned, sq, sv)
    finally:
        solver.selecting = outer


def _select(solver, t, q, qd, tol_pos, tol_vel, exclude, previous, concerned, sq, sv) -> Mode:
    kernel = solver.kernel
    excluded = () if exclude is None else (exclude,) if isinstance(exclude, Mode) else tuple(exclude)
    closed = []
    if solver.unilateral:
        obs = kernel.observables(solver.input(t, q, qd))
        closed = [i for i in solver.unilateral
                  if abs(obs["pos"][i]) <= tol_pos * sq and obs["vel"][i] <= tol_vel * sv]
    names = [kernel.rows[i].name for i in closed]
    # what every candidate shares: the state, its kinematics and the scale of the forces
    y = np.concatenate((q, qd))
    x = solver.input(t, q, qd)
    kin = solver.ck.fn.raw(x, np.empty(solver.ck.size)) if solver.ck else None
    scales = (sq, sv, 1.0 + max_abs(kernel.dynamics(x)["F"]))
    copts = contact_options(solver, kin, (sq, sv), tol_pos, tol_vel)
    held_sets = [frozenset(names[j] for j in sub)
                 for k in range(len(closed), -1, -1) for sub in itertools.combinations(range(len(closed)), k)]
    total = len(held_sets) * math.prod(len(o) for o in copts)
    if total > MAX_COMBINATIONS:
        raise MechanicsError(f"too many simultaneous contact states to enumerate ({total})", t)
    consistent = []
    parents = solver.ck.parents if solver.ck else []
    candidates = [(held, combo) for held in held_sets
                  for combo in (itertools.product(*copts) if copts else [()])
                  if _linked(parents, combo)]
    # static friction is preferred: try the combinations that stick the most first and stop
    # after the first level of stickiness with a consistent choice (sliding onsets, which need a
    # direction search, are then never explored)
    candidates.sort(key=lambda hc: -sum(1 for cs in hc[1] if cs.state == STICK))
    level = None
    fallback = None
    singular: list[Exception] = []
    tried = 0
    for held, combo in candidates:
        sticks = sum(1 for cs in combo if cs.state == STICK)
        if level is not None and sticks < level:
            break
        modes = [Mode(held, tuple(zip(solver.ck.names, combo)))]
        for c, cs in enumerate(combo):
            if cs.state == SLIDE and cs.direction == ("onset",):
                expanded = []
                for m in modes:
                    probe = m.with_contact(solver.ck.names[c], ContactState(SLIDE, (1.0, 0.0), cs.sigma))
                    for s in onset_directions(solver, t, q, qd, probe, c):
                        expanded.append(m.with_contact(solver.ck.names[c], ContactState(SLIDE, s, cs.sigma)))
                modes = expanded
        for mode in modes:
            tried += 1
            motion = solver.motion(t, y, mode, kin)
            try:
                qdd = motion.qdd
            except SetValuedFriction:
                raise
            except (SingularSystem, MechanicsError) as exc:
                singular.append(exc)
                continue
            if not np.isfinite(qdd).all():
                continue
            if _consistent(solver, motion, mode, closed, scales):
                if any(_same(mode, e) for e in excluded):
                    fallback = fallback or (mode, motion)
                    continue
                consistent.append((mode, motion))
                level = sticks if level is None else level
    if not consistent and fallback is not None:
        consistent = [fallback]
    if not consistent and singular and (len(singular) == tried
                                        or all(isinstance(e, SingularSystem) for e in singular)):
        # every candidate is singular or has no answer: the model itself is (mass matrix,
        # dependent constraints, a servo-constraint its control direction cannot realize)
        raise singular[0]
    if not consistent:
        sliding = [n for n, o in zip(solver.ck.names, copts) if any(cs.state == SLIDE for cs in o)]
        if sliding:
            raise _paradox(solver, t, q, qd, sliding, "inconsistent", _state(solver, q, qd))
        raise MechanicsError(
            "no consistent set of held constraints and contact states: every choice among "
            f"{names + solver.ck.names} either pulls (negative normal force) or penetrates", t,
            _state(solver, q, qd))
    best = max(_stickiness(m) for m, _ in consistent)
    # static friction: among the consistent choices prefer those that stick the most
    preferred = [(m, s) for m, s in consistent if _stickiness(m)[0] == best[0]]
    if previous is not None and len(preferred) > 1:
        # with mu < mu_s, which of two sticking contacts slips can be ambiguous in rigid Coulomb
        # theory; the event concerned one contact, so the others keep their friction state.
        # (Only between choices with the same contacts touching: an ambiguity between touching
        # and separating is Painleve's indeterminacy and is reported.)
        normal = {(m.held, tuple(cs.state == SEPARATED for _, cs in m.contacts)) for m, _ in preferred}
        if len(normal) == 1:
            def change(m):
                return sum(1 for (name, a), (_, b) in zip(m.contacts, previous.contacts)
                           if a.state != b.state and name != concerned)
            least = min(change(m) for m, _ in preferred)
            preferred = [(m, sol) for m, sol in preferred if change(m) == least]
    m0, s0, distinct = _differing(preferred)
    if distinct:  # a contact lifting off with a huge mu is no indeterminacy
        preferred = _lifting(solver, preferred, scales[2])
        m0, s0, distinct = _differing(preferred)
    if distinct:
        m1 = distinct[0][0]
        sliding = [n for n, cs in m0.contacts + m1.contacts if cs.state == SLIDE]
        if sliding:
            raise _paradox(solver, t, q, qd, sorted(set(sliding)), "indeterminate", _state(solver, q, qd),
                           [m0.label(), m1.label()])
        raise MechanicsError(
            f"the motion is not unique: [{m0.label()}] and [{m1.label()}] are both consistent "
            "and give different accelerations", t, _state(solver, q, qd))
    return max(preferred, key=lambda ms: _stickiness(ms[0]))[0]


# ----------------------------------------------------------------------------- Painleve


def effective_compliance(solver: ModeSolver, t, q, qd, mode: Mode, contact: str,
                         mu: float | None = None) -> float:
    """``b = dg''/dN`` of a contact in *mode* with the other rows enforced (Schur complement
    of ``G M^-1 B``); sliding with ``N > 0`` is possible only while ``b > 0``.

    With *mu* the friction coefficient of that contact is replaced (to find the critical one).
    """
    x = solver.input(t, q, qd)
    out = solver.kernel.dynamics(x)
    cout = {k: np.array(v) if isinstance(v, np.ndarray) else v for k, v in solver.ck(x).items()}
    c = solver.ck.index[contact]
    if mu is not None:
        cout["mu"] = cout["mu"].copy()
        cout["mu"][c] = mu
    layout = solver.layout(mode)
    G, gamma, B = solver.assemble(mode, layout, out, cout)
    j = next(k for k, r in enumerate(layout) if r.kind == "normal" and r.index == c)
    return compliance_of(solver.kernel.dense(out, "M"), B, G, j)


def critical_friction(solver: ModeSolver, t, q, qd, mode: Mode, contact: str) -> float | None:
    """Friction coefficient at which the contact's effective normal compliance vanishes
    (``b(mu) = b0 - mu b1`` is affine in its own mu): ``mu_crit = b0/b1``, or None."""
    b0 = effective_compliance(solver, t, q, qd, mode, contact, mu=0.0)
    b1 = b0 - effective_compliance(solver, t, q, qd, mode, contact, mu=1.0)
    if abs(b1) < 1e-14 * max(1.0, abs(b0)):
        return None
    mu = b0 / b1
    return float(mu) if mu > 0 else None


def _paradox(solver, t, q, qd, contacts, kind, state, modes=None) -> PainleveParadox:
    details = {}
    for name in contacts:
        c = solver.ck.index[name]
        U = solver.ck.slip(solver.ck(solver.input(t, q, qd)), c)
        direction = (float(np.sign(U[0])) or 1.0,) if len(U) == 1 else tuple(U / max(np.linalg.norm(U), 1e-300))
        held = frozenset(solver.kernel.rows[i].name for i in solver.unilateral)
        probe = Mode(held, tuple((n, ContactState(SLIDE, direction) if n == name else ContactState(SEPARATED))
                                 for n in solver.ck.names))
        try:
            b = effective_compliance(solver, t, q, qd, probe, name)
            mu_c = critical_friction(solver, t, q, qd, probe, name)
        except Exception:  # pragma: no cover - diagnostics must not mask the paradox
            b, mu_c = float("nan"), None
        details[f"{name}: effective normal compliance b = dg''/dN"] = f"{b:.6g}"
        mu_now = solver.ck(solver.input(t, q, qd))["mu"][c]
        details[f"{name}: friction coefficient"] = f"{mu_now:.6g}"
        details[f"{name}: critical friction coefficient"] = f"{mu_c:.6g}" if mu_c is not None else "none"
    if kind == "inconsistent":
        text = (f"Painleve paradox (inconsistency) at contact(s) {', '.join(contacts)}: sliding needs a "
                "negative normal force and separation would penetrate -- no consistent "
                "continuation under rigid-body Coulomb friction (the friction coefficient exceeds the "
                "critical one for this configuration; a tangential impact / compliance model is needed)")
    else:
        text = (f"Painleve paradox (indeterminacy) at contact(s) {', '.join(contacts)}: both "
                f"[{modes[0]}] and [{modes[1]}] are consistent -- the rigid-body problem has more than "
                "one continuation")
    return PainleveParadox(text, t, state, details)


# ----------------------------------------------------------------------------- impacts


def impact(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray, hitting=(),
           restitution: dict | None = None, contacts_hit=()):
    """Velocity jump when unilateral constraints or contacts close.

    Impulse sets are enumerated so that impulses are ``>= 0`` and rows without impulse do not
    approach.  Constraints use their restitution (0 = plastic); a contact's normal impulse
    follows its impact law, and its tangential impulse is that of sticking when
    ``|Lambda_t| <= mu_s Lambda_n``, else Coulomb sliding ``-mu Lambda_n s`` along the
    pre-impact slip (none for a frictionless contact).

    Returns
    -------
    qd_plus : ndarray
    impulses : dict name -> impulse
    """
    restitution = restitution or {}
    kernel, ck = solver.kernel, solver.ck
    x = solver.input(t, q, qd)
    out = kernel.dynamics(x)
    obs = kernel.observables(x)
    cout = {k: np.array(v) if isinstance(v, np.ndarray) else v for k, v in ck(x).items()} if ck else None
    M = kernel.dense(out, "M")
    n = solver.n
    sq = 1 + np.max(np.abs(q))
    G, B = (kernel.dense(out, "G"), kernel.dense(out, "B")) if kernel.m else (np.zeros((0, n)), np.zeros((n, 0)))
    vel = obs["vel"] if kernel.m else np.zeros(0)
    closed = [i for i in solver.unilateral if abs(obs["pos"][i]) <= 1e-8 * sq]
    for i in hitting:
        if i not in closed:
            closed.append(i)
    closed_c = []
    if ck:
        # (the friction torques give no impulse: their bound l N is finite while N is; an
        # impulsive normal force would allow an impulsive torque, not modelled)
        closed_c = [c for c in range(len(ck.data)) if c not in ck.torques
                    and (abs(cout["gap"][c]) <= 1e-8 * sq or ck.names[c] in contacts_hit)]
    eq_rows = [i for i in solver.bilateral if kernel.rows[i].velocity is not None]
    options_c = []
    for c in closed_c:
        U = ck.slip(cout, c)
        nrm = np.linalg.norm(U)
        s = U / nrm if nrm > 1e-12 * (1 + np.max(np.abs(qd))) else None
        if c in solver.frictionless:  # a normal impulse only
            s, opts = np.zeros(len(U)), ["slide", "off"]
        elif c in solver.rolling:  # ideal rolling: the gap closes rolling (or does not close)
            opts = ["stick", "off"]
        else:
            opts = ["stick"] + (["slide"] if s is not None and solver.laws[c].exact else []) + ["off"]
        options_c.append([(c, o, s) for o in opts])
    for k in range(len(closed), -1, -1):
        for subset in itertools.combinations(closed, k):
            for combo in (itertools.product(*options_c) if options_c else [()]):
                Grows, Bcols, target, labels = [], [], [], []
                for i in eq_rows + list(subset):
                    Grows.append(G[i])
                    Bcols.append(B[:, i])
                    e = restitution.get(i, 0.0) if i in subset else 0.0
                    c_i = vel[i] - G[i] @ qd
                    target.append(-c_i - e * min(vel[i], 0.0))
                    labels.append(("c", i))
                for (c, o, s) in combo:
                    if o == "off":
                        continue
                    Gn = cout["Gn"][c]
                    rate = cout["gap_rate"][c]
                    e = ck.data[c].restitution
                    Grows.append(Gn)
                    target.append(-(rate - Gn @ qd) - e * min(rate, 0.0))
                    o_, d = ck.offsets[c], ck.dims[c]
                    W = cout["W"][o_:o_ + d]
                    if o == "stick":
                        Bcols.append(Gn)
                        labels.append(("n", c))
                        for kk in range(d):
                            Grows.append(W[kk])
                            Bcols.append(W[kk])
                            target.append(-(cout["U"][o_ + kk] - W[kk] @ qd))
                            labels.append(("t", c, kk))
                    else:
                        Bcols.append(Gn - cout["mu"][c] * (s @ W))
                        labels.append(("n", c))
                if Grows:
                    try:
                        qd_plus, lam = solve_saddle(M, M @ qd, np.array(Bcols).T, np.array(Grows), -np.array(target))
                    except SingularMatrix:
                        continue
                else:
                    qd_plus, lam = qd.copy(), np.zeros(0)
                tol = 1e-12 * (1 + np.max(np.abs(lam), initial=0.0))
                ok = True
                for lab, value in zip(labels, lam):
                    if lab[0] == "c" and lab[1] in subset and value < -tol:
                        ok = False
                    if lab[0] == "n" and value < -tol:
                        ok = False
                for (c, o, s) in combo:
                    if o == "stick" and c not in solver.rolling:  # rolling: unbounded impulse cone
                        Ln = lam[labels.index(("n", c))]
                        Lt = np.array([lam[labels.index(("t", c, kk))] for kk in range(ck.dims[c])])
                        if np.linalg.norm(Lt) > cout["mu_s"][c] * Ln + tol:
                            ok = False
                    if o == "off":
                        Gn = cout["Gn"][c]
                        if Gn @ qd_plus + (cout["gap_rate"][c] - Gn @ qd) < -1e-10 * (1 + np.max(np.abs(qd_plus))):
                            ok = False
                for i in closed:
                    if i not in subset:
                        vplus = G[i] @ qd_plus + (vel[i] - G[i] @ qd)
                        if vplus < -1e-10 * (1 + np.max(np.abs(qd_plus))):
                            ok = False
                if ok:
                    impulses = {}
                    for lab, value in zip(labels, lam):
                        if lab[0] == "c":
                            impulses[kernel.rows[lab[1]].name] = float(value)
                        elif lab[0] == "n":
                            c = lab[1]
                            impulses[ck.names[c]] = float(value)
                            o = next(o for (cc, o, _) in combo if cc == c)
                            if o == "slide" and c not in solver.frictionless:  # its friction impulse
                                sd = next(sd for (cc, _, sd) in combo if cc == c)
                                for kk in range(ck.dims[c]):
                                    impulses[f"{ck.names[c]}_t{kk + 1}"] = float(-cout["mu"][c] * value * sd[kk])
                        else:
                            impulses[f"{ck.names[lab[1]]}_t{lab[2] + 1}"] = float(value)
                    return qd_plus, impulses
    raise MechanicsError("no consistent impact: every impulse set pulls or lets a contact "
                         "penetrate", t, dict(zip(solver.model.coordinates, q)))
