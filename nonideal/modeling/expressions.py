"""A safe parser for the expressions of model files.

A model file is data.  Expressions are read by a small hand-written recursive-descent parser
over a whitelist of tokens -- numbers, names, ``+ - * / ^ **``, parentheses, commas and
primes -- and turned into SymPy objects directly.  Neither :func:`eval`, :func:`compile`,
:func:`ast.parse` nor :func:`sympy.sympify` ever sees the user's text, so nothing in a model
file can run code, look up attributes or import anything.  Names must be ASCII identifiers
known to the model (parameters, coordinates and their derivatives, ``t``), ``pi``, or calls of
a fixed set of elementary functions.

Grammar (the precedence of Python/SymPy: ``-x^2 = -(x^2)``, ``2^3^2 = 2^9``)::

    expr   := term (("+" | "-") term)*
    term   := unary (("*" | "/") unary)*
    unary  := ("+" | "-")* power
    power  := atom (("^" | "**") unary)?
    atom   := NUMBER | NAME | NAME "(" expr ("," expr)* ")" | "(" expr ")" | FRAME "." AXIS
    NAME   := [A-Za-z_][A-Za-z_0-9]* followed by up to two primes (x' and x''; three or
              more, x''' or x'''', where the names allow it: a constraint's expr)

With the model's kinematics (``vectors``, a :class:`~nonideal.modeling.kinematics.Kinematics`)
a subexpression may be a vector (:class:`~nonideal.modeling.vectors.Vector`, three components
in N): the unit vectors ``B.x``, ``B.y``, ``B.z`` of a declared frame and the calls of
:data:`~nonideal.modeling.vectors.VECTOR_FUNCTIONS` (``omega(B)``, ``vel(P)``, ``dot(a, b)``
...), whose frame, point and body arguments are names, never expressions.  Vectors add and
subtract with vectors and multiply or divide by scalars; ``dot``, ``cross`` and ``norm`` are
the only products.  Whether the whole expression is a scalar or a vector is checked against
what its key expects (:func:`parse_expression`, :func:`parse_vector`).

Guards keep hostile input cheap: a length limit (:data:`MAX_LENGTH`), a nesting limit
(:data:`MAX_DEPTH`, parentheses, powers and calls), a limit on exponents
(:data:`MAX_EXPONENT`, also after SymPy combines ``(x^a)^b``), on the size of numbers
(:data:`MAX_DIGITS`), and sums and products are built in one step (no quadratic re-flattening).
Every error is an :class:`~nonideal.errors.ExpressionError` that names where the text comes
from, the column, and what to write instead; all unknown names of an expression are reported
together (``ExpressionError.unknown``).
"""

from __future__ import annotations

import math
import numbers
import re
import unicodedata
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from ..errors import ExpressionError, did_you_mean
from .floats import MAX_NODES, float_value  # noqa: F401 (re-exported)
from .vectors import VECTOR_FUNCTIONS, Unknown, Vector, add, cross, dot, norm

__all__ = ["parse_expression", "parse_vector", "FUNCTIONS", "CONSTANTS", "MAX_LENGTH", "MAX_DEPTH",
           "MAX_EXPONENT", "MAX_DIGITS", "float_value", "MAX_NODES"]

MAX_LENGTH = 50_000     # characters of one expression
MAX_DEPTH = 100         # nested parentheses / powers / calls
MAX_EXPONENT = 64       # |exponent| of a power with a numeric exponent
MAX_DIGITS = 1_000      # decimal digits of a number (literal or computed)

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

_TOKEN = re.compile(
    r"(?P<ws>\s+)"
    r"|(?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)"
    r"|(?P<attr>[A-Za-z_][A-Za-z_0-9]*\.[A-Za-z_][A-Za-z_0-9]*)"
    r"|(?P<name>[A-Za-z_][A-Za-z_0-9]*'*)"
    r"|(?P<op>\*\*|[-+*/^(),])"
)
_FORBIDDEN_OPS = {
    "%": "the modulo operator '%'", "@": "the operator '@'", "&": "the operator '&'",
    "|": "the operator '|'", "~": "the operator '~'", "<": "comparisons", ">": "comparisons",
    "=": "'=' (an expression is not an equation: write lhs - rhs)", "!": "'!'",
    ".": "attribute access ('.')", "[": "brackets ('[')", "]": "brackets (']')",
    "{": "braces ('{')", "}": "braces ('}')", '"': "a double quote (strings)", "'": "a lone prime",
    ":": "':'", ";": "';'", "#": "comments ('#')", "\\": "backslashes", "$": "'$'",
    "?": "'?'", "`": "'`'",
}


@dataclass(frozen=True)
class _Token:
    kind: str    # "number" | "name" | "op" | "end"
    text: str
    col: int     # 0-based column in the user's text


class _Fail(Exception):
    """Internal: a syntax problem at a column (turned into an ExpressionError)."""

    def __init__(self, col: int, what: str):
        super().__init__(what)
        self.col, self.what = col, what


def parse_expression(
    text: str | int | float,
    names: Mapping[str, sp.Expr],
    where: str,
    vectors=None,
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
    vectors : Kinematics, optional
        The model's frames and points: enables vector subexpressions (the unit vectors
        ``B.x`` and the vector functions); the result must still be a scalar.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    ExpressionError
        With the column of a syntax error, every unknown name with a "did you mean", or the
        construct that is not allowed.  ``exc.unknown`` lists the unknown names.

    Examples
    --------
    >>> import sympy as sp
    >>> x, xd = sp.Symbol('x'), sp.Symbol("x'")
    >>> parse_expression("x'^2/2 + sin(x)", {"x": x, "x'": xd}, "energy.kinetic")
    x'**2/2 + sin(x)
    """
    value = _parse(text, names, where, vectors)
    if isinstance(value, Vector):
        raise ExpressionError(f"{where}: the expression is a vector (3 components in N) but a "
                              "scalar is expected here; take a component, e.g. dot(..., N.x), or "
                              "the length norm(...)")
    return value


def parse_vector(text: str, names: Mapping[str, sp.Expr], where: str, vectors) -> Vector:
    """Parse *text* into a :class:`~nonideal.modeling.vectors.Vector` (components in N), as
    :func:`parse_expression` does scalars; a scalar result is an error naming *where*."""
    value = _parse(text, names, where, vectors)
    if not isinstance(value, Vector):
        raise ExpressionError(f"{where}: the expression is a scalar but a vector is expected here; "
                              "write it with unit vectors (e.g. F*N.x - m*g*N.z) or vector "
                              "functions (vel(P), omega(B), ...)")
    return value


def _parse(text, names, where, vectors):
    if isinstance(text, bool):
        raise ExpressionError(f"{where}: expected an expression, got a boolean ({text}); "
                              "write a number or a quoted expression")
    if isinstance(text, numbers.Integral):
        text = int(text)
        if abs(text) >= 10**MAX_DIGITS:
            raise ExpressionError(f"{where}: number with more than {MAX_DIGITS} digits")
        return sp.Integer(text)
    if isinstance(text, numbers.Real):
        text = float(text)  # also NumPy scalars (whose repr is "np.float64(...)")
        if not math.isfinite(text):
            raise ExpressionError(f"{where}: {text!r} is not a finite number")
        return sp.Rational(repr(text))
    if not isinstance(text, str):
        raise ExpressionError(
            f"{where}: expected an expression string, got {type(text).__name__} "
            f"({_short(repr(text))}); write it as a quoted string, e.g. \"m*g*y\""
        )
    if len(text) > MAX_LENGTH:
        raise ExpressionError(
            f"{where}: expression of {len(text)} characters is longer than the limit of "
            f"{MAX_LENGTH}; split it with parameters or use [[bodies]] to assemble energies"
        )
    if not text.strip():
        raise ExpressionError(f"{where}: empty expression (write \"0\" for zero)")
    try:
        parser = _Parser(text, names, where, vectors)
        expr = parser.parse()
    except _Fail as exc:
        raise ExpressionError(_malformed(where, text, exc.col, exc.what)) from None
    except RecursionError:  # pragma: no cover - MAX_DEPTH keeps far below the limit
        raise ExpressionError(f"{where}: expression nested too deeply") from None
    except ValueError as exc:  # SymPy printing an exact number of more than 4300 digits
        if "digits" not in str(exc):
            raise
        raise ExpressionError(f"{where}: a number in the expression has more than "
                              f"{MAX_DIGITS} digits (e.g. a tower of powers of 0)") from None
    if parser.unknown:
        raise parser.unknown_error()
    return expr


def _bits(e: sp.Expr) -> int:
    """Bits of the numerator and denominator of a rational number (0 for anything else)."""
    if isinstance(e, sp.Rational):
        return int(e.p).bit_length() + int(e.q).bit_length()
    return 0


def _short(s: str, width: int = 60) -> str:
    return s if len(s) <= width else s[: width - 3] + "..."


def _malformed(where: str, text: str, col: int, what: str) -> str:
    """``where: malformed expression at column c: what`` plus the text with a caret."""
    shown = "".join(" " if ch in "\t\r\n\v\f" else ch for ch in text)
    lo = 0
    if len(shown) > 100:
        lo = max(0, min(col - 50, len(shown) - 100))
        shown = ("..." if lo else "") + shown[lo:lo + 100] + ("..." if lo + 100 < len(text) else "")
        caret = col - lo + (3 if lo else 0)
    else:
        caret = col
    return (f"{where}: malformed expression at column {col + 1}: {what}\n"
            f"    {shown}\n    {' ' * caret}^")


def _tokenize(text: str) -> list[_Token]:
    tokens: list[_Token] = []
    pos, n = 0, len(text)
    while pos < n:
        m = _TOKEN.match(text, pos)
        if m is None:
            ch = text[pos]
            if ord(ch) > 127:
                try:
                    uname = unicodedata.name(ch)
                except ValueError:
                    uname = "unnamed"
                raise _Fail(pos, f"non-ASCII character {ch!r} (U+{ord(ch):04X} {uname}); "
                                 "names are ASCII letters, digits and _ (write theta, not a "
                                 "Greek letter)")
            what = _FORBIDDEN_OPS.get(ch, f"the character {ch!r}")
            if ch == "'":
                raise _Fail(pos, "a prime (') must directly follow a coordinate name, as in "
                                 "x' or x'' (quoted strings are not allowed)")
            raise _Fail(pos, f"{what} is not allowed; expressions use numbers, names, "
                             "+ - * / ^ and parentheses")
        kind = m.lastgroup
        if kind != "ws":
            tokens.append(_Token(kind, m.group(), pos))
        pos = m.end()
    tokens.append(_Token("end", "", n))
    return tokens


class _Parser:
    def __init__(self, text: str, names: Mapping[str, sp.Expr], where: str, vectors=None):
        self.text, self.names, self.where, self.vectors = text, names, where, vectors
        self.tokens = _tokenize(text)
        self.i = 0
        self.depth = 0
        self.unknown: dict[str, int] = {}          # unknown name -> first column
        self.placeholders: dict[str, sp.Dummy] = {}

    # ---------------------------------------------------------------- token helpers
    def peek(self) -> _Token:
        return self.tokens[self.i]

    def next(self) -> _Token:
        tok = self.tokens[self.i]
        self.i += 1
        return tok

    def enter(self, col: int) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise _Fail(col, f"nested more than {MAX_DEPTH} levels deep (parentheses, "
                             "powers or calls); simplify the expression")

    def expect_operand(self, tok: _Token) -> _Fail:
        if tok.kind == "end":
            return _Fail(tok.col, "unexpected end of the expression (an operand is missing)")
        return _Fail(tok.col, f"expected a number, a name or '(' but found '{tok.text}'")

    # ---------------------------------------------------------------- grammar
    def parse(self) -> sp.Expr:
        expr = self.expr()
        tok = self.peek()
        if tok.kind != "end":
            if tok.text == ")":
                raise _Fail(tok.col, "unmatched ')'")
            if tok.text == ",":
                raise _Fail(tok.col, "',' outside a function call (an expression is one value)")
            prev = self.tokens[self.i - 1]
            raise _Fail(tok.col, f"missing operator between '{prev.text}' and '{tok.text}' "
                                 f"(write {prev.text}*{tok.text} for a product)")
        self.check_value(expr)
        return expr

    def expr(self) -> sp.Expr:
        terms = [self.term()]
        while self.peek().text in ("+", "-"):
            op = self.next()
            term = self.term()
            if isinstance(term, Vector) != isinstance(terms[0], Vector):
                raise _Fail(op.col, f"'{op.text}' between a vector and a scalar; add vectors to "
                                    "vectors (a scalar times a unit vector such as N.x is a vector)")
            terms.append(term if op.text == "+" else -term)
        if len(terms) == 1:
            return terms[0]
        if isinstance(terms[0], Vector):
            return add(terms)
        return sp.Add(*terms)

    def term(self) -> sp.Expr:
        factors = [self.unary()]
        vector = factors[0] if isinstance(factors[0], Vector) else None
        factors = [] if vector is not None else factors
        bits = _bits(factors[0]) if factors else 0
        while self.peek().text in ("*", "/"):
            op = self.next()
            col = self.peek().col
            factor = self.unary()
            if isinstance(factor, Vector):
                if op.text == "/":
                    raise _Fail(col, "division by a vector")
                if vector is not None:
                    raise _Fail(op.col, "product of two vectors; write dot(a, b) or cross(a, b)")
                vector = factor
                continue
            if op.text == "/":
                if factor == 0:
                    raise _Fail(col, "division by zero")
                factor = sp.Pow(factor, -1)
            bits += _bits(factor)
            if bits > MAX_DIGITS * 3.33:  # SymPy multiplies the numbers exactly
                raise _Fail(col, f"the product's numbers would have more than {MAX_DIGITS} digits")
            factors.append(factor)
        scalar = factors[0] if len(factors) == 1 else sp.Mul(*factors)
        if vector is None:
            return scalar
        return vector.scaled(scalar) if factors else vector

    def unary(self) -> sp.Expr:
        negative = False
        while self.peek().text in ("+", "-"):
            if self.next().text == "-":
                negative = not negative
        value = self.power()
        return -value if negative else value

    def power(self) -> sp.Expr:
        base = self.atom()
        if self.peek().text in ("^", "**"):
            op = self.next()
            self.enter(op.col)
            exponent = self.unary()
            self.depth -= 1
            if isinstance(base, Vector) or isinstance(exponent, Vector):
                raise _Fail(op.col, "a power of a vector; write dot(a, a) for the square of its "
                                    "length")
            return self.pow(base, exponent, op.col)
        return base

    def atom(self) -> sp.Expr:
        tok = self.next()
        if tok.kind == "number":
            return self.number(tok)
        if tok.kind == "name":
            if self.peek().text == "(":
                return self.call(tok)
            return self.name(tok)
        if tok.kind == "attr":
            return self.unit(tok)
        if tok.text == "(":
            self.enter(tok.col)
            if self.peek().text == ")":
                raise _Fail(self.peek().col, "empty parentheses")
            value = self.expr()
            close = self.next()
            if close.text != ")":
                if close.kind == "end":
                    raise _Fail(tok.col, "'(' is never closed")
                raise _Fail(close.col, f"expected ')' but found '{close.text}'")
            self.depth -= 1
            return value
        raise self.expect_operand(tok)

    # ---------------------------------------------------------------- leaves
    def number(self, tok: _Token) -> sp.Expr:
        s = tok.text
        mantissa, _, exp = s.lower().partition("e")
        if len(mantissa.replace(".", "").lstrip("0")) > MAX_DIGITS:
            raise _Fail(tok.col, f"number with more than {MAX_DIGITS} digits")
        if exp and abs(int(exp)) > 300:
            raise _Fail(tok.col, f"number {s} is out of range (|exponent| > 300)")
        nxt = self.peek()
        if nxt.kind == "name" and nxt.col == tok.col + len(s):
            raise _Fail(nxt.col, f"missing operator between '{s}' and '{nxt.text}' "
                                 f"(write {s}*{nxt.text} for a product)")
        if "." in s or exp:
            return sp.Rational(s)
        return sp.Integer(int(s))

    def name(self, tok: _Token) -> sp.Expr:
        name = tok.text
        base, primes = name.rstrip("'"), len(name) - len(name.rstrip("'"))
        if primes >= 3 and name not in self.names:
            top = max((len(k) - len(base) for k in self.names if k.rstrip("'") == base), default=0)
            raise _Fail(tok.col, f"{name}: only first (x') and second (x'') derivatives can be "
                                 "written, and higher ones (x''', x'''', ...) in a constraint's "
                                 "expr only" + (f" (up to order {top} there)" if top >= 3 else ""))
        if name in self.names:
            return self.names[name]
        if name in CONSTANTS:
            return CONSTANTS[name]
        if name in FUNCTIONS:
            raise _Fail(tok.col, f"function '{name}' used without arguments; write {name}(...)")
        if primes:
            if base == "t":
                raise _Fail(tok.col, f"{name}: 't' is time; only coordinates have derivatives")
            if base in self.names:
                if base + "'" not in self.names:
                    raise _Fail(tok.col, f"{name}: derivatives are not allowed here (this "
                                         "expression may depend on coordinates, parameters "
                                         "and time only; and only coordinates have "
                                         "derivatives)")
                raise _Fail(tok.col, f"{name}: accelerations are not allowed here")
            if base in CONSTANTS:
                raise _Fail(tok.col, f"{name}: '{base}' is a constant; only coordinates have "
                                     "derivatives")
        self.unknown.setdefault(name, tok.col)
        return self.placeholders.setdefault(name, sp.Dummy(name))

    def unit(self, tok: _Token) -> Vector:
        """``B.x``: a unit vector of a declared frame."""
        frame, _, axis = tok.text.partition(".")
        if self.vectors is None:
            raise _Fail(tok.col + len(frame), "attribute access ('.') is not allowed here (the "
                                              "unit vectors B.x, B.y, B.z of frames belong to "
                                              "model expressions)")
        try:
            return self.vectors.axis(frame, axis)
        except Unknown as exc:
            raise _Fail(tok.col, str(exc)) from None

    def vector_call(self, tok: _Token) -> sp.Expr | Vector:
        """A call of a vector function: frame, point and body arguments are names."""
        fname, kinds = tok.text, VECTOR_FUNCTIONS[tok.text]
        if self.vectors is None:
            raise _Fail(tok.col, f"{fname}(...) is a vector function of a model's frames and "
                                 "points; it is not available here")
        open_ = self.next()
        self.enter(open_.col)
        args = []
        for k, kind in enumerate(kinds):
            if kind == "vector":
                arg_col = self.peek().col
                value = self.expr()
                if not isinstance(value, Vector):
                    raise _Fail(arg_col, f"{fname} takes vectors; argument {k + 1} is a scalar")
                args.append(value)
            else:
                name = self.next()
                if name.kind != "name" or name.text.endswith("'"):
                    raise _Fail(name.col, f"{fname} takes the name of a {kind} as argument {k + 1}"
                                          f", e.g. {fname}({'B' if kind == 'frame' else 'P'})")
                args.append(name.text)
            sep = self.next()
            if sep.text == ")" and k + 1 < len(kinds) or sep.text == "," and k + 1 == len(kinds) \
                    or sep.text not in (",", ")"):
                if sep.kind == "end":
                    raise _Fail(open_.col, "'(' is never closed")
                raise _Fail(sep.col, f"{fname} takes {len(kinds)} argument(s): "
                                     f"{fname}({', '.join(kinds)})")
        self.depth -= 1
        if fname == "dot":
            return dot(*args)
        if fname == "cross":
            return cross(*args)
        if fname == "norm":
            return norm(*args)
        try:
            value = self.vectors.call(fname, args)
        except Unknown as exc:
            raise _Fail(tok.col, str(exc)) from None
        self.allowed(value, tok)
        return value

    def allowed(self, value: Vector, tok: _Token) -> None:
        """A vector function's value may use only the names this expression may use."""
        known = set(self.names.values())
        extra = sorted((s.name for s in value.free_symbols if s not in known), key=str)
        if extra:
            what = ("accelerations" if any(n.endswith("''") for n in extra) else
                    "velocities" if any(n.endswith("'") for n in extra) else "symbols")
            raise _Fail(tok.col, f"{tok.text}(...) contains {what} ({', '.join(extra)}), which are "
                                 "not allowed here")

    def call(self, tok: _Token) -> sp.Expr:
        fname = tok.text
        if fname in VECTOR_FUNCTIONS:
            return self.vector_call(tok)
        if fname not in FUNCTIONS:
            if fname in self.names or fname in CONSTANTS:
                raise _Fail(tok.col, f"'{fname}' is not a function; write {fname}*(...) for a "
                                     "product")
            known = list(FUNCTIONS) + (list(VECTOR_FUNCTIONS) if self.vectors is not None else [])
            raise _Fail(tok.col, f"unknown function '{fname}'{did_you_mean(fname, known)}; "
                                 "allowed: " + ", ".join(sorted(known)))
        func, arity = FUNCTIONS[fname]
        open_ = self.next()
        self.enter(open_.col)
        args = []
        if self.peek().text == ")":
            raise _Fail(self.peek().col, f"{fname} takes {arity} argument(s), got 0")
        while True:
            args.append(self.expr())
            sep = self.next()
            if sep.text == ",":
                continue
            if sep.text == ")":
                break
            if sep.kind == "end":
                raise _Fail(open_.col, "'(' is never closed")
            raise _Fail(sep.col, f"expected ',' or ')' but found '{sep.text}'")
        self.depth -= 1
        if len(args) != arity:
            raise _Fail(tok.col, f"{fname} takes {arity} argument(s), got {len(args)}")
        if any(isinstance(a, Vector) for a in args):
            raise _Fail(tok.col, f"{fname} of a vector; {fname} takes scalars (a component is "
                                 "dot(v, N.x), a length norm(v))")
        try:
            return func(*args)
        except (TypeError, ValueError, AttributeError, ArithmeticError):
            # SymPy's own evaluation failing on an extreme argument (e.g. acos of sin(1e108)
            # raises from inside its cache); the user gets the place, not the traceback
            raise _Fail(tok.col, f"{fname}(...) cannot be evaluated for this argument; "
                                 "write the value as a number") from None

    # ---------------------------------------------------------------- checks
    def pow(self, base: sp.Expr, exponent: sp.Expr, col: int) -> sp.Expr:
        if exponent.is_number:
            try:
                e = complex(exponent)
            except (TypeError, ValueError):
                raise _Fail(col, "the exponent is not a number") from None
            if not (math.isfinite(e.real) and math.isfinite(e.imag)):
                raise _Fail(col, "the exponent is not finite")
            if abs(e) > MAX_EXPONENT:
                raise _Fail(col, f"exponent {_short(str(exponent), 30)} is larger than "
                                 f"{MAX_EXPONENT} in magnitude")
            if base.is_Rational and exponent.is_Rational:
                bits = max(abs(base.p).bit_length(), abs(base.q).bit_length())
                if bits * abs(e) > MAX_DIGITS * 3.33:
                    raise _Fail(col, f"the number would have more than {MAX_DIGITS} digits")
            if base == 0 and e.real < 0:
                raise _Fail(col, "division by zero (0 to a negative power)")
        result = sp.Pow(base, exponent)
        if isinstance(result, sp.Pow) and result.exp.is_number:
            try:
                big = abs(complex(result.exp)) > MAX_EXPONENT
            except (TypeError, ValueError):
                big = True
            if big:
                raise _Fail(col, f"exponent larger than {MAX_EXPONENT} in magnitude after "
                                 "combining powers")
        return result

    def check_value(self, expr: sp.Expr) -> None:
        if expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
            raise _Fail(0, "the expression is undefined or infinite (a division by zero, "
                           "log(0) or similar)")
        if expr.has(sp.I):
            raise _Fail(0, "the expression is complex (e.g. sqrt of a negative number); "
                           "mechanical quantities are real")

    def unknown_error(self) -> ExpressionError:
        candidates = [n for n in self.names if not n.endswith("'")] + list(CONSTANTS)
        candidates += [n for n in self.names if n.endswith("'")]
        coordinates = [n[:-1] for n in self.names if n.endswith("'") and not n.endswith("''")]
        problems = []
        for name in self.unknown:
            base = name.rstrip("'")
            if base != name:
                problems.append(
                    f"{self.where}: unknown symbol {name}: '{base}' is not a coordinate"
                    f"{did_you_mean(base, coordinates)}; only coordinates have derivatives"
                    + (f" ({', '.join(coordinates)})" if coordinates else ""))
            else:
                problems.append(f"{self.where}: unknown symbol '{name}'"
                                f"{did_you_mean(name, candidates)}")
        return ExpressionError(problems, unknown=[(name, self.where) for name in self.unknown])
