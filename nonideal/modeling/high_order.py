"""Checks of the constraint parts a model file may declare beyond the ordinary ones: third-order
constraints (``x'''`` in expr) with the initial value of their multiplier, the quadratic cost
of several control directions, and the controls shared by several programs (``[[controls]]``).

A constraint of third order ``f(q, q', q'', q''', t) = 0`` is realized by a force whose size
cannot be read off the state (q, q'): the accelerations contain the force, so ``q'''`` contains
its rate, and the constraint is a differential equation for it (Yushkov 1999, ch. IV: for
linear constraints of order three and more the multipliers are "unknown functions of time
determined by differential equations written for them").  The force at ``t0`` is therefore part
of the initial state, given in ``[initial]`` as ``lambda_<constraint>``:

* with ``reaction = [...]`` (a direction ``B(q, q', t)``; required when ``q'''`` enters
  nonlinearly): the force is ``B lambda`` and ``lambda_<constraint>`` is the number lambda(t0);
* without ``reaction`` (ideal, linear in ``q'''``): the generalized reaction ``R`` satisfies the
  Gauss principle of third order, ``R' = Lambda (d f / d q''')^T``, and ``lambda_<constraint>``
  is the list of the n_q components of R(t0).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from .values import parameter_values, to_expr, value_problems

__all__ = ["jerks", "third_order_problem", "initial_multiplier", "cost_problem", "normalize_controls"]


def jerks(model) -> list[sp.Symbol]:
    """The third time derivatives of the coordinates, symbols named ``x'''``."""
    return [sp.Symbol(c + "'''") for c in model.coordinates]


def third_order_problem(model, c, expr: sp.Expr, where: str) -> tuple[str | None, bool]:
    """``(problem or None, nonlinear)`` for the third-order constraint *c* with the parsed *expr*:
    what it may not combine with, and whether ``q'''`` enters it nonlinearly (then it needs
    ``reaction`` and takes a root rule)."""
    j = [s for s in jerks(model) if s in expr.free_symbols]
    nonlinear = any(sp.diff(expr, a, b) != 0 for a in j for b in j)
    if nonlinear and c.reaction is None:
        return (f"{where}: a third-order constraint nonlinear in the third derivatives needs "
                "'reaction' (the generalized direction of the force that realizes it; Yushkov "
                "1999, ch. IV) and, optionally, root = \"largest\" | \"smallest\""), nonlinear
    for what, bad in (("unilateral = true", c.unilateral), ("'transform'", c.transform is not None),
                      ("several control directions", c.controls is not None),
                      ("[[contacts]] in the model", bool(model.contacts))):
        if bad:
            return (f"{where}: a third-order constraint cannot be combined with {what} (not "
                    "supported); write the program at a lower order or drop the other"), nonlinear
    return None, nonlinear


def initial_multiplier(model, c, value: Any, names, problems: list[str]):
    """The initial force of the third-order constraint *c* from ``[initial] lambda_<name>``
    (*value*, None when absent): an expression in the parameters (with ``reaction``) or a tuple
    of n_q of them (ideal: the generalized reaction R(t0)).  Problems are appended to
    *problems*; returns None then."""
    key = f"lambda_{c.name}"
    where = f"[initial] {key}"
    ideal = c.reaction is None
    if value is None:
        value = c.initial
    if value is None:
        what = (f"a list of {model.n_q} numbers, the generalized reaction R at t0 (the ideal "
                "constraint's force; its rate is along d expr/d q''')" if ideal else
                "a number, the multiplier at t0 (the force is reaction * lambda)")
        problems.append(f"{where}: required by the third-order constraint '{c.name}': give {what}; "
                        "its force cannot be computed from q and q' (the constraint fixes only its rate)")
        return None
    items = list(value) if isinstance(value, (list, tuple)) else None
    if ideal and (items is None or len(items) != model.n_q):
        problems.append(f"{where}: must be a list of {model.n_q} numbers (one per coordinate: the "
                        f"generalized reaction of the ideal constraint '{c.name}' at t0)")
        return None
    if not ideal and items is not None:
        problems.append(f"{where}: must be one number (the multiplier of '{c.name}' at t0: its force "
                        "is reaction * lambda)")
        return None
    values = parameter_values(model.parameters)
    out = []
    for k, v in enumerate(items if ideal else [value]):
        w = f"{where}[{k}]" if ideal else where
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
        out.append(e)
    return tuple(out) if ideal else out[0]


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
