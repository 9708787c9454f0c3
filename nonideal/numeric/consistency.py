"""Consistent states: complete an initial state from the constraints, project onto the
constraint manifold, and draw random admissible states (for the cross-form tests).

The rows used here are the model's constraints and the gaps of its contacts (a contact's gap
behaves like a unilateral constraint; a bilateral contact like a bilateral one).  Missing
coordinates are solved from the holonomic rows (Gauss--Newton from a start value of 0.1, or
from a neighbouring state), missing velocities from the velocity-level rows; unilateral rows
and contact gaps are closed (taken as equalities) only when the values cannot be determined
otherwise.  A given value that violates a constraint is an error that names the constraint
and the residual; it is never silently "fixed" beyond round-off (relative 1e-9).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp
from scipy.linalg import qr

from .contact_kernel import contact_kernel_of
from ..errors import InconsistentInitialConditions, MechanicsError, NonidealError
from ..modeling.symbols import t as time
from .kernel import Kernel, kernel_of, parameter_vector, root_failure

__all__ = ["complete_state", "support_problems", "project_state", "project_positions", "project_velocities",
           "random_admissible_states", "initial_branch", "GIVEN_TOL"]

GIVEN_TOL = 1e-9     # relative tolerance on given values (beyond: error)
NEWTON_TOL = 1e-13


def _scale(values: np.ndarray) -> float:
    return 1.0 + float(np.max(np.abs(values))) if values.size else 1.0


@dataclass(frozen=True)
class _Row:
    name: str
    kind: str          # "constraint" or "contact"
    index: int
    holonomic: bool    # has a position level
    unilateral: bool


class _Levels:
    """Position/velocity residuals and Jacobians of constraint rows and contact gaps."""

    def __init__(self, kernel: Kernel, params: np.ndarray):
        self.kernel, self.params = kernel, params
        self.ck = contact_kernel_of(kernel.model)
        rows = [_Row(r.name, "constraint", i, r.position is not None, r.unilateral)
                for i, r in enumerate(kernel.rows)]
        rows += [_Row(c.name, "contact", k, True, not c.bilateral) for k, c in enumerate(self.ck.data)]
        # slip rows (velocity level only): used for states where the contacts stick
        rows += [_Row(f"{c.name}_t{j + 1}", "slip", k, False, False)
                 for k, c in enumerate(self.ck.data) for j in range(len(c.U))]
        # conditions of dynamics of servo-constraints whose control acts through the dynamics
        # (the program itself among them): equalities of the state, not rows of the motion
        self.conditions = kernel.conditions
        if self.conditions is not None:
            _, cnames, cpos = self.conditions
            rows += [_Row(name, "condition", k, hol, False) for k, (name, hol) in enumerate(zip(cnames, cpos))]
        self.n_slip_end = len(kernel.rows) + len(self.ck.data) + sum(len(c.U) for c in self.ck.data)
        self.rows = rows
        self.has_velocity = [kernel.rows[r.index].velocity is not None if r.kind == "constraint" else True
                             for r in rows]
        self.n_gap_end = len(kernel.rows) + len(self.ck.data)

    def __call__(self, t, q, qd):
        """``(G, pos, vel)`` of every row at a state (G is dpos/dq = dvel/dq')."""
        k = self.kernel
        self.last_qd = qd
        x = k.state_input(t, q, qd, self.params)
        m = len(self.rows)
        G = np.zeros((m, k.n))
        pos = np.zeros(m)
        vel = np.zeros(m)
        nk = k.m
        if nk:
            out = k.dynamics(x)
            obs = k.observables(x)
            G[:nk] = k.dense(out, "G")
            pos[:nk] = obs["pos"]
            vel[:nk] = obs["vel"]
        if self.ck:
            cout = self.ck(x)
            ne = self.n_gap_end
            G[nk:ne] = cout["Gn"]
            pos[nk:ne] = cout["gap"]
            vel[nk:ne] = cout["gap_rate"]
            G[ne:self.n_slip_end] = cout["W"]
            vel[ne:self.n_slip_end] = cout["U"]
        if self.conditions is not None:
            cout = self.conditions[0](x)
            G[self.n_slip_end:] = cout["G"]
            pos[self.n_slip_end:] = cout["pos"]
            vel[self.n_slip_end:] = cout["vel"]
        return G, pos, vel


def _newton(levels: _Levels, rows: list[int], unknown: list[int], t, q, qd, level: str,
            max_iter: int = 60):
    """Solve the residuals of *rows* at *level* ("pos" or "vel") for the *unknown* entries.

    Returns ``(q, qd, converged)``.
    """
    q, qd = q.copy(), qd.copy()
    if not rows or not unknown:
        return q, qd, True
    for _ in range(max_iter):
        G, pos, vel = levels(t, q, qd)
        res = (pos if level == "pos" else vel)[rows]
        if not (np.all(np.isfinite(res)) and np.all(np.isfinite(G[rows]))):
            return q, qd, False    # left the domain of a constraint (sqrt, log, ...)
        if np.max(np.abs(res)) < NEWTON_TOL * _scale(q if level == "pos" else qd):
            return q, qd, True
        step, *_ = np.linalg.lstsq(G[rows][:, unknown], -res, rcond=None)
        target = q if level == "pos" else qd
        target[unknown] += step
    G, pos, vel = levels(t, q, qd)
    res = (pos if level == "pos" else vel)[rows]
    ok = np.max(np.abs(res)) < 1e-9 * _scale(q if level == "pos" else qd)
    return q, qd, bool(ok)


def _determined(levels, rows, unknown, t, q, qd) -> bool:
    if not unknown:
        return True
    if not rows:
        return False
    G, _, _ = levels(t, q, qd)
    return np.linalg.matrix_rank(G[rows][:, unknown]) == len(unknown)


def _src(model):
    return None if model.source == "<api>" else model.source


def complete_state(kernel: Kernel, given: Mapping[str, float], params: np.ndarray, t0: float,
                   guess: Mapping[str, float] | None = None):
    """Complete and check an initial state.

    Parameters
    ----------
    kernel : Kernel
    given : mapping name -> value
        Coordinates (``"x"``) and velocities (``"x'"``) given by the user.
    params : ndarray
    t0 : float
    guess : mapping, optional
        Start values for missing coordinates (default 0.1).

    Returns
    -------
    q, qd : ndarray, shape (n_q,)
    closed : list of int
        Unilateral constraint rows that are closed (gap ~ 0) at the initial state.

    Raises
    ------
    InconsistentInitialConditions
    """
    model = kernel.model
    levels = _Levels(kernel, params)
    names = list(model.coordinates)
    speeds = {k: v for k, v in given.items() if k in model.speeds}
    if speeds:   # given speeds: turned into velocities once the coordinates are known
        given = {k: v for k, v in given.items() if k not in speeds}
    rows = levels.rows
    equality = [i for i, r in enumerate(rows) if not r.unilateral and r.kind != "slip"]
    optional = [i for i, r in enumerate(rows) if r.unilateral]
    start_q = np.array([given.get(c, (guess or {}).get(c, 0.1)) for c in names], dtype=float)
    qd = np.array([given.get(c + "'", 0.0) for c in names], dtype=float)
    miss_q = [i for i, c in enumerate(names) if c not in given]
    miss_v = [i for i, c in enumerate(names) if c + "'" not in given]

    # ---- positions (a shape's support point must be unique where the orientation is given)
    problems = support_problems(model, levels.ck.params, params, t0, start_q, given)
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))
    pos_rows = [i for i in equality if rows[i].holonomic]
    q, qd, ok = _newton(levels, pos_rows, miss_q, t0, start_q, qd, "pos")
    closed_extra: list[int] = []
    if miss_q and not (ok and _determined(levels, pos_rows, miss_q, t0, q, qd)):
        found = False
        for k in range(1, len(optional) + 1):
            for subset in itertools.combinations(optional, k):
                rows_try = pos_rows + list(subset)
                if len(rows_try) < len(miss_q):
                    continue
                q2, _, ok2 = _newton(levels, rows_try, miss_q, t0, start_q, qd, "pos")
                if not (ok2 and _determined(levels, rows_try, miss_q, t0, q2, qd)):
                    continue
                _, pos2, _ = levels(t0, q2, qd)
                if all(pos2[i] >= -GIVEN_TOL * _scale(q2) for i in optional):
                    q, closed_extra, found = q2, list(subset), True
                    break
            if found:
                break
        if not found:
            raise InconsistentInitialConditions(
                _missing_positions(levels, pos_rows, miss_q, miss_v, t0, q, qd, ok),
                _src(model))
    G, pos, vel = levels(t0, q, qd)
    _require_finite(levels, G, pos, vel, t0, q, model)
    scale = _scale(q)
    problems = []
    for i in pos_rows:
        if abs(pos[i]) > GIVEN_TOL * scale:
            problems.append(
                f"[initial]: constraint '{rows[i].name}' is violated by the initial coordinates: "
                f"residual {pos[i]:.3e}; give consistent values (expressions in the parameters are "
                "allowed) or leave a dependent coordinate out to have it completed")
    for i in optional:
        if pos[i] < -GIVEN_TOL * scale:
            what = "contact" if rows[i].kind == "contact" else "unilateral constraint"
            problems.append(f"[initial]: {what} '{rows[i].name}' is violated (value {pos[i]:.3e} < 0)")
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))
    closed = [i for i in optional if abs(pos[i]) <= GIVEN_TOL * scale]
    q = _project(levels, pos_rows + closed, t0, q, qd, "pos")
    problems = support_problems(model, levels.ck.params, params, t0, q)
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))

    # ---- velocities
    vel_eq = [i for i in equality if levels.has_velocity[i]]
    if speeds:
        from ..modeling.speeds import radial_indices
        from .speeds import velocities_from_speeds

        radial = radial_indices(model)   # Euler parameters: e . e' = 0 with the speeds

        def constraint_rows(v):
            G, _, vel = levels(t0, q, v)
            E = np.zeros((len(radial), len(q)))
            for k, idx in enumerate(radial):
                E[k, idx] = q[idx]
            return np.vstack([G[vel_eq], E]), np.concatenate([vel[vel_eq], E @ v])
        qd, miss_v = velocities_from_speeds(model, speeds, params, t0, q, qd, miss_v,
                                            constraint_rows if vel_eq or radial else None, _src(model))
    _, qd, _ = _newton(levels, vel_eq, miss_v, t0, q, qd, "vel")
    if miss_v and not _determined(levels, vel_eq, miss_v, t0, q, qd):
        found = False
        closed_v = [i for i in closed if levels.has_velocity[i]]
        # a closed contact that rolls (mu = inf) or sticks holds its slip at zero: its slip rows
        # complete the velocities as constraints do (the rolling contacts' rows first)
        touching = {rows[i].index for i in closed if rows[i].kind == "contact"}
        slips = [i for i, r in enumerate(rows) if r.kind == "slip" and r.index in touching]
        slips.sort(key=lambda i: rows[i].index not in levels.ck.rolling)
        candidates = closed_v + slips
        for k in range(1, len(candidates) + 1):
            for subset in itertools.combinations(candidates, k):
                rows_try = vel_eq + list(subset)
                _, qd2, ok2 = _newton(levels, rows_try, miss_v, t0, q, qd, "vel")
                if ok2 and _determined(levels, rows_try, miss_v, t0, q, qd2):
                    qd, found = qd2, True
                    break
            if found:
                break
        if not found:
            _unreachable_program(levels, t0, q, qd, miss_v)
            raise InconsistentInitialConditions(
                _missing_values(names, [], 0, miss_v, _undetermined(levels, vel_eq, miss_v, t0, q, qd)),
                _src(model))
    G, pos, vel = levels(t0, q, qd)
    vscale = _scale(qd)
    for i in vel_eq:
        if abs(vel[i]) > GIVEN_TOL * vscale:
            problems.append(
                f"[initial]: constraint '{rows[i].name}' is violated by the initial velocities: "
                f"residual {vel[i]:.3e}; give consistent velocities or leave a dependent velocity out")
    for i in closed:
        if levels.has_velocity[i] and vel[i] < -GIVEN_TOL * vscale:
            what = "contact" if rows[i].kind == "contact" else "unilateral constraint"
            problems.append(
                f"[initial]: {what} '{rows[i].name}' is closed at t0 and the initial velocities "
                f"make it penetrate (rate {vel[i]:.3e} < 0)")
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))
    qd = _project(levels, vel_eq, t0, q, qd, "vel")
    closed_constraints = [rows[i].index for i in closed if rows[i].kind == "constraint"]
    return q, qd, closed_constraints


def support_problems(model, symbols, params, t, q, given=None) -> list[str]:
    """The contacts from geometry whose support point is not unique at the state (a disk lying
    flat, a paraboloid touching from outside its valid side), each named with the reason; with
    *given* (names of the given values), only those whose orientation is given."""
    out = []
    for c in model.contacts:
        if c.geometry is None or c.geometry.validity is None:
            continue
        expr, why = c.geometry.validity
        if given is not None and any(str(s) in model.coordinates and str(s) not in given
                                     for s in expr.free_symbols):
            continue
        values = {sp.Symbol(str(k)): float(v) for k, v in zip(symbols, params)}
        values |= {k: float(v) for k, v in zip(model.q, q)} | {time: float(t)}
        value = float(expr.xreplace(values))
        if not value > 1e-12:
            state = ", ".join(f"{n} = {float(v):.6g}" for n, v in zip(model.coordinates, q))
            out.append(f"contact '{c.name}' (shape {c.shape.TYPE} of body '{c.body}'): no unique "
                       f"support point at the initial state ({state}): {why}")
    return out


def _unreachable_program(levels: _Levels, t, q, qd, missing) -> None:
    """A servo-constraint whose control acts through the dynamics and whose condition of
    dynamics, at the initial configuration, neither holds nor depends on the velocities left
    free: no motion from this state keeps the program (exit code 3, the program and the order
    of the derivative tried named)."""
    kernel = levels.kernel
    G, _, vel = levels(t, q, qd)
    for name, reached in kernel.dyn.servo_reach.items():
        i = kernel.row_index[name]
        if reached.order <= 2 or reached.row.velocity is None:
            continue
        free = np.abs(G[i, missing]).max() if missing else 0.0
        if free <= 1e-12 * (1.0 + np.abs(G[i]).max()) and abs(vel[i]) > GIVEN_TOL * _scale(qd):
            state = {c: float(v) for c, v in zip(kernel.model.coordinates, q)}
            raise MechanicsError(
                f"servo-constraint '{name}' cannot be kept from the initial state: its control acts "
                f"through the dynamics (the program differentiated to order {reached.order}) and its "
                f"condition of dynamics is violated (value {vel[i]:.6g}) without depending on the "
                f"free velocities {', '.join(kernel.model.coordinates[j] + chr(39) for j in missing)} "
                "here: the control cannot reach the program at this configuration; start elsewhere",
                t, state, details={"program": name, "order_tried": reached.order})


def _require_finite(levels, G, pos, vel, t, q, model) -> None:
    """Every constraint row must have a finite value and gradient at the initial state."""
    failure = root_failure(levels.kernel, t, q, levels.last_qd, levels.params)
    if failure is not None:
        raise failure
    problems = []
    names = list(model.coordinates)
    state = ", ".join(f"{c} = {float(v):.6g}" for c, v in zip(names, q))
    for i, row in enumerate(levels.rows):
        values = [pos[i], vel[i], *G[i]]
        if not all(np.isfinite(values)):
            what = "contact" if row.kind == "contact" else "constraint"
            problems.append(
                f"[initial]: {what} '{row.name}' cannot be evaluated at the initial state "
                f"(t = {float(t):.6g}, {state}): its value or gradient is not a finite number "
                "(a square root or logarithm of a negative number, a division by zero, or "
                "asin/acos beyond [-1, 1]); give initial values inside its domain or rewrite it")
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))


def _undetermined(levels, rows, unknown, t, q, qd) -> int:
    """How many of the *unknown* entries the *rows* leave undetermined (rank deficit)."""
    if not unknown:
        return 0
    if not rows:
        return len(unknown)
    G, _, _ = levels(t, q, qd)
    return len(unknown) - int(np.linalg.matrix_rank(G[rows][:, unknown]))


def _missing_values(names, miss_q, need_q, miss_v, need_v) -> list[str]:
    """Messages listing every missing coordinate and velocity at once."""
    def part(kind, missing, need):
        listed = ", ".join(missing)
        if need >= len(missing):
            return (f"{kind} {listed} {'is' if len(missing) == 1 else 'are'} not given and not "
                    "determined by the constraints")
        return (f"{kind} {listed} are not given and the constraints determine only "
                f"{len(missing) - need} of them; give {need} more")
    parts = []
    if need_q:
        parts.append(part("coordinate" if len(miss_q) == 1 else "coordinates",
                          [names[i] for i in miss_q], need_q))
    if need_v:
        parts.append(part("velocity" if len(miss_v) == 1 else "velocities",
                          [names[i] + "'" for i in miss_v], need_v))
    example = []
    if need_q:
        example.append(f"{names[miss_q[0]]} = 0.0")
    if need_v:
        example.append(f"\"{names[miss_v[0]]}'\" = 0.0")
    return [f"[initial]: {p}" for p in parts] + [
        "[initial]: missing initial values; add them to [initial] (e.g. "
        + " and ".join(example) + "; velocity keys are quoted because of the prime); "
        "there are no default values"]


def _missing_positions(levels, pos_rows, miss_q, miss_v, t0, q, qd, converged) -> list[str]:
    names = list(levels.kernel.model.coordinates)
    need_q = _undetermined(levels, pos_rows, miss_q, t0, q, qd)
    if need_q == 0 and not converged:
        _, pos, _ = levels(t0, q, qd)
        bad = ", ".join(f"'{levels.rows[i].name}' (residual {pos[i]:.3e})" for i in pos_rows
                        if abs(pos[i]) > 1e-9 * _scale(q))
        return [f"[initial]: the coordinates {', '.join(names[i] for i in miss_q)} cannot be "
                f"completed: no values satisfy the constraints {bad} with the coordinates given "
                "(Newton's method from 0.1 did not converge); check the given values, or give "
                "these coordinates too"]
    vel_eq = [i for i, r in enumerate(levels.rows)
              if not r.unilateral and levels.has_velocity[i]]
    need_v = _undetermined(levels, vel_eq, miss_v, t0, q, qd)
    return _missing_values(names, miss_q, max(need_q, 1), miss_v, need_v)


def _project(levels: _Levels, rows: Sequence[int], t, q, qd, level: str, iters: int = 8):
    rows = [i for i in rows if (levels.rows[i].holonomic if level == "pos" else levels.has_velocity[i])]
    if not rows:
        return q if level == "pos" else qd
    x = (q if level == "pos" else qd).copy()
    for _ in range(iters):
        G, pos, vel = levels(t, x, qd) if level == "pos" else levels(t, q, x)
        res = (pos if level == "pos" else vel)[rows]
        if np.max(np.abs(res)) < 1e-15 * _scale(x):
            break
        step, *_ = np.linalg.lstsq(G[rows], -res, rcond=None)
        x += step
    return x


def project_positions(kernel: Kernel, rows: Sequence[int], t, q, qd, params, iters: int = 8):
    """Least-norm Newton projection of ``q`` onto the holonomic constraint rows *rows*."""
    return _project(_Levels(kernel, params), list(rows), t, q, qd, "pos", iters)


def project_velocities(kernel: Kernel, rows: Sequence[int], t, q, qd, params, iters: int = 6):
    """Least-norm projection of ``q'`` onto the velocity-level constraint rows *rows*."""
    return _project(_Levels(kernel, params), list(rows), t, q, qd, "vel", iters)


def project_state(kernel: Kernel, rows: Sequence[int], t, q, qd, params):
    """Project a state onto the constraint manifold of the kernel constraint rows *rows*."""
    levels = _Levels(kernel, params)
    q = _project(levels, list(rows), t, q, qd, "pos")
    qd = _project(levels, list(rows), t, q, qd, "vel")
    return q, qd


def random_admissible_states(kernel: Kernel, base_q: np.ndarray, base_qd: np.ndarray,
                             params: np.ndarray, count: int, seed: int = 0, spread: float = 0.3,
                             t0: float = 0.0, rows: Sequence[int] | None = None):
    """Random states satisfying every constraint row (unilateral ones taken as closed).

    Independent coordinates (chosen by pivoted QR of the constraint Jacobian) and velocities
    are perturbed randomly around the base state; dependent ones are solved by Newton.

    Returns
    -------
    list of (t, q, qd)
    """
    levels = _Levels(kernel, params)
    rng = np.random.default_rng(seed)
    if rows is None:
        rows = [i for i, r in enumerate(levels.rows) if r.kind == "constraint"]
    pos_rows = [i for i in rows if levels.rows[i].holonomic]
    vel_rows = [i for i in rows if levels.has_velocity[i]]
    out = []
    attempts = 0
    while len(out) < count and attempts < 20 * count:
        attempts += 1
        t = t0 + rng.uniform(0, 1)
        q = base_q.copy()
        G, _, _ = levels(t, q, base_qd)
        dep = sorted(qr(G[pos_rows], pivoting=True)[2][:len(pos_rows)]) if pos_rows else []
        ind = [j for j in range(kernel.n) if j not in dep]
        q[ind] += spread * rng.standard_normal(len(ind))
        if dep:
            q, _, ok = _newton(levels, pos_rows, dep, t, q, base_qd, "pos")
            if not ok:
                continue
        qd = base_qd + rng.standard_normal(kernel.n) * (spread + 0.5 * np.abs(base_qd))
        G, _, _ = levels(t, q, qd)
        if vel_rows:
            depv = sorted(qr(G[vel_rows], pivoting=True)[2][:len(vel_rows)])
            _, qd, ok = _newton(levels, vel_rows, depv, t, q, qd, "vel")
            if not ok:
                continue
        out.append((t, q, qd))
    return out


def initial_branch(model) -> dict[str, float] | None:
    """The model's initial coordinates completed from its constraints, when some are missing.

    Lagrange II chooses the roots of the holonomic constraints through these coordinates
    (``derive(..., branch=)``).  ``None`` when the model gives every coordinate, or when they
    cannot be completed (that error is reported where the state is needed).
    """
    given = model.numeric_initial()
    coords = list(model.coordinates)
    if all(c in given for c in coords):
        return None
    try:
        q0, _, _ = complete_state(kernel_of(model), given, parameter_vector(model), model.t0)
    except (NonidealError, ValueError, ArithmeticError, RuntimeError, TypeError):
        return None
    return {c: float(v) for c, v in zip(coords, q0)}

