"""A safe parser for the expressions of model files.

A model file is data.  Expressions are parsed with :func:`ast.parse` (which builds a syntax
tree and runs nothing) and the tree is walked against a whitelist: numbers, known names,
``+ - * / **`` (``^`` is accepted for powers), unary minus, and calls of a fixed set of
elementary functions.  Attribute access, subscripts, keywords, lambdas, comparisons and every
other construct are rejected with a message that says where.  Neither :func:`eval` nor
:func:`sympy.sympify` ever sees the user's text.

Derivatives are written with primes: ``x'`` is the velocity of coordinate ``x`` and ``x''``
its acceleration.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Mapping

import sympy as sp

from .errors import ExpressionError, did_you_mean

__all__ = ["parse_expression", "FUNCTIONS", "MAX_LENGTH"]

MAX_LENGTH = 50_000
MAX_DEPTH = 200
MAX_EXPONENT = 64

FUNCTIONS: Mapping[str, tuple[object, int]] = {
    "sin": (sp.sin, 1), "cos": (sp.cos, 1), "tan": (sp.tan, 1), "cot": (sp.cot, 1),
    "sec": (sp.sec, 1), "csc": (sp.csc, 1),
    "asin": (sp.asin, 1), "acos": (sp.acos, 1), "atan": (sp.atan, 1), "atan2": (sp.atan2, 2),
    "sinh": (sp.sinh, 1), "cosh": (sp.cosh, 1), "tanh": (sp.tanh, 1),
    "exp": (sp.exp, 1), "log": (sp.log, 1), "ln": (sp.log, 1), "sqrt": (sp.sqrt, 1),
    "abs": (sp.Abs, 1), "Abs": (sp.Abs, 1), "sign": (sp.sign, 1),
    "min": (sp.Min, 2), "max": (sp.Max, 2),
}
CONSTANTS: Mapping[str, sp.Expr] = {"pi": sp.pi}

_PRIME = re.compile(r"([A-Za-z_][A-Za-z_0-9]*)('+)")
_BAD_PRIME = re.compile(r"[^A-Za-z_0-9\s']\s*'|^\s*'")
_D = ("__d1__", "__d2__")


def _encode_primes(text: str, where: str) -> str:
    if _BAD_PRIME.search(text):
        raise ExpressionError(
            f"{where}: a prime (') must follow a coordinate name, as in x' or x'' "
            f"(got {text!r})"
        )

    def repl(m: re.Match) -> str:
        order = len(m.group(2))
        if order > 2:
            raise ExpressionError(
                f"{where}: {m.group(1)}{m.group(2)} -- only first (x') and second (x'') "
                "derivatives can be written"
            )
        return _D[order - 1] + m.group(1)

    return _PRIME.sub(repl, text)


def _decode_name(name: str) -> str:
    for order, tag in enumerate(_D, start=1):
        if name.startswith(tag):
            return name[len(tag):] + "'" * order
    return name


def parse_expression(
    text: str | int | float,
    names: Mapping[str, sp.Expr],
    where: str,
) -> sp.Expr:
    """Parse *text* into a SymPy expression using only the symbols in *names*.

    Parameters
    ----------
    text : str or number
        The expression, e.g. ``"(m + m1)/2*x'^2 - m1*l*x'*theta'*sin(theta)"``.
    names : mapping
        Allowed names -> SymPy objects.  Derivatives are looked up by their primed names
        (``"x'"``, ``"x''"``); ``t`` must be included to allow time.
    where : str
        Where the text comes from, for messages: ``"constraint 'rod': expr"``.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    ExpressionError
        With the position of a syntax error, the unknown name and a "did you mean", or the
        construct that is not allowed.

    Examples
    --------
    >>> import sympy as sp
    >>> x, xd = sp.Symbol('x'), sp.Symbol("x'")
    >>> parse_expression("x'^2/2 + sin(x)", {"x": x, "x'": xd}, "energy.kinetic")
    x'**2/2 + sin(x)
    """
    if isinstance(text, bool):
        raise ExpressionError(f"{where}: expected an expression, got a boolean ({text})")
    if isinstance(text, (int, float)):
        return sp.Rational(repr(text)) if isinstance(text, float) else sp.Integer(text)
    if not isinstance(text, str):
        raise ExpressionError(
            f"{where}: expected an expression string, got {type(text).__name__} ({text!r})"
        )
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"{where}: expression longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError(f"{where}: empty expression (write \"0\" for zero)")
    source = _encode_primes(text, where).replace("^", "**")
    try:
        tree = ast.parse(source.strip(), mode="eval")
    except SyntaxError as exc:
        col = (exc.offset or 1) - 1
        caret = " " * (len(where) + 2 + min(col, len(text))) + "^"
        raise ExpressionError(
            f"{where}: malformed expression {text!r}: {exc.msg} at column {col + 1}\n{caret}"
        ) from None
    except (RecursionError, MemoryError, ValueError):
        raise ExpressionError(f"{where}: expression nested too deeply") from None
    builder = _Builder(names, where, source.strip())
    try:
        return builder.build(tree.body, 0)
    except RecursionError:
        raise ExpressionError(f"{where}: expression nested too deeply") from None


class _Builder:
    def __init__(self, names: Mapping[str, sp.Expr], where: str, source: str):
        self.names, self.where, self.source = names, where, source

    def fail(self, node: ast.AST, what: str) -> ExpressionError:
        segment = ast.get_source_segment(self.source, node) or ""
        for order, tag in enumerate(_D, start=1):
            segment = re.sub(tag + r"([A-Za-z_][A-Za-z_0-9]*)", r"\1" + "'" * order, segment)
        return ExpressionError(f"{self.where}: {what} (in {segment!r})")

    def build(self, node: ast.AST, depth: int) -> sp.Expr:
        if depth > MAX_DEPTH:
            raise ExpressionError(f"{self.where}: expression nested too deeply")
        if isinstance(node, ast.Constant):
            value = node.value
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise self.fail(node, f"only numbers are allowed as constants, got {value!r}")
            if isinstance(value, int):
                return sp.Integer(value)
            literal = ast.get_source_segment(self.source, node) or repr(value)
            try:
                return sp.Rational(literal)
            except (TypeError, ValueError):
                return sp.Float(value)
        if isinstance(node, ast.Name):
            return self.name(node)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = self.build(node.operand, depth + 1)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp):
            left = self.build(node.left, depth + 1)
            right = self.build(node.right, depth + 1)
            op = node.op
            if isinstance(op, ast.Add):
                return left + right
            if isinstance(op, ast.Sub):
                return left - right
            if isinstance(op, ast.Mult):
                return left * right
            if isinstance(op, ast.Div):
                if right == 0:
                    raise self.fail(node, "division by zero")
                return left / right
            if isinstance(op, ast.Pow):
                if right.is_number and abs(float(right)) > MAX_EXPONENT:
                    raise self.fail(node, f"exponent larger than {MAX_EXPONENT} in magnitude")
                return left**right
            raise self.fail(node, f"operator {type(op).__name__} is not allowed (use + - * / ^)")
        if isinstance(node, ast.Call):
            return self.call(node, depth)
        raise self.fail(node, f"{type(node).__name__} is not allowed in an expression")

    def name(self, node: ast.Name) -> sp.Expr:
        raw = node.id
        name = _decode_name(raw)
        if name in self.names:
            return self.names[name]
        if name in CONSTANTS:
            return CONSTANTS[name]
        if name in FUNCTIONS:
            raise self.fail(node, f"function '{name}' used without arguments")
        if name.endswith("'") and name.rstrip("'") in self.names:
            base = name.rstrip("'")
            if base + "'" not in self.names and base + "''" not in self.names:
                kind = "'t' is time" if base == "t" else f"'{base}' is not a coordinate"
                raise ExpressionError(
                    f"{self.where}: {name} -- {kind}; only coordinates have derivatives"
                )
            raise ExpressionError(
                f"{self.where}: {name} is not allowed here (this expression may not contain "
                f"derivatives of '{base}' of that order)"
            )
        candidates = list(self.names) + list(CONSTANTS)
        raise ExpressionError(
            f"{self.where}: unknown symbol '{name}'{did_you_mean(name, candidates)}"
        )

    def call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            raise self.fail(node, "only calls of elementary functions by name are allowed")
        fname = node.func.id
        if fname not in FUNCTIONS:
            raise self.fail(
                node,
                f"unknown function '{fname}'{did_you_mean(fname, FUNCTIONS)}; allowed: "
                + ", ".join(sorted(FUNCTIONS)),
            )
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            raise self.fail(node, "keyword or starred arguments are not allowed")
        func, arity = FUNCTIONS[fname]
        if len(node.args) != arity:
            raise self.fail(node, f"{fname} takes {arity} argument(s), got {len(node.args)}")
        return func(*(self.build(a, depth + 1) for a in node.args))
