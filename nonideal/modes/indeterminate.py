"""Statically indeterminate reactions: the admissible distribution with the widest margins.

When the rows of a mode are dependent -- a ladder sticking at a rough wall and a rough floor
(four rows on three coordinates), a table whose legs stick to a rough floor -- the
accelerations are unique but the multipliers are not: with ``B`` the mode's reaction columns
and ``R = M q'' - F`` the total generalized reaction, every

    lambda = lambda_p + Z w,        B lambda_p = R,   B Z = 0

(``lambda_p`` the minimum-norm solution, ``Z`` an orthonormal basis of the null space of ``B``)
gives the same motion.  In rigid-body Coulomb theory the mode continues as long as SOME
distribution satisfies every condition of the rows it involves:

* a held unilateral constraint: ``lambda >= 0``;
* a touching contact: ``N >= 0`` (``sigma N >= 0`` for a bilateral one sliding);
* a sticking contact: ``mu_s N - |F| >= 0`` -- two linear conditions for one slip component,
  a second-order cone (the disc ``|F| <= mu_s N``) for two; a bilateral contact uses ``|N|``
  with the sign of ``N`` in the minimum-norm distribution.

:func:`best_distribution` reports the distribution that maximizes the smallest of these
margins (force units) over the conditions whose rows are indeterminate (rows with a zero row of
``Z`` keep their unique multiplier and their own events) and, among those (a table on four legs
has a family of them), the one of least norm; the margin is capped at the scale of the forces,
``1 + max |R| + max |lambda_p|``, so that a body wedged between rough supports, whose margins
have no bound, gets finite forces.  The stick/slip decisions then read it: a mode
is consistent iff its best margin is >= 0, and the events of the contacts (slip, lift-off) fire
where the best margin reaches zero -- when no admissible distribution is left -- at the
contact whose condition binds.  The minimum-norm distribution, used before, could violate a
cone while another distribution satisfied all of them (spurious slip events at times that
followed the step size).

Solution.  Maximize ``t`` over ``(w, t)`` subject to ``margin_i(lambda_p + Z w) >= t``: a linear
program for linear conditions (:func:`scipy.optimize.linprog`, HiGHS); each disc is replaced by
an outer polygon (its tangent half-planes ``u . F <= mu_s N - t``), refined by cuts at the
friction direction of the current solution (Kelley's cutting planes), and the solution is
polished by Newton's method on the optimality conditions of the active conditions (the discs
as the smooth ``mu_s N - |F|``).  Every candidate's smallest margin is evaluated exactly, so
the value returned is always attained by the distribution returned; the outer polygon's optimum
bounds it from above, and the iteration stops when the two agree to ``1e-12`` of the force
scale (machine precision for linear conditions; for discs after a few cuts).  That makes the
slip events as exact as the others: Brent's method on the margin locates them to ~1e-12 of
the force scale over the margin's rate.  The maximizer of least norm is then the point of least
norm where every margin is at least the optimum: least-distance programming (Lawson & Hanson,
one non-negative least-squares problem) on the polygons, cut again where a disc is violated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog, nnls

from .types import STICK

__all__ = ["Distribution", "best_distribution", "maxmin", "least_norm_distribution", "row_weights",
           "admissible_ranges", "split_report", "split_phases", "RULE_TEXT", "minimum_norm"]

#: how each rule of ``[simulation] split`` is described in the outputs
RULE_TEXT = {
    "widest-margin": "widest margin (the distribution maximizing the smallest of N, mu_s N - |F| "
                     "and the held multipliers; the least-norm one among several)",
    "least-norm": "least norm (the admissible distribution minimizing the sum of the squared "
                  "reactions, each weighted by its compliance: the limit of stiff elastic "
                  "supports, Menabrea's least work)",
}

#: singular values of ``B`` below this (relative) span its null space
NULL_RTOL = 1e-10
#: rows of ``Z`` (orthonormal) below this norm are determinate
DETERMINATE_TOL = 1e-9
#: the outer polygon's optimum and the best margin found agree to this (of the force scale)
GAP_TOL = 1e-12
MAX_CUTS = 40
_HIGHS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


@dataclass(frozen=True)
class Distribution:
    """The multipliers of a mode's rows chosen by :func:`best_distribution`.

    Attributes
    ----------
    values : ndarray, shape (m,)
        Multipliers of the layout rows.
    margin : float
        The smallest margin of the conditions that involve indeterminate rows (``inf`` when
        none does).
    determinate : frozenset of str
        Names of the rows whose multiplier is unique.
    """

    values: np.ndarray
    margin: float
    determinate: frozenset[str]


def _solutions(B: np.ndarray, R: np.ndarray):
    """Every solution of ``B lambda = R``: the least-norm one, a basis ``Z`` of the null space
    (``lambda + Z w``) and which multipliers the null space moves (the indeterminate ones)."""
    U, S, Vt = np.linalg.svd(B, full_matrices=True)
    rank = int(np.sum(S > NULL_RTOL * max(S[0], 1e-300))) if S.size else 0
    lam = Vt[:rank].T @ ((U[:, :rank].T @ R) / S[:rank])
    Z = Vt[rank:].T
    free = np.linalg.norm(Z, axis=1) > DETERMINATE_TOL if Z.size else np.zeros(B.shape[1], dtype=bool)
    return lam, Z, free


def best_distribution(solver, mode, layout, B: np.ndarray, R: np.ndarray, cout: dict) -> Distribution:
    """The admissible distribution of a dependent mode's multipliers with the widest margins
    (see the module docstring).

    Parameters
    ----------
    solver : ModeSolver
    mode : Mode
    layout : list of RowSpec
        The mode's rows.
    B : ndarray, shape (n_q, m)
        Their reaction columns at the state.
    R : ndarray, shape (n_q,)
        The total generalized reaction ``M q'' - F``.
    cout : dict
        The contact kernel's outputs at the state (``mu_s``).

    Returns
    -------
    Distribution
    """
    lam, Z, free = _solutions(B, R)
    determinate = frozenset(r.name for r, f in zip(layout, free) if not f)
    linear, cones = _conditions(solver, mode, layout, lam, cout, free)
    if not free.any() or not (linear or cones):
        return Distribution(lam, np.inf, determinate)
    scale = 1.0 + float(np.max(np.abs(R))) + float(np.max(np.abs(lam)))
    # the conditions in w, per unit of the force scale
    lin_a = np.array([Z.T @ c for c in linear]).reshape(len(linear), Z.shape[1])
    lin_b = np.array([c @ lam for c in linear]) / scale
    cone_data = [(Z.T @ nv, nv @ lam / scale, T @ Z, T @ lam / scale) for nv, T in cones]
    w, t = maxmin(lin_a, lin_b, cone_data, cap=1.0)
    return Distribution(lam + Z @ (w * scale), t * scale, determinate)


def row_weights(solver, layout, weights) -> np.ndarray:
    """The compliance of each layout row from ``[simulation] split_weights`` (*weights*: name ->
    ``(c,)`` or ``(c_normal, c_tangential)``; 1 where not given)."""
    names = solver.ck.names if solver.ck else []
    out = np.ones(len(layout))
    for j, r in enumerate(layout):
        name = solver.kernel.rows[r.index].name if r.kind == "constraint" else names[r.index]
        w = weights.get(name)
        if w:
            out[j] = w[-1] if r.kind == "tangent" else w[0]
    return out


def least_norm_distribution(solver, mode, layout, B: np.ndarray, R: np.ndarray, cout: dict,
                            weights: np.ndarray) -> np.ndarray | None:
    """The admissible distribution of least weighted norm: ``min sum_j c_j lambda_j^2`` over
    ``lambda = lambda_p + Z w`` with every condition of the module docstring satisfied (``c_j``
    the rows' compliances *weights*).  With ``c_j = 1/k_j`` this is the complementary energy of
    supports of stiffness ``k_j`` (Menabrea's least work): the rigid limit of stiff elastic
    supports loaded from rest, as long as none of them slips.  Solved as least-distance
    programming (:meth:`_Problem.least_norm`) in the coordinates ``v = R w + Q^T b`` of the
    factorization ``D Z = Q R`` (``D = diag(sqrt(c))``, ``b = D lambda_p``); None when no
    distribution is admissible (at a switching instant) or the cuts do not converge.

    Parameters
    ----------
    solver, mode, layout, B, R, cout
        As for :func:`best_distribution`.
    weights : ndarray, shape (m,)
        Compliance of each layout row (> 0).

    Returns
    -------
    ndarray, shape (m,), or None
    """
    lam, Z, free = _solutions(B, R)
    if not free.any():
        return lam
    linear, cones = _conditions(solver, mode, layout, lam, cout, free)
    scale = 1.0 + float(np.max(np.abs(R))) + float(np.max(np.abs(lam)))
    if not (linear or cones):       # nothing bounds the split: the weighted least squares
        D = np.sqrt(np.asarray(weights, dtype=float))
        w = np.linalg.lstsq(D[:, None] * Z, -D * lam, rcond=None)[0]
        return lam + Z @ w
    D = np.sqrt(np.asarray(weights, dtype=float))
    Q, Rf = np.linalg.qr(D[:, None] * Z)
    c0 = Q.T @ (D * lam) / scale
    Ri = np.linalg.inv(Rf)          # w = Ri (v - c0), in units of the force scale
    lin_a = np.array([Z.T @ c for c in linear]).reshape(len(linear), Z.shape[1]) @ Ri
    lin_b = np.array([c @ lam for c in linear]) / scale - lin_a @ c0
    cone_data = []
    for nv, T in cones:
        a, A = (Z.T @ nv) @ Ri, (T @ Z) @ Ri
        cone_data.append((a, nv @ lam / scale - a @ c0, A, T @ lam / scale - A @ c0))
    problem = _Problem(lin_a, lin_b, cone_data)
    v = problem.least_norm(0.0, None)
    if v is None:
        return None
    return lam + Z @ (Ri @ (v - c0) * scale)


def _conditions(solver, mode, layout, lam, cout, free):
    """The conditions of the module docstring whose rows include an indeterminate one, as
    vectors over the multipliers: linear ``c . lambda >= t``; cones ``n . lambda - |T lambda| >= t``
    (``n`` carrying ``mu_s`` and the sign)."""
    m = len(layout)
    linear, cones = [], []
    tangents: dict[int, list[int]] = {}
    for j, r in enumerate(layout):
        if r.kind == "tangent":
            tangents.setdefault(r.index, []).append(j)

    def unit(j, factor=1.0):
        v = np.zeros(m)
        v[j] = factor
        return v
    for j, r in enumerate(layout):
        if r.kind == "constraint":
            if solver.kernel.rows[r.index].unilateral and free[j]:
                linear.append(unit(j))
            continue
        if r.kind != "normal":
            continue
        c = r.index
        cs = mode.contacts[c][1]
        rows = [j] + tangents.get(c, [])
        if not free[rows].any():
            continue
        bilateral = solver.ck.data[c].bilateral
        sigma = cs.sigma if not bilateral or cs.state != STICK else (1.0 if lam[j] >= 0 else -1.0)
        if not bilateral or cs.state != STICK:
            linear.append(unit(j, sigma))
        if cs.state == STICK and c not in solver.rolling:  # ideal rolling (mu = inf): no cone
            nv = unit(j, sigma * float(cout["mu_s"][c]))
            T = np.array([unit(k) for k in tangents[c]])
            if len(T) == 1:
                linear += [nv - T[0], nv + T[0]]
            else:
                cones.append((nv, T))
    normal = {r.index: j for j, r in enumerate(layout) if r.kind == "normal"}
    for c in solver.ck.torques:   # a sticking friction torque: |M| <= l N of its contact
        j = normal.get(solver.ck.parents[c])
        if mode.contacts[c][1].state != STICK or j is None or not free[[j] + tangents[c]].any():
            continue
        nv = unit(j, float(cout["mu_s"][c]))
        T = np.array([unit(k) for k in tangents[c]])
        if len(T) == 1:
            linear += [nv - T[0], nv + T[0]]
        else:
            cones.append((nv, T))
    return linear, cones


def maxmin(lin_a: np.ndarray, lin_b: np.ndarray, cones, cap: float):
    """Maximize the smallest of the concave margins ``lin_a w + lin_b`` and
    ``a_N . w + b_N - |A_F w + b_F|`` (for ``(a_N, b_N, A_F, b_F)`` in *cones*), capped at
    *cap*; among the maximizers, the one of least norm.

    Returns
    -------
    w : ndarray, shape (k,)
        The maximizer (its components along directions no margin depends on are zero).
    t : float
        Its smallest margin (``<= cap``).

    Examples
    --------
    >>> w, t = maxmin(np.array([[1.0], [-1.0]]), np.array([0.0, 1.0]), [], cap=10.0)
    >>> round(float(w[0]), 14), round(float(t), 14)
    (0.5, 0.5)
    >>> w, t = maxmin(np.zeros((0, 2)), np.zeros(0), [(np.zeros(2), 1.0, np.eye(2), np.array([0.6, 0.8]))], 10.0)
    >>> np.allclose(w, [-0.6, -0.8]), round(float(t), 12)
    (True, 1.0)
    """
    k = lin_a.shape[1]
    rows = list(lin_a) + [a for a, _, _, _ in cones] + [r for _, _, A, _ in cones for r in A]
    # the directions some margin depends on (w = Q v, v in them): the program has vertices
    _, S, Vt = np.linalg.svd(np.array(rows).reshape(len(rows), k))
    Q = Vt[:int(np.sum(S > 1e-12 * max(S[0], 1e-300)))].T if S.size else np.zeros((k, 0))
    problem = _Problem(lin_a @ Q, lin_b, [(a @ Q, b, A @ Q, f) for a, b, A, f in cones])
    v, t = problem.solve(cap)
    v = problem.least_norm(t, v)
    return Q @ v, min(float(np.min(problem.margins(v))), cap)


class _Problem:
    """``max t`` subject to ``margin_i(v) >= t``, ``t <= cap``, in coordinates ``v`` on which the
    margins depend (the full-column-rank form of :func:`maxmin`); the discs' polygons
    (:attr:`cuts`, unit vectors ``u``: ``u . F <= mu_s N - t``) grow with every solve."""

    def __init__(self, lin_a, lin_b, cones):
        self.lin_a, self.lin_b, self.cones = lin_a, lin_b, cones
        self.p = lin_a.shape[1] if lin_a.size else (cones[0][0].size if cones else 0)
        angles = np.arange(8) * np.pi / 4
        self.cuts = [[np.array([np.cos(a), np.sin(a)]) for a in angles] for _ in cones]

    def margins(self, v: np.ndarray) -> np.ndarray:
        """Every margin at ``v`` (linear ones first)."""
        out = list(self.lin_a @ v + self.lin_b) if len(self.lin_b) else []
        for a, b, A, f in self.cones:
            out.append(a @ v + b - float(np.linalg.norm(A @ v + f)))
        return np.array(out)

    def _cut(self, v: np.ndarray, below: float = np.inf) -> None:
        """Add to each disc's polygon the tangent at the friction direction at ``v`` (only for
        the discs whose margin there is below *below*)."""
        for cut, (a, b, A, f) in zip(self.cuts, self.cones):
            F = A @ v + f
            norm = float(np.linalg.norm(F))
            if norm > 1e-14 and a @ v + b - norm < below:
                cut.append(F / norm)

    def _rows(self):
        """The margins with the discs replaced by their polygons: ``G v + h >= t`` for every
        row, and the disc of each row (None for a linear margin)."""
        G, h, disc = list(self.lin_a), list(self.lin_b), [None] * len(self.lin_b)
        for i, (cut, (a, b, A, f)) in enumerate(zip(self.cuts, self.cones)):
            for u in cut:  # a v + b - u . (A v + f) >= t
                G.append(a - u @ A)
                h.append(b - u @ f)
                disc.append(i)
        return np.array(G).reshape(len(h), self.p), np.array(h), disc

    def solve(self, cap: float):
        """The maximizer ``(v, t)`` (see the module docstring)."""
        best_v, best_t = None, -np.inf
        for _ in range(MAX_CUTS):
            v, t_out, duals = self._outer(cap)
            candidates = [v]
            polished = self._polish(v, duals)
            if polished is not None:
                candidates.append(polished)
            for u in candidates:
                t_in = min(float(np.min(self.margins(u))), cap)
                if t_in > best_t:
                    best_v, best_t = u, t_in
            if t_out - best_t <= GAP_TOL:
                break
            for u in candidates:
                self._cut(u)
        return best_v, best_t

    def _outer(self, cap):
        """The linear program with every disc replaced by its polygon: ``(v, t, duals)``,
        ``duals`` the multipliers of the linear margins, then of each disc (its cuts summed)."""
        G, h, disc = self._rows()
        res = linprog(np.concatenate((np.zeros(self.p), [-1.0])), A_ub=np.hstack((-G, np.ones((len(h), 1)))),
                      b_ub=h, bounds=[(None, None)] * self.p + [(None, cap)], method="highs", options=_HIGHS)
        marg = -res.ineqlin.marginals
        nl = len(self.lin_b)
        duals = np.zeros(nl + len(self.cones))
        duals[:nl] = marg[:nl]
        for d, i in zip(marg[nl:], disc[nl:]):
            duals[nl + i] += d
        return res.x[:self.p], float(res.x[self.p]), duals

    def least_norm(self, t: float, v0: np.ndarray) -> np.ndarray:
        """The least-norm ``v`` with every margin ``>= t`` (when *t* is the optimum: the
        maximizer of least norm), by least-distance programming on the polygons
        (:func:`_least_distance`) with cuts where a disc is violated; *v0* (a maximizer) when
        that does not converge."""
        for _ in range(MAX_CUTS):
            G, h, _ = self._rows()
            v = _least_distance(G, t - h)
            if v is None:
                break
            if float(np.min(self.margins(v))) >= t - GAP_TOL:
                return v
            self._cut(v, below=t - GAP_TOL)
        return v0

    def _polish(self, v, duals):
        """Newton's method on the optimality conditions of the active margins (positive
        *duals*): ``sum nu_i grad_i = 0``, ``sum nu_i = 1``, ``margin_i(v) = t``; None when it
        does not converge or a disc's friction vanishes on the way (its apex, where the
        polygon is exact)."""
        active = [i for i, d in enumerate(duals) if d > 1e-12]
        if not active or len(active) > self.p + 1:
            return None
        nl = len(self.lin_b)
        nu = np.array([duals[i] for i in active])
        nu /= nu.sum()
        t = float(np.min(self.margins(v)))
        p, a = self.p, len(active)
        for _ in range(20):
            grads, values = np.zeros((a, p)), np.zeros(a)
            H = np.zeros((p, p))
            for row, i in enumerate(active):
                if i < nl:
                    grads[row], values[row] = self.lin_a[i], self.lin_a[i] @ v + self.lin_b[i]
                    continue
                ca, cb, A, f = self.cones[i - nl]
                F = A @ v + f
                norm = float(np.linalg.norm(F))
                if norm < 1e-12:
                    return None
                u = F / norm
                grads[row], values[row] = ca - A.T @ u, ca @ v + cb - norm
                H -= nu[row] * (A.T @ (np.eye(len(F)) - np.outer(u, u)) @ A) / norm
            res = np.concatenate((grads.T @ nu, [1.0 - nu.sum()], values - t))
            if float(np.max(np.abs(res))) <= 1e-15:
                break
            J = np.zeros((p + 1 + a, p + 1 + a))
            J[:p, :p] = H
            J[:p, p + 1:] = grads.T
            J[p, p + 1:] = -1.0
            J[p + 1:, :p] = grads
            J[p + 1:, p] = -1.0
            step = np.linalg.lstsq(J, -res, rcond=None)[0]
            v, t, nu = v + step[:p], t + step[p], nu + step[p + 1:]
        else:
            return None
        return v


def _least_distance(G: np.ndarray, h: np.ndarray) -> np.ndarray | None:
    """``min |v|`` subject to ``G v >= h`` (Lawson & Hanson's least-distance programming,
    *Solving Least Squares Problems* (1974), ch. 23: one non-negative least-squares problem);
    None when the constraints are incompatible."""
    E = np.vstack((G.T, h[None, :]))
    f = np.zeros(E.shape[0])
    f[-1] = 1.0
    u, _ = nnls(E, f)
    r = E @ u - f
    if abs(r[-1]) < 1e-14:
        return None
    return -r[:-1] / r[-1]


def admissible_ranges(solver, mode, layout, B: np.ndarray, R: np.ndarray, cout: dict,
                      sides: int = 64) -> dict[int, tuple[float, float]]:
    """The range of each indeterminate multiplier over ALL admissible distributions: for each
    layout row ``j`` whose multiplier is not unique, ``(min, max)`` of ``lambda_j`` over
    ``lambda_p + Z w`` subject to the conditions of the module docstring (a disc
    ``|F| <= mu_s N`` replaced by its inscribed polygon of *sides* sides, so that the bounds
    are attained).  ``-inf``/``inf`` where a bound does not exist.  Empty when the mode is
    determinate or has no admissible distribution."""
    lam, Z, free = _solutions(B, R)
    if not free.any():
        return {}
    linear, cones = _conditions(solver, mode, layout, lam, cout, free)
    rows = [c for c in linear]
    for nv, T in cones:               # n . lambda - |T lambda| >= 0, inscribed polygon
        c = np.cos(np.pi / sides)
        for k in range(sides):
            u = np.array([np.cos(2 * np.pi * k / sides), np.sin(2 * np.pi * k / sides)])[:len(T)]
            rows.append(c * nv - u @ T)
    A = np.array([Z.T @ r for r in rows]).reshape(len(rows), Z.shape[1])
    b = np.array([r @ lam for r in rows])
    out = {}
    for j in np.flatnonzero(free):
        bounds = []
        for sign in (1.0, -1.0):      # min and max of lam_j + Z_j w  s.t.  A w + b >= 0
            res = linprog(sign * Z[j], A_ub=-A, b_ub=b, bounds=[(None, None)] * Z.shape[1],
                          method="highs")
            if res.status == 3:
                bounds.append(-sign * np.inf)
            elif res.status != 0:
                return {}
            else:
                bounds.append(lam[j] + sign * res.fun)
        out[int(j)] = (float(bounds[0]), float(bounds[1]))
    return out


def split_report(solver, mode, sol, t: float, q: np.ndarray, qd: np.ndarray) -> dict:
    """The rule of the split shown (``[simulation] split``) and the admissible range of each
    statically indeterminate force, ``{"rule", "ranges": {label: [min, max, shown]}}``; empty
    when the mode's reactions are unique.  Labels: ``N <contact>``, ``F <contact>`` (``[k]``
    for a component of two), ``lambda_<constraint>``.

    Parameters
    ----------
    solver : ModeSolver
    mode : Mode
    sol : Solution
        The motion at the state, with the reported multipliers (``Solution.reported``).
    t : float
    q, qd : ndarray, shape (n_q,)
    """
    if not sol.layout or not solver.system(mode).dependent(sol.Gm):
        return {}
    cout = solver.ck(solver.input(t, q, qd)) if solver.ck else {}
    ranges = admissible_ranges(solver, mode, sol.layout, sol.Bm, sol.M @ sol.qdd - sol.F, cout)
    names = solver.ck.names if solver.ck else []
    shown = sol.reported.values
    out = {}
    for j, (lo, hi) in ranges.items():
        r = sol.layout[j]
        if r.kind == "constraint":
            label = f"lambda_{solver.kernel.rows[r.index].name}"
        elif r.kind == "normal":
            label = f"N {names[r.index]}"
        else:
            label = f"F {names[r.index]}" + (f"[{r.k + 1}]" if solver.ck.dims[r.index] > 1 else "")
        out[label] = [lo, hi, float(shown[j])]
    rule = solver.split[0]
    return {"rule": RULE_TEXT[rule], "split": rule, "ranges": out}


def split_phases(solver, motions) -> dict:
    """Where along a trajectory the reactions are statically indeterminate: ``{"rule", "split",
    "phases": [{"t": [start, end], "mode", "start": ranges, "end": ranges}]}`` (ranges as in
    :func:`split_report`, at the first and last sample of each phase); empty when nowhere.

    Parameters
    ----------
    solver : ModeSolver
    motions : sequence of Motion or None
        The motion at each sample, in time order (None: a sample of a mode without rows).
    """
    phases, previous = [], -2
    for k, m in enumerate(motions):
        if m is None or not m.indeterminate:
            continue
        label = m.mode.label()
        if phases and phases[-1][0] == label and previous == k - 1:
            phases[-1][2] = m
        else:
            phases.append([label, m, m])
        previous = k
    if not phases:
        return {}
    out = []
    for label, first, last in phases:
        entry = {"t": [float(first.t), float(last.t)], "mode": label}
        for key, m in (("start", first), ("end", last)):
            sol = solver.solve(m.t, m.q, m.qd, m.mode).reported
            entry[key] = split_report(solver, m.mode, sol, m.t, m.q, m.qd).get("ranges", {})
        out.append(entry)
    rule = solver.split[0]
    return {"rule": RULE_TEXT[rule], "split": rule, "phases": out}


def minimum_norm(M, F, B, G, gamma):
    """Redundant contacts (a body resting on more supports than it needs, both ends of a flat
    rod sticking): the accelerations are unique but the contact forces are statically
    indeterminate.  The accelerations and the minimum-norm forces, if the system is consistent
    (:func:`best_distribution` then finds the forces reported)."""
    n, m = M.shape[0], G.shape[0]
    K = np.zeros((n + m, n + m))
    K[:n, :n] = M
    K[:n, n:] = -B
    K[n:, :n] = G
    rhs = np.concatenate((F, -gamma))
    x, *_ = np.linalg.lstsq(K, rhs, rcond=1e-12)
    scale = 1.0 + float(np.max(np.abs(rhs)))
    if np.max(np.abs(K @ x - rhs)) > 1e-9 * scale:
        return None
    # the accelerations must be unique: M must be definite on the null space of G
    rank = np.linalg.matrix_rank(G)
    if rank < n:
        _, _, Vt = np.linalg.svd(G)
        null = Vt[rank:].T
        if np.linalg.matrix_rank(null.T @ M @ null) < null.shape[1]:
            return None
    return x[:n], x[n:]
