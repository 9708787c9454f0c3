"""Checks of the constraint parts a model file may declare beyond the ordinary ones: constraints
of order three and more (``x'''``, ``x''''``, ... in expr) with the initial values of their force
and its derivatives, the quadratic cost of several control directions, and the controls shared
by several programs (``[[controls]]``).

A constraint of order n >= 3, ``f(q, q', ..., q^(n), t) = 0``, is realized by a force whose size
cannot be read off the state (q, q'): the accelerations contain the force, so ``q^(k)``
contains its derivatives up to ``k - 2``, and the constraint is a differential equation of
order ``n - 2`` for it (Yushkov 1999, ch. IV, secs. 5 and 7: for linear constraints of order
three and more the multipliers are "unknown functions of time determined by differential
equations written for them").  The force and its derivatives up to order ``n - 3`` at ``t0``
are therefore part of the initial state, given in ``[initial]`` as ``lambda_<constraint>``,
``lambda_<constraint>'``, ``lambda_<constraint>''``, ...:

* with ``reaction = [...]`` (a direction ``B(q, q', t)``; required when ``q^(n)`` enters
  nonlinearly): the force is ``B lambda`` and each key is a number, ``lambda^(k)(t0)``;
* without ``reaction`` (ideal, linear in ``q^(n)``): the generalized reaction ``R`` satisfies the
  generalized Gauss principle of order n, ``R^(n-2) = Lambda (d f / d q^(n))^T``, and each key
  is the list of the n_q components of ``R^(k)(t0)``.

On a :class:`~nonideal.modeling.declarations.Constraint` the same values are ``initial``: the
normalized model keeps them as a tuple of ``n - 2`` levels (``lambda, lambda', ...``; ideal: one
n_q-tuple per level).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from .values import parameter_values, to_expr, value_problems

__all__ = ["MAX_ORDER", "derivatives", "initial_keys", "high_order_problem", "initial_forces",
           "cost_problem", "normalize_controls"]

#: the highest order of a constraint (each order adds one time derivative of the accelerations,
#: whose size grows fast with it)
MAX_ORDER = 8


def derivatives(model, k: int) -> list[sp.Symbol]:
    """The time derivatives of order *k* of the coordinates, symbols named ``x`` + k primes."""
    return [sp.Symbol(c + "'" * k) for c in model.coordinates]


def initial_keys(name: str, order: int) -> list[str]:
    """The ``[initial]`` keys of the force of the constraint *name* of order *order* (>= 3) and
    of its derivatives: ``lambda_<name>``, ``lambda_<name>'``, ... (``order - 2`` keys)."""
    return [f"lambda_{name}" + "'" * k for k in range(order - 2)]


def high_order_problem(model, c, expr: sp.Expr, where: str, order: int) -> tuple[str | None, bool]:
    """``(problem or None, nonlinear)`` for the constraint *c* of order *order* (>= 3) with the
    parsed *expr*: what it may not combine with, and whether ``q^(n)`` enters it nonlinearly
    (then it needs ``reaction`` and takes a root rule)."""
    top = [s for s in derivatives(model, order) if s in expr.free_symbols]
    nonlinear = any(sp.diff(expr, a, b) != 0 for a in top for b in top)
    what = f"order-{order}" if order > 3 else "third-order"
    if nonlinear and c.reaction is None:
        top_name = "the third derivatives" if order == 3 else f"the derivatives of order {order}"
        return (f"{where}: a {what} constraint nonlinear in {top_name} needs "
                "'reaction' (the generalized direction of the force that realizes it; Yushkov "
                "1999, ch. IV) and, optionally, root = \"largest\" | \"smallest\""), nonlinear
    for item, bad in (("unilateral = true", c.unilateral), ("'transform'", c.transform is not None),
                      ("several control directions", c.controls is not None),
                      ("[[contacts]] in the model", bool(model.contacts))):
        if bad:
            return (f"{where}: a {what} constraint cannot be combined with {item} (not "
                    "supported); write the program at a lower order or drop the other"), nonlinear
    return None, nonlinear


def _levels(value: Any, ideal: bool, n_q: int, count: int) -> list | None:
    """The API's ``Constraint.initial`` as a list of *count* levels, or None when its shape is
    not one of: a number (one level, along a reaction), a flat sequence of *count* numbers
    (along a reaction), a sequence of n_q numbers (ideal, one level), a sequence of *count*
    sequences of n_q numbers (ideal)."""
    seq = isinstance(value, (list, tuple))
    if not ideal:
        if not seq:
            return [value] if count == 1 else None
        return list(value) if len(value) == count and not any(isinstance(v, (list, tuple)) for v in value) \
            else None
    if not seq:
        return None
    if all(isinstance(v, (list, tuple)) for v in value) and value:
        return [list(v) for v in value] if len(value) == count else None
    return [list(value)] if count == 1 and not any(isinstance(v, (list, tuple)) for v in value) else None


def initial_forces(model, c, given: dict, names, problems: list[str]):
    """The initial force of the constraint *c* of order n >= 3 and its derivatives up to
    ``n - 3``: from ``[initial] lambda_<name>``, ``lambda_<name>'``, ... (taken out of *given*),
    else from ``c.initial``.  Returns a tuple of ``n - 2`` levels -- expressions in the
    parameters (with ``reaction``) or tuples of n_q of them (ideal: the generalized reaction R
    and its derivatives) -- or None, with the problems appended to *problems*."""
    ideal = c.reaction is None
    keys = initial_keys(c.name, c.order)
    count = len(keys)
    from_keys = [given.pop(k, None) for k in keys]
    extra = sorted(k for k in given if isinstance(k, str) and k.rstrip("'") == f"lambda_{c.name}")
    for k in extra:
        given.pop(k)
        problems.append(f"[initial] {k}: the constraint '{c.name}' is of order {c.order}, so its "
                        f"initial force takes {' and '.join(keys)} only (the force's derivatives up to "
                        f"order {count - 1}); remove {k} or write the constraint at order "
                        f"{len(k) - len(k.rstrip(chr(39))) + 3}")
    if extra:
        return None
    api = None
    if c.initial is not None:
        api = _levels(c.initial, ideal, model.n_q, count)
        if api is None:
            shape = (f"{count} lists of {model.n_q} numbers" if ideal else f"{count} numbers") \
                if count > 1 else (f"a list of {model.n_q} numbers" if ideal else "a number")
            problems.append(f"constraint '{c.name}': initial must be {shape} (the force at t0"
                            + (" and its derivatives up to order " + str(count - 1) if count > 1 else "")
                            + f"; got {c.initial!r})")
            return None
    values = parameter_values(model.parameters)
    out = []
    for k, (key, value) in enumerate(zip(keys, from_keys)):
        where = f"[initial] {key}"
        if value is None and api is not None:
            value = api[k]
        what = "the force" if k == 0 else f"the derivative of order {k} of the force"
        if value is None:
            shape = (f"a list of {model.n_q} numbers, {what} (the generalized reaction R"
                     + "'" * k + " at t0, one number per coordinate)" if ideal else
                     f"a number, {what} at t0 (lambda" + "'" * k + "; the force is reaction * lambda)")
            why = ("its force cannot be computed from q and q' (the constraint fixes only its rate)"
                   if count == 1 else
                   f"the constraint of order {c.order} fixes only the force's derivative of order "
                   f"{c.order - 2}, so the force and its derivatives up to order {count - 1} at t0 "
                   f"are part of the initial state ({', '.join(keys)})")
            by = "third-order" if c.order == 3 else f"order-{c.order}"
            problems.append(f"{where}: required by the {by} constraint '{c.name}': "
                            f"give {shape}; {why}")
            return None
        items = list(value) if isinstance(value, (list, tuple)) else None
        if ideal and (items is None or len(items) != model.n_q):
            problems.append(f"{where}: must be a list of {model.n_q} numbers (one per coordinate: "
                            f"{what}, the generalized reaction of the ideal constraint '{c.name}' "
                            "at t0)")
            return None
        if not ideal and items is not None:
            problems.append(f"{where}: must be one number ({what}: lambda" + "'" * k
                            + f" of '{c.name}' at t0; the force is reaction * lambda)")
            return None
        level = []
        for j, v in enumerate(items if ideal else [value]):
            w = f"{where}[{j}]" if ideal else where
            try:
                e = to_expr(v, names, w, ())
            except Exception as exc:  # ExpressionError: its problems are the message
                problems.extend(getattr(exc, "problems", [str(exc)]))
                return None
            if e.free_symbols - set(names.values()):
                problems.append(f"{w}: initial values may use parameters only")
                return None
            if bad := value_problems(e, w, values):
                problems.extend(bad)
                return None
            level.append(e)
        out.append(tuple(level) if ideal else level[0])
    return tuple(out)


def cost_problem(cost, parameters) -> str | None:
    """Why a quadratic cost of the controls is not symmetric positive definite (at the
    parameters' values), or None."""
    values = parameter_values(parameters)
    try:
        W = np.array([[float(sp.sympify(x).xreplace(values)) for x in row] for row in cost])
    except (TypeError, ValueError):
        return "must contain numbers or expressions in the parameters only"
    if not np.allclose(W, W.T):
        return "must be symmetric"
    if np.min(np.linalg.eigvalsh(W)) <= 0:
        return "must be positive definite (the rule minimizes u^T cost u)"
    return None


def normalize_controls(norm) -> None:
    """The model's shared controls (``[[controls]]``) with their directions parsed (expressions
    in q, q', t) and their weights checked (positive, in the parameters); problems go to the
    normalizer's list.  Béghin 1922: one set of j controls for all the programs declared as
    servo-constraints without ``reaction``."""
    from dataclasses import replace

    from .declarations import Control
    from .symbols import is_identifier

    m = norm.m
    out, seen = [], set(m.coordinates) | set(m.parameters) | {getattr(c, "name", None) for c in m.constraints}
    for k, u in enumerate(m.controls):
        if not isinstance(u, Control):
            norm.problems.append(f"controls[{k}]: must be a Control(name, direction, weight)")
            continue
        where = f"control '{u.name}'"
        if not isinstance(u.name, str) or not is_identifier(u.name) or u.name in seen:
            norm.problems.append(f"{where}: name must be an identifier not used by a coordinate, "
                                 "parameter, constraint or another control")
            continue
        seen.add(u.name)
        d = norm.vector(u.direction, f"{where}: direction", (m.n_q,), order=1)
        w = norm.expr(u.weight, f"{where}: weight", 0)
        if d is None or w is None:
            continue
        if all(x == 0 for x in d):
            norm.problems.append(f"{where}: direction is zero")
            continue
        bad = cost_problem([[w]], m.parameters)
        if bad:
            norm.problems.append(f"{where}: weight {bad.replace('must be positive definite', 'must be > 0')}")
            continue
        out.append(replace(u, direction=tuple(d), weight=w))
    norm.set("controls", tuple(out))
