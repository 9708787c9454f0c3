"""Values of a model: expressions normalized to the library's symbols (strings through the safe
parser, SymPy expressions and ``dynamicsymbols`` mapped onto ``x``, ``x'``, ``x''``), the
derivative order of an expression, and parameters resolved in dependency order (derived
parameters are expressions in the others)."""

from __future__ import annotations

import numbers
import random
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import symengine as se
import sympy as sp
from sympy.core.function import AppliedUndef

from ..errors import ExpressionError, ModelError, did_you_mean, short_repr
from .expressions import float_value, parse_expression
from .quantities import base_unit_of, parse_quantity
from .symbols import t

from .declarations import Parameter

__all__ = ["to_expr", "normalize_sympy", "derivative_order", "resolve_parameters",
           "parameter_values", "identically_zero"]


def to_expr(value: Any, names: Mapping[str, sp.Expr], where: str,
            coordinates: Iterable[str], vectors=None) -> sp.Expr:
    """An expression of the model: a string through the safe parser (with the vector
    functions of *vectors*, the model's kinematics, when given), a SymPy expression with its
    symbols mapped onto the model's."""
    if isinstance(value, str) or isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        return parse_expression(value, names, where, vectors)
    if isinstance(value, sp.Basic):
        check_depth(value, where)
        return normalize_sympy(sp.sympify(value), names, where, tuple(coordinates))
    raise ExpressionError(
        f"{where}: expected an expression (string or SymPy), got {type(value).__name__}"
    )


MAX_TREE_DEPTH = 500
"""Levels of a SymPy expression given to a Model at most (the parser's :data:`MAX_DEPTH` for
text; the equations of motion of a bicycle are some 30 levels deep).  SymPy walks deeper trees
by recursion, for minutes."""


def check_depth(expr: sp.Basic, where: str) -> None:
    """Refuse a SymPy expression nested deeper than :data:`MAX_TREE_DEPTH`, walked without
    recursion (``sin(sin(...))`` 3000 deep).

    Examples
    --------
    >>> e = sp.Symbol("x")
    >>> for _ in range(600):
    ...     e = sp.sin(e, evaluate=False)
    >>> try:
    ...     check_depth(e, "potential")
    ... except ExpressionError as exc:
    ...     print(exc.problems[0])
    potential: the expression is nested more than 500 levels deep; build it from parts (parameters, [[bodies]])
    """
    stack, seen = [(expr, 1)], set()
    while stack:
        node, depth = stack.pop()
        if depth > MAX_TREE_DEPTH:
            raise ExpressionError(f"{where}: the expression is nested more than {MAX_TREE_DEPTH} "
                                  "levels deep; build it from parts (parameters, [[bodies]])")
        for arg in node.args:
            if id(arg) not in seen:
                seen.add(id(arg))
                stack.append((arg, depth + 1))


def normalize_sympy(expr: sp.Basic, names: Mapping[str, sp.Expr], where: str,
                     coordinates: tuple[str, ...]) -> sp.Expr:
    """Map dynamicsymbols q(t), q'(t), q''(t) and assumption-carrying symbols onto ours."""
    repl = {}
    for d in expr.atoms(sp.Derivative):
        f = d.expr
        if isinstance(f, AppliedUndef) and f.func.__name__ in coordinates:
            order = sum(c for v, c in d.variable_count if v == t or str(v) == "t")
            key = f.func.__name__ + "'" * order
            if key not in names:
                raise ExpressionError(f"{where}: derivative {key} is not allowed here")
            repl[d] = names[key]
    expr = expr.xreplace(repl) if repl else expr
    repl = {}
    for f in expr.atoms(AppliedUndef):
        fname = f.func.__name__
        if fname not in coordinates:
            raise ExpressionError(
                f"{where}: unknown function of time '{fname}'{did_you_mean(fname, coordinates)}"
            )
        repl[f] = names[fname]
    expr = expr.xreplace(repl) if repl else expr
    repl = {}
    unknown = sorted({s.name for s in expr.free_symbols if s.name not in names})
    if unknown:
        raise ExpressionError(
            [f"{where}: unknown symbol '{u}'{did_you_mean(u, names)}" for u in unknown],
            unknown=[(u, where) for u in unknown])
    for s in expr.free_symbols:
        if s is not names[s.name]:
            repl[s] = names[s.name]
    return expr.xreplace(repl) if repl else expr


def derivative_order(expr: sp.Expr, coordinates: Iterable[str]) -> int:
    names = {s.name for s in expr.free_symbols}
    coords = set(coordinates)
    order = 0
    for name in names:
        base = name.rstrip("'")
        if base in coords:
            order = max(order, len(name) - len(base))
    return order


def resolve_parameters(raw: Mapping[str, Any], base: Mapping[str, Any] | None = None
                       ) -> tuple[dict[str, float], list[str]]:
    """Numeric values of parameters given as numbers, as quantities with a unit (``"30 deg"``,
    converted to the base units *base*: ``{"length": "cm", ...}``, SI where not given) or as
    expressions (strings) in the other parameters -- derived parameters such as
    ``theta_eq = "acos(g/(w^2*R))"`` -- evaluated in dependency order with the safe parser.

    Returns
    -------
    values : dict name -> float
        The parameters that could be evaluated.
    problems : list of str
        One message per parameter that could not (not a number, unknown names, a cycle).
    """
    values: dict[str, float] = {}
    problems: list[str] = []
    pending: dict[str, sp.Expr] = {}
    symbols = {n: sp.Symbol(n) for n in raw}
    for name, value in raw.items():
        where = f"[parameters] {name}"
        try:
            quantity = parse_quantity(value)
            if quantity is not None:
                values[name] = quantity.in_base(base)
                continue
        except ValueError as exc:
            problems.append(f"{where} = {value!r}: {exc}")
            continue
        if isinstance(value, str):
            try:
                pending[name] = parse_expression(value, symbols, where)
            except ExpressionError as exc:
                problems += [p.replace("unknown symbol", "unknown parameter", 1) for p in exc.problems]
        elif isinstance(value, bool) or not isinstance(value, numbers.Real):
            problems.append(f"{where}: value must be a finite number or an expression in the other "
                            f"parameters, in quotes (got {short_repr(value)})")
        else:
            try:
                values[name] = float_value(value, where)
            except ExpressionError as exc:
                problems += exc.problems
    # in dependency order (Kahn): linear in the number of parameters, however long the chains
    waiting = {n: {s.name for s in e.free_symbols} - set(values) for n, e in pending.items()}
    users: dict[str, list[str]] = {}
    for name, needs in waiting.items():
        for need in needs:
            users.setdefault(need, []).append(name)
    ready = [n for n, needs in waiting.items() if not needs]
    while ready:
        name = ready.pop()
        expr = pending.pop(name)
        try:  # in floating point: exact arithmetic has no bound on its cost
            values[name] = float_value(expr, f"[parameters] {name}", values, raw[name])
        except ExpressionError as exc:
            problems += exc.problems
            continue
        for user in users.get(name, ()):
            waiting[user].discard(name)
            if not waiting[user]:
                ready.append(user)
    for name in sorted(pending):
        needs = sorted(s.name for s in pending[name].free_symbols if s.name not in values)
        broken = [n for n in needs if n not in pending]
        if broken:
            why = f"it depends on {', '.join(broken)}, which has no value"
        elif needs == [name]:
            why = "it is defined in terms of itself; give it a number"
        else:
            why = (f"it depends on {', '.join(needs)}: the definitions form a cycle; give "
                   "one of them a number")
        problems.append(f"[parameters] {name}: cannot be evaluated -- {why}")
    return values, problems


def parameter_values(parameters: Mapping[str, Parameter]) -> dict[sp.Symbol, sp.Expr]:
    """``{symbol: value}`` of the parameters, for ``xreplace`` (a plain substitution of
    symbols by numbers: ``subs`` would search for subexpressions, 10-100x slower)."""
    return {sp.Symbol(n): sp.sympify(p.value) for n, p in parameters.items()}


def identically_zero(expr: sp.Expr) -> bool:
    """Whether *expr* vanishes identically: ``|expr| <= 1e-12`` at four random points (never
    a symbolic expansion of a large power), evaluated in SymEngine (10-20x cheaper than
    SymPy's ``evalf``).  Expressions that cannot be evaluated there count as nonzero."""
    if expr == 0:
        return True
    rng = random.Random(12345)
    try:
        e = se.sympify(expr)
    except (se.SympifyError, RuntimeError, TypeError):
        return False
    syms = sorted(e.free_symbols, key=lambda s: s.name)
    for _ in range(4):
        try:
            value = complex(e.xreplace({s: se.Float(rng.uniform(0.3, 1.7)) for s in syms}).n())
        except (RuntimeError, TypeError, ValueError, ZeroDivisionError, OverflowError):
            return False
        if not abs(value) <= 1e-12:
            return False
    return True


def value_problems(expr: sp.Expr, where: str, values: Mapping[sp.Symbol, Any]) -> list[str]:
    """The problems of the number *expr* gives with the parameter *values* (``{symbol:
    value}``), computed in floating point (:func:`~.expressions.float_value`); ``[]`` when it
    is a finite real number."""
    try:
        float_value(expr, where, {s.name: float(v) for s, v in values.items()})
    except ExpressionError as exc:
        return exc.problems
    return []


def override_parameters(data: dict[str, Any], values: Mapping[str, Any], source: str) -> dict[str, Any]:
    """*data* (a model file's tables) with ``[parameters]`` values replaced by *values*.

    A value is a number or a string (a number, or an expression in the other parameters,
    checked by the safe parser when the model is built).  Unknown names are reported together,
    each with the closest parameter name.
    """
    table = data.get("parameters", {})
    if not isinstance(table, dict):
        return data     # reported by model_from_dict
    problems = []
    new = dict(table)
    for name, value in values.items():
        if name not in table:
            known = ", ".join(table) if table else "none"
            problems.append(f"--set {name}: not a parameter of the model{did_you_mean(name, list(table))} "
                            f"(its [parameters]: {known}); --set overrides a parameter the file "
                            "declares")
            continue
        if isinstance(value, str):
            text = value.strip()
            try:
                value = float(text)
            except ValueError:
                value = text
        if isinstance(table[name], dict):
            new[name] = {**table[name], "value": value}
            unit = table[name].get("unit")
            if isinstance(unit, str) and unit:   # --set gives base units: the unit becomes theirs
                new[name]["unit"] = base_unit_of(unit, data.get("units"))
        else:
            new[name] = value
    if problems:
        raise ModelError(problems, source)
    return {**data, "parameters": new}
