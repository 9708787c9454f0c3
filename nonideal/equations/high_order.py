"""Constraints of order n >= 3 as second-order ones of a model extended by the force's impulses.

A constraint ``f(q, q', ..., q^(n), t) = 0`` is realized by a generalized force ``R`` that the
state (q, q') does not determine: the accelerations contain it, ``q^(k)`` contains its
derivatives up to ``R^(k-2)``, and the constraint is a differential equation of order ``n - 2``
for it (Yushkov 1999, ch. IV, secs. 5 and 7: for linear constraints of order three and more the
multipliers become unknown functions of time governed by their own differential equations; the
state of the motion is ``(q, q', R, R', ..., R^(n-3))``).  Two ways of realizing it:

* **along a given direction** ``B(q, q', t)`` (``reaction = [...]``; a servo-constraint in
  Béghin's sense): ``R = B lambda`` with one scalar ``lambda`` -- the constraint may then be
  nonlinear in ``q^(n)`` (quadratic along B: a root rule chooses the branch);
* **ideal** (no ``reaction``; linear in ``q^(n)``): the generalized Gauss principle of order n
  (Yushkov 1999, ch. IV, secs. 3 and 5; appendix D).  The equations of motion ``M W = Y + R`` of the
  representing point, differentiated ``n - 2`` times as vectors, give ``M W^(n-2) = Y^(n-2) +
  R^(n-2)``; among the n-th derivatives the constraint allows, the actual one minimizes the
  compulsion ``M |W^(n-2) - Y^(n-2)/M|^2 / 2``, so ``R^(n-2) = Lambda grad f``: in generalized
  coordinates, ``(D^(n-2) R)_s = Lambda g_s``, ``g = (d f / d q^(n))^T``, where ``D`` is the
  covariant derivative along the motion in the metric of the mass matrix (the rate of the
  vector, not of its components: ``(D P)_s = P_s' - Gamma^r_(s u) q'^u P_r``).  In Cartesian
  coordinates of particles (M constant) ``D`` is the plain derivative, ``R^(n-2) = Lambda g``
  (for order two the same principle gives ``R = lambda g``, for order three ``R' = Lambda g``);
  in curvilinear ones (a satellite in polar coordinates, appendix D) the basis turns, and
  without the connection term the motion would depend on the coordinates chosen.  R is an
  n_q-vector of the state, with ``D R, .., D^(n-3) R``.

**The extension.**  The force's unknown components ``w`` (lambda, or R) and their derivatives
``w^(k)`` (ideal: ``D^k R``), ``k = 0 .. n - 3``, become the velocities of auxiliary coordinates
``z_k`` (``z_0`` is the impulse of the force, ``int w dt``; ``z_k``, ``k >= 1``, the impulse
of ``w^(k)``) with the kinetic energy ``|z_k'|^2/2``.  The force acts on the coordinates as the generalized force ``D w``
(``D = B``, or the identity), and the chain ``z_k'' = z_(k+1)'`` is the generalized force
``z_(k+1)'`` on ``z_k`` (``k < n - 3``; ideal: ``z_(k+1)' + Gamma q' z_k'``, and ``Gamma q'
z_(n-3)'`` on the last level).  With the other constraints' reactions solved for,
``q'' = a(q, q', w, t)`` (linear in w), so ``q^(n) = d^(n-2) a/dt^(n-2)`` is linear in
``w^(n-2) = z_(n-3)''`` and

    f_ext(q, q', z_0', .., z_(n-3)', z_(n-3)'', t) = f(q, q', a, da/dt, .., d^(n-2)a/dt^(n-2), t) = 0

is a *second-order* constraint of the extended model, realized by a force on ``z_(n-3)`` alone
along ``e`` (direction B) or ``g`` (ideal): ``z_(n-3)'' = e mu`` -- ``mu = lambda^(n-2)`` -- or
``z_(n-3)'' = Gamma q' z_(n-3)' + g mu`` -- ``mu = Lambda``.  The extended model is an ordinary model: its simulation
is the motion; the auxiliary energy ``sum |z_k'|^2/2`` and the works of the chain and of ``mu`` on
the ``z_k`` cancel in its balance and are taken out again by
:func:`nonideal.simulation.extended.reduce`.  Explicit symbolic cost: one LU solve of the other
constraints' saddle-point system, then ``n - 2`` total time derivatives of the accelerations
(their size grows with n; :data:`nonideal.modeling.high_order.MAX_ORDER` bounds n).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..errors import ModelError
from ..modeling.model import Constraint, Model
from .dynamics import dynamics_of
from .servo import saddle_system

__all__ = ["Extension", "HighOrder", "extension_of", "extended", "aux_names"]


@dataclass(frozen=True)
class HighOrder:
    """One constraint of order n >= 3 in the extended model: its name, order, whether it is
    ideal, the auxiliary coordinates that carry its force and the force's derivatives (one tuple
    per level ``k = 0 .. n - 3``, each of one name -- lambda^(k) -- or n_q names -- the ideal
    R^(k)) and its direction ``B`` (SymPy, n_q entries; None when ideal)."""

    name: str
    order: int
    ideal: bool
    aux: tuple[tuple[str, ...], ...]
    B: tuple | None

    @property
    def levels(self) -> int:
        """``n - 2``: the force and its derivatives up to order ``n - 3``."""
        return self.order - 2


@dataclass(frozen=True)
class Extension:
    """A model with constraints of order three and more and the extended model that simulates
    it."""

    original: Model
    model: Model
    constraints: tuple[HighOrder, ...]


def extension_of(model: Model) -> Extension | None:
    """The extension of *model* (cached), or None when it has no constraint of order >= 3."""
    if not isinstance(model, Model) or not any(c.order >= 3 for c in model.constraints):
        return None
    return model.cached("third_order_extension", lambda: _extend(model))


def extended(model: Model) -> Model:
    """The model that stands for *model* at a state: its extension when it has constraints of
    order three and more (the state then includes the forces that realize them and their
    derivatives, as the velocities of the auxiliary coordinates ``<constraint>_impulse``,
    ``<constraint>_impulse_d1``, ...), else *model* itself.  ``check``, ``evaluate``, ``derive``
    and the cross-check of the forms work on it."""
    ext = extension_of(model)
    return model if ext is None else ext.model


def aux_names(name: str, level: int, coordinates, ideal: bool) -> list[str]:
    """The auxiliary coordinates of level *level* of the constraint *name* (before making them
    unique): ``<name>_impulse`` (level 0), ``<name>_impulse_d<k>`` (level k), with ``_<q>`` per
    coordinate when ideal."""
    base = f"{name}_impulse" + (f"_d{level}" if level else "")
    return [f"{base}_{q}" for q in coordinates] if ideal else [base]


def _unique(name: str, taken: set) -> str:
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def _velocity(name: str) -> sp.Symbol:
    return sp.Symbol(name + "'")


def _extend(model: Model) -> Extension:
    high = [c for c in model.constraints if c.order >= 3]
    others = tuple(c for c in model.constraints if c.order < 3)
    if any(c.unilateral for c in others):
        raise ModelError(f"constraint '{high[0].name}': a constraint of order {high[0].order} cannot be "
                         "combined with unilateral constraints (not supported)", _source(model))
    orders = sorted({c.order for c in high})
    if len(orders) > 1:
        shown = ", ".join(f"'{c.name}' (order {c.order})" for c in high)
        raise ModelError(f"constraints {shown}: constraints of order three and more in one model must "
                         "have the same order (the derivatives of the lower one's force would enter the "
                         "higher one's equation); differentiate the lower-order program up to order "
                         f"{orders[-1]}, or write the higher one at order {orders[0]}", _source(model))
    order = orders[0]
    levels = order - 2
    n = model.n_q
    taken = set(model.coordinates) | set(model.parameters)
    specs = []
    for c in high:
        ideal = c.reaction is None
        aux = tuple(tuple(_unique(a, taken) for a in aux_names(c.name, k, model.coordinates, ideal))
                    for k in range(levels))
        specs.append(HighOrder(c.name, order, ideal, aux, None if ideal else tuple(sp.sympify(b) for b in c.reaction)))
    # w: the velocities of level 0 of every constraint (the forces)
    w = [_velocity(a) for s in specs for a in s.aux[0]]
    # D: the generalized force of the level-0 velocities on the coordinates, n x (columns)
    cols = []
    for s in specs:
        cols += [[sp.Integer(1 if i == k else 0) for i in range(n)] for k in range(n)] if s.ideal \
            else [list(s.B)]
    D = sp.Matrix(n, len(cols), lambda i, j: cols[j][i])
    a, M = _accelerations(model.replace(constraints=others, outputs={}), D, w)
    turn = _connection(model, M) if any(s.ideal for s in specs) else None
    # the time derivative of each level: the next level, plus for an ideal force (a covector, its
    # levels the covariant derivatives D^k R) the turn of the coordinate basis, Gamma q' D^k R
    chain = {q: v for q, v in zip(model.q, model.qd)}
    aux_forces = {}   # the generalized force on each auxiliary coordinate: the chain and the turn
    for s in specs:
        for k in range(levels):
            z = [_velocity(x) for x in s.aux[k]]
            extra = turn(z) if s.ideal else [sp.Integer(0)] * len(z)
            if k + 1 < levels:   # d/dt D^k R = D^(k+1) R + Gamma q' D^k R
                nxt = [_velocity(x) for x in s.aux[k + 1]]
                chain.update({v: nv + e for v, nv, e in zip(z, nxt, extra)})
                aux_forces.update({x: nv + e for x, nv, e in zip(s.aux[k], nxt, extra)})
            else:                # the last level's rate is its acceleration, the unknown
                chain.update({v: sp.Symbol(str(v) + "'") for v in z})
                aux_forces.update({x: e for x, e in zip(s.aux[k], extra) if e != 0})
    sub = {}
    current = a
    for m in range(2, order + 1):
        if m > 2:
            current = _rate(model, current, a, chain)
        sub.update(zip((sp.Symbol(s.name + "'" * (m - 2)) for s in model.qdd), current))
    top = [sp.Symbol(s.name + "'" * (order - 2)) for s in model.qdd]
    forces = {c: f + sum((D[i, j] * w[j] for j in range(len(w))), sp.Integer(0))
              for i, (c, f) in enumerate(zip(model.coordinates, model.forces))}
    forces.update(aux_forces)
    aux_all = [x for s in specs for level in s.aux for x in level]
    constraints, initial = list(others), dict(model.initial)
    for s, c in zip(specs, high):
        f_ext = sp.sympify(c.expr).xreplace(sub)
        g = [sp.diff(c.expr, j).xreplace(sub) for j in top] if s.ideal else [sp.Integer(1)]
        direction = dict(zip(s.aux[-1], g))
        reaction = [0] * n + [direction.get(z, 0) for z in aux_all]
        constraints.append(Constraint(c.name, f_ext, "servo", reaction=tuple(reaction), root=c.root))
        for level, values in zip(s.aux, c.initial):
            initial.update({z: 0 for z in level})
            initial.update({z + "'": v for z, v in zip(level, values if s.ideal else (values,))})
    kinetic = model.kinetic + sum((_velocity(z) ** 2 for z in aux_all), sp.Integer(0)) / 2
    ext = Model(name=model.name, coordinates=tuple(model.coordinates) + tuple(aux_all),
                parameters=model.parameters, kinetic=kinetic, potential=model.potential, forces=forces,
                bodies=model.bodies, loads=model.loads, gravity=model.gravity, frames=model.frames,
                points=model.points, constraints=tuple(constraints), initial=initial, t0=model.t0,
                independent=model.independent, simulation=model.simulation, source=model.source,
                description=model.description, units=model.units, controls=tuple(
                    replace(u, direction=tuple(u.direction) + (0,) * len(aux_all)) for u in model.controls))
    return Extension(model, ext, tuple(specs))


def _accelerations(base: Model, D: sp.Matrix, w: list) -> list:
    """``q'' = a0 + P D w`` under the constraints of *base* (SymPy, one per coordinate)."""
    dyn = dynamics_of(base)
    n = dyn.n
    K, rhs = saddle_system(dyn, dyn.rows(), [D[:, j] for j in range(D.shape[1])])
    sol = K.LUsolve(rhs)
    out = []
    for i in range(n):
        e = sol[i, 0] + sum((sol[i, 1 + j] * w[j] for j in range(len(w))), sp.Integer(0))
        out.append(sp.cancel(e) if sp.count_ops(e) < 2000 else e)
    return out, K[:n, :n]


def _connection(model: Model, M: sp.Matrix):
    """``P -> Gamma q' P``: the rate of a covector's components ``P`` (a generalized force) that
    is not its covariant derivative along the motion in the metric of the mass matrix M(q),
    ``(Gamma q' P)_s = Gamma^r_(s u) q'^u P_r`` with Levi-Civita's symbols of M.  Zero where M
    does not depend on the coordinates (Cartesian coordinates of particles), so that there the
    covariant derivatives are the plain ones.  A mass matrix that depends on time is refused: the
    rate of its basis is then not in M."""
    t = sp.Symbol("t")
    if M.has(t):
        raise ModelError("an ideal constraint of order three or more needs a mass matrix that does not "
                         "depend on time explicitly (its force's derivatives are taken in the metric of "
                         "M(q)); give the constraint a reaction = [...] direction, or use coordinates in "
                         "which the kinetic energy does not contain t", _source(model))
    q, qd = list(model.q), list(model.qd)
    if not any(M.has(x) for x in q):
        return lambda P: [sp.Integer(0)] * len(P)
    n = len(q)
    # Gamma_(l, s u) q'^u: Christoffel's symbols of the first kind contracted with the velocities
    K = sp.Matrix(n, n, lambda l, s_: sum((sp.diff(M[l, u], q[s_]) + sp.diff(M[l, s_], q[u])
                                            - sp.diff(M[s_, u], q[l])) * qd[u] for u in range(n)) / 2)

    def turn(P):
        v = M.LUsolve(sp.Matrix(P))          # the contravariant components M^-1 P
        return [sp.cancel(sum((v[l] * K[l, s_] for l in range(n)), sp.Integer(0))) for s_ in range(n)]
    return turn


def _rate(model: Model, exprs: list, a: list, chain: dict) -> list:
    """The total time derivatives of *exprs* along the motion: ``q'`` for ``dq``, ``a`` for
    ``dq'`` and, by *chain*, each force derivative's next one (the last: the unknown ``w^(n-2)``)."""
    t = sp.Symbol("t")
    qd = list(model.qd)
    out = []
    for e in exprs:
        d = sp.diff(e, t)
        d += sum((sp.diff(e, v) * acc for v, acc in zip(qd, a)), sp.Integer(0))
        d += sum((sp.diff(e, x) * v for x, v in chain.items()), sp.Integer(0))
        out.append(d)
    return out


def _source(model: Model) -> str | None:
    return None if model.source == "<api>" else model.source
