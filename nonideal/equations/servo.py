"""Servo-constraints beyond the ordinary case, as rows of the equations of motion.

Three transformations, each a symbolic solve of the other constraints' saddle-point system:
:func:`reach` (a control that reaches its program only through the dynamics, below),
:func:`root_row` (a second-order constraint nonlinear in the accelerations, with a root rule)
and :func:`least_cost_direction` (several control directions for one program, Béghin's r < j,
resolved by the least quadratic cost); and the direction of a quasi-ideal constraint's
reaction, :func:`quasi_ideal_direction` (``adj(A) grad f``, finite where ``det A = 0``).

**Controls acting through the dynamics.**

A servo-constraint (Béghin 1922; Appell 1911) is a program ``phi(q, q', t) = 0`` realized by a
control force ``D u`` of given direction ``D``.  At acceleration level the program reads
``G q'' + gamma = 0``; with the other constraints' reactions solved for, the motion is

    q'' = a0(q, q', t) + a_u(q, q', t) u.

When ``G a_u`` vanishes identically the control does not enter the program's second derivative
(``G M^-1 D = 0`` on the constraint manifold): the acceleration-level program is then a condition
on the state alone, Manglieva & Beknazarov's "condition of dynamics" (2022, (3.3)),

    c(q, q', t) = G a0 + gamma = 0,

which the control must keep: it is differentiated in turn, until the control appears (the mixed
problem of dynamics, Yushkov 1999, ch. IV).  The program is then replaced, in the equations of
motion, by the last condition ``c_k = 0`` realized by ``D u`` (a first-order or holonomic row with
the program's name); the program and the earlier conditions hold along the motion because they
hold at the initial instant and their derivatives are the next conditions (they are checked and
completed in the initial state).

The order reached is the order of the time derivative of the coordinates in which the control
first appears: 2 for an ordinary servo-constraint, 3 for the friction speed regulator (the program
``phi2' = w0`` is of first order, the force on the wheel's axle appears in ``phi2'''``).

This is symbolic work (a linear solve of the other constraints' saddle-point system, then time
derivatives); it is done only for servo-constraints whose control is found decoupled numerically.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import symengine as se
import sympy as sp

from ..errors import IndeterminateSystem, MechanicsError
from ..modeling.symbols import to_se, to_sp

__all__ = ["adjugate", "quasi_ideal_direction", "ServoReach", "Condition", "reach", "root_row",
           "least_cost_direction", "saddle_system", "shared_directions", "shared_rows", "control_rows", "directions_dependent", "MAX_EXTRA_ORDER"]

MAX_EXTRA_ORDER = 4      # differentiate at most this many times beyond the acceleration level
DECOUPLED_TOL = 1e-11    # |G a_u| relative to |G| |a_u| below this at every probe: decoupled
PROBES = 4
CANCEL_OPS = 20000      # cancel the condition of dynamics below this size (operations)


@dataclass(frozen=True)
class Condition:
    """A condition on the state that must hold along the motion (checked at the initial state).

    ``position`` (f(q, t), or None) and ``velocity`` (its time derivative, or phi(q, q', t))
    play the roles they play in a constraint row; ``G`` is the row's gradient."""

    name: str
    position: object
    velocity: object
    G: tuple


@dataclass(frozen=True)
class ServoReach:
    """How a servo-constraint's control reaches its program.

    Attributes
    ----------
    name : str
        The servo-constraint (program).
    order : int
        Order of the time derivative of the coordinates in which the control appears
        (2: the ordinary case).
    program_order : int
        Order of the program itself (0 holonomic, 1 first order, 2 second order).
    conditions : tuple of Condition
        The program and the conditions of dynamics before the last, to hold at t0.
    row : object
        The constraint row that replaces the program in the equations of motion (the last
        condition, realized by the control).
    """

    name: str
    order: int
    program_order: int
    conditions: tuple = field(default_factory=tuple)
    row: object = None

    @property
    def differentiated(self) -> int:
        """How many times the program was differentiated beyond its acceleration level."""
        return self.order - 2


def _probe_points(dyn, rng, count):
    """Random states (t, q, q') with the model's parameter values, as substitution dicts."""
    params = dyn.model.parameter_values
    pv = {se.Symbol(k): float(v) for k, v in params.items()}
    out = []
    for _ in range(count):
        sub = dict(pv)
        sub[dyn.t] = float(rng.uniform(0.1, 0.9))
        for s in dyn.q + dyn.qd:
            sub[s] = float(rng.uniform(0.3, 1.3))
        out.append(sub)
    return out


def _numeric(expr, sub):
    try:
        v = complex(se.sympify(expr).subs(sub).n())
    except (RuntimeError, TypeError, ValueError, ZeroDivisionError):
        return float("nan")
    return v.real if abs(v.imag) <= 1e-12 * (1 + abs(v.real)) else float("nan")


def saddle_system(dyn, others, columns, sub=None):
    """The saddle matrix ``[[M, -B], [G, 0]]`` of the rows *others* and its right-hand sides
    ``[F, d_1 .. d_j]`` (``-gamma`` below F): ``q'' = a0 + P (d_1 u_1 + ..)`` from one solve.
    SymPy, or numbers when *sub* is given."""
    n, m = dyn.n, len(others)
    K = sp.zeros(n + m, n + m)
    rhs = sp.zeros(n + m, 1 + len(columns))
    conv = (lambda e: _numeric(e, sub)) if sub is not None else to_sp
    for i in range(n):
        for j in range(n):
            K[i, j] = conv(dyn.M[i, j])
        rhs[i, 0] = conv(dyn.F[i])
        for j, d in enumerate(columns):
            rhs[i, 1 + j] = conv(d[i])
        for k, r in enumerate(others):
            K[i, n + k] = -conv(r.B[i])
    for k, r in enumerate(others):
        for j in range(n):
            K[n + k, j] = conv(r.G[j])
        rhs[n + k, 0] = -conv(r.gamma)
    return K, rhs


def _coupling_vanishes(dyn, others, G, gamma, D, rng) -> bool:
    """Whether ``G a_u`` vanishes at random states (the control misses this level)."""
    n = dyn.n
    seen = 0
    for sub in _probe_points(dyn, rng, PROBES):
        K, rhs = saddle_system(dyn, others, [D], sub)
        Kn = np.array(K.tolist(), dtype=float)
        bn = np.array(rhs.tolist(), dtype=float)
        g = np.array([_numeric(x, sub) for x in G])
        if not (np.all(np.isfinite(Kn)) and np.all(np.isfinite(bn)) and np.all(np.isfinite(g))):
            continue
        try:
            sol = np.linalg.solve(Kn, bn)
        except np.linalg.LinAlgError:
            continue
        a_u = sol[:n, 1]
        scale = np.linalg.norm(g) * np.linalg.norm(a_u) + 1e-300
        if abs(g @ a_u) > DECOUPLED_TOL * scale and np.linalg.norm(a_u) > 0:
            return False
        seen += 1
    return seen > 0


def _condition(dyn, others, G, gamma, D):
    """``c = G a0 + gamma`` (SymEngine), a0 the motion with the control switched off, as one
    cancelled fraction when it is small enough to cancel (explicit symbolic cost: one LU solve
    of the saddle-point system of the other rows, then a cancellation)."""
    K, rhs = saddle_system(dyn, others, [D])
    sol = K.LUsolve(rhs[:, 0])
    c = sum((to_sp(g) * a for g, a in zip(G, sol[:dyn.n])), sp.Integer(0)) + to_sp(gamma)
    if sp.count_ops(c) < CANCEL_OPS:
        c = sp.cancel(c)
    return to_se(c)


def directions_dependent(dyn, rows) -> bool:
    """Whether the control directions of the servo rows *rows* are dependent at random states
    (r programs, fewer than r independent controls: Béghin's impossible case, diagnosed as such
    elsewhere -- no program is differentiated then)."""
    if len(rows) < 2:
        return False
    rng = np.random.default_rng(7)
    for sub in _probe_points(dyn, rng, 2):
        B = np.array([[_numeric(x, sub) for x in r.B] for r in rows], dtype=float)
        if np.all(np.isfinite(B)) and np.linalg.matrix_rank(B) == len(rows):
            return False
    return True


def _stateless(name: str, level: int, c) -> MechanicsError:
    """The program's derivative of order *level*, with the control switched off, is *c*, free
    of the state: the control never reaches the program."""
    what = (f"servo-constraint '{name}': its control direction does not act on the program: with "
            f"the control switched off the program's time derivative of order {level} is {c} = 0")
    details = {"program": name, "order_tried": level}
    if sp.simplify(c) == 0:
        return IndeterminateSystem(
            what + ", identically, so the motion keeps the program by itself and the program does "
            "not determine the control (Béghin 1922: fewer independent conditions than controls, "
            "the problem is indeterminate); give the control a direction that acts on the "
            "programmed coordinates, or drop the servo-constraint", details=details)
    return MechanicsError(
        what + ", which no state satisfies: the program is unreachable by this control (Béghin "
        "1922; Yushkov 1999, ch. IV, the mixed problem); give the control a direction that acts on "
        "the programmed coordinates", details=details)


def reach(dyn, row, others, make_row) -> ServoReach:
    """Differentiate the program of servo row *row* until its control appears.

    Parameters
    ----------
    dyn : Dynamics
    row : ConstraintRow
        The servo-constraint at acceleration level.
    others : list of ConstraintRow
        The other bilateral rows of the model (their reactions are solved for).
    make_row : callable
        ``make_row(name, expr, order, B)`` -> ConstraintRow for a condition of the state.

    Returns
    -------
    ServoReach

    Raises
    ------
    MechanicsError
        When the control does not appear after ``MAX_EXTRA_ORDER`` differentiations, or a
        condition of dynamics does not depend on the state (the program is unreachable).
    """
    rng = np.random.default_rng(20221)
    program_order = row.order
    if not _coupling_vanishes(dyn, others, row.G, row.gamma, row.B, rng):
        return ServoReach(row.name, 2, program_order, (), row)
    conditions = []
    if row.position is not None or row.velocity is not None:
        conditions.append(Condition(row.name, row.position, row.velocity, tuple(row.G)))
    current = row
    level = 2       # derivative order of q in the current row's G q'' + gamma
    for extra in range(1, MAX_EXTRA_ORDER + 1):
        c = _condition(dyn, others, current.G, current.gamma, current.B)
        free = set(c.free_symbols)
        if not free & (set(dyn.q) | set(dyn.qd)):
            raise _stateless(row.name, level, to_sp(c))
        order = 1 if free & set(dyn.qd) else 0
        new = make_row(row.name, c, order, row.B)
        level += 1 if order == 1 else 2
        if not _coupling_vanishes(dyn, others, new.G, new.gamma, new.B, rng):
            return ServoReach(row.name, level, program_order,
                              tuple(conditions), new)
        conditions.append(Condition(f"{row.name}_d{extra}", new.position, new.velocity, tuple(new.G)))
        current = new
    raise MechanicsError(
        f"servo-constraint '{row.name}': its control does not appear in the program's time "
        f"derivatives up to order {level}; the program is unreachable by this control "
        "(Béghin 1922; Yushkov 1999, ch. IV, the mixed problem); give a control direction that "
        "acts on the programmed coordinates",
        details={"program": row.name, "order_tried": level})


def root_row(dyn, name: str, expr, B, rule: str, others, make_row):
    """The row of a second-order constraint ``phi(q, q', q'', t) = 0`` nonlinear in ``q''``,
    realized by a force ``B lambda`` (Yushkov 1999, ch. IV: a thrust that keeps the magnitude
    of the acceleration).

    With the other rows' reactions solved for, ``q'' = a0 + a_l lambda`` and ``phi`` becomes a
    polynomial in ``lambda``; its root chosen by *rule* (``"largest"`` or ``"smallest"``; the
    two roots of a quadratic are the two continuous branches, which meet only where its
    discriminant vanishes) gives the accelerations ``q''*``, and the constraint enters the
    equations of motion as its linearization there, ``G (q'' - q''*) = 0`` with
    ``G = d phi / d q''`` at ``q''*`` -- the same motion and the same multiplier, since
    ``G a_l = d phi / d lambda`` does not vanish at a simple root.

    Returns ``(row, discriminant)``: the discriminant (None for a linear one) must stay positive
    along the motion.

    Explicit symbolic cost: one LU solve of the other rows' saddle-point system.
    """
    from ..errors import ModelError
    lam = sp.Dummy("lambda")
    K, rhs = saddle_system(dyn, others, [B])
    sol = K.LUsolve(rhs)
    n = dyn.n
    acc = [sp.cancel(sol[i, 0]) + sp.cancel(sol[i, 1]) * lam for i in range(n)]
    phi = to_sp(expr).xreplace({to_sp(a): v for a, v in zip(dyn.qdd, acc)})
    try:
        poly = sp.Poly(sp.expand(phi), lam)
    except sp.PolynomialError:
        poly = None
    if poly is None or poly.degree() > 2 or poly.degree() < 1:
        raise ModelError(
            f"constraint '{name}': after the accelerations are expressed through its multiplier "
            f"the constraint is {'not polynomial' if poly is None else f'of degree {poly.degree()}'} "
            "in the multiplier; a constraint nonlinear in the accelerations is supported when it is "
            "quadratic in them along the reaction direction (e.g. |a|^2 = w^2)")
    if poly.degree() == 1:
        b1, b0 = poly.all_coeffs()
        root, disc = -b0 / b1, None
    else:
        a2, a1, a0 = (sp.cancel(c) for c in poly.all_coeffs())
        disc = sp.cancel(a1 ** 2 - 4 * a2 * a0)
        r1 = (-a1 + sp.sqrt(disc)) / (2 * a2)
        r2 = (-a1 - sp.sqrt(disc)) / (2 * a2)
        root = sp.Max(r1, r2) if rule == "largest" else sp.Min(r1, r2)
    star = [a.xreplace({lam: root}) for a in acc]
    grad = [sp.diff(to_sp(expr), to_sp(a)) for a in dyn.qdd]
    sub = {to_sp(a): v for a, v in zip(dyn.qdd, star)}
    G = [g.xreplace(sub) for g in grad]
    gamma = -sum((g * v for g, v in zip(G, star)), sp.Integer(0))
    row = make_row(name, tuple(to_se(g) for g in G), to_se(gamma), tuple(B))
    return row, (to_se(disc) if disc is not None else None), to_se(root)


def least_cost_direction(dyn, row, others, columns, cost):
    """Béghin's indeterminate case r < j resolved by a stated rule: the j controls ``u`` along
    the directions ``D = [d_1 .. d_j]`` that keep the program with the least cost ``u^T W u``
    (W the identity: the least-norm controls).

    With ``P`` the compliance of the system under the other constraints (``q'' = a0 + P D u``),
    the program ``G q'' + gamma = 0`` is one linear condition on u, and the least-cost controls
    are ``u = W^-1 D^T P^T G^T mu`` for a scalar mu: the program is realized by the single
    direction ``B = D W^-1 D^T P^T G^T`` with multiplier mu.  Returns ``(B, coefficients)`` with
    ``u_k = coefficients[k] * mu`` (SymEngine).  Explicit symbolic cost: one LU solve of the
    other rows' saddle-point system and the inverse of W (j x j)."""
    n = dyn.n
    K, _ = saddle_system(dyn, others, [])
    rhs = sp.zeros(K.shape[0], 1)
    for i in range(n):
        rhs[i, 0] = to_sp(row.G[i])
    x = K.T.LUsolve(rhs)[:n, 0]     # P^T G^T (P = P^T only when the other rows are ideal)
    D = sp.Matrix([[to_sp(col[i]) for col in columns] for i in range(n)])      # n x j
    W = sp.Matrix([[to_sp(v) for v in r] for r in cost]) if cost is not None else sp.eye(len(columns))
    coef = W.inv() * D.T * x                                                    # j x 1
    coef = coef.applyfunc(lambda e: sp.cancel(e) if sp.count_ops(e) < CANCEL_OPS else e)
    B = D * coef
    return tuple(to_se(b) for b in B), tuple(to_se(c) for c in coef)


def shared_directions(dyn, rows, others, columns, weights):
    """Béghin's r programs realized by one set of j shared controls (``[[controls]]``), the
    controls chosen by the least weighted norm ``sum_k w_k u_k^2`` among those that keep every
    program (r < j; the unique ones when r = j).

    With ``P`` the compliance under the other constraints (``q'' = a0 + P D u``) the programs
    ``G_s q'' + gamma_s = 0`` are r linear conditions on u; the least-cost u is
    ``u = W^-1 D^T P G_s^T mu`` with one multiplier per program, so program i is realized by the
    direction ``B_i = D W^-1 D^T P G_i^T`` with multiplier ``mu_i`` -- r ordinary servo rows.
    Returns ``(B, C)``: the r directions and the j x r matrix ``C`` with ``u = C mu`` (SymEngine).
    Explicit symbolic cost: one LU solve of the other rows' saddle-point system with r
    right-hand sides.
    """
    n = dyn.n
    K, _ = saddle_system(dyn, others, [])
    rhs = sp.zeros(K.shape[0], len(rows))
    for i in range(n):
        for k, r in enumerate(rows):
            rhs[i, k] = to_sp(r.G[i])
    X = K.T.LUsolve(rhs)[:n, :]     # P^T G_s^T, n x r (P = P^T when the other rows are ideal)
    D = sp.Matrix([[to_sp(col[i]) for col in columns] for i in range(n)])        # n x j
    Winv = sp.diag(*[1 / to_sp(w) for w in weights])
    C = (Winv * D.T * X).applyfunc(lambda e: sp.cancel(e) if sp.count_ops(e) < CANCEL_OPS else e)
    B = D * C
    return ([tuple(to_se(B[i, k]) for i in range(n)) for k in range(len(rows))],
            [[to_se(C[a, k]) for k in range(len(rows))] for a in range(len(columns))])


def shared_rows(dyn, row_of, make_row) -> tuple:
    """``(names, rows, C)`` of the programs realized by the model's shared controls
    (``[[controls]]``): each program's row along its least-cost direction
    (:func:`shared_directions`) and the j x r matrix ``C`` with ``u = C mu``.  Béghin 1922: r
    programs, j controls; r > j is impossible and raised here, naming the programs.
    *row_of(constraint)* gives a constraint's row, *make_row* builds a row."""
    model = dyn.model
    programs = [c for c in model.constraints if c.shared]
    if not programs:
        return [], [], None
    controls = model.controls
    if len(programs) > len(controls):
        raise MechanicsError(
            f"{len(programs)} programs ({', '.join(repr(c.name) for c in programs)}) but only "
            f"{len(controls)} shared control(s) ({', '.join(u.name for u in controls)}): with more "
            "programs than controls the problem is impossible (Béghin 1922: r > j); add controls or "
            "drop programs", details={"programs": [c.name for c in programs], "r": len(programs),
                                      "j": len(controls)})
    others = [row_of(o) for o in model.constraints
              if not o.shared and o.root is None and o.controls is None and not o.unilateral]
    base = [row_of(c) for c in programs]
    cols = [[to_se(x) for x in u.direction] for u in controls]
    B, C = shared_directions(dyn, base, others, cols, [to_se(u.weight) for u in controls])
    rows = [make_row(r.name, r.G, r.gamma, b, r.position, r.velocity, r.order, False, "servo")
            for r, b in zip(base, B)]
    return [c.name for c in programs], rows, C


def control_rows(dyn, row_of, make_row) -> dict:
    """``{name: (row, coefficients)}`` for every servo-constraint with several control
    directions (Béghin's r < j): its row realized by the least-cost combination of them
    (:func:`least_cost_direction`) and ``u_k = coefficients[k] * multiplier``.  *row_of(c)*
    gives a constraint's row, *make_row* builds a row."""
    out = {}
    for c in dyn.model.constraints:
        if c.controls is None:
            continue
        base = row_of(c)
        others = [row_of(o) for o in dyn.model.constraints
                  if o.name != c.name and o.root is None and o.controls is None and not o.unilateral]
        cols = [[to_se(x) for x in col] for col in c.controls]
        cost = [[to_se(x) for x in r] for r in c.cost] if c.cost is not None else None
        B, coef = least_cost_direction(dyn, base, others, cols, cost)
        out[c.name] = (make_row(c.name, base.G, base.gamma, B, base.position, base.velocity,
                                base.order, base.unilateral, "servo"), coef)
    return out


def adjugate(A) -> se.Matrix:
    """The adjugate (classical adjoint) of the square matrix *A* (a list of rows of symengine
    expressions): ``adj(A)_ij = (-1)^(i+j) det(A without row j and column i)``, so that
    ``A adj(A) = det(A) I`` -- polynomial in the entries, finite where ``A`` is singular."""
    n = len(A)
    if n == 1:
        return se.Matrix([[se.Integer(1)]])
    out = se.zeros(n, n)
    for i in range(n):
        for j in range(n):
            minor = se.Matrix([[A[r][k] for k in range(n) if k != i] for r in range(n) if r != j])
            out[i, j] = (-1) ** (i + j) * minor.det()
    return out


def quasi_ideal_direction(A, G) -> list:
    """The direction of a quasi-ideal constraint's reaction: ``adj(A) grad f``.

    The definition ``A R = lambda grad f`` (Briskin et al. 2021, (1.3), (2.1)) gives
    ``R = A^-1 grad f lambda = adj(A) grad f mu`` with ``lambda = det(A) mu``.  The second form
    is finite and continuous through ``det A = 0``: there the reaction lies along
    ``adj(A) grad f`` (in the null space of ``A``) and ``lambda = 0``, the motion the definition
    fixes whenever ``adj(A) grad f != 0``.  The row's multiplier is ``mu``.
    """
    adj = adjugate(A)
    return [se.expand(sum((adj[i, j] * G[j] for j in range(len(G))), se.Integer(0)))
            for i in range(len(G))]
