"""The machinery of the first approximation (see :mod:`nonideal.analysis.stability.linearize`).

``E = M q'' - F - B lambda = 0``, ``C = G q'' + gamma = 0`` and the constraint levels
``f(q, t) = 0`` (holonomic) and ``c(q, q', t) = 0`` (``df/dt`` and the nonholonomic rows) are
compiled with their Jacobians once per model (:class:`LinearKernel`); :func:`partition`
chooses the dependent coordinates and velocities (pivots of ``f_q`` and ``c_v``);
:func:`state_matrices` gives ``A`` and ``B`` of the reduced state ``(dq_I, dp)``, numerically
or in SymPy.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import symengine as se
import sympy as sp

from ...equations.dynamics import dynamics_of
from ...errors import LinearizationUndefined, ModelError, did_you_mean
from ...modeling.expressions import parse_expression
from ...modeling.model import Model
from ...modeling.symbols import to_se, to_sp
from ...numeric.display import number
from ...numeric.kernel import Compiled

__all__ = ["LinearKernel", "kernel_of", "Partition", "partition", "tangent", "state_matrices",
           "saddle", "solve", "Point", "NEWTON_STEPS", "check_parameters", "clean",
           "parse_state", "natural_frequencies", "ignorable_set", "parameter_substitution",
           "exact_number"]

NEWTON_STEPS = 40


# ====================================================================== the kernel


class LinearKernel:
    """Compiled Jacobians of the implicit motion ``E = 0, C = 0`` and of the constraint levels.

    Inputs ``[t, q, q', a, lambda, parameters]``; ``a`` and ``lambda`` enter linearly, so
    ``M = E_a``, ``B = -E_lambda``, ``F = -E(a=0, lambda=0)`` etc.
    """

    def __init__(self, model: Model, controls: Sequence[str]):
        if model.contacts:
            raise ModelError(
                f"stability: the model has contacts ({', '.join(c.name for c in model.contacts)}); "
                "linearize it in one contact state: write the touching contact as a constraint "
                "(sticking: gap and slip as [[constraints]]) or drop it",
                _src(model))
        dyn = dynamics_of(model)
        self.model, self.dyn, self.n = model, dyn, dyn.n
        self.rows = dyn.rows()
        self.r = len(self.rows)
        self.lam = [se.Symbol(f"lambda_{row.name}") for row in self.rows]
        self.controls = tuple(controls)
        self.holonomic = [i for i, row in enumerate(self.rows) if row.order == 0]
        # the holonomic rows' velocities first, in the order of f (partition relies on it)
        self.velocity_rows = self.holonomic + [i for i, row in enumerate(self.rows) if row.order == 1]
        # programs kept through the dynamics (a servo-constraint whose control reaches the
        # program only through the dynamics): the program and its earlier conditions of dynamics
        # hold along the closed-loop motion; the perturbations are kept on them, as on the rows
        conditions = dyn.servo_conditions()
        cond_f = [c for c in conditions if c.position is not None]
        cond_c = [c for c in conditions if c.position is None and c.velocity is not None]
        self.held = tuple((c.name, str(to_sp(c.position if c.position is not None else c.velocity)))
                          for c in cond_f + cond_c)
        q, v, a = dyn.q, dyn.qd, dyn.qdd
        M, F = dyn.M, dyn.F
        n, r = self.n, self.r
        E = [sum((M[i, j] * a[j] for j in range(n)), se.Integer(0)) - F[i]
             - sum((self.rows[k].B[i] * self.lam[k] for k in range(r)), se.Integer(0)) for i in range(n)]
        C = [sum((row.G[j] * a[j] for j in range(n)), se.Integer(0)) + row.gamma for row in self.rows]
        f = [self.rows[i].position for i in self.holonomic] + [x.position for x in cond_f]
        c = ([self.rows[i].velocity for i in self.holonomic] + [x.velocity for x in cond_f]
             + [self.rows[i].velocity for i in self.velocity_rows[len(self.holonomic):]]
             + [x.velocity for x in cond_c])
        u = [se.Symbol(name) for name in self.controls]
        blocks = {
            "E": [E], "C": [C], "f": [f], "c": [c],
            "E_q": dyn.jacobian(E, q), "E_v": dyn.jacobian(E, v), "E_a": dyn.jacobian(E, a),
            "E_l": dyn.jacobian(E, self.lam), "E_u": dyn.jacobian(E, u),
            "C_q": dyn.jacobian(C, q), "C_v": dyn.jacobian(C, v), "C_a": dyn.jacobian(C, a),
            "C_u": dyn.jacobian(C, u),
            "f_q": dyn.jacobian(f, q), "c_q": dyn.jacobian(c, q), "c_v": dyn.jacobian(c, v),
        }
        nf, nc_ = len(f), len(c)
        dims = {"E": (n, 1), "C": (r, 1), "f": (nf, 1), "c": (nc_, 1), "E_q": (n, n), "E_v": (n, n),
                "E_a": (n, n), "E_l": (n, r), "E_u": (n, len(u)), "C_q": (r, n), "C_v": (r, n),
                "C_a": (r, n), "C_u": (r, len(u)), "f_q": (nf, n), "c_q": (nc_, n), "c_v": (nc_, n)}
        self.shapes = {}
        flat = []
        for key, mat in blocks.items():
            rows_ = [list(rw) for rw in mat]
            if key in ("E", "C", "f", "c"):
                rows_ = [[x] for x in rows_[0]]
            nr, nc = dims[key]
            self.shapes[key] = (nr, nc, len(flat))
            for rw in rows_:
                flat.extend(se.sympify(x) for x in rw)
        self.inputs = [dyn.t] + list(q) + list(v) + list(a) + self.lam + list(dyn.params)
        self.flat = flat
        # compiled with the library's Compiled (its inputs renamed so that the CSE temporaries
        # x0, x1, ... cannot capture a model symbol of that name)
        self._numeric = Compiled(self.inputs, {"flat": flat}) if flat else None
        self.names = list(model.parameters)

    # ---------------------------------------------------------------- evaluation
    def _input(self, t, q, v, a, lam, params):
        return np.concatenate([[t], q, v, a, lam, params]).astype(float)

    def numeric(self, t, q, v, a, lam, params) -> dict:
        out = self._numeric.raw(self._input(t, q, v, a, lam, params)).copy() \
            if self._numeric is not None else np.zeros(0)
        res = {}
        for key, (nr, nc, start) in self.shapes.items():
            res[key] = out[start:start + nr * nc].reshape(nr, nc)
        return res

    def symbolic(self, t, q, v, a, lam, fixed: Mapping[str, sp.Expr]) -> dict:
        """The blocks as SymPy matrices in the parameters not in *fixed* (those substituted:
        see :func:`parameter_substitution`).  *q*, *v*, *a*, *lam* may be SymPy expressions in
        the parameters kept."""
        dyn = self.dyn
        sub = {dyn.t: to_se(t)}
        for sym, val in zip(dyn.q, q):
            sub[sym] = to_se(val)
        for sym, val in zip(dyn.qd, v):
            sub[sym] = to_se(val)
        for sym, val in zip(dyn.qdd, a):
            sub[sym] = to_se(val)
        for sym, val in zip(self.lam, lam):
            sub[sym] = to_se(val)
        for sym in dyn.params:
            if str(sym) in fixed:
                sub[sym] = to_se(fixed[str(sym)])
        res = {}
        for key, (nr, nc, start) in self.shapes.items():
            items = [to_sp(se.sympify(x).subs(sub)) for x in self.flat[start:start + nr * nc]]
            res[key] = sp.Matrix(nr, nc, items) if nr and nc else sp.zeros(nr, nc)
        return res


def exact_number(value: float) -> sp.Expr:
    """*value* as an exact SymPy number: an integer, else the rational of its shortest decimal
    (``9.81 -> 981/100``), so that symbolic work on it leaves no rounding residue."""
    value = float(value)
    if value.is_integer():
        return sp.Integer(int(value))
    return sp.Rational(repr(value))


def parameter_substitution(model: Model, keep: Sequence[str]) -> dict[str, sp.Expr]:
    """What replaces each parameter not in *keep* in a result symbolic in *keep*.

    A derived parameter (given by an expression in others, :attr:`Parameter.definition`)
    that depends, directly or through other derived ones, on a parameter kept is replaced by
    its definition expanded down to the kept parameters and the numbers of the rest (the
    moments of inertia ``A = m*r^2/4`` of a disk stay functions of ``r`` under ``--symbolic r``);
    every other parameter by its value as an exact number (:func:`exact_number`)."""
    keep = set(keep)
    symbols = {name: sp.Symbol(name) for name in model.parameters}
    done: dict[str, sp.Expr] = {}

    def expanded(name: str, trail: tuple = ()) -> sp.Expr:
        if name in keep:
            return symbols[name]
        if name in done:
            return done[name]
        p = model.parameters[name]
        out = exact_number(p.value)
        if p.definition and name not in trail:
            expr = parse_expression(p.definition, symbols, f"[parameters] {name}")
            inner = {s: expanded(s.name, trail + (name,)) for s in expr.free_symbols
                     if s.name in symbols}
            if any(e.free_symbols & {symbols[k] for k in keep} for e in inner.values()):
                out = expr.xreplace(inner)
        done[name] = out
        return out

    return {name: expanded(name) for name in model.parameters if name not in keep}


def kernel_of(model: Model, controls: Sequence[str]) -> LinearKernel:
    """The compiled :class:`LinearKernel` of *model* with *controls* (cached on the model)."""
    return model.cached(("linear kernel", tuple(controls)), lambda: LinearKernel(model, controls))


def _src(model: Model):
    return None if model.source == "<api>" else model.source


# ====================================================================== linear algebra


def saddle(b, numeric: bool):
    """The acceleration-level solve ``[[M, -B], [G, 0]] [a; lambda] = rhs`` (blocks *b*)."""
    if numeric:
        return np.block([[b["E_a"], b["E_l"]], [b["C_a"], np.zeros((b["C_a"].shape[0],) * 2)]])
    r = b["C_a"].rows
    return sp.Matrix.vstack(sp.Matrix.hstack(b["E_a"], b["E_l"]),
                            sp.Matrix.hstack(b["C_a"], sp.zeros(r, r)))


def solve(K, rhs, numeric: bool, what: str, model: Model):
    if numeric:
        cond = np.linalg.cond(K) if K.size else 1.0
        if not np.isfinite(cond) or cond > 1e13:
            raise LinearizationUndefined(what + f" (condition number {cond:.3g})")
        return np.linalg.solve(K, rhs)
    try:
        return K.LUsolve(rhs)
    except (ValueError, ZeroDivisionError) as exc:
        raise LinearizationUndefined(what + f" ({exc})") from None


@dataclass
class Partition:
    coords_I: list
    coords_D: list
    vel_I: list
    vel_D: list


def partition(b, n: int, independent: Sequence[int] | None, model: Model) -> Partition:
    """Dependent coordinates (pivots of f_q) and velocities (pivots of c_v), numerically.
    Coordinates in *independent* are kept independent when possible."""
    import scipy.linalg as sl

    prefer = list(independent or [])

    def pivots(J, allowed, prefer):
        """Dependent columns of J among *allowed*: the non-preferred ones first (pivoted QR),
        completed from the preferred ones when they do not reach full rank."""
        if J.shape[0] == 0:
            return []
        tol = 1e-9 * max(1.0, float(np.abs(J).max(initial=0.0)))
        chosen: list = []
        for group in ([j for j in allowed if j not in prefer], [j for j in allowed if j in prefer]):
            if len(chosen) == J.shape[0] or not group:
                continue
            base = J[:, chosen]
            # the part of the group's columns outside the span of the chosen ones
            if chosen:
                Qb, _ = np.linalg.qr(base)
                rest = J[:, group] - Qb @ (Qb.T @ J[:, group])
            else:
                rest = J[:, group]
            _, R, piv = sl.qr(rest, pivoting=True, mode="economic")
            d = np.abs(np.diag(R)) if R.size else np.zeros(0)
            need = J.shape[0] - len(chosen)
            take = [group[p] for k, p in enumerate(piv[:need]) if k < d.size and d[k] > tol]
            chosen += take
        if len(chosen) < J.shape[0]:
            raise LinearizationUndefined(
                f"the constraint rows are dependent at this state (rank {len(chosen)} of {J.shape[0]}): "
                "the linearization is undefined (a singular configuration of the constraints)")
        return sorted(chosen)

    fq = b["f_q"]
    D = pivots(fq, range(n), prefer)
    I = [j for j in range(n) if j not in D]
    cv = b["c_v"]
    # velocity rows: the holonomic rows eliminate the same dependent velocities
    nh = [i for i in range(cv.shape[0]) if i >= len(D)]
    if nh:
        # eliminate the holonomic-dependent velocities first
        Jh = cv[:len(D)]
        Jn = cv[len(D):]
        if D:
            X = np.linalg.solve(Jh[:, D], Jh[:, I])
            eff = Jn[:, I] - Jn[:, D] @ X
        else:
            eff = Jn[:, I]
        # (the columns of eff are the independent coordinates' velocities, numbered locally)
        piv_local = pivots(eff, range(len(I)), [k for k, j in enumerate(I) if j in prefer])
        Dn = [I[j] for j in piv_local]
    else:
        Dn = []
    vel_D = sorted(D + Dn)
    vel_I = [j for j in range(n) if j not in vel_D]
    if prefer:
        _check_kept(model, prefer, n, D, I, Dn)
    return Partition(I, D, vel_I, vel_D)


def _check_kept(model: Model, prefer, n: int, D, I, Dn) -> None:
    """``[forms] independent`` read as everywhere (docs/MODEL_FORMAT.md, [forms]): at most
    ``n - h`` coordinates, kept independent; the velocities kept among them as far as the
    velocity-level constraints allow."""
    names = list(model.coordinates)
    listed = [names[j] for j in prefer]
    h, k = len(D), len(Dn)
    if len(prefer) > n - h:
        raise ModelError(
            f"[forms] independent: {len(prefer)} coordinates listed ({', '.join(listed)}), but the "
            f"{h} holonomic constraint(s) on {n} coordinates leave {n - h}; list at most {n - h} "
            "(the coordinates kept independent)", _src(model))
    lost = [names[j] for j in prefer if j in D]
    if not lost:
        inside = [j for j in I if j in prefer]
        if len(inside) <= len(I) - k:
            lost = [names[j] for j in inside if j in Dn]
        else:
            lost = [names[j] for j in I if j not in prefer and j not in Dn]
    if lost:
        raise ModelError(
            f"[forms] independent = {listed}: the constraints cannot keep {', '.join(lost)} "
            "independent at this state (a singular choice); choose other independent coordinates",
            _src(model))


def tangent(b, part: Partition, n: int, numeric: bool):
    """Maps ``(dq_I, dp) -> dq`` and ``-> dq'`` (shapes n x (nI + nV))."""
    nI, nV = len(part.coords_I), len(part.vel_I)
    xp = np if numeric else None
    if numeric:
        Tq = np.zeros((n, nI + nV))
        Tq[part.coords_I, list(range(nI))] = 1.0
        if part.coords_D:
            fq = b["f_q"]
            Tq[np.ix_(part.coords_D, range(nI))] = -np.linalg.solve(fq[:, part.coords_D], fq[:, part.coords_I])
        Tv = np.zeros((n, nI + nV))
        Tv[part.vel_I, list(range(nI, nI + nV))] = 1.0
        if part.vel_D:
            cq, cv = b["c_q"], b["c_v"]
            rhs = cq @ Tq + cv[:, part.vel_I] @ Tv[part.vel_I]
            Tv[part.vel_D] = -np.linalg.solve(cv[:, part.vel_D], rhs)
        return Tq, Tv
    Tq = sp.zeros(n, nI + nV)
    for k, j in enumerate(part.coords_I):
        Tq[j, k] = 1
    if part.coords_D:
        fq = b["f_q"]
        X = -fq.extract(list(range(fq.rows)), part.coords_D).LUsolve(fq.extract(list(range(fq.rows)), part.coords_I))
        for a_, j in enumerate(part.coords_D):
            for k in range(nI):
                Tq[j, k] = X[a_, k]
    Tv = sp.zeros(n, nI + nV)
    for k, j in enumerate(part.vel_I):
        Tv[j, nI + k] = 1
    if part.vel_D:
        cq, cv = b["c_q"], b["c_v"]
        allr = list(range(cv.rows))
        rhs = cq * Tq + cv.extract(allr, part.vel_I) * Tv.extract(part.vel_I, list(range(nI + nV)))
        X = -cv.extract(allr, part.vel_D).LUsolve(rhs)
        for a_, j in enumerate(part.vel_D):
            for k in range(nI + nV):
                Tv[j, k] = X[a_, k]
    del xp
    return Tq, Tv


def state_matrices(b, part: Partition, n: int, numeric: bool, model: Model):
    """``A`` (rows: dq_I' = dq'_I, dp' = da_I) and ``B`` of the full reduced state."""
    Tq, Tv = tangent(b, part, n, numeric)
    K = saddle(b, numeric)
    what = ("the motion is undetermined at this state: the system [[M, -B], [G, 0]] of the "
            "accelerations and multipliers is singular (dependent constraint rows, or a servo "
            "constraint its control cannot realize)")
    if numeric:
        rhs = -np.vstack([b["E_q"] @ Tq + b["E_v"] @ Tv, b["C_q"] @ Tq + b["C_v"] @ Tv])
        rhs_u = -np.vstack([b["E_u"], b["C_u"]])
        sol = solve(K, np.hstack([rhs, rhs_u]), True, what, model)
        da, du = sol[:n, :rhs.shape[1]], sol[:n, rhs.shape[1]:]
        A = np.vstack([Tv[part.coords_I], da[part.vel_I]])
        nI = len(part.coords_I)
        B = np.vstack([np.zeros((nI, du.shape[1])), du[part.vel_I]])
        return A, B
    rhs = -sp.Matrix.vstack(b["E_q"] * Tq + b["E_v"] * Tv, b["C_q"] * Tq + b["C_v"] * Tv)
    rhs_u = -sp.Matrix.vstack(b["E_u"], b["C_u"])
    full = sp.Matrix.hstack(rhs, rhs_u)
    sol = solve(K, full, False, what, model)
    m = rhs.cols
    da = sol.extract(list(range(n)), list(range(m)))
    du = sol.extract(list(range(n)), list(range(m, full.cols)))
    A = sp.Matrix.vstack(Tv.extract(part.coords_I, list(range(m))), da.extract(part.vel_I, list(range(m))))
    B = sp.Matrix.vstack(sp.zeros(len(part.coords_I), du.cols), du.extract(part.vel_I, list(range(du.cols))))
    return A.applyfunc(sp.simplify), B.applyfunc(sp.simplify)


# ====================================================================== the state


class Point:
    """Numeric evaluation of the motion at a state, with the dependent values completed."""

    def __init__(self, kernel: LinearKernel, params: np.ndarray, t: float):
        self.k, self.params, self.t = kernel, params, t
        self.n = kernel.n

    def blocks(self, q, v, a=None, lam=None):
        n, r = self.n, self.k.r
        a = np.zeros(n) if a is None else a
        lam = np.zeros(r) if lam is None else lam
        return self.k.numeric(self.t, q, v, a, lam, self.params)

    def motion(self, q, v):
        """``(a0, lambda0, blocks at (a0, lambda0))``."""
        b0 = self.blocks(q, v)
        K = saddle(b0, True)
        rhs = -np.concatenate([b0["E"].ravel(), b0["C"].ravel()])
        sol = solve(K, rhs, True, self.singular_what(q, v, b0), self.k.model)
        a, lam = sol[:self.n], sol[self.n:]
        return a, lam, self.blocks(q, v, a, lam)

    def singular_what(self, q, v, b0) -> str:
        """Why the acceleration-level system is singular at the state, with the state: the mass
        matrix itself (a model without constraints rows, or M singular: a singular point of the
        coordinates, such as a polar angle at its pole) or the constraint rows."""
        names = list(self.k.model.coordinates)
        state = ", ".join([f"{c} = {number(x)}" for c, x in zip(names, q)]
                          + [f"{c}' = {number(x)}" for c, x in zip(names, v) if number(x) != "0"])
        M = b0["E_a"]
        sv = np.linalg.svd(M, compute_uv=False) if M.size else np.zeros(0)
        if self.k.r == 0 or (sv.size and sv[-1] <= 1e-12 * max(1.0, sv[0])):
            return (f"the mass matrix M is singular at the state ({state}): the coordinates are "
                    "singular there (as a polar angle at its pole), the accelerations are undefined")
        return (f"the motion is undetermined at the state ({state}): the system [[M, -B], [G, 0]] "
                "is singular (dependent constraint rows, or a servo constraint its control cannot "
                "realize)")

    def complete(self, q, v, part: Partition):
        """Dependent coordinates from f = 0 and dependent velocities from c = 0 (Newton)."""
        q, v = q.copy(), v.copy()
        D = part.coords_D
        for _ in range(NEWTON_STEPS):
            b = self.blocks(q, v)
            f = b["f"].ravel()
            if not D or np.max(np.abs(f), initial=0.0) < 1e-13 * (1 + np.abs(q).max()):
                break
            q[D] -= np.linalg.solve(b["f_q"][:, D], f)
        VD = part.vel_D
        for _ in range(NEWTON_STEPS):
            b = self.blocks(q, v)
            c = b["c"].ravel()
            if not VD or np.max(np.abs(c), initial=0.0) < 1e-13 * (1 + np.abs(v).max()):
                break
            v[VD] -= np.linalg.solve(b["c_v"][:, VD], c)
        return q, v


def check_parameters(model: Model, names: Sequence[str], option: str) -> None:
    params = list(model.parameters)
    bad = [f"{option}: '{n}' is not a parameter{did_you_mean(n, params)}; parameters: {', '.join(params)}"
           for n in names if n not in params]
    if bad:
        raise ModelError(bad, _src(model))


def clean(X: np.ndarray) -> np.ndarray:
    """Round-off (below 1e-13 of the largest entry) set to exact zeros."""
    X = np.array(X, float)
    if X.size:
        X[np.abs(X) < 1e-13 * max(1.0, float(np.abs(X).max()))] = 0.0
    return X + 0.0


def parse_state(model: Model, at, symbolic: Sequence[str]) -> dict:
    """``at`` (mapping, or the CLI text ``"q=0.1, q'=2"``) -> {name: sympy expr in parameters}."""
    if at is None:
        return {}
    allowed = list(model.coordinates) + [c + "'" for c in model.coordinates]
    names = {n: sp.Symbol(n) for n in model.parameters}
    if isinstance(at, str):
        pairs = []
        problems = []
        for part in at.split(","):
            if not part.strip():
                continue
            if part.count("=") != 1:
                problems.append(f"--at: '{part.strip()}' is not of the form name=value (pairs "
                                f"separated by commas, e.g. \"{allowed[0]}=0.1, {allowed[-1]}=0\")")
                continue
            key, _, val = part.partition("=")
            pairs.append((key.strip(), val.strip()))
        if problems:
            raise ModelError(problems, _src(model))
    else:
        pairs = list(dict(at).items())
    out, problems = {}, []
    for key, val in pairs:
        if key not in allowed:
            problems.append(f"--at: '{key}' is not a coordinate or velocity{did_you_mean(key, allowed)}; "
                            f"allowed: {', '.join(allowed)}")
            continue
        if key in out:
            problems.append(f"--at: '{key}' is given twice")
            continue
        if isinstance(val, (int, float)) and not isinstance(val, bool):
            out[key] = sp.Float(val) if not float(val).is_integer() else sp.Integer(int(val))
            continue
        try:
            out[key] = parse_expression(val, names, f"--at {key}")
        except ModelError as exc:
            problems.extend(exc.problems)
    if problems:
        raise ModelError(problems, _src(model))
    return out


# ====================================================================== linearize


def natural_frequencies(pt: "Point", q, v, part: "Partition", kept) -> list:
    """Natural frequencies of small oscillations (generalized eigenproblem K x = w^2 M x on
    the kept independent coordinates) of a system without velocity forces at rest."""
    import scipy.linalg as sl

    if len(part.vel_D) != len(part.coords_D):
        return []
    a, lam, b = pt.motion(q, v)
    Tq, _ = tangent(b, part, pt.n, True)
    cols = [part.coords_I.index(j) for j in kept]
    if not cols:
        return []
    T = Tq[:, cols]
    Mr = T.T @ b["E_a"] @ T
    Kr = T.T @ b["E_q"] @ T
    Dr = T.T @ b["E_v"] @ T
    # holonomic constraints' curvature (the multipliers' term) is in E_q
    sc = max(1.0, float(np.abs(Kr).max(initial=0.0)))
    if float(np.abs(Dr).max(initial=0.0)) > 1e-9 * sc or float(np.abs(Kr - Kr.T).max(initial=0.0)) > 1e-8 * sc:
        return []
    w2 = sl.eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T), eigvals_only=True)
    if np.any(w2 <= 0):
        return []
    return sorted(float(np.sqrt(x)) for x in w2)


def ignorable_set(A: np.ndarray, candidates) -> list:
    """The largest subset S of the state indices *candidates* that nothing outside S depends
    on (the columns of S vanish in the other rows) and whose own block is nilpotent (no
    dependence cycle within S: a cyclic coordinate, a velocity feeding only cyclic
    coordinates).  Dropping S removes only zero eigenvalues and leaves the rest closed."""
    A = np.asarray(A, float)
    tol = 1e-9 * max(1.0, float(np.abs(A).max(initial=0.0)))
    S = set(candidates)
    while True:
        changed = True
        while changed:
            changed = False
            rows = [i for i in range(A.shape[0]) if i not in S]
            for idx in sorted(S):
                if rows and np.abs(A[rows, idx]).max() > tol:
                    S.discard(idx)
                    changed = True
                    break
        order = sorted(S)
        if not order:
            return []
        adj = (np.abs(A[np.ix_(order, order)]) > tol).astype(int)   # adj[i, j]: i depends on j
        reach = adj.copy()
        for _ in range(len(order)):
            reach = np.minimum(1, reach + reach @ adj)
        on_cycle = [order[i] for i in range(len(order)) if reach[i, i]]
        if not on_cycle:
            return order
        S -= set(on_cycle)
