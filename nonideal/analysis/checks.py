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
from ..equations.high_order import extended
from ..modeling.model import Model
from ..modeling.symbols import to_sp
from ..modes.diagnosis import diagnose_state
from ..modes.solver import ModeSolver
from ..modes.switching import select_mode
from ..modeling.normalize_kinematics import describe as describe_kinematics
from ..numeric.kernel import kernel_of, parameter_vector
from .contact.statics import servo_equilibrium

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
    kinematics: list[str] = field(default_factory=list)   # one line per declared frame and point

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
        if self.kinematics:
            out["frames_and_points"] = self.kinematics
        return out

    def as_text(self) -> str:
        c = self.counts
        lines = [f"{self.model}  ({self.source})",
                 f"  coordinates ({c['n_q']}): {', '.join(self.coordinates)}",
                 *[f"  {line}" for line in self.kinematics],
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
                         f"friction {ct['friction']}" + friction_text(ct))
        lines.append("  initial state: " + ", ".join(f"{k} = {v:.10g}" for k, v in self.initial.items()))
        lines.append(f"  initial mode: {self.initial_mode}")
        lines += [f"  note: {n}" for n in self.notes]
        lines.append("  ok")
        return "\n".join(lines)


def check_model(model: Model) -> CheckReport:
    """Validate *model* beyond parsing (raises the same errors a simulation would)."""
    model = extended(model)  # third-order constraints: the forces are part of the state
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
        shared = [c.name for c in servo if c.shared]
        if shared:
            rs, js = len(shared), len(model.controls)
            own = len(servo) - rs
            determinacy = (determinacy + "; " if own else "") + (
                f"the program(s) {', '.join(repr(x) for x in shared)} share the controls "
                            f"{', '.join(u.name for u in model.controls)} (r = {rs}, j = {js}: "
                            + ("determinate" if rs == js else "indeterminate, resolved by the least "
                               "weighted norm sum w_k u_k^2; Béghin 1922") + ")")
    else:
        determinacy = "all constraints ideal: the motion is determinate"
    given = model.numeric_initial()
    q, qd, closed = complete_state(kernel, given, params, model.t0)
    problem = diagnose_state(model, model.t0, q, qd, closed, definite=True)
    if problem is not None:
        raise problem
    solver = ModeSolver(kernel, params)
    from ..modes.validation import validate_state

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
    friction = _coulomb_contacts(solver, model.t0, q, qd, mode)
    if friction:
        for entry in contacts:
            entry.update(friction.get(entry["name"], {}))
        determinacy = _with_friction(determinacy, friction)
    return CheckReport(model.name, model.source, list(model.coordinates), model.parameter_values,
                       cons, contacts, counts, determinacy, initial, mode.label(), notes, equilibrium,
                       describe_kinematics(model.kinematics))


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


# ------------------------------------------------------------------ Coulomb contacts


def _coulomb_contacts(solver, t, q, qd, mode) -> dict[str, dict[str, Any]]:
    """Per Coulomb contact with friction: its mu at the parameters, and the critical mu of
    Painleve's paradox at the initial state -- the friction coefficient at which the effective
    normal compliance ``b = dg''/dN`` of the contact sliding (the other contacts as in the
    initial mode) vanishes; above it sliding there has no consistent or no unique continuation.
    For one slip component both directions are tried; for two, the direction of the slip (or,
    at rest, none is tried)."""
    import numpy as np

    from ..modes.switching import critical_friction
    from ..modes.types import SLIDE, ContactState

    out: dict[str, dict[str, Any]] = {}
    if not mode.contacts:
        return out
    cout = solver.ck(solver.input(t, q, qd))
    for c, (name, cs) in enumerate(mode.contacts):
        data = solver.ck.data[c]
        if not data.law.exact or c in solver.frictionless:
            continue
        if c in solver.rolling:  # never slides: Painleve's analysis does not apply
            out[name] = {"mu": "inf", "state_at_t0": cs.label(), "critical_mu": None,
                         "ideal_rolling": True}
            continue
        if cs.state == "separated":
            out[name] = {"mu": float(cout["mu"][c]), "state_at_t0": cs.label(), "critical_mu": None}
            continue
        U = np.asarray(solver.ck.slip(cout, c), dtype=float)
        if len(U) == 1:
            directions = [(1.0,), (-1.0,)]
        elif np.linalg.norm(U) > 0:
            directions = [tuple(U / np.linalg.norm(U))]
        else:
            directions = []
        critical = []
        for d in directions:
            probe = mode.with_contact(name, ContactState(SLIDE, d, cs.sigma))
            try:
                mu_c = critical_friction(solver, t, q, qd, probe, name)
            except Exception:  # noqa: BLE001 - a diagnosis must not mask the check
                mu_c = None
            if mu_c is not None:
                critical.append((mu_c, d))
        entry: dict[str, Any] = {"mu": float(cout["mu"][c]), "state_at_t0": cs.label()}
        if cs.state == "separated":
            entry["critical_mu"] = None
        elif critical:
            mu_c, d = min(critical)
            entry["critical_mu"] = float(mu_c)
            entry["critical_direction"] = (("+" if d[0] > 0 else "-") if len(d) == 1
                                           else [float(v) for v in d])
        else:
            entry["critical_mu"] = None
        out[name] = entry
    return out


def _with_friction(determinacy: str, friction: dict[str, dict[str, Any]]) -> str:
    """The determinacy line, with what the Coulomb contacts make of it (the numbers are on
    the contacts' lines)."""
    rolling = [n for n, e in friction.items() if e.get("ideal_rolling")]
    if rolling:
        determinacy += (f"; contact(s) {', '.join(rolling)} roll ideally (mu = inf): an ideal "
                        "nonholonomic constraint while the gap is closed, released with it -- "
                        "friction unbounded, no sliding, no Painleve paradox")
        friction = {n: e for n, e in friction.items() if not e.get("ideal_rolling")}
        if not friction:
            return determinacy
    head = determinacy.replace("all constraints ideal: the motion is determinate",
                               "all constraints ideal")
    above = [n for n, e in friction.items() if e.get("critical_mu") is not None and e["mu"] >= e["critical_mu"]]
    if above:
        verdict = f"mu is at or above the critical value at contact(s) {', '.join(above)}: Painleve's paradox"
    elif any(e.get("critical_mu") is not None for e in friction.values()):
        verdict = "at t0 every mu is below its critical value (see the contacts)"
    else:
        verdict = "at t0 no value of mu does (see the contacts)"
    return (f"{head}; with Coulomb friction the motion is determinate only while each sliding "
            "contact's effective normal compliance b = dg''/dN stays positive, which a large mu "
            f"can break (Painleve 1895): {verdict}")


def friction_text(entry: dict[str, Any]) -> str:
    """What ``check`` says of one Coulomb contact's friction at t0."""
    if "mu" not in entry:
        return ""
    if entry.get("ideal_rolling"):
        return ("; ideal rolling: friction unbounded (mu = inf), so no critical mu (Painleve's "
                "analysis skipped: the contact never slides; it rolls while the gap is closed and "
                "lifts off when N reaches 0)")
    if entry.get("state_at_t0") == "separated":
        return f"; mu = {entry['mu']:.6g}, separated at t0"
    mu_c = entry.get("critical_mu")
    if mu_c is None:
        return (f"; mu = {entry['mu']:.6g}: no critical value at t0 (sliding there stays "
                "determinate whatever mu)")
    where = f"sliding {entry['critical_direction']}"
    if entry["mu"] >= mu_c:
        return (f"; mu = {entry['mu']:.6g} is at or above the critical mu = {mu_c:.6g} at t0 "
                f"({where}): Painleve's paradox")
    return f"; mu = {entry['mu']:.6g}, critical mu = {mu_c:.6g} at t0 ({where}): Painleve's paradox above it"
