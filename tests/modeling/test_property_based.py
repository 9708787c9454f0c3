"""Property-based tests (Hypothesis) of the expression parser and the model-file reader: for
random and adversarial expressions and TOML documents the answer is always a result or a
ModelError / ExpressionError (exit code 2) -- never another exception, a hang or unbounded
memory."""

import math
import string
import time

import sympy as sp
from hypothesis import HealthCheck, example, given, settings, strategies as st

from nonideal.errors import ExpressionError, ModelError
from nonideal.modeling.expressions import FUNCTIONS, float_value, parse_expression
from nonideal.modeling.modelfile import model_from_dict

NAMES = {"x": sp.Symbol("x"), "y": sp.Symbol("y"), "x'": sp.Symbol("x'"), "t": sp.Symbol("t")}
SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])

numbers = st.one_of(st.integers(-10 ** 6, 10 ** 6).map(str),
                    st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr),
                    st.sampled_from(["1e300", "1e-300", "0", "0.0", "9" * 400, "1e308"]))
atoms = st.one_of(numbers, st.sampled_from(["x", "y", "x'", "t", "pi", "q", "x''", "t'"]))


def _combine(children):
    return st.one_of(
        st.tuples(children, st.sampled_from(["+", "-", "*", "/", "^", "**"]), children)
        .map(lambda a: f"{a[0]}{a[1]}{a[2]}"),
        st.tuples(st.sampled_from(sorted(FUNCTIONS) + ["exp", "foo"]), children)
        .map(lambda a: f"{a[0]}({a[1]})"),
        children.map(lambda a: f"({a})"),
        children.map(lambda a: f"-{a}"),
    )


expressions = st.recursive(atoms, _combine, max_leaves=25)
junk = st.text(alphabet=string.printable + "\x00\x1b\u00e9\u2212\u00b2'", max_size=200)


def _parse_or_refuse(text):
    start = time.process_time()
    try:
        expr = parse_expression(text, NAMES, "expr")
    except ExpressionError:
        expr = None
    assert time.process_time() - start < 5.0
    return expr


@SETTINGS
@given(expressions)
@example("-acos(sin(5.174473092118671e+108))")  # found by Hypothesis: SymPy raised from its cache
def test_generated_expressions_parse_or_are_refused(text):
    expr = _parse_or_refuse(text)
    if expr is None:
        return
    assert isinstance(expr, sp.Basic)
    try:  # a number from it: a finite float, or a refusal that names where
        value = float_value(expr, "expr", {"x": 0.5, "y": -1.5, "x'": 2.0, "t": 0.25})
    except ExpressionError as exc:
        assert str(exc).startswith("expr:")
    else:
        assert math.isfinite(value)


@SETTINGS
@given(junk)
def test_adversarial_text_parses_or_is_refused(text):
    _parse_or_refuse(text)


toml_scalars = st.one_of(st.integers(-10 ** 30, 10 ** 30), st.floats(), st.booleans(),
                         expressions, junk, st.just(""))
toml_values = st.recursive(toml_scalars, lambda c: st.one_of(
    st.lists(c, max_size=4), st.dictionaries(st.sampled_from(["name", "expr", "type", "gap", "slip",
                                                              "mu", "value", "q", "x", "t_end"]), c,
                                             max_size=4)), max_leaves=12)
documents = st.fixed_dictionaries({}, optional={
    "model": st.fixed_dictionaries({}, optional={"name": toml_scalars, "format": toml_scalars}),
    "parameters": st.dictionaries(st.sampled_from(["m", "g", "k", "x", "t", "pi"]), toml_values, max_size=3),
    "coordinates": st.fixed_dictionaries({"q": st.one_of(st.lists(st.sampled_from(["x", "y", "t", "1a"]),
                                                                  max_size=3), toml_values)}),
    "energy": st.dictionaries(st.sampled_from(["kinetic", "potential", "other"]), toml_values, max_size=2),
    "constraints": st.lists(toml_values, max_size=2),
    "contacts": st.lists(toml_values, max_size=2),
    "initial": st.dictionaries(st.sampled_from(["x", "y", "x'", "z"]), toml_values, max_size=3),
    "simulation": st.dictionaries(st.sampled_from(["t_end", "rtol", "method", "t0"]), toml_values, max_size=3),
    "extra": toml_values,
})


@SETTINGS
@given(documents)
def test_model_documents_build_or_are_refused(data):
    start = time.process_time()
    try:
        model_from_dict(data, "doc.toml")
    except ModelError as exc:
        assert exc.exit_code == 2 and str(exc)
    assert time.process_time() - start < 10.0
