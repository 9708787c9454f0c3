"""Attacks on the expression parser: a model file is data.

Every hostile input must be rejected with a clean :class:`ExpressionError` (never another
exception), quickly (< 1 s), and nothing may be executed -- checked with a marker file that
the payloads try to create and with a trap on ``builtins.__import__``, ``eval``, ``exec``
and ``compile``.
"""

import builtins
import contextlib
import time
import types
from pathlib import Path

import pytest
import sympy as sp

from nonideal.errors import ExpressionError
from nonideal.modeling.expressions import MAX_DEPTH, MAX_LENGTH, parse_expression

x, m = sp.symbols("x m")
NAMES = {"x": x, "m": m, "x'": sp.Symbol("x'"), "t": sp.Symbol("t")}

ATTACKS = [
    "__import__('os').system('touch {marker}')",
    "__import__(\"os\").system(\"touch {marker}\")",
    "eval(\"__import__('os').system('touch {marker}')\")",
    "exec('open(\"{marker}\", \"w\")')",
    "open('{marker}', 'w').write('pwned')",
    "(lambda: open('{marker}', 'w'))()",
    "lambda: 0",
    "[c for c in ().__class__.__base__.__subclasses__()]",
    "{{k: 1 for k in x}}",
    "(y := 3)",
    "x.__class__",
    "x.__class__.__mro__[1].__subclasses__()",
    "().__class__",
    "sin.__globals__",
    "__builtins__",
    "__import__",
    "__class__",
    "globals()",
    "getattr(x, 'evalf')()",
    "x if x else x",
    "x[0]",
    "x < 1",
    "not x",
    "x and m",
    "f'{{x}}'",
    "'a string'",
    "b'bytes'",
    "1j",
    "...",
    "x; import os",
    "import os",
    "x # comment",
    "`x`",
    "$x",
    "x\\\n+1",
    "sin(*[x])",
    "sin(x=1)",
    "Symbol('x')",
    "sympify('x')",
    "S('x')",
    "9**9**9",
    "10**10**10",
    "x**99999999",
    "x^99999999",
    "x**(10**100)",
    "(x**64)**64",
    "((9**60)**60)**60",
    "2**64**2",
    "9" * 2000,
    "1e999999",
    "1.5e-400",
    "1/(x - x)",
    "0**-1",
    "log(0)",
    "sqrt(-1)",
    "x**sqrt(-1)",
    "(" * 10_000 + "x" + ")" * 10_000,
    "(" * (MAX_DEPTH + 1) + "x" + ")" * (MAX_DEPTH + 1),
    "sin(" * 500 + "x" + ")" * 500,
    "-" * 100_000 + "x",
    "x" + "^x" * 1000,
    "x" * (MAX_LENGTH + 1),
    "x + " * (MAX_LENGTH // 4) + "x",
    "\u0445",                      # Cyrillic small ha, looks like x
    "\uff58",                      # fullwidth x (NFKC-normalizes to x in Python source)
    "\U0001d431",                  # mathematical bold x
    "x\u200b",                     # zero-width space
    "x\u2032",                     # prime symbol instead of apostrophe
    "\u03b8",                      # Greek theta
    "e\u0301",                     # combining accent
    "x\x00",
    "x\u202e+1",                   # right-to-left override
    "__d1__x",                     # the old internal encoding of primes
    "x'''",
]


@contextlib.contextmanager
def trap():
    """Record (and refuse) any import of a dangerous module and any eval, exec, compile or
    sympify made inside the block.  Armed only around the parser call: pytest itself compiles
    while it reports, and a trap left armed there breaks the run (INTERNALERROR)."""
    calls = []
    real_import = builtins.__import__

    def spy_import(name, *args, **kwargs):
        if name in ("os", "subprocess", "shutil", "socket", "ctypes", "pty"):
            calls.append(("import", name))
        return real_import(name, *args, **kwargs)

    def forbidden(what):
        real = getattr(builtins, what, None)

        def f(*args, **kwargs):
            code = args[0] if args else None
            if isinstance(code, types.CodeType) and Path(code.co_filename).is_file():
                # a library module imported lazily (importlib executes its compiled file);
                # text from the model would first have to pass through the trapped compile
                return real(*args, **kwargs)
            calls.append((what, args[:1]))
            raise AssertionError(f"{what} called by the parser")
        return f

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(builtins, "__import__", spy_import)
        for name in ("eval", "exec", "compile"):
            patch.setattr(builtins, name, forbidden(name))
        patch.setattr(sp, "sympify", forbidden("sympify"))
        patch.setattr(sp, "parse_expr", forbidden("parse_expr"), raising=False)
        yield calls


@pytest.mark.parametrize("attack", ATTACKS, ids=lambda a: repr(a[:40]))
def test_attack_is_rejected_quickly_and_runs_nothing(attack, tmp_path):
    marker = tmp_path / "PWNED"
    text = attack.format(marker=marker) if "{marker}" in attack or "{{" in attack else attack
    start = time.process_time()     # processor time: a loaded machine does not fail it
    with trap() as calls, pytest.raises(ExpressionError) as info:
        parse_expression(text, NAMES, "[energy] kinetic")
    elapsed = time.process_time() - start
    assert elapsed < 1.0, f"took {elapsed:.2f} s"
    assert not marker.exists()
    assert calls == []
    message = str(info.value)
    assert message.startswith("[energy] kinetic: ")
    assert len(message) < 2000                    # the message stays readable


def test_nothing_but_expression_error_escapes_on_random_junk():
    """Fuzz: random strings of the expression alphabet and hostile characters never raise
    anything but ExpressionError (or parse)."""
    import random

    rng = random.Random(2024)
    alphabet = list("x m t ' ^ * / + - ( ) , . 0 1 9 e E _ sin cos pi ** [ ] { } : ; = < > % @ \" \\".split())
    alphabet += [" ", "\n", "\u03b8", "__"]
    start = time.process_time()
    for _ in range(3000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randint(1, 25)))
        try:
            parse_expression(text, NAMES, "fuzz")
        except ExpressionError:
            pass
    assert time.process_time() - start < 10


def test_non_ascii_message_names_the_character():
    with pytest.raises(ExpressionError) as info:
        parse_expression("m*\u03b8'^2", NAMES, "[energy] kinetic")
    assert "non-ASCII character '\u03b8' (U+03B8 GREEK SMALL LETTER THETA)" in str(info.value)
    assert "at column 3" in str(info.value)


def test_huge_exponent_message():
    with pytest.raises(ExpressionError) as info:
        parse_expression("9**9**9", NAMES, "[energy] potential")
    assert "exponent 387420489 is larger than 64 in magnitude" in str(info.value)


def test_combined_powers_are_bounded():
    with pytest.raises(ExpressionError) as info:
        parse_expression("(x^60)^60", NAMES, "[energy] potential")
    assert "after combining powers" in str(info.value)


# ---------------------------------------------------------------- the vector grammar

VECTOR_ATTACKS = [
    "N.__class__",
    "B.x.__class__",
    "B.x.y",
    "B.__dict__",
    "omega.__globals__",
    "omega(__import__)",
    "omega(B.x)",
    "vel(x.__class__)",
    "vel('P')",
    "vel(P)(1)",
    "dot(N.x, N.x)(1)",
    "cross(N.x)",
    "dot(*[N.x, N.x])",
    "norm(N.x, N.y)",
    "momentum(__builtins__)",
    "angular_momentum(body, __class__)",
    "omega(" * 200 + "B" + ")" * 200,
    "dot(" * 60 + "N.x, N.x" + ")" * 60,
    "N.x" + " + N.x" * 3000,
    "B.x * B.y",
    "N.x ^ 2",
    "exp(N.x)",
    "vel(P)",                      # a vector where a scalar is expected
    "N.x + 1",
]


@pytest.fixture(scope="module")
def kinematics():
    from nonideal import Model
    from nonideal.modeling.frames import Frame
    from nonideal.modeling.points import Point

    return Model("k", coordinates=["x"], parameters={"m": 1.0},
                 frames=[Frame("B", rotation="body Z", angles=["x"])],
                 points=[Point("P", ["m", "0", "0"], frame="B")]).kinematics


@pytest.mark.parametrize("attack", VECTOR_ATTACKS, ids=lambda a: repr(a[:40]))
def test_vector_attack_is_rejected_quickly_and_runs_nothing(attack, kinematics, tmp_path):
    start = time.process_time()     # processor time: a loaded machine does not fail it
    with trap() as calls, pytest.raises(ExpressionError) as info:
        parse_expression(attack, NAMES, "[energy] kinetic", kinematics)
    assert time.process_time() - start < 10   # a refusal, not a blow-up (~0.05 s)
    assert calls == []
    message = str(info.value)
    assert message.startswith("[energy] kinetic: ") and len(message) < 2000


def test_vector_grammar_fuzz(kinematics):
    import random

    rng = random.Random(7)
    alphabet = "x m ' ^ * / + - ( ) , . N B P x y z omega vel pos acc dot cross norm _ 0 1 [ ] ".split()
    alphabet += [" ", "N.x", "B.y", "__class__"]
    start = time.process_time()
    for _ in range(3000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randint(1, 20)))
        try:
            parse_expression(text, NAMES, "fuzz", kinematics)
        except ExpressionError:
            pass
    assert time.process_time() - start < 20


def test_without_kinematics_attribute_access_stays_refused():
    with pytest.raises(ExpressionError, match="attribute access"):
        parse_expression("N.x", NAMES, "[parameters] a")
