"""``nonideal check``: what the model is, and whether its mechanics is well posed at t0.

Counts coordinates, constraints and degrees of freedom; completes and checks the initial
state; solves the motion there (singular mass matrix, dependent constraints and
unrealizable servo-constraints surface here, named); and reports the Beghin--Appell
determinacy count for servo-constraints (``r`` program constraints vs ``j`` control
directions: impossible if r > j, indeterminate if r < j, determinate if r = j).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .consistency import complete_state
from .errors import MechanicsError, ModelError, PainleveParadox, SingularSystem
from .model import Model
from .modes import ModeSolver, select_mode
from .numeric import kernel_of, parameter_vector

__all__ = ["CheckReport", "check_model", "diagnose_state", "diagnose_initial_state"]


@dataclass
class CheckReport:
    model: str
    source: str
    coordinates: list[str]
    parameters: dict[str, float]
    constraints: list[dict[str, Any]]
    contacts: list[dict[str, Any]]
    counts: dict[str, int]
    determinacy: str
    initial: dict[str, float]
    initial_mode: str
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return {
            "model": self.model, "source": self.source, "ok": True,
            "coordinates": self.coordinates, "parameters": self.parameters,
            "constraints": self.constraints, "contacts": self.contacts, "counts": self.counts,
            "determinacy": self.determinacy, "initial_state": self.initial,
            "initial_mode": self.initial_mode, "notes": self.notes,
        }

    def as_text(self) -> str:
        c = self.counts
        lines = [f"{self.model}  ({self.source})",
                 f"  coordinates ({c['n_q']}): {', '.join(self.coordinates)}",
                 f"  constraints: {c['holonomic']} holonomic, {c['nonholonomic']} nonholonomic"
                 f" (first order), {c['second_order']} second order, {c['unilateral']} unilateral,"
                 f" {c['servo']} servo/quasi-ideal",
                 f"  contacts: {c['contacts']}",
                 f"  degrees of freedom: configuration {c['configuration_dof']}, velocities {c['dof']}",
                 f"  determinacy: {self.determinacy}"]
        for con in self.constraints:
            lines.append(f"    - {con['name']}: {con['kind']}, order {con['order']}, reaction "
                         f"{con['reaction']}{', unilateral' if con['unilateral'] else ''}: {con['expr']} "
                         f"{'>=' if con['unilateral'] else '='} 0")
        for ct in self.contacts:
            held = "= 0 (bilateral guide, N of either sign)" if ct["bilateral"] else ">= 0"
            lines.append(f"    - contact {ct['name']}: gap {ct['gap']} {held}, slip {ct['slip']}, "
                         f"friction {ct['friction']}")
        lines.append("  initial state: " + ", ".join(f"{k} = {v:.10g}" for k, v in self.initial.items()))
        lines.append(f"  initial mode: {self.initial_mode}")
        lines += [f"  note: {n}" for n in self.notes]
        lines.append("  ok")
        return "\n".join(lines)


def check_model(model: Model) -> CheckReport:
    """Validate *model* beyond parsing (raises the same errors a simulation would)."""
    kernel = kernel_of(model)
    params = parameter_vector(model)
    cons = []
    counts = dict(n_q=model.n_q, holonomic=0, nonholonomic=0, second_order=0, unilateral=0,
                  servo=0, contacts=len(model.contacts))
    for c in model.constraints:
        cons.append({"name": c.name, "kind": c.kind, "order": c.order, "reaction": c.reaction_kind,
                     "unilateral": c.unilateral, "expr": str(c.expr)})
        if c.unilateral:
            counts["unilateral"] += 1
        elif c.order == 0:
            counts["holonomic"] += 1
        elif c.order == 1:
            counts["nonholonomic"] += 1
        else:
            counts["second_order"] += 1
        if c.reaction_kind != "ideal":
            counts["servo"] += 1
    counts["configuration_dof"] = model.n_q - counts["holonomic"]
    counts["dof"] = model.n_q - counts["holonomic"] - counts["nonholonomic"] - counts["second_order"]
    contacts = []
    for ct in model.contacts:
        law = type(ct.friction).__name__
        contacts.append({"name": ct.name, "gap": str(ct.gap), "slip": [str(s) for s in ct.slip],
                         "friction": law, "bilateral": ct.bilateral})
    servo = [c for c in model.constraints if c.reaction_kind != "ideal"]
    if servo:
        r = len(servo)
        determinacy = (f"{r} servo/quasi-ideal constraint(s), each with its own control direction "
                       "(r = j): determinate if the control directions can realize the program "
                       "(checked at t0 below)")
    else:
        determinacy = "all constraints ideal: the motion is determinate"
    given = model.numeric_initial()
    q, qd, closed = complete_state(kernel, given, params, model.t0)
    problem = diagnose_state(model, model.t0, q, qd, closed, definite=True)
    if problem is not None:
        raise problem
    solver = ModeSolver(kernel, params)
    from .switching import validate_state

    validate_state(solver, model.t0, q, qd)  # finite terms, the contacts' friction data
    mode = select_mode(solver, model.t0, q, qd)
    solver.solve(model.t0, q, qd, mode)  # raises on singular M / dependent constraints
    initial = {c: float(v) for c, v in zip(model.coordinates, q)}
    initial.update({c + "'": float(v) for c, v in zip(model.coordinates, qd)})
    notes = []
    completed = [k for k in initial if k not in given]
    if completed:
        notes.append("completed from the constraints: " + ", ".join(completed))
    return CheckReport(model.name, model.source, list(model.coordinates), model.parameter_values,
                       cons, contacts, counts, determinacy, initial, mode.label(), notes)


# ------------------------------------------------------------------ well-posedness at a state


def _fmt_state(model: Model, t: float, q) -> str:
    values = ", ".join(f"{c} = {float(v):.6g}" for c, v in zip(model.coordinates, q))
    return f"t = {float(t):.6g} ({values})"


def _combination(coeffs, names, tol=1e-9, prime="'") -> str:
    terms = []
    for c, nm in zip(coeffs, names):
        if abs(c) <= tol:
            continue
        mag = f"{abs(c):.3g}*" if abs(abs(c) - 1) > 1e-9 else ""
        sign = "-" if c < 0 else "+"
        terms.append((sign, f"{mag}{nm}{prime}"))
    if not terms:
        return "0"
    text = ("-" if terms[0][0] == "-" else "") + terms[0][1]
    for sign, term in terms[1:]:
        text += f" {sign} {term}"
    return text


def diagnose_state(model: Model, t: float, q, qd, closed=(), definite: bool = False,
                   params=None) -> ModelError | None:
    """Why the equations of motion at a state are singular, or ``None`` when they are not.

    Checks, for the bilateral constraints and the unilateral ones in *closed* (kernel row
    indices): constraints with a zero gradient, dependent (redundant) constraints -- named,
    with the combination -- and a mass matrix that is singular (or, with ``definite``, not
    positive definite) on the velocities the constraints allow.

    Returns
    -------
    SingularSystem or None
    """
    kernel = kernel_of(model)
    params = parameter_vector(model) if params is None else params
    src = None if model.source == "<api>" else model.source
    names = list(model.coordinates)
    x = kernel.state_input(t, q, qd, params)
    out = kernel.dynamics(x)
    M = np.asarray(out["M"], dtype=float)
    rows = [i for i, r in enumerate(kernel.rows) if not r.unilateral or i in set(closed)]
    where = _fmt_state(model, t, q)
    G = np.asarray(out["G"], dtype=float)[rows] if rows and kernel.m else np.zeros((0, kernel.n))
    problems = []
    scale = 1.0 + (float(np.max(np.abs(G))) if G.size else 0.0)
    keep: list[int] = []
    for j, i in enumerate(rows):
        name = kernel.rows[i].name
        g = G[j]
        if np.max(np.abs(g), initial=0.0) <= 1e-12 * scale:
            problems.append(
                f"constraint '{name}' has a zero gradient at {where}, so its reaction has no "
                "direction and its multiplier is undetermined (e.g. y^2 = 0 at y = 0); write it "
                "with a nonzero gradient (y = 0 instead of y^2 = 0) or remove it")
            continue
        if keep and np.linalg.matrix_rank(G[keep + [j]], tol=1e-10 * scale) < len(keep) + 1:
            coef, *_ = np.linalg.lstsq(G[keep].T, g, rcond=None)
            parts = [(c, kernel.rows[rows[k]].name) for c, k in zip(coef, keep) if abs(c) > 1e-9]
            if len(parts) == 1:
                c, other = parts[0]
                how = (f"repeats constraint '{other}'" if abs(c - 1) < 1e-9 else
                       f"repeats constraint '{other}' (its gradient is {c:.6g} times that of "
                       f"'{other}')")
            else:
                how = ("is a combination of constraints "
                       + ", ".join(f"'{nm}'" for _, nm in parts)
                       + " (gradient = " + " + ".join(f"{c:.4g}*grad('{nm}')" for c, nm in parts)
                       + ")")
            problems.append(
                f"dependent (redundant) constraints: '{name}' {how} at {where}; the "
                "multipliers of dependent constraints are not unique: remove "
                f"'{name}' or make the constraints independent")
            continue
        keep.append(j)
    if problems:
        return SingularSystem(problems, src)
    Gk = G[keep]
    if Gk.shape[0]:
        _, sv, Vt = np.linalg.svd(Gk)
        null = Vt[Gk.shape[0]:].T
    else:
        null = np.eye(kernel.n)
    if null.shape[1] == 0:
        return None
    Mr = null.T @ M @ null
    Mr = (Mr + Mr.T) / 2
    w, v = np.linalg.eigh(Mr)
    tol = 1e-10 * max(1.0, float(np.max(np.abs(M))))
    for k in range(len(w)):
        if w[k] > tol or (w[k] < -tol and not definite):
            continue
        vec = null @ v[:, k]
        vec = vec / vec[np.argmax(np.abs(vec))]
        combo = _combination(vec, names)
        single = [c for c, a in zip(names, vec) if abs(a) > 1e-9]
        if abs(w[k]) <= tol:
            if len(single) == 1:
                what = (f"the kinetic energy does not depend on {single[0]}', so coordinate "
                        f"'{single[0]}' has no inertia and its acceleration is undetermined")
            else:
                what = (f"the kinetic energy does not depend on the velocity combination "
                        f"{combo}: that motion has no inertia and its acceleration is "
                        "undetermined")
            return SingularSystem(
                f"singular mass matrix at {where}: {what}; give it inertia (a mass or moment "
                "of inertia in [energy] kinetic or [[bodies]]), constrain it with a "
                "[[constraints]] block, or remove the coordinate", src)
        if definite and w[k] < -tol:
            return SingularSystem(
                f"the kinetic energy is not positive definite at {where}: along the velocity "
                f"combination {combo} it is negative (inertia {w[k]:.4g}); check the signs of "
                "[energy] kinetic (T = m/2*x'^2 >= 0) and the masses and moments of inertia of [[bodies]]", src)
    return None


def diagnose_initial_state(model: Model, definite: bool = False) -> ModelError | None:
    """:func:`diagnose_state` at the model's (completed) initial state; ``None`` if fine or if
    the initial state itself cannot be completed (that error is raised elsewhere)."""
    kernel = kernel_of(model)
    params = parameter_vector(model)
    try:
        q, qd, closed = complete_state(kernel, model.numeric_initial(), params, model.t0)
    except ModelError:
        return None
    return diagnose_state(model, model.t0, q, qd, closed, definite=definite, params=params)


def explain_mechanics_error(model: Model, exc: MechanicsError) -> Exception:
    """Replace a generic "no consistent mode" error by a named singularity when there is one.

    The mode selection treats a singular system as "no consistent choice"; a singular mass
    matrix or dependent constraints are bad input (exit code 2), not a paradox.
    """
    if isinstance(exc, PainleveParadox):
        return exc
    found = None
    names = list(model.coordinates)
    if exc.t is not None and all(c in exc.state and c + "'" in exc.state for c in names):
        q = np.array([exc.state[c] for c in names], dtype=float)
        qd = np.array([exc.state[c + "'"] for c in names], dtype=float)
        found = diagnose_state(model, exc.t, q, qd)
        if found is not None and diagnose_initial_state(model) is None:
            return SingularSystem(
                [p + "; the equations are regular at the initial state, so this is a singular "
                 "configuration of the coordinates or constraints (like r = 0 in polar "
                 "coordinates): choose another state or other coordinates" for p in found.problems],
                found.source)
    if found is None:
        found = diagnose_initial_state(model)
    return found if found is not None else exc
