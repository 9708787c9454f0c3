"""Numbers from expressions: a SymPy expression of numbers (or of symbols given values)
evaluated in double precision, with the overflow, domain and size checks a model file needs."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping

import sympy as sp

from ..errors import ExpressionError

__all__ = ["float_value", "MAX_NODES"]


def _short(s: str, width: int = 60) -> str:
    return s if len(s) <= width else s[: width - 3] + "..."


MAX_NODES = 100_000
"""Nodes of an expression evaluated to a number (a size check before any arithmetic)."""

_FLOAT_FUNCTIONS = {
    sp.sin: math.sin, sp.cos: math.cos, sp.tan: math.tan,
    sp.cot: lambda x: 1.0 / math.tan(x), sp.sec: lambda x: 1.0 / math.cos(x),
    sp.csc: lambda x: 1.0 / math.sin(x),
    sp.asin: math.asin, sp.acos: math.acos, sp.atan: math.atan, sp.atan2: math.atan2,
    sp.sinh: math.sinh, sp.cosh: math.cosh, sp.tanh: math.tanh,
    sp.exp: math.exp, sp.log: math.log, sp.Abs: abs,
    sp.sign: lambda x: float((x > 0) - (x < 0)), sp.Min: min, sp.Max: max,
}


def float_value(expr, where: str, values: Mapping[str, float] | None = None,
                text: str | None = None) -> float:
    """The value of a SymPy expression with numbers only (or symbols in *values*), computed in
    double precision -- never by exact or arbitrary-precision arithmetic, whose cost has no
    bound (``sin(exp(exp(exp(3))))`` would need hundreds of millions of digits of pi; even
    printing such an expression makes SymPy evaluate it, so messages never print it).

    *text*, the expression as the user wrote it, is quoted in messages.

    Raises
    ------
    ExpressionError
        Naming *where* and the reason: an overflow (``exp(1000)``), a value outside a
        function's domain (``sqrt(-1)``, ``log(0)``), a division by zero, a non-finite result,
        an unknown symbol, or an expression too large to evaluate (:data:`MAX_NODES`).

    Examples
    --------
    >>> float_value(sp.sin(sp.pi / 6) + sp.Rational(1, 2), "m")
    1.0
    """
    if isinstance(expr, bool):
        raise ExpressionError(f"{where}: expected a number, got a boolean")
    if isinstance(expr, numbers.Real) and not isinstance(expr, sp.Basic):
        try:
            value = float(expr)
        except OverflowError:
            raise ExpressionError(f"{where}: {_short_number(expr)} is too large for a floating-point "
                                  "number (|x| < 1.8e308)") from None
    else:
        expr = sp.sympify(expr) if not isinstance(expr, sp.Basic) else expr
        budget = [MAX_NODES]
        shown = f" {_short(text)}" if text else ""  # never str(expr): see above
        try:
            value = _float(expr, values or {}, budget)
        except OverflowError:
            raise ExpressionError(f"{where}: the expression{shown} overflows: a number in it "
                                  "exceeds the floating-point range (|x| < 1.8e308)") from None
        except ZeroDivisionError:
            raise ExpressionError(f"{where}: the expression{shown} divides by zero") from None
        except (ValueError, TypeError) as exc:
            raise ExpressionError(f"{where}: the expression{shown} has no finite real value "
                                  f"({exc}); check its domain (sqrt, log, asin, acos ...)") from None
        except _TooLarge:
            raise ExpressionError(f"{where}: expression with more than {MAX_NODES} operations; "
                                  "too large to evaluate to a number") from None
    if not math.isfinite(value):
        raise ExpressionError(f"{where}: the value is not finite ({value})")
    return value


class _TooLarge(Exception):
    pass


def _short_number(x) -> str:
    s = str(x)
    return s if len(s) <= 40 else f"{s[:12]}...{s[-6:]} ({len(s)} digits)"


def _float(e: sp.Basic, values: Mapping[str, float], budget: list[int]) -> float:
    budget[0] -= 1
    if budget[0] < 0:
        raise _TooLarge
    if e.is_Integer:
        return float(int(e))
    if e.is_Rational:
        return int(e.p) / int(e.q)
    if e.is_Float:
        return float(e)
    if e is sp.pi:
        return math.pi
    if e is sp.E:
        return math.e
    if e.is_Symbol:
        if e.name in values:
            return float(values[e.name])
        raise ValueError(f"unknown symbol '{e.name}'")
    if e.is_Add:
        return math.fsum(_float(a, values, budget) for a in e.args)
    if e.is_Mul:
        out = 1.0
        for a in e.args:
            out *= _float(a, values, budget)
        return out
    if e.is_Pow:
        base, exp = _float(e.base, values, budget), _float(e.exp, values, budget)
        if base == 0.0 and exp < 0:
            raise ZeroDivisionError
        out = math.pow(base, exp)
        return out
    func = _FLOAT_FUNCTIONS.get(e.func)
    if func is None:
        raise ValueError(f"cannot evaluate {e.func.__name__} numerically")
    args = [_float(a, values, budget) for a in e.args]
    if e.func is sp.log and args[0] <= 0:
        raise ValueError("log of a non-positive number")
    return float(func(*args))
