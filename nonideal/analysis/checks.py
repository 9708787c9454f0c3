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

from ..numeric.consistency import complete_state
from ..modeling.model import Model
from ..modeling.symbols import to_sp
from ..modes.diagnosis import diagnose_state
from ..modes.solver import ModeSolver
from ..modes.switching import select_mode
from ..numeric.kernel import kernel_of, parameter_vector
from .statics import servo_equilibrium

__all__ = ["CheckReport", "check_model"]


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
    equilibrium: dict[str, Any] | None = None   # servo-constraints, initial state at rest

    def to_dict(self) -> dict[str, Any]:
        out = {
            "model": self.model, "source": self.source, "ok": True,
            "coordinates": self.coordinates, "parameters": self.parameters,
            "constraints": self.constraints, "contacts": self.contacts, "counts": self.counts,
            "determinacy": self.determinacy, "initial_state": self.initial,
            "initial_mode": self.initial_mode, "notes": self.notes,
        }
        if self.equilibrium is not None:
            out["servo_equilibrium"] = self.equilibrium
        return out

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
    reached = kernel.dyn.servo_reach
    for c in model.constraints:
        cons.append({"name": c.name, "kind": c.kind, "order": c.order, "reaction": c.reaction_kind,
                     "unilateral": c.unilateral, "expr": str(c.expr)})
        if c.name in reached:
            cons[-1]["control_order"] = reached[c.name].order
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
    several = [c for c in servo if c.controls is not None]
    if servo:
        r = len(servo)
        j = r + sum(len(c.controls) - 1 for c in several)
        determinacy = (f"{r} servo/quasi-ideal constraint(s), each with its own control direction "
                       "(r = j): determinate if the control directions can realize the program "
                       "(checked at t0 below)")
        if several:
            determinacy = (
                f"r = {r} program(s), j = {j} control direction(s): indeterminate (r < j; Béghin "
                "1922), resolved by a stated rule: "
                + "; ".join(f"'{c.name}': {len(c.controls)} directions, "
                            + ("least cost u^T W u with the given cost W" if c.cost is not None
                               else "least norm |u|")
                            for c in several))
    else:
        determinacy = "all constraints ideal: the motion is determinate"
    given = model.numeric_initial()
    q, qd, closed = complete_state(kernel, given, params, model.t0)
    problem = diagnose_state(model, model.t0, q, qd, closed, definite=True)
    if problem is not None:
        raise problem
    solver = ModeSolver(kernel, params)
    from ..modes.switching import validate_state

    validate_state(solver, model.t0, q, qd)  # finite terms, the contacts' friction data
    mode = select_mode(solver, model.t0, q, qd)
    solver.solve(model.t0, q, qd, mode)  # raises on singular M / dependent constraints
    initial = {c: float(v) for c, v in zip(model.coordinates, q)}
    initial.update({c + "'": float(v) for c, v in zip(model.coordinates, qd)})
    notes = []
    completed = [k for k in initial if k not in given]
    if completed:
        notes.append("completed from the constraints: " + ", ".join(completed))
    notes += servo_notes(kernel.dyn)
    equilibrium = None
    if any(c.reaction_kind == "servo" for c in model.constraints) and not any(qd):
        found = servo_equilibrium(model, q)
        notes.append(found.note())
        equilibrium = found.to_dict()
    return CheckReport(model.name, model.source, list(model.coordinates), model.parameter_values,
                       cons, contacts, counts, determinacy, initial, mode.label(), notes, equilibrium)


def servo_notes(dyn) -> list[str]:
    """One line per servo-constraint whose control acts through the dynamics: the order of the
    derivative in which the control appears and the condition of dynamics it keeps."""
    out = []
    for name, reach in dyn.servo_reach.items():
        if reach.order <= 2:
            continue
        cond = reach.row.velocity if reach.row.velocity is not None else reach.row.position
        out.append(
            f"servo-constraint '{name}': the control reaches the program only through the dynamics; "
            f"it appears in the time derivative of order {reach.order} of the coordinates (the "
            f"program differentiated {reach.differentiated} time(s) beyond its acceleration level; "
            "Yushkov 1999, ch. IV, the mixed problem); the motion keeps the condition of dynamics "
            f"{to_sp(cond)} = 0 (Manglieva & Beknazarov 2022, (3.3)), which fixes part of the "
            "initial state")
    return out
