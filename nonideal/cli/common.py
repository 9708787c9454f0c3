"""What the commands share: reading a model (a file or a gallery example, with ``--set``
overrides), the checks of numbers and outputs before any work, the parsing of states, times and
lists, and the argument types of the parser."""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
import warnings
from pathlib import Path

from ..errors import MechanicsError, ModelError, NonidealError, UnitWarning, did_you_mean
from .outputs import output_problems

__all__ = ["ParserContext", "json_option", "model_argument", "load_spec", "model_path", "check_options",
           "parse_times", "parse_at", "parse_independent", "parse_substitutions",
           "parse_contact_states", "parse_overrides", "numerical_warnings", "explained",
           "well_posed_at_start", "form_type", "method_type", "METHODS", "FORM_NAMES", "PLOT_SAMPLES", "RTOL_MIN"]

METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
#: the forms of ``nonideal.equations.formalisms.FORMS``, named here so that building the parser
#: (``--help``) does not import SymPy; tests/cli/test_cli_startup.py checks they agree
FORM_NAMES = ("lagrange1", "lagrange2", "maggi", "appell", "shulgin", "servo", "kane", "boltzmann_hamel",
              "poincare_chetaev", "voronets", "chaplygin")
PLOT_SAMPLES = 601   # samples of a plotted or tabulated (--csv) run when --times is not given

#: the smallest relative tolerance: SciPy's integrators raise a smaller one to 100 machine
#: epsilons (2.22e-14) with a warning; rounded up so that the number shown is accepted
RTOL_MIN = 2.3e-14


def parse_overrides(items) -> dict[str, str]:
    """``--set NAME=VALUE`` options as a mapping (the last of repeated names wins); every
    malformed item is reported."""
    values: dict[str, str] = {}
    problems = []
    for item in items or ():
        name, eq, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not eq or not name or not value:
            problems.append(f"--set {item}: expected NAME=VALUE, e.g. --set mu=0.8 or "
                            "--set \"l=2*r\"")
        elif not name.isidentifier():
            problems.append(f"--set {item}: '{name}' is not a parameter name")
        else:
            values[name] = value
    if problems:
        raise ModelError(problems)
    return values


def load_spec(spec: str, overrides=None):
    """The model of a model file path or of a gallery example's name; *overrides* are the
    ``--set`` options (a list of ``NAME=VALUE`` strings)."""
    from ..modeling.modelfile import load_model

    values = parse_overrides(overrides)
    return load_model(model_path(spec), parameters=values)


def model_path(spec: str) -> Path:
    """The file of a model file path (anything that exists: reading it says what is wrong) or
    of a gallery example's name; a name that is neither is refused with the nearest ones."""
    from .. import gallery

    path = Path(spec)
    if path.exists():
        return path
    if spec in gallery.names():
        return gallery.model_path(spec)
    if spec.endswith(".toml"):
        try:
            nearby = [str(path.parent / f.name) if str(path.parent) != "." else f.name
                      for f in (path.parent if path.parent.is_dir() else Path(".")).iterdir()
                      if f.suffix == ".toml"]
        except OSError:  # pragma: no cover
            nearby = []
        hint = did_you_mean(spec, nearby)
    else:
        hint = did_you_mean(spec, gallery.names())
    raise ModelError(f"model file not found: {spec}{hint}; check the path (relative to "
                     f"{Path.cwd()}), or give a gallery example name (see 'nonideal examples "
                     "list')")


def check_options(args) -> None:
    """Check the numbers and the output paths of the command line before any work is done;
    report every problem at once."""
    problems = number_problems(args) + output_problems(args, args.model)
    if problems:
        raise ModelError(problems)


def number_problems(args) -> list[str]:
    """Times must be finite numbers; tolerances in the range the integrators accept."""
    problems = []
    for key, example in (("t", "0.5"), ("t_end", "2")):
        value = getattr(args, key, None)
        if value is not None and not math.isfinite(value):
            flag = "--" + key.replace("_", "-")
            problems.append(f"{flag}: must be a finite number, e.g. {flag} {example} (got {value})")
    rtol = getattr(args, "rtol", None)
    if rtol is not None and not RTOL_MIN <= rtol < 1:
        problems.append(f"--rtol: must be a number in [{RTOL_MIN:g}, 1) (about 100 machine "
                        "epsilons, the finest the integrators honour, up to 1), e.g. 1e-9 "
                        f"(got {rtol!r})")
    atol = getattr(args, "atol", None)
    if atol is not None and not 0 < atol < 1:
        problems.append(f"--atol: must be a number in (0, 1), e.g. 1e-9 (got {atol!r})")
    return problems


def parse_times(text: str) -> list[float]:
    """``--times 0,0.5,1``: finite, strictly increasing numbers."""
    parts = [p.strip() for p in text.replace(";", ",").split(",")]
    if not any(parts):
        raise ModelError(f"--times: no times given (got {text!r}); write comma-separated "
                         "numbers, e.g. --times 0,0.5,1")
    empty = [k + 1 for k, p in enumerate(parts) if not p]
    if empty:
        raise ModelError(f"--times: item{'s' if len(empty) > 1 else ''} "
                         f"{', '.join(map(str, empty))} of {len(parts)} "
                         f"{'are' if len(empty) > 1 else 'is'} empty (got {text!r}); write one "
                         "number between each pair of commas, e.g. --times 0,0.5,1")
    values, bad = [], []
    for p in parts:
        try:
            v = float(p)
        except ValueError:
            bad.append(p)
            continue
        if not math.isfinite(v):
            bad.append(p)
            continue
        values.append(v)
    if bad:
        raise ModelError(f"--times: {', '.join(repr(b) for b in bad)} "
                         f"{'is not a finite number' if len(bad) == 1 else 'are not finite numbers'}"
                         f"; write comma-separated numbers, e.g. --times 0,0.5,1 (got {text!r})")
    for a, b in zip(values, values[1:]):
        if not b > a:
            raise ModelError(f"--times: the times must increase strictly, but {b:g} follows "
                             f"{a:g} (got {text!r}); sort them and remove repetitions")
    return values


def parse_at(model, text: str | None) -> dict[str, float]:
    """``--at "x=0.1, theta=0.3, x'=1"``; values may be expressions in the parameters.

    Every malformed entry is reported at once."""
    if text is None:
        return {}
    import sympy as sp

    from ..errors import ExpressionError
    from ..modeling.expressions import float_value, parse_expression

    allowed = list(model.coordinates) + [c + "'" for c in model.coordinates] + list(model.speeds)
    names = {n: sp.Symbol(n) for n in model.parameters}
    values = {sp.Symbol(n): p.value for n, p in model.parameters.items()}
    out: dict[str, float] = {}
    problems: list[str] = []
    parts = [p for p in text.split(",")]
    if not text.strip():
        raise ModelError(f"--at: empty state; write name=value pairs separated by commas, e.g. "
                         f"--at \"{allowed[0]}=0.1, {allowed[-1]}=0\"")
    for part in parts:
        if not part.strip():
            continue
        if "=" not in part:
            problems.append(f"--at: '{part.strip()}' is not of the form name=value (pairs are "
                            f"separated by commas, e.g. \"{allowed[0]}=0.1, {allowed[-1]}=0\")")
            continue
        key, _, val = part.partition("=")
        key = key.strip()
        if key not in allowed:
            problems.append(f"--at: '{key}' is not a coordinate or velocity{' or speed' if model.speeds else ''}"
                            f"{did_you_mean(key, allowed)}; allowed: {', '.join(allowed)}")
            continue
        if key in out:
            problems.append(f"--at: '{key}' is given twice")
            continue
        if "=" in val:
            problems.append(f"--at: '{part.strip()}' has more than one '='; separate the pairs "
                            "with commas")
            continue
        try:
            expr = parse_expression(val.strip(), names, f"--at {key}")
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        try:
            out[key] = float_value(expr, f"--at {key}", {s.name: float(v) for s, v in values.items()})
        except ExpressionError as exc:
            problems.extend(exc.problems)
    if problems:
        raise ModelError(problems)
    return out


def parse_independent(text: str | None, model, form: str) -> tuple[str, ...] | None:
    """``--independent x,theta``: distinct coordinates, for a form that has independent ones."""
    from ..equations.formalisms import FORMS

    if text is None:
        return None
    reduced = [f for f in FORMS if f != "lagrange1"]
    if form not in reduced:
        raise ModelError(f"--independent: the form {form} keeps every coordinate (its unknowns "
                         "are all the accelerations, with the constraints' multipliers), so it "
                         "has no independent coordinates to choose; drop --independent or use a "
                         f"reduced form: --form {', '.join(reduced)}")
    parts = [s.strip() for s in text.split(",")]
    if not any(parts):
        raise ModelError(f"--independent: no coordinates given (got {text!r}); write "
                         "comma-separated coordinate names, e.g. --independent "
                         f"{model.coordinates[0]}")
    problems = []
    empty = [k + 1 for k, n in enumerate(parts) if not n]
    if empty:
        problems.append(f"--independent: item{'s' if len(empty) > 1 else ''} "
                        f"{', '.join(map(str, empty))} of {len(parts)} "
                        f"{'are' if len(empty) > 1 else 'is'} empty (got {text!r}); write one "
                        "coordinate name between each pair of commas")
    names = tuple(n for n in parts if n)
    for n in dict.fromkeys(names):
        if n not in model.coordinates:
            problems.append(f"--independent: '{n}' is not a coordinate"
                            f"{did_you_mean(n, model.coordinates)}; coordinates: "
                            + ", ".join(model.coordinates))
        elif names.count(n) > 1:
            problems.append(f"--independent: '{n}' is given {names.count(n)} times; name each "
                            "independent coordinate once")
    if problems:
        raise ModelError(problems)
    return names


def parse_substitutions(text: str | None, model) -> dict:
    """``"x1 = x + l*cos(theta), y1 = l*sin(theta)"`` -> SymPy substitutions for display; names
    that are not in the model (theta) become new symbols."""
    import re

    import sympy as sp

    from ..errors import ExpressionError
    from ..modeling.expressions import parse_expression

    if not text:
        return {}
    out = {}
    names = model.names(order=1)
    problems = []
    for part in re.split(r",(?![^()]*\))", text):
        if not part.strip():
            continue
        if "=" not in part:
            problems.append(f"--substitute: '{part.strip()}' is not of the form name = expression")
            continue
        key, _, expr = part.partition("=")
        key = key.strip()
        if key not in names:
            problems.append(f"--substitute: '{key}' is not a name of the model{did_you_mean(key, names)}")
            continue
        local = dict(names)
        for ident in re.findall(r"[A-Za-z_][A-Za-z_0-9]*", expr):
            if ident not in local and ident not in ("sin", "cos", "tan", "sqrt", "exp", "log", "pi"):
                local[ident] = sp.Symbol(ident)
        try:
            out[names[key]] = parse_expression(expr.strip(), local, f"--substitute {key}")
        except ExpressionError as exc:
            problems.extend(exc.problems)
    if problems:
        raise ModelError(problems)
    return out


def parse_contact_states(items, model) -> dict[str, str]:
    out = {}
    for item in items or []:
        if "=" not in item:
            raise ModelError(f"--contact: '{item}' is not of the form NAME=STATE (e.g. floor=slide+)")
        name, _, state = item.partition("=")
        out[name.strip()] = state.strip()
    return out


@contextlib.contextmanager
def numerical_warnings():
    """NumPy's floating-point warnings during a command (overflow on the way to a blow-up)
    carry a source path and a line of code that mean nothing to the user: when the command
    fails they are dropped -- its error explains the failure -- and when it succeeds each is
    shown once, as one line.  Other warnings are shown as usual."""
    caught: list = []
    failed = True
    try:
        with warnings.catch_warnings(record=True) as caught:
            yield
        failed = False
    finally:
        seen = set()
        for w in caught:
            if issubclass(w.category, UnitWarning):
                print(f"warning: {w.message}", file=sys.stderr)
            elif not issubclass(w.category, RuntimeWarning):
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
            elif not failed and str(w.message) not in seen:
                seen.add(str(w.message))
                print(f"warning: {w.message}", file=sys.stderr)


def explained(model, exc: MechanicsError) -> Exception:
    """A singular mass matrix or dependent constraints are bad input, not a paradox: when
    the mode selection reports "no consistent mode" and the initial state is singular, say
    what is singular instead."""
    from ..modes.diagnosis import explain_mechanics_error

    try:
        return explain_mechanics_error(model, exc)
    except NonidealError:  # pragma: no cover - the diagnosis must not mask the error
        return exc


def well_posed_at_start(model) -> None:
    """The equations are symbolic, but a negative mass or a kinetic energy that is not positive
    definite at the initial state is bad input for them too (checked when the initial state
    is complete; a model without one is derived as it is)."""
    from ..modes.diagnosis import diagnose_initial_state

    problem = diagnose_initial_state(model, definite=True)
    if problem is not None:
        raise problem


def form_type(forms):
    def convert(value: str) -> str:
        if value not in forms:
            raise argparse.ArgumentTypeError(
                f"unknown form '{value}'{did_you_mean(value, forms)}; choose one of "
                + ", ".join(forms))
        return value
    convert.__name__ = "form"
    return convert


def method_type(value: str) -> str:
    if value not in METHODS:
        raise argparse.ArgumentTypeError(
            f"unknown integrator '{value}'{did_you_mean(value, METHODS)}; choose one of "
            + ", ".join(METHODS))
    return value


class ParserContext:
    """What the commands' parsers share: the forms of the equations and the solvers."""

    def __init__(self):
        self.forms = list(FORM_NAMES)
        self.form_help = f"the form: {', '.join(self.forms)} (default lagrange1)"
        self.solvers = self.forms + ["gauss"]
        self.solver_help = (f"the form evaluating the accelerations: {', '.join(self.solvers)} "
                            "(gauss: the generalized Gauss principle with friction, a numerical "
                            "solver); default lagrange1")


def json_option(parser) -> None:
    """``--json [OUT]``: machine-readable output, to OUT or to standard output.

    The value must look like an output file: a bare ``--json`` followed by the model file
    would otherwise take the model as its output (``check --json model.toml``)."""
    parser.add_argument("--json", nargs="?", const="-", metavar="OUT",
                        help="machine-readable output (to OUT, or standard output)")


def model_argument(parser) -> None:
    """The model positional argument and ``--set NAME=VALUE`` (every command that reads a model)."""
    parser.add_argument("model", help="model file (TOML) or gallery example name")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", dest="set",
                        help="override a parameter of [parameters]: a number or an expression in "
                        "the other parameters (repeatable), e.g. --set mu=0.8 --set \"l=2*r\"")
