"""Normalization of a :class:`~nonideal.modeling.model.Model`: every field parsed, checked and
converted to SymPy, every problem collected (one :class:`~nonideal.errors.ModelError` lists
them all).  Called once, by ``Model.__post_init__``."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np
import sympy as sp

from .bodies import Force, Particle, PlanarBody, RigidBody, Torque
from .contact_normalize import normalize_contacts
from ..errors import ExpressionError, did_you_mean
from .symbols import is_identifier

from .quantities import base_units, with_units
from .declarations import CONSTRAINT_TYPES, METHODS, ROOT_RULES, RESERVED_NAMES, Constraint, Parameter, SimulationSettings
from .normalize_kinematics import (norm_constraints, normalize_kinematics, normalize_quaternion_initial,
                                   resolve_body)
from .members import MemberExpansion
from .high_order import cost_problem, initial_multiplier, normalize_controls, third_order_problem
from .speeds import finish_speeds_and_outputs, normalize_speeds
from .values import derivative_order, identically_zero, parameter_values, resolve_parameters, to_expr, value_problems

__all__ = ["Normalizer"]


class Normalizer:
    """Fills a Model's fields with normalized SymPy objects; collects every problem."""

    def __init__(self, model, problems: list[str]):
        self.m, self.problems = model, problems
        self._names: dict[int, dict[str, sp.Expr]] = {}   # by derivative order, once known
        self.kinematics = None    # the frames and points, once normalized

    def set(self, name: str, value: Any) -> None:
        object.__setattr__(self.m, name, value)
    def smooth(self, e: sp.Expr | None, where: str) -> sp.Expr | None:
        """Expressions that the equations differentiate must be smooth (SymEngine cannot
        differentiate abs/sign/min/max, and the motion would not be defined at the kinks)."""
        if e is None:
            return None
        kinks = e.atoms(sp.Abs, sp.sign, sp.Min, sp.Max)
        if not kinks:  # (the usual case: no O(n_q) set of the model's names per expression)
            return e
        live = set(self.names(2).values()) - set(self.m.parameter_symbols)
        rough = sorted({str(f) for f in kinks if f.free_symbols & live})
        if rough:
            self.problems.append(
                f"{where}: {', '.join(rough)} is not differentiable, and this expression is "
                "differentiated to form the equations of motion; write it smoothly (abs(u) -> "
                "sqrt(u^2) away from 0; min/max of time -> a smooth ramp such as "
                "1 - exp(-(t/tau)^2))")
            return None
        return e

    def names(self, order: int) -> dict[str, sp.Expr]:
        """The model's names up to derivative *order* (parameters and coordinates are fixed
        by the time expressions are read)."""
        if order not in self._names:
            self._names[order] = self.m.names(order)
        return self._names[order]

    def expr(self, value: Any, where: str, order: int = 1) -> sp.Expr | None:
        try:
            return to_expr(value, self.names(order), where, self.m.coordinates, self.kinematics)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            self.unknown.extend(exc.unknown)
            return None

    def run(self) -> None:
        self.unknown: list[tuple[str, str]] = []
        members = MemberExpansion(self.m.members, self.problems) if self.m.members else None
        if members is not None:   # elastic members: their amplitudes are coordinates
            self.set("coordinates", members.coordinates(tuple(self.m.coordinates)))
            self.set("initial", members.initial(self.m.initial))
        self.names_and_parameters()
        if self.problems:
            return
        if members is not None:   # their material points are points of the model
            self.set("points", tuple(self.m.points) + tuple(members.points(self)))
        self.kinematics = normalize_kinematics(self)
        self.m.__dict__["_kinematics"] = self.kinematics
        normalize_speeds(self)       # the speed names may be used in every later expression
        self.bodies_and_loads()      # first: momentum(body) may appear in energies and forces
        self.energy_and_forces()
        if members is not None:   # expanded once: a replaced model keeps the energies, not the members
            T, V = members.energies(self)
            self.set("kinetic", self.m.kinetic + T)
            self.set("potential", self.m.potential + V)
            self.m.__dict__["_members"] = tuple(members.members)
            self.set("members", ())
        normalize_controls(self)
        self.constraints()
        self.contacts()
        self.initial_and_settings()
        self.summarize_unknown()
        finish_speeds_and_outputs(self)

    def summarize_unknown(self) -> None:
        """One line listing every undefined name and where it is used (when there are several)."""
        uses: dict[str, list[str]] = {}
        for name, where in self.unknown:
            if not name.endswith("'"):
                uses.setdefault(name, [])
                if where not in uses[name]:
                    uses[name].append(where)
        if not uses:
            return
        known = [*self.m.parameters, *self.m.coordinates, *RESERVED_NAMES]
        if all(did_you_mean(name, known) for name in uses):
            return   # typos: each message already suggests the name
        if len(self.unknown) == 1:
            name = next(iter(uses))
            self.problems.append(f"'{name}' is not a parameter, coordinate or known function: define "
                                 f"it in [parameters] as {name} = value (SI units), or correct the "
                                 "spelling; there are no default values")
            return
        listing = "; ".join(f"{name} (in {', '.join(w)})" for name, w in sorted(uses.items()))
        self.problems.append(
            f"missing parameters: {', '.join(sorted(uses))} -- used in: {listing}; define each "
            "in [parameters] as name = value (SI units), or correct the spelling; there are no "
            "default values"
        )

    # -- names
    def names_and_parameters(self) -> None:
        m = self.m
        coords = m.coordinates
        if isinstance(coords, str):
            coords = (coords,)
        self.set("coordinates", tuple(coords))
        if not m.coordinates:
            self.problems.append("[coordinates] q: at least one coordinate is required")
        seen: set[str] = set()
        for c in m.coordinates:
            if not isinstance(c, str) or not is_identifier(c):
                self.problems.append(
                    f"[coordinates] q: {c!r} is not a valid name (letters, digits, _; "
                    "not starting with a digit)"
                )
            elif c in RESERVED_NAMES:
                self.problems.append(f"[coordinates] q: '{c}' is reserved; choose another name")
            elif c in seen:
                self.problems.append(f"[coordinates] q: '{c}' appears twice")
            seen.add(c)
        params: dict[str, Parameter] = {}
        for name, value in dict(m.parameters).items():
            where = f"[parameters] {name}"
            if not isinstance(name, str) or not is_identifier(name):
                self.problems.append(f"{where}: not a valid name (letters, digits, _, not starting "
                                     "with a digit, not a Python keyword such as 'lambda' or 'if')")
                continue
            if name in RESERVED_NAMES:
                self.problems.append(f"{where}: '{name}' is reserved; choose another name")
                continue
            if name in seen:
                self.problems.append(f"{where}: '{name}' is also a coordinate")
                continue
            if isinstance(value, Parameter):
                p = value
            elif isinstance(value, Mapping):
                p = Parameter(name, value.get("value"), str(value.get("unit", "")),
                              str(value.get("description", "")))
            else:
                p = Parameter(name, value)
            params[name] = with_units(p, base_units(m.units), where, self.problems)
        values, problems = resolve_parameters({n: p.value for n, p in params.items()}, base_units(m.units))
        self.problems += problems
        self.set("parameters", {n: Parameter(n, values[n], p.unit, p.description,
                                             definition=p.value if isinstance(p.value, str) else p.definition,
                                             given=p.given)
                                for n, p in params.items() if n in values})

    # -- energy
    def energy_and_forces(self) -> None:
        m = self.m
        kin = self.expr(m.kinetic, "[energy] kinetic", 1)
        if kin is not None:
            velocities = set(m.qd)
            rough = sorted({str(f) for f in kin.atoms(sp.Abs, sp.sign, sp.Min, sp.Max)
                            if f.free_symbols & velocities})
            if rough:
                self.problems.append(
                    f"[energy] kinetic: {', '.join(rough)} is not differentiable in the "
                    "velocities; the kinetic energy must be smooth in the velocities (the "
                    "equations of motion use its second derivatives), e.g. m/2*x'^2 instead "
                    "of m/2*abs(x')^2")
                kin = None
        pot = self.smooth(self.expr(m.potential, "[energy] potential", 0), "[energy] potential")
        self.set("kinetic", kin if kin is not None else sp.Integer(0))
        self.set("potential", pot if pot is not None else sp.Integer(0))
        forces = m.forces
        if isinstance(forces, Mapping):
            bad = [k for k in forces if k not in m.coordinates]
            for k in bad:
                self.problems.append(
                    f"[forces] {k}: not a coordinate{did_you_mean(str(k), m.coordinates)}; "
                    "generalized forces are given per coordinate"
                )
            forces = [forces.get(c, 0) for c in m.coordinates]
        forces = list(forces)
        if len(forces) != m.n_q:
            self.problems.append(f"[forces]: expected {m.n_q} entries, got {len(forces)}")
            forces = [0] * m.n_q
        out = []
        for c, f in zip(m.coordinates, forces):
            e = self.expr(f, f"[forces] {c}", 1)
            out.append(e if e is not None else sp.Integer(0))
        self.set("forces", tuple(out))

    def vector(self, values: Any, where: str, sizes: tuple[int, ...], order: int = 0):
        values = list(values) if not isinstance(values, str) else [values]
        if len(values) not in sizes:
            self.problems.append(
                f"{where}: expected {' or '.join(map(str, sizes))} components, got {len(values)}"
            )
            return None
        out = [self.expr(v, f"{where}[{i}]", order) for i, v in enumerate(values)]
        if order == 0:  # geometry (positions, rotations) is differentiated: it must be smooth
            out = [self.smooth(e, f"{where}[{i}]") for i, e in enumerate(out)]
        return None if any(e is None for e in out) else tuple(out)

    def bodies_and_loads(self) -> None:
        m = self.m
        bodies, names = [], set()
        for b in m.bodies:
            where = f"body '{getattr(b, 'name', '?')}'"
            if b.name in names:
                self.problems.append(f"{where}: duplicate body name")
            names.add(b.name)
            b = resolve_body(self, self.kinematics, b, where)
            if b is None:
                continue
            mass = self.expr(b.mass, f"{where}: mass", 0)
            if isinstance(b, Particle):
                pos = self.vector(b.position, f"{where}: position", (2, 3))
                if mass is not None and pos is not None:
                    bodies.append(replace(b, mass=mass, position=pos))
            elif isinstance(b, PlanarBody):
                pos = self.vector(b.position, f"{where}: position", (2,))
                inertia = self.expr(b.inertia, f"{where}: inertia", 0)
                angle = self.smooth(self.expr(b.angle, f"{where}: angle", 0), f"{where}: angle")
                if None not in (mass, pos, inertia, angle):
                    bodies.append(PlanarBody(b.name, mass, inertia, pos, angle))
            elif isinstance(b, RigidBody):
                pos = self.vector(b.position, f"{where}: position", (3,))
                rows_i = [self.vector(r, f"{where}: inertia", (3,)) for r in b.inertia]
                rows_r = [self.vector(r, f"{where}: rotation", (3,)) for r in b.rotation]
                if len(rows_i) != 3 or len(rows_r) != 3:
                    self.problems.append(f"{where}: inertia and rotation must be 3x3")
                elif None not in (mass, pos, *rows_i, *rows_r):
                    bodies.append(replace(b, mass=mass, inertia=tuple(rows_i), position=pos,
                                          rotation=tuple(rows_r)))
            else:
                self.problems.append(f"{where}: not a Particle, PlanarBody or RigidBody")
        self.set("bodies", tuple(bodies))
        self.kinematics.bodies = {b.name: b for b in bodies}
        if m.gravity is not None:
            self.set("gravity", self.vector(m.gravity, "[gravity] vector", (2, 3)))
        loads = []
        body_names = {b.name: b for b in bodies}
        for ld in m.loads:
            where = f"load '{getattr(ld, 'name', '?')}'"
            if isinstance(ld, Force):
                pt = self.vector(ld.point, f"{where}: point", (2, 3))
                fv = self.vector(ld.force, f"{where}: force", (2, 3), order=1)
                if pt is not None and fv is not None:
                    if len(pt) != len(fv):
                        self.problems.append(f"{where}: point and force have different dimensions")
                    else:
                        loads.append(Force(ld.name, pt, fv))
            elif isinstance(ld, Torque):
                body = body_names.get(ld.body) if ld.body is not None else None
                if ld.body is not None and body is None:
                    self.problems.append(f"{where}: body '{ld.body}' is not a body of this model"
                                         + did_you_mean(ld.body, body_names))
                    continue
                if isinstance(body, PlanarBody):   # Q_j = torque * d(angle)/dq_j
                    if isinstance(ld.torque, (tuple, list)):
                        self.problems.append(f"{where}: body '{ld.body}' is planar: its torque is "
                                             "one expression (about the normal to the plane)")
                        continue
                    tq = self.expr(ld.torque, f"{where}: torque", 1)
                    if tq is not None:
                        loads.append(Torque(ld.name, tq, body.angle, None))
                elif isinstance(body, RigidBody):
                    tq = self.vector(ld.torque, f"{where}: torque", (3,), order=1)
                    if tq is not None:
                        loads.append(Torque(ld.name, tq, None, ld.body))
                elif body is not None:
                    self.problems.append(f"{where}: body '{ld.body}' is a particle: a torque acts on "
                                         "a planar or rigid body")
                else:
                    tq = self.expr(ld.torque, f"{where}: torque", 1)
                    ang = self.expr(ld.angle, f"{where}: angle", 0) if ld.angle is not None else None
                    if ld.angle is None:
                        self.problems.append(f"{where}: a planar torque needs 'angle' (or 'body')")
                    elif tq is not None and ang is not None:
                        loads.append(Torque(ld.name, tq, ang, None))
            else:
                self.problems.append(f"{where}: not a Force or Torque")
        self.set("loads", tuple(loads))

    # -- constraints
    def constraints(self) -> None:
        m = self.m
        out, names = [], set()
        for c in norm_constraints(self.kinematics, m.constraints, self.problems):
            where = f"constraint '{c.name}'"
            if not isinstance(c.name, str) or not is_identifier(c.name):
                self.problems.append(f"{where}: name must be an identifier (letters, digits, _)")
                continue
            if c.name in names:
                self.problems.append(f"{where}: duplicate constraint name")
            names.add(c.name)
            if isinstance(c.reaction, (list, tuple)) and c.reaction \
                    and all(isinstance(r, (list, tuple)) for r in c.reaction):   # reaction = [[..], [..]]
                c = replace(c, reaction=None, controls=tuple(map(tuple, c.reaction)))
            if c.kind not in ("auto",) + CONSTRAINT_TYPES:
                self.problems.append(
                    f"{where}: type '{c.kind}' unknown{did_you_mean(c.kind, CONSTRAINT_TYPES)}; "
                    "use holonomic, nonholonomic or servo"
                )
                continue
            expr = self.smooth(self.expr(c.expr, f"{where}: expr", 3), f"{where}: expr")
            if expr is None:
                continue
            order = derivative_order(expr, m.coordinates)
            kind = c.kind
            if kind == "holonomic" and order > 0:
                self.problems.append(
                    f"{where}: declared holonomic but contains velocities or accelerations; "
                    "declare it nonholonomic"
                )
                continue
            if kind == "nonholonomic" and order == 0:
                self.problems.append(
                    f"{where}: declared nonholonomic but contains no velocities; declare it holonomic"
                )
                continue
            shared = c.shared or kind == "servo" and c.reaction is None and c.controls is None
            if shared and not m.controls:
                self.problems.append(
                    f"{where}: a servo-constraint needs 'reaction' (the generalized direction "
                    "of the control force, one entry per coordinate) or the model's [[controls]]"
                )
                continue
            nonlinear = False
            if order == 3:
                bad, nonlinear = third_order_problem(m, c, expr, where)
                if bad:
                    self.problems.append(bad)
                    continue
            if order == 2:
                acc = [a for a in m.qdd if a in expr.free_symbols]
                nonlinear = any(sp.diff(expr, a, b) != 0 for a in acc for b in acc)
                if nonlinear and c.reaction is None:
                    self.problems.append(
                        f"{where}: a second-order constraint nonlinear in the accelerations needs "
                        "'reaction' (the generalized direction of the force that realizes it; "
                        "Yushkov 1999, ch. IV) and, optionally, root = \"largest\" | \"smallest\"")
                    continue
            if c.root is not None and c.root not in ROOT_RULES:
                self.problems.append(f"{where}: root must be one of {', '.join(ROOT_RULES)} "
                                     f"(got {c.root!r}){did_you_mean(str(c.root), ROOT_RULES)}")
                continue
            if c.root is not None and not nonlinear:
                self.problems.append(f"{where}: 'root' applies only to a constraint nonlinear in "
                                     "its highest derivative (this one has a single multiplier); remove it")
                continue
            if identically_zero(expr):
                shown = c.expr if isinstance(c.expr, str) else str(c.expr)
                self.problems.append(
                    f"{where}: expr {shown!r} is identically zero, so it constrains nothing; "
                    "correct the expression or remove the constraint")
                continue
            if c.unilateral and order > 0:
                self.problems.append(
                    f"{where}: only holonomic constraints can be unilateral (expr >= 0)"
                )
                continue
            reaction = None
            if c.reaction is not None:
                reaction = self.vector(c.reaction, f"{where}: reaction", (m.n_q,), order=1)
                if reaction is None:
                    continue
                if all(r == 0 for r in reaction):
                    self.problems.append(f"{where}: reaction direction is zero")
                    continue
            controls = cost = None
            several = c.controls
            if c.cost is not None and several is None:
                self.problems.append(f"{where}: 'cost' weighs several control directions: give "
                                     "reaction as a list of directions, reaction = [[...], [...]]")
                continue
            if several is not None:
                cols = [self.vector(col, f"{where}: reaction[{k}]", (m.n_q,), order=1)
                        for k, col in enumerate(several)]
                if any(col is None for col in cols):
                    continue
                if c.reaction is not None or c.transform is not None or nonlinear:
                    self.problems.append(f"{where}: several control directions (reaction = [[..], ..]) "
                                         "exclude a single reaction, a transform and a root rule")
                    continue
                controls = tuple(tuple(col) for col in cols)
                j = len(controls)
                if c.cost is not None:
                    square = isinstance(c.cost, (list, tuple)) and len(c.cost) == j \
                        and all(isinstance(r, (list, tuple)) and len(r) == j for r in c.cost)
                    rows_ = [self.vector(r, f"{where}: cost", (j,), order=0) for r in c.cost] if square else []
                    if not square or any(r is None for r in rows_):
                        self.problems.append(f"{where}: cost must be {j}x{j} (one row and column "
                                             "per control direction)")
                        continue
                    cost = tuple(tuple(r) for r in rows_)
                    bad = cost_problem(cost, self.m.parameters)
                    if bad:
                        self.problems.append(f"{where}: cost {bad}")
                        continue
            transform = None
            if c.transform is not None:
                rows = [self.vector(r, f"{where}: transform", (m.n_q,), order=1) for r in c.transform]
                if len(rows) != m.n_q:
                    self.problems.append(f"{where}: transform must be {m.n_q}x{m.n_q}")
                    continue
                if any(r is None for r in rows):
                    continue
                transform = tuple(rows)
                if c.reaction is not None:
                    self.problems.append(f"{where}: give either 'reaction' (servo) or 'transform' (quasi-ideal), not both")
                    continue
            losses = self.vector(c.losses, f"{where}: losses", (m.n_q,)) if c.losses is not None else None
            others = sorted({str(s) for e in losses or () for s in e.free_symbols} - set(m.parameters))
            if c.losses is not None and (losses is None or others):
                self.problems += [f"{where}: losses must be numbers or expressions in the parameters "
                                  f"(got {', '.join(others)})"] if others else []
                continue
            kind = "holonomic" if order == 0 else "nonholonomic"
            restitution = float(c.restitution)
            if not 0.0 <= restitution <= 1.0:
                self.problems.append(f"{where}: restitution must lie in [0, 1] (got {restitution})")
                continue
            out.append(Constraint(c.name, expr, kind, bool(c.unilateral), reaction, transform,
                                  restitution=restitution, order=order, losses=losses,
                                  root=(c.root or "largest") if nonlinear else None,
                                  controls=controls, cost=cost, initial=c.initial,
                                  shared=shared and c.transform is None and order < 3))
        self.set("constraints", tuple(out))

    def contacts(self) -> None:
        normalize_contacts(self)

    # -- initial state and settings
    def initial_and_settings(self) -> None:
        m = self.m
        allowed = set(m.coordinates) | {c + "'" for c in m.coordinates} | set(m.speeds)
        names = {n: sp.Symbol(n) for n in m.parameters}
        values = parameter_values(m.parameters)
        out, given = {}, dict(m.initial)
        self.set("constraints", tuple(replace(c, initial=initial_multiplier(
            m, c, given.pop(f"lambda_{c.name}", None), names, self.problems)) if c.order == 3 else c
            for c in m.constraints))
        for key, value in given.items():
            where = f"[initial] {key}"
            if key not in allowed:
                self.problems.append(
                    f"{where}: not a coordinate or velocity{' or speed' * bool(m.speeds)}{did_you_mean(str(key), allowed)}"
                )
                continue
            try:
                e = to_expr(value, names, where, ())
            except ExpressionError as exc:
                self.problems.extend(exc.problems)
                continue
            if e.free_symbols - set(names.values()):
                self.problems.append(f"{where}: initial values may use parameters only")
                continue
            if bad := value_problems(e, where, values):  # a finite real number, in floating point
                self.problems.extend(bad)
                continue
            out[key] = e
        out, problems = normalize_quaternion_initial(self.kinematics, out, values)
        self.set("initial", out)
        self.problems += problems
        if m.independent is not None:
            ind = tuple(m.independent)
            for name in ind:
                if name not in m.coordinates:
                    self.problems.append(
                        f"[forms] independent: '{name}' is not a coordinate"
                        + did_you_mean(str(name), m.coordinates)
                    )
            self.set("independent", ind)
        sim = m.simulation
        if isinstance(sim, Mapping):
            try:
                sim = SimulationSettings(**sim)
            except TypeError as exc:
                self.problems.append(f"[simulation]: {exc}")
                sim = SimulationSettings()
        if sim.method not in METHODS:
            self.problems.append(
                f"[simulation] method: '{sim.method}' unknown{did_you_mean(sim.method, METHODS)}; "
                f"choose one of {', '.join(METHODS)}"
            )
        for key in ("rtol", "atol"):
            v = getattr(sim, key)
            if not (isinstance(v, (int, float)) and 0 < v < 1):
                self.problems.append(f"[simulation] {key}: must be a number in (0, 1) (got {v!r})")
        if sim.t_end is not None and not (isinstance(sim.t_end, (int, float)) and sim.t_end > m.t0):
            self.problems.append(f"[simulation] t_end: must be a number > t0 = {m.t0} (got {sim.t_end!r})")
        self.set("simulation", sim)
