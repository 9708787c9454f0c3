"""The friction law of the system (Manglieva & Beknazarov 2022, sections 1.1-1.3), derived symbolically.

With the constraint rows ``G`` (the model's constraints and the normal rows of the touching
contacts, all taken as ideal), Painleve's split of the reaction ``R = G^T lambda + R_tau``
gives constraint forces ``lambda`` that do not depend on friction.  For a contact sliding with
a fixed direction ``s`` (one slip component) the physical reaction is
``R = G^T N + W^T F`` with Coulomb's ``F = -f s N_c``; projecting,

    lambda = N + k F,       k = (G M^-1 G^T)^-1 G M^-1 W^T,

so the normal force, the friction force and Manglieva & Beknazarov's coefficient ``mu`` (the slip
acceleration imparted by friction: ``mu = W M^-1 R_tau = F / m_eff``) follow from
``lambda_c`` alone:

    N_c = lambda_c / (1 - f s k_c),      F = -f s N_c,      mu = F / m_eff,
    1/m_eff = W M^-1 W^T - W M^-1 G^T k.

The denominator ``1 - f s k_c`` vanishing is Painleve's paradox.  A bilateral contact (a slider
in a rough guide) presses either way and Coulomb's law reads ``F = -f s |N_c|``: for a normal
force of sign ``sigma`` (``normal_sign``) ``F = -f s sigma N_c`` and
``N_c = lambda_c / (1 - f s sigma k_c)``, a branch that holds while ``sigma N_c > 0``.  ``mu`` in the paper is
normalized this way: for Painleve's two points (1.13) ``mu = R_x / (m + m1 cos^2 theta)``,
i.e. ``m_eff = m + m1 cos^2 theta``.

Cost: this uses the symbolic inverse of ``M`` -- meant for textbook-sized systems.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import sympy as sp

from ...equations.dynamics import Dynamics, dynamics_of
from ...equations.formalisms.base import reduce_velocities
from ...errors import FormNotApplicable, did_you_mean
from ...modeling.contacts import IdealRolling
from ...modeling.model import Constraint, Model, Parameter
from ...modeling.symbols import latex_names, to_sp

__all__ = ["FrictionLaw", "friction_law"]


@dataclass
class FrictionLaw:
    """Symbolic friction law of the system for one contact and slip direction."""

    contact: str
    direction: int
    normal_sign: int
    rows: list[str]
    lambdas: list[sp.Symbol]
    f: sp.Expr
    N: sp.Expr
    F: sp.Expr
    mu: sp.Expr
    effective_mass: sp.Expr
    k: sp.Expr
    denominator: sp.Expr
    substitutions: dict = field(default_factory=dict)
    bilateral: bool = False

    def as_text(self) -> str:
        lam = sp.Symbol(f"lambda_{self.contact}")
        lines = [f"friction law of the system, contact '{self.contact}', slip direction "
                 f"s = {self.direction:+d}" + (f", normal force of sign {self.normal_sign:+d} "
                                              f"(bilateral: F = -f s |N|)" if self.bilateral else "")
                 + " (Manglieva & Beknazarov 2022, (1.21)-(1.23), (1.81)-(1.82))",
                 f"  constraint rows (lambda independent of friction): {', '.join(self.rows)}",
                 f"  effective tangential mass m_eff = {sp.sstr(self.effective_mass)}",
                 f"  coupling k = {sp.sstr(self.k)}     ({lam} = N + k F)",
                 f"  N  = {sp.sstr(self.N)}",
                 f"  F  = {sp.sstr(self.F)}",
                 f"  mu = F/m_eff = {sp.sstr(self.mu)}",
                 f"  Painleve: sliding is consistent only while {sp.sstr(self.denominator)} > 0"]
        if self.bilateral:
            lines.append(f"  this branch holds while {self.normal_sign:+d}*N > 0")
        if self.substitutions:
            lines.append("  with " + ", ".join(f"{k} = {v}" for k, v in self.substitutions.items()))
        return "\n".join(lines)

    def as_latex(self) -> str:
        syms = set().union(*(e.free_symbols for e in (self.N, self.F, self.mu, self.effective_mass)))
        names = latex_names(syms)
        return (r"\begin{align*}" + "\n"
                + r"m_{\mathrm{eff}} &= " + sp.latex(self.effective_mass, symbol_names=names) + r"\\" + "\n"
                + r"N &= " + sp.latex(self.N, symbol_names=names) + r"\\" + "\n"
                + r"\mu &= " + sp.latex(self.mu, symbol_names=names) + "\n" + r"\end{align*}")

    def to_dict(self) -> dict:
        return {"contact": self.contact, "direction": self.direction, "normal_sign": self.normal_sign,
                "bilateral": self.bilateral, "rows": self.rows,
                "N": sp.sstr(self.N), "F": sp.sstr(self.F), "mu": sp.sstr(self.mu),
                "effective_mass": sp.sstr(self.effective_mass), "k": sp.sstr(self.k),
                "paradox_when_nonpositive": sp.sstr(self.denominator),
                "latex": self.as_latex()}


def _simplify(e: sp.Expr, substitutions) -> sp.Expr:
    if substitutions:
        e = e.subs(substitutions)
    e = sp.together(e)
    try:
        return sp.factor(sp.trigsimp(e))
    except Exception:  # pragma: no cover - simplification is cosmetic
        return e


def friction_law(model: Model, contact: str, direction: int = 1, constraints=None,
                 substitutions: dict | None = None, simplify: bool = True,
                 normal_sign: int = 1) -> FrictionLaw:
    """Derive the friction law of the system for *contact* sliding in *direction*.

    Parameters
    ----------
    model : Model
    contact : str
        A contact with one slip component.
    direction : {+1, -1}
        Sign of the slip velocity.
    constraints : list of str, optional
        Constraint rows taken as active (default: every constraint of the model).
    substitutions : mapping, optional
        Expressions substituted for display, e.g. ``{x1: x + l*cos(theta)}``.
    normal_sign : {+1, -1}
        Sign of the normal force; -1 only for a bilateral contact, whose friction is
        ``-f s |N|``.
    """
    dyn = dynamics_of(model)
    names = [c.name for c in model.contacts]
    if contact not in names:
        raise FormNotApplicable(f"friction law: no contact '{contact}'{did_you_mean(contact, names)} "
                                f"(the model's contacts: {', '.join(names) or 'none'})")
    c = names.index(contact)
    cd = dyn.contacts[c]
    if len(cd.U) != 1:
        raise FormNotApplicable(f"friction law: contact '{contact}' has {len(cd.U)} slip components; "
                                "the scalar law is for one (the vector law follows with s = U/|U|)")
    if direction not in (1, -1):
        raise FormNotApplicable("friction law: direction must be +1 or -1")
    if normal_sign not in (1, -1):
        raise FormNotApplicable("friction law: the normal force's sign must be +1 or -1")
    if normal_sign == -1 and not cd.bilateral:
        raise FormNotApplicable(f"friction law: contact '{contact}' is unilateral, its normal force "
                                "is never negative; --normal-sign -1 is for bilateral contacts")
    rows = dyn.rows(constraints)
    n = dyn.n
    M = to_sp(dyn.M)
    G = sp.Matrix([[to_sp(r.G[j]) for j in range(n)] for r in rows] + [[to_sp(x) for x in cd.Gn]])
    W = sp.Matrix([[to_sp(x) for x in cd.W[0]]])
    Minv = M.inv(method="LU")
    Minv = Minv.applyfunc(lambda e: sp.trigsimp(sp.together(e)))
    D = G * Minv * G.T
    GMW = G * Minv * W.T
    k = D.LUsolve(GMW)
    kc = sp.trigsimp(sp.together(k[-1]))
    inv_meff = (W * Minv * W.T)[0, 0] - (W * Minv * G.T * k)[0, 0]
    meff = sp.trigsimp(sp.together(1 / inv_meff))
    f = to_sp(cd.mu)
    lam = sp.Symbol(f"lambda_{contact}")
    den = 1 - f * direction * normal_sign * kc
    N = lam / den
    F = -f * direction * normal_sign * N
    mu = F / meff
    subs = substitutions or {}
    if simplify:
        N, F, mu, meff, kc, den = (_simplify(e, subs) for e in (N, F, mu, meff, kc, den))
    return FrictionLaw(contact, direction, normal_sign, [r.name for r in rows] + [contact],
                       [sp.Symbol(f"lambda_{r.name}") for r in rows] + [lam],
                       f, N, F, mu, meff, kc, den, {str(k_): str(v) for k_, v in subs.items()},
                       bool(cd.bilateral))


def painleve_model(model: Model, contacts=None) -> tuple[Model, list[str]]:
    """The model in Manglieva & Beknazarov's representation of friction (Manglieva & Beknazarov 2022, (1.52), (2.7)-(2.8)).

    Every touching contact (default: all) becomes an ideal bilateral constraint ``gap = 0``
    (its multiplier is the constraint force ``lambda``, independent of friction), and the
    friction force of the system enters as the generalized force ``M V mu`` -- ``V`` the basis
    of the possible velocities, ``mu_j`` one coefficient per independent velocity (parameters
    of value 0 in the returned model; the friction law of the system expresses them through
    ``lambda``).  Deriving this model in any form gives Manglieva & Beknazarov's equations with friction:
    Lagrange I (1.53)/(2.8), Lagrange II (1.56), Shulgin (1.64), Appell (1.65).

    Returns
    -------
    model : Model
    mu_names : list of str
    """
    return contact_gap_constraints(model, contacts)


def touching_contacts(model: Model, states: dict | None = None) -> list[str]:
    """The contacts that touch in the mode the simulation starts in (their state at the
    model's initial state; *states* -- contact -> state, as for :func:`derive_in_mode` --
    overrides it): the contacts the Painleve representation closes by default.  A contact
    that does not touch (e.g. the top of a ladder that reaches the floor only when the ladder
    falls flat) must not be closed together with the others."""
    from ...numeric.consistency import complete_state
    from ...modes.solver import ModeSolver
    from ...numeric.kernel import kernel_of, parameter_vector
    from ...modes.switching import select_mode

    names = [c.name for c in model.contacts]
    states = _checked_states(states, names)
    if len(states) < len(names):
        kernel = kernel_of(model)
        params = parameter_vector(model)
        q, qd, _ = complete_state(kernel, model.numeric_initial(), params, model.t0)
        mode = select_mode(ModeSolver(kernel, params), model.t0, q, qd)
        for name, cs in mode.contacts:
            states.setdefault(name, cs.label().replace("(N<0)", ""))
    return [n for n in names if states[n] != "separated"]


CONTACT_STATES = ("separated", "stick", "slide+", "slide-", "slide")


def _checked_states(states, names) -> dict:
    """The ``--contact`` states as a dict, each contact and state checked."""
    states = dict(states or {})
    for k, v in states.items():
        if k not in names:
            raise FormNotApplicable(f"--contact: no contact '{k}'{did_you_mean(k, names)}")
        if v not in CONTACT_STATES:
            raise FormNotApplicable(f"--contact {k}: state '{v}' unknown{did_you_mean(v, CONTACT_STATES)}; "
                                    "use " + ", ".join(CONTACT_STATES))
    return states


def derive_in_mode(model: Model, form: str = "lagrange1", states: dict | None = None,
                   independent=None):
    """Equations of motion with the contacts in given states (the physical representation:
    a sliding contact's normal force carries Coulomb's friction ``-mu N s``).

    Parameters
    ----------
    states : mapping contact -> state, optional
        ``"separated"``, ``"stick"``, ``"slide+"``/``"slide-"`` (one slip component, sign of
        the slip) or ``"slide"`` (two components: the direction ``s = U/|U|`` appears as the
        symbols ``s[contact,k]``).  Contacts not given take their state at the initial state
        (the mode the simulation starts in).
    """
    import symengine as se

    from ...numeric.consistency import complete_state
    from ...equations.formalisms import derive as derive_symbolic
    from ...numeric.consistency import initial_branch
    from ...modes.solver import ModeSolver
    from ...numeric.kernel import kernel_of, parameter_vector
    from ...modes.switching import select_mode

    dyn = dynamics_of(model)
    names = [c.name for c in dyn.contacts]   # the contacts, then their friction torques
    states = _checked_states(states, names)
    kernel = kernel_of(model)
    params = parameter_vector(model)
    held = {r.name for r in kernel.rows if r.unilateral}
    if len(states) < len(names) or held:
        q, qd, _ = complete_state(kernel, model.numeric_initial(), params, model.t0)
        mode = select_mode(ModeSolver(kernel, params), model.t0, q, qd)
        held = set(mode.held)
        for name, cs in mode.contacts:
            states.setdefault(name, cs.label().replace("(N<0)", ""))
    rows = [r for r in dyn.rows() if not r.unilateral or r.name in held]
    notes = []
    for c, name in enumerate(names):
        st = states[name]
        d = len(dyn.contacts[c].U)
        if dyn.contacts[c].parent is not None:
            rows = _torque_rows(dyn, c, st, states, rows, notes)
            continue
        if st == "separated":
            notes.append(f"contact '{name}': separated (no force)")
            continue
        rolling = isinstance(dyn.contacts[c].law, IdealRolling)
        if st == "stick" and rolling:
            rows += dyn.contact_rows(c, "stick")
            notes.append(f"contact '{name}': rolling ideally (mu = inf) -- an ideal nonholonomic "
                         "constraint (its slip rows, multipliers = the friction force, unbounded) "
                         "with the unilateral gap (multiplier = N >= 0; released when N reaches 0)")
            continue
        if st == "stick":
            rows += dyn.contact_rows(c, "stick")
            notes.append(f"contact '{name}': sticking (the multipliers of its slip rows are the "
                         "friction force)")
            continue
        if rolling:
            raise FormNotApplicable(f"--contact {name}: '{st}' is not a state of an ideally rolling "
                                    "contact (mu = inf: it never slides); use stick or separated")
        if st == "smooth" and dyn.contacts[c].law.exact:   # the state of a frictionless contact
            rows += dyn.contact_rows(c, "slide", 1, [se.Integer(0)] * d)
            notes.append(f"contact '{name}': touching without friction (smooth)")
            continue
        if st in ("slide+", "slide-") and d != 1 or st == "slide" and d != 2:
            raise FormNotApplicable(f"--contact {name}: '{st}' does not fit {d} slip component(s); "
                                    "use slide+/slide- for one, slide for two")
        direction = [se.Integer(1 if st == "slide+" else -1)] if d == 1 else None
        rows += dyn.contact_rows(c, "slide", 1, direction)
        notes.append(f"contact '{name}': sliding ({st}); its normal force N carries the friction "
                     "-mu N s" + ("" if d == 1 else " with s = U/|U| (symbols s[...])"))
    branch = initial_branch(model) if form == "lagrange2" else None   # as nonideal.derive does
    eom = derive_symbolic(model, form, rows=rows, independent=independent, branch=branch)
    return replace(eom, notes=tuple(notes) + tuple(eom.notes))


def _torque_rows(dyn, c: int, st: str, states: dict, rows: list, notes: list) -> list:
    """The rows of friction torque *c* in state *st*: sticking, its angular-velocity rows
    (multipliers: the torque); sliding, ``-sigma l N s W`` added to its contact's gap row."""
    import symengine as se

    cd = dyn.contacts[c]
    parent = dyn.contacts[cd.parent].name
    d = len(cd.U)
    if states[parent] == "separated" or st == "separated":
        if (states[parent] == "separated") != (st == "separated"):
            raise FormNotApplicable(f"--contact {cd.name}: a friction torque touches exactly when its contact "
                                    f"'{parent}' does (it is '{states[parent]}', the torque '{st}')")
        return rows
    if st == "stick":
        notes.append(f"friction torque '{cd.name}': sticking (the multipliers of its rows are the torque, "
                     f"bounded by {cd.mu} N)")
        return rows + dyn.contact_rows(c, "stick")[1:]
    if st in ("slide+", "slide-") and d != 1 or st == "slide" and d != 2 or st == "smooth":
        raise FormNotApplicable(f"--contact {cd.name}: '{st}' does not fit {d} angular-velocity component(s); "
                                "use stick, slide+/slide- for one, slide for two")
    s = [se.Integer(1 if st == "slide+" else -1)] if d == 1 else \
        [se.Symbol(f"s[{cd.name},{k + 1}]") for k in range(d)]
    torque = [cd.mu * sum((cd.W[k][j] * s[k] for k in range(d)), se.Integer(0)) for j in range(dyn.n)]
    notes.append(f"friction torque '{cd.name}': {st}; the normal force N of '{parent}' carries the torque "
                 f"-{cd.mu} N s" + ("" if d == 1 else " with s = w/|w| (symbols s[...])"))
    out = []
    for r in rows:
        if r.name == parent and r.order == 0:
            r = replace(r, B=tuple(b - t for b, t in zip(r.B, torque)), reaction_kind="friction")
        out.append(r)
    return out


def contact_gap_constraints(model: Model, contacts=None) -> tuple[Model, list[str]]:
    """See :func:`painleve_model`."""
    names = [c.name for c in model.contacts] if contacts is None else list(contacts)
    chosen = [c for c in model.contacts if c.name in names]
    if not chosen:
        raise FormNotApplicable("painleve representation: no contact to close (the model has no contacts, "
                                "or none of those asked for touches; e.g. --contact NAME=slide+ closes one)")
    constraints = list(model.constraints) + [Constraint(c.name, c.gap, "holonomic") for c in chosen]
    base = model.replace(constraints=tuple(constraints),
                         contacts=tuple(c for c in model.contacts if c.name not in names))
    dyn = Dynamics(base)
    red = reduce_velocities(dyn, dyn.rows(), base.independent)
    if red.auxiliaries:
        raise FormNotApplicable("painleve representation: the velocity basis is too large to write "
                                "explicitly; use the physical representation")
    k = len(red.independent)
    if k == 0:
        raise FormNotApplicable("painleve representation: with the contacts " + ", ".join(
            f"'{c.name}'" for c in chosen) + " closed the system has no possible velocity (no degree "
            "of freedom is left for the friction force M V mu); close only the contacts that touch "
            "together (e.g. --contact NAME=separated for the others)")
    taken = set(model.parameters) | set(model.coordinates)
    mu_names = []
    for j in range(k):
        name = f"mu_{j + 1}" if f"mu_{j + 1}" not in taken else f"mu_tau_{j + 1}"
        mu_names.append(name)
    M = to_sp(dyn.M)
    V = to_sp(red.V)
    mus = sp.Matrix([sp.Symbol(n) for n in mu_names])
    friction = M * V * mus
    forces = [f + friction[i] for i, f in enumerate(model.forces)]
    params = dict(model.parameters)
    for n_ in mu_names:
        params[n_] = Parameter(n_, 0.0, "", "friction coefficient of the system (Manglieva & Beknazarov 2022, (1.52))")
    new = base.replace(forces=dict(zip(model.coordinates, forces)), parameters=params,
                       name=f"{model.name} (friction as M V mu)")
    return new, mu_names
