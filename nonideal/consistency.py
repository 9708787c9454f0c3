"""Consistent states: complete an initial state from the constraints, project onto the
constraint manifold, and draw random admissible states (for the cross-form tests).

Missing coordinates are solved from the holonomic constraints (Gauss--Newton from a start
value of 0.1, or from a neighbouring state), missing velocities from the velocity-level
constraints.  A given value that violates a constraint is an error that names the constraint
and the residual; it is never silently "fixed" beyond round-off (relative 1e-9).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence

import numpy as np
from scipy.linalg import qr

from .errors import InconsistentInitialConditions
from .numeric import Kernel

__all__ = ["complete_state", "project_state", "random_admissible_states", "GIVEN_TOL"]

GIVEN_TOL = 1e-9     # relative tolerance on given values (beyond: error)
NEWTON_TOL = 1e-13


def _scale(values: np.ndarray) -> float:
    return 1.0 + float(np.max(np.abs(values))) if values.size else 1.0


def _eval(kernel: Kernel, t: float, q: np.ndarray, qd: np.ndarray, params: np.ndarray):
    x = kernel.state_input(t, q, qd, params)
    dyn = kernel.dynamics(x)
    obs = kernel.observables(x)
    return dyn, obs


def _newton(kernel: Kernel, rows: list[int], unknown: list[int], t, q, qd, params, level: str,
            max_iter: int = 60):
    """Solve the residuals of *rows* at *level* ("pos" or "vel") for the *unknown* entries.

    Returns ``(q, qd, converged)``.
    """
    q, qd = q.copy(), qd.copy()
    if not rows or not unknown:
        return q, qd, True
    for _ in range(max_iter):
        dyn, obs = _eval(kernel, t, q, qd, params)
        res = obs[level][rows]
        if np.max(np.abs(res)) < NEWTON_TOL * _scale(q if level == "pos" else qd):
            return q, qd, True
        J = dyn["G"][rows][:, unknown]
        step, *_ = np.linalg.lstsq(J, -res, rcond=None)
        target = q if level == "pos" else qd
        target[unknown] += step
    dyn, obs = _eval(kernel, t, q, qd, params)
    ok = np.max(np.abs(obs[level][rows])) < 1e-9 * _scale(q if level == "pos" else qd)
    return q, qd, bool(ok)


def _solve_level(kernel, rows, missing, t, q, qd, params, level):
    return _newton(kernel, rows, missing, t, q, qd, params, level)


def complete_state(kernel: Kernel, given: Mapping[str, float], params: np.ndarray, t0: float,
                   active: Sequence[int] | None = None, guess: Mapping[str, float] | None = None):
    """Complete and check an initial state.

    Parameters
    ----------
    kernel : Kernel
    given : mapping name -> value
        Coordinates (``"x"``) and velocities (``"x'"``) given by the user.
    params : ndarray
    t0 : float
    active : sequence of int, optional
        Constraint rows that must hold (default: every bilateral row; unilateral rows are
        added as closed contacts when the coordinates cannot be determined otherwise).
    guess : mapping, optional
        Start values for missing coordinates (default 0.1).

    Returns
    -------
    q, qd : ndarray, shape (n_q,)
    closed : list of int
        Unilateral rows that are closed (gap ~ 0) at the initial state.

    Raises
    ------
    InconsistentInitialConditions
    """
    model = kernel.model
    names = list(model.coordinates)
    n = kernel.n
    rows = kernel.rows
    bilateral = [i for i, r in enumerate(rows) if not r.unilateral]
    unilateral = [i for i, r in enumerate(rows) if r.unilateral]
    if active is None:
        active = bilateral
    q = np.array([given.get(c, (guess or {}).get(c, 0.1)) for c in names], dtype=float)
    qd = np.array([given.get(c + "'", 0.0) for c in names], dtype=float)
    miss_q = [i for i, c in enumerate(names) if c not in given]
    miss_v = [i for i, c in enumerate(names) if c + "'" not in given]
    problems = []

    pos_rows = [i for i in active if rows[i].position is not None]
    start_q = q.copy()

    def determined(rows_used, q_try):
        dyn_, _ = _eval(kernel, t0, q_try, qd, params)
        return bool(rows_used) and np.linalg.matrix_rank(dyn_["G"][rows_used][:, miss_q]) == len(miss_q)

    q, qd, ok = _solve_level(kernel, pos_rows, miss_q, t0, start_q, qd, params, "pos")
    if miss_q and not (ok and determined(pos_rows, q)):
        # close unilateral constraints (contacts assumed closed at t0), smallest sets first
        found = False
        extra = [i for i in unilateral if i not in active]
        for k in range(1, len(extra) + 1):
            for subset in itertools.combinations(extra, k):
                rows_try = pos_rows + list(subset)
                if len(rows_try) < len(miss_q):
                    continue
                q2, qd, ok2 = _solve_level(kernel, rows_try, miss_q, t0, start_q, qd, params, "pos")
                if not (ok2 and determined(rows_try, q2)):
                    continue
                _, obs2 = _eval(kernel, t0, q2, qd, params)
                if all(obs2["pos"][i] >= -GIVEN_TOL * _scale(q2) for i in unilateral):
                    q, pos_rows, active, found = q2, rows_try, list(active) + list(subset), True
                    break
            if found:
                break
        if not found:
            missing = [names[i] for i in miss_q]
            raise InconsistentInitialConditions(
                f"[initial]: coordinates {missing} are not given and cannot be determined from "
                "the constraints; give them in [initial]", _src(model))
    dyn, obs = _eval(kernel, t0, q, qd, params)
    scale = _scale(q)
    for i in pos_rows:
        res = obs["pos"][i]
        if abs(res) > GIVEN_TOL * scale:
            problems.append(
                f"[initial]: constraint '{rows[i].name}' is violated by the initial coordinates: "
                f"residual {res:.3e}; give consistent values (expressions in the parameters are "
                "allowed) or leave a dependent coordinate out to have it completed"
            )
    for i in unilateral:
        res = obs["pos"][i]
        if res < -GIVEN_TOL * scale:
            problems.append(
                f"[initial]: unilateral constraint '{rows[i].name}' is violated (value {res:.3e} < 0)"
            )
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))
    closed = [i for i in unilateral if abs(obs["pos"][i]) <= GIVEN_TOL * scale]
    vel_active = [i for i in active if rows[i].velocity is not None]
    vel_active += [i for i in closed if i not in vel_active]
    q = project_positions(kernel, [i for i in pos_rows] + [i for i in closed if i not in pos_rows], t0, q, qd, params)

    qd, ok = _velocities(kernel, vel_active, miss_v, t0, q, qd, params, given, names)
    dyn, obs = _eval(kernel, t0, q, qd, params)
    vscale = _scale(qd)
    for i in vel_active:
        res = obs["vel"][i]
        if abs(res) > GIVEN_TOL * vscale:
            kind = "unilateral constraint (closed at t0)" if rows[i].unilateral else "constraint"
            if rows[i].unilateral and res > 0:
                continue  # separating from a closed contact is allowed
            problems.append(
                f"[initial]: {kind} '{rows[i].name}' is violated by the initial velocities: "
                f"residual {res:.3e}; give consistent velocities or leave a dependent velocity out"
            )
    if problems:
        raise InconsistentInitialConditions(problems, _src(model))
    return q, qd, closed


def _velocities(kernel, rows_v, miss_v, t0, q, qd, params, given, names):
    if not miss_v:
        return qd, True
    # unilateral rows that separate are inequalities: use only equality rows first
    eq_rows = [i for i in rows_v if not kernel.rows[i].unilateral]
    q_, qd, ok = _solve_level(kernel, eq_rows, miss_v, t0, q, qd, params, "vel")
    dyn, obs = _eval(kernel, t0, q, qd, params)
    G = dyn["G"]
    rank_eq = np.linalg.matrix_rank(G[eq_rows][:, miss_v]) if eq_rows else 0
    if rank_eq < len(miss_v):
        uni = [i for i in rows_v if kernel.rows[i].unilateral]
        rows_all = eq_rows + uni
        q_, qd, ok = _solve_level(kernel, rows_all, miss_v, t0, q, qd, params, "vel")
        dyn, _ = _eval(kernel, t0, q, qd, params)
        rank = np.linalg.matrix_rank(dyn["G"][rows_all][:, miss_v]) if rows_all else 0
        if rank < len(miss_v):
            missing = [names[i] + "'" for i in miss_v]
            raise InconsistentInitialConditions(
                f"[initial]: velocities {missing} are not given and cannot be determined from "
                "the constraints; give them in [initial]", _src(kernel.model))
    return qd, ok


def _src(model):
    return None if model.source == "<api>" else model.source


def project_positions(kernel: Kernel, rows: Sequence[int], t, q, qd, params, iters: int = 8):
    """Least-norm Newton projection of ``q`` onto ``f_rows(q, t) = 0``."""
    rows = [i for i in rows if kernel.rows[i].position is not None]
    if not rows:
        return q
    q = q.copy()
    for _ in range(iters):
        dyn, obs = _eval(kernel, t, q, qd, params)
        res = obs["pos"][rows]
        if np.max(np.abs(res)) < 1e-15 * _scale(q):
            break
        step, *_ = np.linalg.lstsq(dyn["G"][rows], -res, rcond=None)
        q += step
    return q


def project_velocities(kernel: Kernel, rows: Sequence[int], t, q, qd, params, iters: int = 6):
    """Least-norm projection of ``q'`` onto the velocity-level constraints of *rows*."""
    rows = [i for i in rows if kernel.rows[i].velocity is not None]
    if not rows:
        return qd
    qd = qd.copy()
    for _ in range(iters):
        dyn, obs = _eval(kernel, t, q, qd, params)
        res = obs["vel"][rows]
        if np.max(np.abs(res)) < 1e-15 * _scale(qd):
            break
        step, *_ = np.linalg.lstsq(dyn["G"][rows], -res, rcond=None)
        qd += step
    return qd


def project_state(kernel: Kernel, rows: Sequence[int], t, q, qd, params):
    """Project a state onto the constraint manifold of *rows* (positions, then velocities)."""
    q = project_positions(kernel, rows, t, q, qd, params)
    qd = project_velocities(kernel, rows, t, q, qd, params)
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
    rng = np.random.default_rng(seed)
    if rows is None:
        rows = list(range(len(kernel.rows)))
    pos_rows = [i for i in rows if kernel.rows[i].position is not None]
    vel_rows = [i for i in rows if kernel.rows[i].velocity is not None]
    out = []
    attempts = 0
    while len(out) < count and attempts < 20 * count:
        attempts += 1
        t = t0 + rng.uniform(0, 1)
        q = base_q.copy()
        dyn, _ = _eval(kernel, t, q, base_qd, params)
        if pos_rows:
            _, _, piv = qr(dyn["G"][pos_rows], pivoting=True)
            dep = sorted(piv[:len(pos_rows)])
        else:
            dep = []
        ind = [j for j in range(kernel.n) if j not in dep]
        q[ind] += spread * rng.standard_normal(len(ind))
        if dep:
            q, _, ok = _newton(kernel, pos_rows, dep, t, q, base_qd, params, "pos")
            if not ok:
                continue
        qd = base_qd + rng.standard_normal(kernel.n) * (spread + 0.5 * np.abs(base_qd))
        dyn, _ = _eval(kernel, t, q, qd, params)
        if vel_rows:
            _, _, piv = qr(dyn["G"][vel_rows], pivoting=True)
            depv = sorted(piv[:len(vel_rows)])
            _, qd, ok = _newton(kernel, vel_rows, depv, t, q, qd, params, "vel")
            if not ok:
                continue
        out.append((t, q, qd))
    return out
