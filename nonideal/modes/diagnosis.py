"""One diagnosis of singular states: why the equations of motion at a state have no unique solution.

A constraint with a zero gradient, dependent (redundant) constraints -- named, with the
combination --, a mass matrix that is singular (or not positive definite) on the velocities
the constraints allow, and non-ideal reactions (servo, quasi-ideal, friction) that cannot
realize the constraints (``G M^-1 B`` singular).  Every stage that meets a singular system
(the mode solver, the mode selection, the checks of a model, the command line) asks here.
"""

from __future__ import annotations

import numpy as np

from ..errors import MechanicsError, ModelError, PainleveParadox, SingularSystem
from ..equations.high_order import extended
from ..modeling.model import Model
from ..numeric.blocks import definite_above, definite_above_sparse, dependent_rows
from ..numeric.consistency import complete_state
from ..numeric.kernel import kernel_of, parameter_vector

__all__ = ["format_state", "diagnose_state", "diagnose_initial_state", "singular_configuration",
           "explain_mechanics_error", "diagnose_singular", "weakest_reactions"]

SINGULAR_CONFIGURATION = (
    "; the equations are regular at the initial state, so this is a singular configuration of "
    "the coordinates or constraints (like r = 0 in polar coordinates): choose another state or "
    "other coordinates")


def singular_configuration(found: SingularSystem) -> SingularSystem:
    """*found* (a singularity at a state other than the initial one), each problem followed by
    the explanation that the coordinates or constraints are singular there."""
    return SingularSystem([p + SINGULAR_CONFIGURATION for p in found.problems], found.source)


def format_state(model: Model, t: float, q) -> str:
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
    rows = [i for i, r in enumerate(kernel.rows) if not r.unilateral or i in set(closed)]
    where = format_state(model, t, q)
    if kernel.compact:   # many coordinates: sparse tests first, dense only to name a problem
        problem = _compact_problem(kernel, out, rows)
        if problem is None:
            return None
        if kernel.n > DENSE_DIAGNOSIS_MAX:
            return SingularSystem(f"{problem} at {where}", src)
    M = kernel.dense(out, "M")
    G = kernel.dense(out, "G")[rows] if rows and kernel.m else np.zeros((0, kernel.n))
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
        if null.shape[1] == 0:
            return None
    else:
        null = None  # no rows: every velocity is allowed (no n x n identity, no O(n^3) products)
    Mr = null.T @ M @ null if null is not None else M
    Mr = (Mr + Mr.T) / 2
    tol = 1e-10 * max(1.0, float(np.max(np.abs(M))))
    if definite_above(Mr, tol):  # nothing to report (by blocks for a block-diagonal M)
        return None
    w, v = np.linalg.eigh(Mr)
    for k in range(len(w)):
        if w[k] > tol or (w[k] < -tol and not definite):
            continue
        vec = null @ v[:, k] if null is not None else v[:, k]
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


DENSE_DIAGNOSIS_MAX = 5000
"""Up to this many coordinates a singular system of a compact kernel (many coordinates, sparse
matrices) is explained on dense matrices, naming the velocity combination or the constraints;
beyond, the error says what is singular from the sparse tests alone."""


def _compact_problem(kernel, out, rows) -> str | None:
    """What the sparse tests find wrong with a compact kernel's system, or None when ``M`` is
    positive definite (Cholesky block by block) and the rows are independent (rank tests
    component by component) -- then ``M`` is definite on every velocity the rows allow."""
    if rows:
        G = kernel.gradients(out)[rows]
        scale = 1.0 + (float(abs(G).max()) if G.nnz else 0.0)
        norms = np.asarray(abs(G).max(axis=1).todense()).ravel()
        zero = [kernel.rows[rows[j]].name for j in np.flatnonzero(norms <= 1e-12 * scale)]
        if zero:
            return f"constraint(s) {', '.join(repr(z) for z in zero)} have a zero gradient"
        dep = [kernel.rows[rows[j]].name for j in dependent_rows(G, 1e-10 * scale)]
        if dep:
            return (f"dependent (redundant) constraints: {', '.join(repr(d) for d in dep)} repeat what "
                    "the others impose; remove them or make them independent")
    M = kernel.mass(out)
    tol = 1e-10 * max(1.0, float(abs(M).max()) if M.nnz else 0.0)
    if definite_above_sparse(M, tol):
        return None
    return ("the mass matrix is not positive definite (a coordinate or a combination without "
            "inertia, or a kinetic energy that is negative along some velocity)")


def diagnose_initial_state(model: Model, definite: bool = False) -> ModelError | None:
    """:func:`diagnose_state` at the model's (completed) initial state; ``None`` if fine or if
    the initial state itself cannot be completed (that error is raised elsewhere)."""
    model = extended(model)  # third-order constraints: the forces are part of the state
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
    if isinstance(exc, PainleveParadox) or "discriminant" in exc.details \
            or "order_tried" in exc.details:
        return exc     # already named: a root rule selecting nothing, an unreachable program
    found = None
    names = list(model.coordinates)
    if exc.t is not None and all(c in exc.state and c + "'" in exc.state for c in names):
        q = np.array([exc.state[c] for c in names], dtype=float)
        qd = np.array([exc.state[c + "'"] for c in names], dtype=float)
        found = diagnose_state(model, exc.t, q, qd)
        if found is not None and diagnose_initial_state(model) is None:
            return singular_configuration(found)
    if found is None:
        found = diagnose_initial_state(model)
    return found if found is not None else exc


def diagnose_singular(solver, M, G, B, layout, t, q, qd) -> Exception:
    """Turn a singular linear system into an actionable error naming what is singular."""
    kernel = solver.kernel
    if all(np.isfinite(G).ravel()) and np.all(np.isfinite(M)):
        # constraints and the mass matrix: the detailed diagnosis above
        closed = [r.index for r in layout if r.kind == "constraint" and kernel.rows[r.index].unilateral]
        found = diagnose_state(kernel.model, t, q, qd, closed, params=solver.params)
        if found is not None:
            if diagnose_initial_state(kernel.model) is None:
                return singular_configuration(found)
            return found
    names = list(kernel.model.coordinates)
    n = kernel.n
    src = None if kernel.model.source == "<api>" else kernel.model.source
    state = ", ".join(f"{c} = {v:.6g}" for c, v in zip(names, q))
    rates = ", ".join(f"{c}' = {v:.6g}" for c, v in zip(names, qd))
    where = f" at t = {t:.6g} ({state}; {rates})"
    m = len(layout)
    bad = [r.name for j, r in enumerate(layout) if not (np.all(np.isfinite(G[j])) and np.all(np.isfinite(B[:, j])))]
    if bad:
        from ..numeric.kernel import root_failure
        failure = root_failure(kernel, t, q, qd, solver.params)
        if failure is not None:
            return failure
    singular = _singular_transforms(kernel, [r.name for r in layout], t, q, qd, solver.params)
    if singular:
        return MechanicsError(singular + where.replace(" at t", "; at t", 1)
                              + ": the motion cannot be continued through this state")
    if bad or not (np.all(np.isfinite(M))):
        what = (f"constraint(s) {', '.join(repr(b) for b in bad)} are not differentiable" if bad
                else "the mass matrix is not finite")
        return MechanicsError(
            f"{what}{where}: their gradient is NaN or infinite (e.g. sqrt or a norm of velocities "
            "at zero, a singular point of a nonlinear constraint); the motion cannot be continued "
            "through this state")
    if m:
        rank = np.linalg.matrix_rank(G)
        if rank < m:
            dep, keep = [], []
            for j, r in enumerate(layout):
                if np.linalg.matrix_rank(G[keep + [j]]) == len(keep) + 1:
                    keep.append(j)
                else:
                    dep.append(r.name)
            return SingularSystem(
                f"dependent (redundant) constraints: {', '.join(repr(d) for d in dep)} "
                f"repeat what the others impose{where}; remove them or make them independent", src)
        _, _, Vt = np.linalg.svd(G)
        null = Vt[rank:].T
    else:
        null = np.eye(n)
    Mr = null.T @ M @ null if null.size else np.zeros((0, 0))
    if null.size and (np.linalg.matrix_rank(Mr) < Mr.shape[0]):
        w, v = np.linalg.eigh(Mr)
        vec = null @ v[:, 0]
        vec /= np.max(np.abs(vec))
        combo = " + ".join(f"{c:.3g}*{nm}'" for c, nm in zip(vec, names) if abs(c) > 1e-9)
        return SingularSystem(
            f"singular mass matrix{where}: the kinetic energy does not depend on the velocity "
            f"combination {combo}; give that motion inertia (mass or moment of inertia) or "
            "constrain it", src)
    servo = [j for j, r in enumerate(layout)
             if r.kind == "constraint" and kernel.rows[r.index].reaction_kind != "ideal"]
    if len(servo) > 1 and np.linalg.matrix_rank(B[:, servo]) < len(servo):
        j = int(np.linalg.matrix_rank(B[:, servo]))
        names_ = ", ".join(repr(layout[k].name) for k in servo)
        return MechanicsError(
            f"{len(servo)} servo/quasi-ideal constraints ({names_}) but their control directions "
            f"span only j = {j}: with r = {len(servo)} programs and j = {j} < r independent controls "
            "the problem is, in general, impossible (Béghin's count; Appell 1911, servo-constraints); give each program "
            "its own control direction" + where)
    if m and not np.allclose(B, G.T):
        # the combination of reactions that moves nothing along the constraints names them
        _, w = weakest_reactions(M, G, B)
        parts = [(w[j], r.name) for j, r in enumerate(layout) if abs(w[j]) > 1e-6 * np.max(np.abs(w))]
        return MechanicsError(
            "the non-ideal reactions (servo / quasi-ideal / friction) cannot realize the "
            f"constraints: G M^-1 B is singular -- the reactions of {', '.join(repr(x) for _, x in parts)} "
            "in the combination " + ", ".join(f"{c:.4g}*{x}" for c, x in parts)
            + " accelerate the system only along motions the constraints allow, so they cannot "
            "enforce them (a servo-constraint whose control direction is orthogonal, in the "
            "metric of M, to the program's gradient; for a sliding contact the boundary of "
            "Painleve's paradox); choose another reaction direction" + where)
    return SingularSystem(f"the equations of motion are singular{where}", src)


def weakest_reactions(M: np.ndarray, G: np.ndarray, B: np.ndarray) -> tuple[float, np.ndarray]:
    """How nearly the reactions ``B`` fail to realize the constraints ``G``: the smallest
    singular value of ``G M^-1 B`` relative to ``|G| |M^-1 B|`` (what it would be with the
    reactions along the gradients), and its combination of the reactions (unit vector)."""
    Minv_B = np.linalg.solve(M, B)
    _, sv, Vt = np.linalg.svd(G @ Minv_B)
    scale = float(np.linalg.norm(G) * np.linalg.norm(Minv_B))
    return float(sv[-1]) / max(scale, 1e-300), Vt[-1]


def _singular_transforms(kernel, names, t, q, qd, params) -> str:
    """The explanation when a quasi-ideal constraint among *names* has a singular transform
    ``A`` with ``adj(A) grad f = 0`` at the state (``A R = lambda grad f``, Briskin et al. 2021,
    (1.3), (2.1)): its reaction direction ``adj(A) grad f`` vanishes, ``grad f`` lies in the
    range of ``A`` and the definition does not fix the reaction; empty otherwise.  (Where
    ``adj(A) grad f != 0`` the reaction lies along it with ``lambda = det(A) mu = 0``: a motion
    the library computes.)"""
    import sympy as sp

    model = kernel.model
    values = {sp.Symbol(k): float(v) for k, v in zip(model.parameter_values, params)}
    values.update({sp.Symbol("t"): t})
    values.update(dict(zip(model.q, q)))
    values.update(dict(zip(model.qd, qd)))
    out = []
    for c in model.constraints:
        if c.name not in names or c.transform is None:
            continue
        A = sp.Matrix([[sp.sympify(x) for x in row] for row in c.transform])
        try:
            An = np.array(A.xreplace(values).evalf(), dtype=float)
        except (TypeError, ValueError):
            continue
        scale = max(1.0, float(np.abs(An).max()))
        det = float(np.linalg.det(An))
        if abs(det) > 1e-12 * scale ** len(An):
            continue
        grad = np.array([float(sp.diff(c.expr, x).xreplace(values))
                         for x in (model.q if c.order == 0 else model.qd)], dtype=float)
        adj = np.array(A.adjugate().xreplace(values).evalf(), dtype=float) @ grad
        if np.any(np.abs(adj) > 1e-12 * scale ** (len(An) - 1) * max(1.0, float(np.abs(grad).max()))):
            continue
        out.append(
            f"constraint '{c.name}': its transform A is singular (det A = 0) and adj(A) grad f = 0 "
            "-- grad f lies in the range of A, so the definition A R = lambda grad f (Briskin et "
            "al. 2021, (1.3), (2.1)) does not fix the reaction here (the reaction R = adj(A) "
            "grad f mu vanishes, and A R = lambda grad f leaves a family of reactions R = lambda "
            "R0 + null(A)): the reaction is indeterminate; move the transform off this point")
    return "; ".join(out)
