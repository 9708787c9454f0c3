"""The motion at one state: accelerations, multipliers, reactions split into constraint and
friction parts (Painleve's split, Manglieva & Beknazarov 2022, section 1.2).

For the constraint Jacobian ``G`` of the active constraints (as ideal constraints) and the
possible velocities ``V`` (``G V = 0``), every generalized reaction decomposes uniquely as

    R = G^T lambda + M V mu    (constraint force + friction force),

because ``V^T M V`` is positive definite.  Hence ``lambda = (G M^-1 G^T)^-1 G M^-1 R`` and
the friction part is ``P R`` with ``P = I - G^T (G M^-1 G^T)^-1 G M^-1``.  The constraint part
does not depend on friction: ``lambda = -(G M^-1 G^T)^-1 (gamma + G M^-1 F)``.  Per row ``j``
the constraint part is ``G_j^T lambda_j`` and the friction part the rest of its physical
reaction, ``R_j - G_j^T lambda_j``; their sum over the rows is ``P R``.
"""

from __future__ import annotations

from ..numeric.display import number, numbers

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..numeric.consistency import complete_state
from ..errors import ModelError, did_you_mean
from ..equations.formalisms import FORMS
from ..modeling.arguments import real_number, require_form, require_mapping, require_model
from ..modeling.expressions import float_value, parse_expression
from ..equations.high_order import extended
from ..modeling.model import Model
from ..modes.indeterminate import split_report
from ..modes.solver import ModeSolver
from ..numeric.kernel import kernel_of, parameter_vector

__all__ = ["Evaluation", "evaluate", "parse_state", "painleve_split"]


@dataclass(frozen=True)
class Evaluation:
    """Everything about the motion at one state (see :func:`evaluate`)."""

    model: str
    form: str
    t: float
    coordinates: tuple[str, ...]
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    mode: str
    multipliers: dict[str, float]
    reactions: dict[str, dict[str, list[float]]]
    contacts: dict[str, dict[str, Any]]
    split_available: bool
    indeterminate: dict[str, Any] = field(default_factory=dict)
    speeds: dict[str, float] = field(default_factory=dict)
    speeds_dot: dict[str, float] = field(default_factory=dict)
    outputs: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The JSON structure of ``evaluate --json`` (keys fixed; more may be added)."""
        c = self.coordinates
        return {
            "model": self.model, "form": self.form, "t": self.t,
            "q": dict(zip(c, map(float, self.q))),
            "qdot": dict(zip(c, map(float, self.qd))),
            "qddot": dict(zip(c, map(float, self.qdd))),
            "multipliers": dict(self.multipliers),
            "reactions": self.reactions,
            "reaction_total": self.reaction_total(),
            "contacts": self.contacts,
            "mode": self.mode,
            "indeterminate": self.indeterminate,
            "speeds": dict(self.speeds),
            "speeds_dot": dict(self.speeds_dot),
            "outputs": dict(self.outputs),
        }

    def reaction_total(self) -> dict[str, list[float]]:
        """The total generalized reaction ``M q'' - F`` and its Painleve split, summed over all
        constraints and contacts: ``G^T lambda`` and Manglieva & Beknazarov's friction force ``M V mu``
        (Manglieva & Beknazarov 2022, (1.14)-(1.17))."""
        n = len(self.coordinates)
        out = {}
        for key in ("generalized", "constraint_part", "friction_part"):
            total = np.zeros(n)
            for r in self.reactions.values():
                if key in r and len(r[key]) == n:
                    total += np.asarray(r[key], dtype=float)
            out[key] = [float(v) for v in total]
        return out

    def _repr_latex_(self) -> str:
        """Jupyter: the accelerations and multipliers at the state, typeset."""
        from ..modeling.symbols import latex_names
        import sympy as sp

        accelerations = [sp.Symbol(c + "''") for c in self.coordinates]
        multipliers = [sp.Symbol("lambda_" + k) for k in self.multipliers]
        names = latex_names(accelerations + multipliers)
        sa = max(float(np.max(np.abs(self.qdd))) if len(self.qdd) else 1.0, 1.0)
        rows = [f"{names[s]} &= {_tex(number(a, sa))}" for s, a in zip(accelerations, self.qdd)]
        rows += [f"{names[s]} &= {_tex(number(v))}" for s, v in zip(multipliers, self.multipliers.values())
                 if np.ndim(v) == 0]
        return "$$\\begin{aligned}\n" + " \\\\\n".join(rows) + "\n\\end{aligned}$$"

    def _repr_html_(self) -> str:
        """Jupyter: the state and its accelerations, the multipliers and the contacts."""
        from html import escape

        from ..numeric.display import html_table

        sq, sv, sa = (max(float(np.max(np.abs(a))), 1.0) if len(a) else 1.0
                      for a in (self.q, self.qd, self.qdd))
        parts = [f"<div><b>{escape(self.model)}</b> at t = {self.t:g} (form {escape(self.form)}, "
                 f"mode {escape(self.mode)})",
                 html_table(["coordinate", "q", "q'", "q''"],
                            [[c, number(q, sq), number(v, sv), number(a, sa)]
                             for c, q, v, a in zip(self.coordinates, self.q, self.qd, self.qdd)])]
        rows = [[k, number(v)] for k, v in self.multipliers.items() if k not in self.contacts]
        if rows:
            parts.append(html_table(["constraint", "multiplier"], rows))
        if self.contacts:
            parts.append(html_table(
                ["contact", "mode", "N", "friction", "slip", "gap"],
                [[k, c.get("mode"), number(c.get("normal", 0.0)), _fmt(c.get("friction", ())),
                  _fmt(c.get("slip", ())), number(c.get("gap", 0.0))] for k, c in self.contacts.items()]))
        if self.indeterminate:
            parts.append("statically indeterminate: " + escape(self.indeterminate.get("rule", "")))
        return "".join(parts) + "</div>"

    def as_text(self) -> str:
        lines = [f"{self.model} at t = {self.t:g}  (form: {self.form}, mode: {self.mode})"]
        width = max(len(n) for n in self.coordinates) + 2
        sq, sv, sa = (max(np.max(np.abs(a)), 1.0) for a in (self.q, self.qd, self.qdd))
        for i, n in enumerate(self.coordinates):
            lines.append(f"  {n:<{width}} = {number(self.q[i], sq, 10, True)}   "
                         f"{n}' = {number(self.qd[i], sv, 10, True)}   "
                         f"{n}'' = {number(self.qdd[i], sa, 10, True)}")
        if self.speeds:
            width_u = max(len(n) for n in self.speeds) + 2
            for n, v in self.speeds.items():
                lines.append(f"  {n:<{width_u}} = {number(v, None, 10, True)}   "
                             f"{n}' = {number(self.speeds_dot[n], None, 10, True)}   (speed)")
        for n, v in self.outputs.items():
            lines.append(f"  {n} = {number(v, None, 10, True)}   (output)")
        for name, value in self.multipliers.items():
            r = self.reactions[name]
            if name in self.contacts:
                c = self.contacts[name]
                lines.append(f"  contact {name}: {c['mode']}, N = {number(c['normal'], None, 10, True)}, "
                             f"F = {_fmt(c['friction'])}, slip = {_fmt(c['slip'])}, gap = {c['gap']:.3g}")
                if c.get("ideal_rolling") and "friction_needed" in c:
                    lines.append(f"    rolling ideally (mu = inf): friction {c['friction_needed']:.8g}, "
                                 "unbounded (an ideal nonholonomic constraint while the gap is "
                                 "closed; it ends only when N reaches 0)")
                elif "margin" in c:
                    lines.append(f"    sticking: friction needed {c['friction_needed']:.8g} of "
                                 f"mu_s N = {c['friction_available']:.8g} (margin {c['margin']:.6g})")
            elif "det_A" in r:
                lines.append(f"  mu_{name} = {number(value, None, 10, True)}   (R = adj(A) grad f mu; "
                             f"lambda = det(A) mu = {number(r['lambda'], None, 10, True)}, "
                             f"det A = {number(r['det_A'], None, 10, True)})")
            else:
                lines.append(f"  lambda_{name} = {number(value, None, 10, True)}")
            lines.append(f"    reaction (generalized) = {_fmt(r['generalized'])}")
            if self.split_available and "control_part" in r:
                lines.append(f"    ideal part             = {_fmt(r['ideal_part'])}")
                lines.append(f"    control part           = {_fmt(r['control_part'])}  "
                             f"({r['kind']}: the part that does work)")
            elif self.split_available:
                lines.append(f"    constraint part        = {_fmt(r['constraint_part'])}")
                lines.append(f"    friction part          = {_fmt(r['friction_part'])}")
        if self.split_available and len(self.reactions) > 1 and any(
                any(v != 0 for v in r.get("friction_part", ())) for r in self.reactions.values()):
            tot = self.reaction_total()
            lines.append("  all reactions (the friction parts add up to Manglieva & Beknazarov's friction force "
                         "M V mu)")
            lines.append(f"    total (generalized)    = {_fmt(tot['generalized'])}")
            lines.append(f"    constraint part        = {_fmt(tot['constraint_part'])}")
            lines.append(f"    friction part          = {_fmt(tot['friction_part'])}")
        if self.indeterminate:
            lines.append("  statically indeterminate: the split of these forces is NOT unique (any "
                         "split in the ranges below that keeps every contact admissible gives the "
                         "same motion); shown: " + self.indeterminate["rule"])
            for label, (lo, hi, shown) in self.indeterminate["ranges"].items():
                lines.append(f"    {label}: shown {number(shown, None, 8)}, admissible from "
                             f"{number(lo, None, 8)} to {number(hi, None, 8)}")
        return "\n".join(lines)


def _fmt(values) -> str:
    return numbers(values)


def _tex(text: str) -> str:
    """A number as printed (``1.5e-08``) in LaTeX (``1.5 \\cdot 10^{-8}``)."""
    if "e" in text:
        mant, exp = text.split("e")
        return rf"{mant} \cdot 10^{{{int(exp)}}}"
    return text


def parse_state(model: Model, text: str | None) -> dict[str, float]:
    """Parse ``"x=0.1, theta=0.3, x'=1"`` (values may be expressions in the parameters)."""
    if not text:
        return {}
    out = {}
    allowed = set(model.coordinates) | {c + "'" for c in model.coordinates} | set(model.speeds)
    import sympy as sp
    names = {n: sp.Symbol(n) for n in model.parameters}
    values = {sp.Symbol(n): p.value for n, p in model.parameters.items()}
    for part in text.split(","):
        if not part.strip():
            continue
        if "=" not in part:
            raise ModelError(f"--at: '{part.strip()}' is not of the form name=value")
        key, _, val = part.partition("=")
        key = key.strip()
        if key not in allowed:
            raise ModelError(f"--at: '{key}' is not a coordinate or velocity{did_you_mean(key, allowed)}")
        expr = parse_expression(val.strip(), names, f"--at {key}")
        out[key] = float_value(expr, f"--at {key}", {s.name: float(v) for s, v in values.items()})
    return out


def _complete_at(kernel, model: Model, at, params, t):
    """The state at ``--at``: its values over the model's initial ones.  If that mix violates a
    constraint (the user moved a coordinate the initial values of others depended on), the
    initial coordinates not given at ``--at`` become start values for the completion, and the
    initial velocities not given are kept where they can be -- as many as possible, the
    dependent ones completed from the constraints."""
    import itertools

    from ..errors import InconsistentInitialConditions

    init = dict(model.numeric_initial())
    given = {**init, **(at or {})}
    try:
        q, qd, _ = complete_state(kernel, given, params, t)
        return q, qd
    except InconsistentInitialConditions as exc:
        if not at:
            raise
        first_error = exc
    coords = set(model.coordinates)

    def velocity_like(k):   # a velocity or a speed
        return k.endswith("'") or k in model.speeds
    velocities = [k for k in init if velocity_like(k) and k not in at]
    for drop_coords in (False, True):
        base, guess = dict(at), {}
        for k, v in init.items():
            if k in at or velocity_like(k):
                continue
            if drop_coords and any(c in coords for c in at):
                guess[k] = v
            else:
                base[k] = v
        for k in range(len(velocities) + 1):
            for dropped in itertools.combinations(velocities, k):
                trial = {**base, **{v: init[v] for v in velocities if v not in dropped}}
                try:
                    q, qd, _ = complete_state(kernel, trial, params, t, guess=guess)
                    return q, qd
                except InconsistentInitialConditions:
                    continue
    problems = [p.replace("[initial]:", "--at (other values from [initial]):", 1)
                for p in first_error.problems]
    raise InconsistentInitialConditions(problems, first_error.source) from None


def painleve_split(M: np.ndarray, G: np.ndarray, R: np.ndarray):
    """Split a generalized reaction ``R`` into ``G^T lambda`` and the friction part ``P R``.

    Returns ``(lambda, friction_part)`` or ``None`` when ``M`` is singular or the rows ``G``
    are dependent (statically indeterminate: the constraint parts of the rows are not unique).
    """
    try:
        Minv_GT = np.linalg.solve(M, G.T)
        Minv_R = np.linalg.solve(M, R)
        lam = np.linalg.solve(G @ Minv_GT, G @ Minv_R)
    except np.linalg.LinAlgError:
        return None
    return lam, R - G.T @ lam


def evaluate(model: Model, at: Mapping[str, float] | None = None, t: float | None = None,
             form: str = "lagrange1", parameters: Mapping[str, float] | None = None,
             independent=None) -> Evaluation:
    """Accelerations, multipliers, reactions and contact forces at a state.

    Parameters
    ----------
    model : Model
    at : mapping, optional
        Values overriding the model's initial state (missing dependent values are completed
        from the constraints).
    t : float, optional
        Time (default: the model's ``t0``).
    form : str
        Formalism evaluating the accelerations (the result must not depend on it).

    Returns
    -------
    Evaluation
        ``reactions[name]`` holds, for every constraint and contact, its physical generalized
        reaction ``R_j`` (``kind``: ``"ideal"``, ``"servo"``, ``"quasi-ideal"`` or
        ``"contact"``), the constraint part ``G_j^T lambda_j`` of Painleve's split (which does
        not depend on friction) and the friction part ``R_j - G_j^T lambda_j``, what friction
        adds to that row's reaction: at the contact its friction force and the change of its
        normal force, at an ideal constraint the change of its reaction that friction elsewhere
        causes (Manglieva & Beknazarov 2022, (1.14)-(1.17); zero in a frictionless system).  Each row's parts add
        up to its reaction; summed over all rows the friction parts are ``M V mu``, the
        friction force of the paper, which accelerates along possible velocities only (a single
        row's friction part need not).  For a servo or quasi-ideal constraint the two parts are
        also given as ``ideal_part`` and ``control_part``: the rest of its reaction is the
        control, which does work (Briskin et al. 2021); ``friction_part`` keeps the same
        numbers under the name every row has.  Where the
        reactions are statically indeterminate (dependent rows: a ladder sticking at a rough
        wall and floor), the multipliers and contact forces are the admissible distribution
        chosen by ``[simulation] split``: by default the one with the widest margins, the
        least-norm one among several; with ``split = "least-norm"`` the one of least
        (compliance-weighted) norm (:mod:`nonideal.modes.indeterminate`); ``indeterminate``
        then holds the rule and the admissible range of each of these forces, and a sticking
        contact's ``margin`` is its margin in the distribution shown.
    """
    from ..modes.switching import select_mode
    from ..modes.validation import validate_state

    require_model(model, "evaluate")
    model = extended(model)  # third-order constraints: the forces are part of the state
    require_mapping(at, "evaluate", "at", "{'x': 0.1, \"x'\": 1.0}")
    require_mapping(parameters, "evaluate", "parameters", "{'m': 2.0}")
    require_form(form, "evaluate", [*FORMS, "gauss"])
    t = real_number(t, "evaluate", "t")
    allowed = set(model.coordinates) | {c + "'" for c in model.coordinates} | set(model.speeds)
    bad = [k for k in (at or {}) if k not in allowed]
    if bad:
        raise ModelError([f"at: '{k}' is not a coordinate or velocity{' or speed' if model.speeds else ''}"
                          f"{did_you_mean(k, allowed)}"
                          for k in bad], None if model.source == "<api>" else model.source)
    kernel = kernel_of(model)
    params = parameter_vector(model, parameters)
    t = model.t0 if t is None else float(t)
    q, qd = _complete_at(kernel, model, at, params, t)
    solver = ModeSolver(kernel, params, form, independent)
    validate_state(solver, t, q, qd)
    mode = select_mode(solver, t, q, qd)
    sol = solver.solve(t, q, qd, mode).reported
    return _report(model, form, t, q, qd, mode, sol, solver)


def _transform_det(model, name, t, q, qd, params) -> float:
    """``det A`` of the quasi-ideal constraint *name*'s transform at the state."""
    import sympy as sp

    c = next(c for c in model.constraints if c.name == name)
    values = {sp.Symbol(k): float(v) for k, v in zip(model.parameter_values, params)}
    values[sp.Symbol("t")] = float(t)
    values.update(zip(model.q, (float(v) for v in q)))
    values.update(zip(model.qd, (float(v) for v in qd)))
    A = sp.Matrix([[sp.sympify(x) for x in row] for row in c.transform])
    return float(A.det().xreplace(values))


def _report(model, form, t, q, qd, mode, sol, solver) -> Evaluation:
    kernel = solver.kernel
    n = kernel.n
    rows = kernel.rows
    # the frictionless constraint set: constraint rows and the normal rows of touching contacts
    normal_rows = [j for j, r in enumerate(sol.layout) if r.kind != "tangent"]
    dense = lambda A: A.toarray() if hasattr(A, "toarray") else A   # noqa: E731 - sparse for many coordinates
    B_all, G_all = dense(sol.B), dense(sol.G)
    G_ideal = dense(sol.Gm)[normal_rows]
    R_total = sol.M @ sol.qdd - sol.F
    split = painleve_split(dense(sol.M), G_ideal, R_total) if normal_rows else None
    lam_split = {}
    if split is not None:
        for k, j in enumerate(normal_rows):
            lam_split[sol.layout[j].name] = split[0][k]
    multipliers, reactions, contacts = {}, {}, {}
    for r_i, row in enumerate(rows):
        name = row.name
        active = r_i in sol.rows
        lam = sol.multiplier(r_i) if active else 0.0
        multipliers[name] = float(lam)
        generalized = B_all[:, r_i] * lam if active else np.zeros(n)
        if split is not None and active:
            constraint_part = G_all[r_i] * lam_split[name]
            friction_part = generalized - constraint_part
        else:
            constraint_part, friction_part = generalized, np.zeros(n)
        reactions[name] = {
            "generalized": [float(v) for v in generalized],
            "constraint_part": [float(v) for v in constraint_part],
            "friction_part": [float(v) for v in friction_part],
            "active": bool(active),
            "kind": row.reaction_kind,
        }
        if row.reaction_kind != "ideal":
            # a servo or quasi-ideal reaction: its part that does work on the possible
            # displacements is the control, not friction (Briskin et al. 2021, (1.1)-(2.3))
            reactions[name]["ideal_part"] = reactions[name]["constraint_part"]
            reactions[name]["control_part"] = reactions[name]["friction_part"]
        if row.reaction_kind == "quasi-ideal":
            # R = adj(A) grad f mu: the paper's multiplier is lambda = det(A) mu
            det = _transform_det(model, name, t, q, qd, solver.params)
            reactions[name]["det_A"] = det
            reactions[name]["lambda"] = det * float(lam)
    ck = solver.ck
    for c, (name, cs) in enumerate(mode.contacts):
        cf = sol.contacts[name]
        o, d = ck.offsets[c], ck.dims[c]
        x = solver.input(t, q, qd)
        cout = ck(x)
        Gn, W = cout["Gn"][c].copy(), cout["W"][o:o + d].copy()
        # a friction torque: only the torque (its contact's normal force is its contact's)
        normal_force = Gn * cf.N if c not in ck.torques else np.zeros(n)
        friction_force = cf.F @ W
        generalized = normal_force + friction_force
        if split is not None and name in lam_split:
            constraint_part = Gn * lam_split[name]
            friction_part = generalized - constraint_part
        else:
            constraint_part, friction_part = normal_force, friction_force
        reactions[name] = {
            "generalized": [float(v) for v in generalized],
            "constraint_part": [float(v) for v in constraint_part],
            "friction_part": [float(v) for v in friction_part],
            "active": cs.state != "separated",
            "kind": "contact",
        }
        multipliers[name] = float(cf.N)
        info = cf.to_dict()
        info["mu"] = cf.mu
        info["mu_static"] = cf.mu_s
        info["slip_acceleration"] = [float(v) for v in cf.Udot]
        if c in solver.rolling:  # ideal rolling: an ideal nonholonomic constraint, no limit
            info["mu"] = info["mu_static"] = "inf"
            info["ideal_rolling"] = True
            if cs.state == "stick":
                info["friction_needed"] = float(np.sqrt(cf.F @ cf.F))
        elif cs.state == "stick":
            need = float(np.sqrt(cf.F @ cf.F))
            info["friction_needed"] = need
            info["friction_available"] = float(cf.mu_s * abs(cf.N))
            info["margin"] = float(cf.mu_s * abs(cf.N) - need)
        if split is not None and name in lam_split:
            info["constraint_multiplier"] = float(lam_split[name])
        contacts[name] = info
    from ..numeric.speeds import output_kernel_of, speed_kernel_of

    params = solver.params
    speeds, speeds_dot, outputs = {}, {}, {}
    if model.speeds:
        sk = speed_kernel_of(model)
        speeds = dict(zip(sk.names, map(float, sk.values(t, q, qd, params))))
        speeds_dot = dict(zip(sk.names, map(float, sk.rates(t, q, qd, sol.qdd, params))))
    if model.outputs:
        ok = output_kernel_of(model)
        outputs = dict(zip(ok.names, map(float, ok(t, q, qd, params, multipliers))))
    return Evaluation(model.name, form, t, tuple(model.coordinates), q, qd, sol.qdd, mode.label(),
                      multipliers, reactions, contacts, split is not None,
                      split_report(solver, mode, sol, t, q, qd), speeds, speeds_dot, outputs)
