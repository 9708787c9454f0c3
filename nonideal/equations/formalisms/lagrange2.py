"""Lagrange's equations of the second kind: holonomic constraints eliminated by minimal coordinates.

Every ideal holonomic constraint ``f_i(q, t) = 0`` among the rows is solved for one dependent
coordinate, ``q_d = phi_d(q_k, t)`` (scleronomic or rheonomic alike), and the model is
rewritten in the kept coordinates ``q_k`` (:func:`reduced_model`): the kinetic and potential
energies, bodies and loads with ``q_d = phi_d`` and ``q_d' = d(phi_d)/dt`` substituted, the
declared generalized forces transferred by virtual work ``Q_k + sum_d Q_d dphi_d/dq_k``.  The
kernel of that reduced model gives

    d/dt dT/dq_k' - dT/dq_k = Q_k + sum_j B_jk lambda_j,      G q_k'' + gamma = 0,

where the remaining rows -- nonholonomic ones (Routh--Voss multipliers, reaction
``d(phi)/dq_k'`` of the substituted constraint by Chetaev's rule) and non-ideal holonomic ones
(servo, quasi-ideal, sliding contacts: not eliminated, their reaction is transferred by
virtual work) -- keep their multipliers.  The multipliers are those of Lagrange I: the
substituted constraint is the same function.  Accelerations of the eliminated coordinates
follow from ``q_d'' = d^2 phi_d/dt^2`` (``R, r``).

The dependent coordinates are the complement of ``independent`` (the coordinates kept; it may
also name fewer, as for the reduced forms, and then the others are chosen here), else one per
constraint preferring coordinates that enter linearly and whose partial derivative does not
vanish at the model's initial state.  Each constraint is solved with ``sympy.solve``; of
several roots the one through the model's initial state is taken (completed from the
constraints, as the simulation does, when dependent values are not given), else the first
real one, or the one through the point *branch* (``derive(..., branch=)``).  The equations
hold on that chart only (e.g. ``y1 = sqrt(l^2 - (x1 - x)^2)`` needs ``y1 > 0``); the
simulation changes charts along the motion (:mod:`nonideal.modes.charts`).
:class:`FormNotApplicable` is raised when no closed-form solution exists.

Without holonomic constraints to eliminate this is Lagrange's form with multipliers in the
model's coordinates (Routh--Voss): the same numbers as ``lagrange1``.

Code names: ``A`` = mass matrix of the reduced model, ``c`` = its velocity terms,
``Q_f`` = its generalized forces (``-dV/dq`` included).

Sources: Lagrange, *Mecanique analytique* (1788); Manglieva & Beknazarov 2022, (1.55)-(1.56)
(friction forces enter as ``Q^r``, here the non-ideal rows); Yushkov 1999, ch. I sec. 2
(Lagrange I and II as one construction); Routh 1884, Voss 1885 (multipliers of the
nonholonomic constraints).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import symengine as se
import sympy as sp

from ...modeling.bodies import Force, Particle, PlanarBody, RigidBody, Torque
from ..dynamics import ConstraintRow, Dynamics, count_ops
from ..eom import EquationsOfMotion
from ...errors import FormNotApplicable, did_you_mean
from ...modeling.model import Model
from ...modeling.symbols import t as t_sp
from ...modeling.symbols import to_se, to_sp
from .base import Formalism, Reduction, project_rows
from .lagrange1 import lagrange1_equations

__all__ = ["Lagrange2", "Chart", "holonomic_chart", "reduced_model"]

SOLVE_MAX_OPS = 400   # larger constraint expressions are not handed to sympy.solve
PRINT_MAX_OPS = 400   # reduced T printed in extras only below this size


@dataclass(frozen=True)
class Chart:
    """Minimal coordinates of the holonomic constraints: ``q_d = phi[d](q_kept, t)``.

    Attributes
    ----------
    dependent, kept : list of int
        Coordinate indices (eliminated / kept), ascending.
    phi : dict int -> sympy.Expr
        The solution for each eliminated coordinate, in the kept coordinates and time.
    notes : tuple of str
        The substitutions and the branch choices, for printing.
    """

    dependent: list[int]
    kept: list[int]
    phi: dict
    notes: tuple[str, ...]


def _holonomic_rows(rows: list[ConstraintRow]):
    """Rows eliminated by Lagrange II (ideal, position level) and the rows kept."""
    elim = [r for r in rows if r.order == 0 and r.reaction_kind == "ideal" and r.position is not None]
    names = {r.name for r in elim}
    return elim, [r for r in rows if r.name not in names]


# ----------------------------------------------------------------------------- numerics


def _num(expr, point) -> complex | None:
    """Value of a SymPy expression at a point (``{Symbol: Float}``), or None."""
    try:
        v = complex(sp.N(sp.sympify(expr).xreplace(point)))
    except (TypeError, ValueError, ZeroDivisionError, ArithmeticError):
        return None
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        return None
    return v


def _initial_point(model: Model, branch: dict[str, float] | None = None):
    """The model's initial coordinates, or the coordinates *branch* when given (the numeric
    stages pass the initial state completed from the constraints:
    :func:`nonideal.numeric.consistency.initial_branch`).

    Returns ``(point, known)``: values for parameters, ``t`` and every coordinate (0.1 where
    nothing is known), and the set of coordinate indices whose value comes from the model.
    """
    coords = list(model.coordinates)
    given = dict(branch) if branch is not None else model.numeric_initial()
    values = {c: given[c] for c in coords if c in given}
    point = {sp.Symbol(k): sp.Float(v) for k, v in model.parameter_values.items()}
    point[t_sp] = sp.Float(model.t0)
    known = set()
    for j, (c, s) in enumerate(zip(coords, model.q)):
        if c in values:
            point[s] = sp.Float(values[c])
            known.add(j)
        else:
            point[s] = sp.Float(0.1)
    return point, known


# ----------------------------------------------------------------------------- solving


def _mixed(f: sp.Expr, x: sp.Symbol) -> bool:
    """True when *x* enters both algebraically and inside a transcendental function (or inside
    functions of different families), e.g. ``x + sin(x)``, or a function of x under a root
    (``sqrt(sin(x)^2 + ...)``, a contact point on a wheel): no closed form, and
    ``sympy.solve`` can spend seconds to minutes finding that out."""
    funcs: set = set()
    algebraic = radical = False

    def walk(e):
        nonlocal algebraic, radical
        if not e.has(x):
            return
        if e == x:
            algebraic = True
        elif isinstance(e, sp.Function):
            funcs.add(type(e))
        else:
            if isinstance(e, sp.Pow) and not e.exp.is_Integer:
                radical = True
            for a in e.args:
                walk(a)

    walk(f)
    trig = {sp.sin, sp.cos, sp.tan, sp.cot}
    other = funcs - trig
    return bool(funcs) and (algebraic or radical or len(other) > 1 or bool(other and funcs & trig))


def _solve(f: sp.Expr, x: sp.Symbol) -> list:
    """Closed-form roots of ``f = 0`` in *x* (``sympy.solve``), or [] when there is none."""
    if _mixed(f, x):
        return []
    try:
        sols = sp.solve(f, x, check=False, simplify=False, rational=False)
    except (NotImplementedError, ValueError, TypeError, AttributeError, RecursionError):
        return []
    if isinstance(sols, dict):
        sols = [sols.get(x)] if x in sols else []
    out = []
    for s in sols:
        if isinstance(s, dict):
            s = s.get(x)
        if isinstance(s, tuple):
            s = s[0] if len(s) == 1 else None
        if isinstance(s, sp.Expr) and x not in s.free_symbols:
            out.append(s)
    return out


def _degree(f, x) -> int:
    """Degree of *f* in *x* when it is a polynomial of degree <= 4 in *x*, else 9 (SymEngine:
    the first derivative free of *x*)."""
    d = f
    for k in range(1, 5):
        d = se.diff(d, x)
        if x not in d.free_symbols:
            return k
    return 9


def _num_se(expr, point) -> complex | None:
    """Value of a SymEngine expression at a point (``{Symbol: float}``), or None."""
    try:
        v = complex(se.sympify(expr).xreplace(point).n())
    except (RuntimeError, TypeError, ValueError, ZeroDivisionError):
        return None
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        return None
    return v


def _tidy(e: sp.Expr) -> sp.Expr:
    """Expand the radicands of a solution when that makes them smaller (``sympy.solve``
    returns them factored: ``sqrt(-(-l + y1)*(l + y1))`` becomes ``sqrt(l**2 - y1**2)``)."""
    def fix(p):
        b = sp.expand(p.base)
        return sp.Pow(b, p.exp) if sp.count_ops(b) <= sp.count_ops(p.base) else p

    return e.replace(lambda x: x.is_Pow and x.exp.is_Rational and not x.exp.is_Integer, fix)


def _reach(solved: dict, q) -> dict:
    """For each solved coordinate, the unsolved coordinates its solution depends on (through
    the other solved ones)."""
    out: dict[int, set] = {}

    def visit(d, stack=()):
        if d in out:
            return out[d]
        acc = set()
        for j, s in enumerate(q):
            if s in solved[d].free_symbols:
                if j in solved:
                    if j not in stack:
                        acc |= visit(j, stack + (d,))
                else:
                    acc.add(j)
        out[d] = acc
        return acc

    for d in solved:
        visit(d)
    return out


def _unsolved_deps(f, solved: dict, reach: dict, q) -> set:
    """Unsolved coordinates *f* depends on, directly or through solved ones."""
    out = set()
    for j, s in enumerate(q):
        if s in f.free_symbols:
            out |= reach[j] if j in solved else {j}
    return out


def _resolve_for(f, j: int, solved: dict, reach: dict, q):
    """*f* with the solved coordinates whose solution involves ``q[j]`` substituted (repeated
    until ``q[j]`` enters only directly)."""
    for _ in range(len(solved) + 1):
        subs = {q[d]: solved[d] for d in solved if q[d] in f.free_symbols and j in reach[d]}
        if not subs:
            return f
        f = f.xreplace(subs)
    return f  # pragma: no cover - the solved chain is acyclic


def _not_applicable(name: str, expr, cands: list[str], why: str) -> FormNotApplicable:
    which = f" for {', '.join(cands)}" if cands else ""
    return FormNotApplicable(
        f"lagrange2: the holonomic constraint '{name}' ({sp.sstr(expr)}) {why}{which}; use "
        "--form lagrange1 or --form maggi (they keep redundant coordinates), or choose the "
        "coordinates to keep with [forms] independent"
    )


def holonomic_chart(dyn: Dynamics, rows: list[ConstraintRow],
                    keep: tuple[str, ...] | None, branch: dict[str, float] | None = None) -> Chart:
    """Solve the ideal holonomic *rows* for one dependent coordinate each (module docstring).

    Parameters
    ----------
    dyn : Dynamics
    rows : list of ConstraintRow
        Position-level rows to eliminate.
    keep : tuple of str or None
        Coordinates that must be kept (all the kept ones, or a part of them).
    branch : dict name -> float, optional
        Coordinates through which the roots are chosen (default: the initial state).

    Raises
    ------
    FormNotApplicable
        When a constraint has no closed-form solution for an admissible coordinate.
    """
    model = dyn.model
    coords = list(model.coordinates)
    q = list(model.q)
    n, m = len(coords), len(rows)
    by_name = {c.name: c for c in model.constraints}
    exprs = []
    for r in rows:
        c = by_name.get(r.name)
        exprs.append(c.expr if c is not None and c.order == 0 else to_sp(r.position))
    names = [r.name for r in rows]
    allowed = list(range(n))
    if keep is not None:
        bad = [c for c in keep if c not in coords]
        if bad:
            raise FormNotApplicable(
                f"[forms] independent: '{bad[0]}' is not a coordinate{did_you_mean(bad[0], coords)}")
        if len(set(keep)) > n - m:
            raise FormNotApplicable(
                f"[forms] independent: {len(set(keep))} coordinates to keep, but the {m} holonomic "
                f"constraint(s) ({', '.join(names)}) on {n} coordinates leave {n - m}; lagrange2 "
                f"keeps {n - m} coordinates"
            )
        allowed = [j for j in range(n) if coords[j] not in keep]
    point, known = _initial_point(model, branch)
    q_se = [to_se(s) for s in q]
    exprs_se = [to_se(e) for e in exprs]
    point_se = {to_se(k): float(v) for k, v in point.items()}
    # Each constraint is solved in its own variables (small expressions for sympy.solve); a
    # solved coordinate is substituted into a later constraint only when its solution depends
    # on the variable being solved for (no cycles), and the chain is resolved at the end.
    # The choice of the variable is made in SymEngine (derivatives and values at the point).
    solved: dict[int, sp.Expr] = {}
    solved_se: dict[int, object] = {}
    branch_notes: dict[int, str] = {}
    remaining = list(range(m))
    while remaining:
        reach = _reach(solved_se, q_se)
        best = None
        for i in remaining:
            cands = [j for j in sorted(_unsolved_deps(exprs_se[i], solved_se, reach, q_se)) if j in allowed]
            if not cands:
                raise _not_applicable(
                    names[i], exprs[i],
                    [], "depends on no coordinate left to eliminate after the others were "
                        "solved (dependent constraints, or the kept coordinates are constrained)")
            forms = {j: _resolve_for(exprs_se[i], j, solved_se, reach, q_se) for j in cands}
            mags = {}
            for j in cands:
                g = _num_se(se.diff(forms[j], q_se[j]), point_se)
                mags[j] = abs(g) if g is not None else 0.0
            top = max(mags.values()) or 1.0
            keys = []
            for j in cands:
                rel = mags[j] / top
                keys.append(((rel < 1e-6), _degree(forms[j], q_se[j]), -round(rel, 3), -j))
            order = sorted(zip(keys, cands))
            nonsingular = sum(1 for k, _ in order if not k[0])
            key = (nonsingular == 0, nonsingular, order[0][0])
            if best is None or key < best[0]:
                best = (key, i, [j for _, j in order], forms)
        _, i, cands, forms = best
        choice = None
        why = []
        for j in cands:  # best candidate first; fall back to the others
            if count_ops([forms[j]]) > SOLVE_MAX_OPS:
                why.append(f"{coords[j]}: too large for sympy.solve")
                continue
            f, x = _resolve_for(exprs[i], j, solved, reach, q), q[j]
            roots = _solve(f, x)
            picked = _pick_root(f, x, roots, point, j in known, coords[j]) if roots else None
            if picked is not None:
                choice = (j, picked)
                break
            why.append(f"{coords[j]}: " + ("no real root at the initial state" if roots
                                           else "no closed-form solution"))
        if choice is None:
            raise _not_applicable(names[i], exprs[i], [],
                                  "cannot be solved for a coordinate (" + "; ".join(why) + ")")
        j, (root, value, note) = choice
        solved[j] = root
        solved_se[j] = to_se(root)
        if note:
            branch_notes[j] = note
        if j not in known:
            point[q[j]] = sp.Float(value)
            point_se[q_se[j]] = float(value)
        remaining.remove(i)
    dep = sorted(solved)
    kept = [j for j in range(n) if j not in solved]
    resolved: dict[int, sp.Expr] = {}

    def resolve(d):
        if d not in resolved:
            e = solved[d]
            inner = {q[s]: resolve(s) for s in solved if q[s] in e.free_symbols}
            resolved[d] = _tidy(e.xreplace(inner) if inner else e)
        return resolved[d]

    solved = {d: resolve(d) for d in dep}
    notes = [f"{coords[d]} = {sp.sstr(solved[d])}" + (f"  ({branch_notes[d]})" if d in branch_notes else "")
             for d in dep]
    return Chart(dep, kept, solved, tuple(notes))


def _pick_root(f, x, roots, point, known: bool, name: str):
    """The root through the initial state: ``(root, value, note)`` or None."""
    vals = []
    for s in roots:
        v = _num(s, point)
        if v is None or abs(v.imag) > 1e-9 * (1.0 + abs(v.real)):
            continue
        p = dict(point)
        p[x] = sp.Float(v.real)
        res = _num(f, p)
        scale = 1.0 + sum(abs(float(val)) for val in p.values() if isinstance(val, sp.Float))
        if res is None or abs(res) > 1e-8 * scale:  # spurious root (e.g. from squaring)
            continue
        vals.append((s, v.real))
    if not vals:
        return None
    if len(vals) == 1:
        return vals[0][0], vals[0][1], ""
    if known:
        x0 = float(point[x])
        s, v = min(vals, key=lambda sv: abs(sv[1] - x0))
        return s, v, f"of {len(vals)} roots, the one through the initial value {name} = {x0:.6g}"
    s, v = vals[0]
    return s, v, f"of {len(vals)} roots, the first real one at the initial point ({name} = {v:.6g})"


# ----------------------------------------------------------------------------- reduced model


def reduced_model(model: Model, chart: Chart) -> Model:
    """The model in the kept coordinates (energies, bodies, loads, forces; no constraints).

    Declared generalized forces are transferred by virtual work,
    ``Q_k + sum_d Q_d dphi_d/dq_k``; loads and bodies by substituting their positions (the
    kernel then applies virtual work itself).
    """
    q, qd = model.q, model.qd
    kept = chart.kept
    subs = {}
    jac = {}
    t_se = to_se(t_sp)
    for d, phi in chart.phi.items():  # derivatives in SymEngine (SymPy's diff is slow here)
        subs[q[d]] = phi
        phi_se = to_se(phi)
        rate = se.diff(phi_se, t_se)
        for i in kept:
            g = se.diff(phi_se, to_se(q[i]))
            jac[d, i] = to_sp(g) if g != 0 else sp.Integer(0)
            rate += g * to_se(qd[i])
        subs[qd[d]] = to_sp(rate)

    def S(e):
        return sp.sympify(e).xreplace(subs)

    forces = {}
    for i in kept:
        Qi = S(model.forces[i])
        for d in chart.phi:
            if model.forces[d] != 0 and jac[d, i] != 0:
                Qi += S(model.forces[d]) * jac[d, i]
        forces[model.coordinates[i]] = Qi
    bodies = []
    for b in model.bodies:
        if isinstance(b, Particle):
            bodies.append(Particle(b.name, S(b.mass), [S(c) for c in b.position]))
        elif isinstance(b, PlanarBody):
            bodies.append(PlanarBody(b.name, S(b.mass), S(b.inertia), [S(c) for c in b.position], S(b.angle)))
        elif isinstance(b, RigidBody):
            bodies.append(RigidBody(b.name, S(b.mass), [[S(x) for x in row] for row in b.inertia],
                                    [S(c) for c in b.position], [[S(x) for x in row] for row in b.rotation]))
    loads = []
    for ld in model.loads:
        if isinstance(ld, Force):
            loads.append(Force(ld.name, [S(c) for c in ld.point], [S(c) for c in ld.force]))
        elif isinstance(ld, Torque):
            tq = tuple(S(c) for c in ld.torque) if isinstance(ld.torque, tuple) else S(ld.torque)
            loads.append(Torque(ld.name, tq, S(ld.angle) if ld.angle is not None else None, ld.body))
    names = [model.coordinates[i] for i in kept]
    keys = set(names) | {c + "'" for c in names}
    return Model(
        name=f"{model.name} [in {', '.join(names)}]",
        coordinates=names,
        parameters=model.parameters,
        kinetic=S(model.kinetic),
        potential=S(model.potential),
        forces=forces,
        bodies=bodies,
        loads=loads,
        gravity=model.gravity,
        initial={k: v for k, v in model.initial.items() if k in keys},
        t0=model.t0,
        source=model.source,
    )


# ----------------------------------------------------------------------------- the form


class Lagrange2(Formalism):
    name = "lagrange2"
    title = "Lagrange equations of the second kind (holonomic constraints eliminated)"
    title_routh = "Lagrange equations of the second kind with multipliers (Routh-Voss form)"
    citation = ("Lagrange 1788; Manglieva & Beknazarov 2022, (1.55)-(1.56); Yushkov 1999, ch. I "
                "sec. 2; Routh 1884 / Voss 1885 multipliers for the remaining constraints")

    def derive(self, dyn, rows, independent):
        elim, kept_rows = _holonomic_rows(rows)
        coords = list(dyn.model.coordinates)
        n = dyn.n
        if not elim:
            A, c, Q, B, G, gamma = lagrange1_equations(dyn, kept_rows)
            notes = ["no ideal holonomic constraint to eliminate: the model's coordinates are kept"]
            if kept_rows:
                notes.append("multipliers for " + ", ".join(r.name for r in kept_rows)
                             + " (reactions d(phi)/dq' by Chetaev's rule, or the given directions)")
            return EquationsOfMotion(
                form=self.name, title=self.title_routh, citation=self.citation, model=dyn.model,
                unknowns=tuple(s.name for s in dyn.qdd),
                multipliers=tuple(f"lambda_{r.name}" for r in kept_rows),
                constraint_names=tuple(r.name for r in kept_rows), rows=tuple(rows),
                independent=tuple(coords), A_=A, c_=c, Qf_=Q, B_=B, G_=G, gamma_=gamma,
                R_=se.eye(n), r_=se.zeros(n, 1), notes=tuple(notes),
            )
        chart = holonomic_chart(dyn, elim, independent, self.branch)
        kept, dep = chart.kept, chart.dependent
        k = len(kept)
        if k:
            rdyn = Dynamics(reduced_model(dyn.model, chart))
            A, c, Q = rdyn.M, rdyn.h, se.Matrix(rdyn.Q)
        else:  # the constraints fix every coordinate: no equation of motion is left
            rdyn = None
            A, c, Q = se.zeros(0, 0), se.zeros(0, 1), se.zeros(0, 1)
        # back to all coordinates: q_d'' = d^2 phi_d/dt^2 (q_k'' unknown)
        phi = {d: to_se(chart.phi[d]) for d in dep}
        rate = {d: dyn.dt(phi[d], with_acceleration=False) for d in dep}
        R = se.zeros(n, k)
        r = se.zeros(n, 1)
        for col, j in enumerate(kept):
            R[j, col] = 1
        for d in dep:
            for col, j in enumerate(kept):
                R[d, col] = se.diff(phi[d], dyn.q[j])
            r[d, 0] = dyn.dt(rate[d], with_acceleration=False)
        # remaining rows in the kept coordinates (Routh-Voss; virtual work for the reactions)
        subs = {dyn.q[d]: phi[d] for d in dep}
        subs.update({dyn.qd[d]: rate[d] for d in dep})
        sub_rows = [replace(row, G=tuple(se.sympify(g).subs(subs) for g in row.G),
                            gamma=se.sympify(row.gamma).subs(subs),
                            B=tuple(se.sympify(b).subs(subs) for b in row.B)) for row in kept_rows]
        G, gamma, B = project_rows(sub_rows, Reduction(dep, kept, R, r, ()), n)
        notes = list(chart.notes)
        notes.append("kept coordinates: " + ", ".join(coords[j] for j in kept)
                     + "; eliminated: " + ", ".join(row.name for row in elim))
        if kept_rows:
            notes.append("multipliers for " + ", ".join(row.name for row in kept_rows)
                         + " (reactions transferred by virtual work to the kept coordinates)")
        extras = {}
        if rdyn is not None and count_ops([rdyn.T]) <= PRINT_MAX_OPS:
            extras["T"] = rdyn.T
        if dep:
            # the chart: these residuals vanish on the branch the equations were derived for
            extras["chart"] = se.Matrix([dyn.q[d] - phi[d] for d in dep])
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in kept),
            multipliers=tuple(f"lambda_{row.name}" for row in kept_rows),
            constraint_names=tuple(row.name for row in kept_rows), rows=tuple(rows),
            independent=tuple(coords[j] for j in kept),
            A_=A, c_=c, Qf_=Q, B_=B, G_=G, gamma_=gamma, R_=R, r_=r,
            extras_=extras, notes=tuple(notes), eliminated=tuple(row.name for row in elim),
        )
