"""Third-order constraints as second-order ones of a model extended by the force's impulse.

A constraint ``f(q, q', q'', q''', t) = 0`` is realized by a generalized force ``R`` that the
state (q, q') does not determine: the accelerations contain it, ``q'''`` contains its rate, and
the constraint is a differential equation for it (Yushkov 1999, ch. IV: for linear constraints
of order three and more the multipliers become unknown functions of time governed by their own
differential equations).  Two ways of realizing it:

* **along a given direction** ``B(q, q', t)`` (``reaction = [...]``; a servo-constraint in
  Béghin's sense): ``R = B lambda`` with one scalar ``lambda`` -- the constraint may then be
  nonlinear in ``q'''`` (quadratic along B: a root rule chooses the branch);
* **ideal** (no ``reaction``; linear in ``q'''``): the Gauss principle of third order.  With
  ``M q'' = F + R`` differentiated, ``M q''' = F' - M' q'' + R'``; among the third derivatives
  the constraint allows, the actual one minimizes ``(q''' - q'''_0)^T M (q''' - q'''_0)/2``, where
  ``q'''_0`` is the third derivative with the reaction held (``R' = 0``).  Its minimum has
  ``M (q''' - q'''_0) = Lambda g``, ``g = (d f / d q''')^T``: the *rate* of the ideal reaction is
  along the gradient, ``R' = Lambda g`` (for order two the same principle gives ``R = lambda
  g``).  R is an n_q-vector of the state.

**The extension.**  The force's unknown components ``w`` (lambda, or R) become the velocities of
auxiliary coordinates ``z`` (``z`` is the impulse of the force, ``int w dt``) with the kinetic
energy ``|z'|^2/2`` and the generalized force ``D w`` on the coordinates (``D = B``, or the
identity).  With the other constraints' reactions solved for, ``q'' = a(q, q', w, t)`` (linear in
w), so ``q''' = da/dt`` is linear in ``w' = z''`` and

    f_ext(q, q', z', z'', t) = f(q, q', a, da/dt, t) = 0

is a *second-order* constraint of the extended model, realized by a force on ``z`` alone along
``e`` (direction B) or ``g`` (ideal): ``z'' = e mu`` -- ``mu = lambda'`` -- or ``z'' = g mu`` --
``mu = Lambda``.  The extended model is an ordinary model: its simulation is the motion; the
auxiliary energy ``|z'|^2/2`` and the work of ``mu`` on ``z`` cancel in its balance and are taken
out again by :func:`nonideal.simulation.extended.reduce`.  Explicit symbolic cost: one LU solve
of the other constraints' saddle-point system, then one time derivative of the accelerations.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..errors import ModelError
from ..modeling.model import Constraint, Model
from .dynamics import dynamics_of
from .servo import saddle_system

__all__ = ["Extension", "ThirdOrder", "extension_of", "extended"]


@dataclass(frozen=True)
class ThirdOrder:
    """One third-order constraint in the extended model: its name, whether it is ideal, the
    auxiliary coordinates that carry its force (one: lambda; n_q: the ideal R) and its
    direction ``B`` (SymPy, n_q entries; None when ideal)."""

    name: str
    ideal: bool
    aux: tuple[str, ...]
    B: tuple | None


@dataclass(frozen=True)
class Extension:
    """A model with third-order constraints and the extended model that simulates it."""

    original: Model
    model: Model
    constraints: tuple[ThirdOrder, ...]


def extension_of(model: Model) -> Extension | None:
    """The extension of *model* (cached), or None when it has no third-order constraint."""
    if not isinstance(model, Model) or not any(c.order == 3 for c in model.constraints):
        return None
    return model.cached("third_order_extension", lambda: _extend(model))


def extended(model: Model) -> Model:
    """The model that stands for *model* at a state: its extension when it has third-order
    constraints (the state then includes the forces that realize them, as the velocities of the
    auxiliary coordinates ``<constraint>_impulse``), else *model* itself.  ``check``,
    ``evaluate``, ``derive`` and the cross-check of the forms work on it."""
    ext = extension_of(model)
    return model if ext is None else ext.model


def _unique(name: str, taken: set) -> str:
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def _extend(model: Model) -> Extension:
    third = [c for c in model.constraints if c.order == 3]
    others = tuple(c for c in model.constraints if c.order != 3)
    if any(c.unilateral for c in others):
        raise ModelError(f"constraint '{third[0].name}': a third-order constraint cannot be combined "
                         "with unilateral constraints (not supported)", _source(model))
    n = model.n_q
    taken = set(model.coordinates) | set(model.parameters)
    specs, w = [], []
    for c in third:
        ideal = c.reaction is None
        names = [f"{c.name}_impulse_{q}" for q in model.coordinates] if ideal else [f"{c.name}_impulse"]
        aux = tuple(_unique(a, taken) for a in names)
        B = None if ideal else tuple(sp.sympify(b) for b in c.reaction)
        specs.append(ThirdOrder(c.name, ideal, aux, B))
        w += [sp.Symbol(a + "'") for a in aux]
    # D: the generalized force of the auxiliary velocities w on the coordinates, n x k
    cols = []
    for s in specs:
        cols += [[sp.Integer(1 if i == k else 0) for i in range(n)] for k in range(n)] if s.ideal \
            else [list(s.B)]
    D = sp.Matrix(n, len(cols), lambda i, j: cols[j][i])
    a = _accelerations(model.replace(constraints=others), D, w)
    wd = [sp.Symbol(str(s)[:-1] + "''") for s in w]
    da = _rate(model, a, w, wd)
    qdd = list(model.qdd)
    jerk = [sp.Symbol(s.name + "'") for s in qdd]
    sub = dict(zip(jerk, da))
    sub.update(zip(qdd, a))
    forces = {c: f + sum((D[i, j] * w[j] for j in range(len(w))), sp.Integer(0))
              for i, (c, f) in enumerate(zip(model.coordinates, model.forces))}
    constraints, initial, k0 = list(others), dict(model.initial), 0
    for s, c in zip(specs, third):
        k = len(s.aux)
        f_ext = sp.sympify(c.expr).xreplace(sub)
        if s.ideal:
            g = [sp.diff(c.expr, j).xreplace(sub) for j in jerk]
        else:
            g = [sp.Integer(1)]
        reaction = [0] * n + [0] * k0 + g + [0] * (len(w) - k0 - k)
        constraints.append(Constraint(c.name, f_ext, "servo", reaction=tuple(reaction), root=c.root))
        values = c.initial if s.ideal else (c.initial,)
        initial.update({z: 0 for z in s.aux})
        initial.update({z + "'": v for z, v in zip(s.aux, values)})
        k0 += k
    kinetic = model.kinetic + sum((x ** 2 for x in w), sp.Integer(0)) / 2
    ext = Model(name=model.name, coordinates=tuple(model.coordinates) + tuple(a for s in specs for a in s.aux),
                parameters=model.parameters, kinetic=kinetic, potential=model.potential, forces=forces,
                bodies=model.bodies, loads=model.loads, gravity=model.gravity,
                constraints=tuple(constraints), initial=initial, t0=model.t0,
                independent=model.independent, simulation=model.simulation, source=model.source,
                description=model.description, units=model.units, controls=tuple(
                    replace(u, direction=tuple(u.direction) + (0,) * len(w)) for u in model.controls))
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
    return out


def _rate(model: Model, a: list, w: list, wd: list) -> list:
    """``da/dt`` along the motion: ``q' `` for ``dq``, ``a`` for ``dq'``, ``w'`` for ``dw``."""
    t = sp.Symbol("t")
    q, qd = list(model.q), list(model.qd)
    out = []
    for ai in a:
        e = sp.diff(ai, t)
        e += sum((sp.diff(ai, x) * v for x, v in zip(q, qd)), sp.Integer(0))
        e += sum((sp.diff(ai, v) * acc for v, acc in zip(qd, a)), sp.Integer(0))
        e += sum((sp.diff(ai, x) * v for x, v in zip(w, wd)), sp.Integer(0))
        out.append(e)
    return out


def _source(model: Model) -> str | None:
    return None if model.source == "<api>" else model.source
