"""The safe expression parser (nonideal/expressions.py): what it accepts, and that its
messages say where (key and column) and what to write instead."""

import pytest
import sympy as sp

from nonideal.errors import ExpressionError
from nonideal.modeling.expressions import MAX_EXPONENT, parse_expression

x, y, theta, m, t = sp.symbols("x y theta m t")
xd, thd, xdd = sp.Symbol("x'"), sp.Symbol("theta'"), sp.Symbol("x''")
NAMES = {"x": x, "y": y, "theta": theta, "m": m, "t": t, "x'": xd, "theta'": thd, "x''": xdd}


def parse(text, names=NAMES, where="[energy] kinetic"):
    return parse_expression(text, names, where)


def error(text, names=NAMES, where="[energy] kinetic") -> ExpressionError:
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, names, where)
    return info.value


@pytest.mark.parametrize("text, expected", [
    ("m/2*x'^2", m / 2 * xd**2),
    ("m/2*x'**2", m / 2 * xd**2),
    ("-x^2", -x**2),                      # unary minus binds weaker than the power
    ("2^3^2", sp.Integer(512)),           # powers associate to the right
    ("x^-1", 1 / x),
    ("(x + y)*(x - y)", (x + y) * (x - y)),
    ("x - y - theta", x - y - theta),     # left associative
    ("x/y/theta", x / y / theta),
    ("--x", x),
    ("sin(theta)^2 + cos(theta)^2", sp.sin(theta)**2 + sp.cos(theta)**2),
    ("atan2(y, x) + min(x, y)", sp.atan2(y, x) + sp.Min(x, y)),
    ("0.1*x", sp.Rational(1, 10) * x),    # decimal literals are exact
    ("1e-3 + 2.5E2", sp.Rational(1, 1000) + 250),
    (".5*pi", sp.pi / 2),
    ("x'' + t", xdd + t),
    ("  x\n  + y\t", x + y),              # whitespace and newlines (TOML multi-line strings)
    (3, sp.Integer(3)),
    (0.25, sp.Rational(1, 4)),
])
def test_accepted(text, expected):
    assert sp.simplify(parse(text) - expected) == 0


def test_long_sum_is_flat_and_fast():
    # a sum of 5000 terms used to hit the nesting limit of the ast-based parser
    text = " + ".join(f"{k}*x" for k in range(1, 5001))
    assert parse(text) == sum(range(1, 5001)) * x


def test_unknown_symbol_with_suggestion():
    err = error("-x'*sin(thetta)", where="constraint 'knife_edge': expr")
    assert str(err) == "constraint 'knife_edge': expr: unknown symbol 'thetta' (did you mean 'theta'?)"
    assert err.unknown == [("thetta", "constraint 'knife_edge': expr")]


def test_every_unknown_symbol_of_an_expression_is_reported():
    err = error("k*x + c*x' + k*y + g")
    assert [p.split(": ", 1)[1] for p in err.problems] == [
        "unknown symbol 'k'", "unknown symbol 'c'", "unknown symbol 'g'"]
    assert [u for u, _ in err.unknown] == ["k", "c", "g"]


@pytest.mark.parametrize("text, column, what", [
    ("m/2*x'^2 +* 3", 11, "expected a number, a name or '(' but found '*'"),
    ("m*(x + 1", 3, "'(' is never closed"),
    ("m*x + 1)", 8, "unmatched ')'"),
    ("2x", 2, "missing operator between '2' and 'x' (write 2*x for a product)"),
    ("x y", 3, "missing operator between 'x' and 'y'"),
    ("x +", 4, "unexpected end of the expression"),
    ("sin()", 5, "sin takes 1 argument(s), got 0"),
    ("atan2(x)", 1, "atan2 takes 2 argument(s), got 1"),
    ("x % 2", 3, "the modulo operator '%' is not allowed"),
    ("x = 2", 3, "'=' (an expression is not an equation: write lhs - rhs) is not allowed"),
    ("x'''", 1, "only first (x') and second (x'') derivatives"),
    ("(x + y)'", 8, "a prime (') must directly follow a coordinate name"),
    ("1, 2", 2, "',' outside a function call"),
    ("x / 0", 5, "division by zero"),
    ("m(x + 1)", 1, "'m' is not a function; write m*(...) for a product"),
    ("sinn(x)", 1, "unknown function 'sinn' (did you mean 'sin'?)"),
    ("sin + 1", 1, "function 'sin' used without arguments"),
])
def test_malformed_names_column_and_shows_a_caret(text, column, what):
    err = error(text, where="[energy] kinetic")
    message = str(err)
    first, shown, caret = message.split("\n")
    assert first.startswith(f"[energy] kinetic: malformed expression at column {column}: ")
    assert what in first
    assert shown == "    " + text
    assert caret == "    " + " " * (column - 1) + "^"


def test_caret_in_a_long_expression_points_at_the_error():
    text = " + ".join(["x"] * 100) + " + * y"
    message = str(error(text))
    _, shown, caret = message.split("\n")
    col = len(caret) - len("    ") - 1
    assert shown[4 + col] == "*"


def test_derivatives_where_they_are_not_allowed():
    potential = {"x": x, "m": m, "t": t}               # order 0: no velocities
    assert "derivatives are not allowed here" in str(error("m*x'", potential, "[energy] potential"))
    order1 = {"x": x, "x'": xd, "t": t}
    assert "accelerations are not allowed here" in str(error("x''", order1))
    assert "'t' is time; only coordinates have derivatives" in str(error("t'", order1))


def test_exponent_limit():
    assert parse(f"x^{MAX_EXPONENT}") == x**MAX_EXPONENT
    assert "larger than 64" in str(error(f"x^{MAX_EXPONENT + 1}"))


@pytest.mark.parametrize("value, what", [
    (True, "got a boolean"),
    ([1, 2], "expected an expression string, got list"),
    (None, "expected an expression string, got NoneType"),
    ("", "empty expression (write \"0\" for zero)"),
    ("   ", "empty expression"),
    (float("nan"), "not a finite number"),
])
def test_wrong_types(value, what):
    assert what in str(error(value))


def test_derivative_of_an_unknown_coordinate():
    err = error("m*thetta'^2 + z'")
    assert err.problems == [
        "[energy] kinetic: unknown symbol thetta': 'thetta' is not a coordinate (did you mean "
        "'theta'?); only coordinates have derivatives (x, theta)",
        "[energy] kinetic: unknown symbol z': 'z' is not a coordinate; only coordinates have "
        "derivatives (x, theta)",
    ]
