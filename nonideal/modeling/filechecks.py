"""Checks of a model file's values, shared by the reader: unknown keys (with the closest known
one), numbers and expressions in the parameters, control characters, and TOML syntax errors
shown with the offending line."""

from __future__ import annotations

import math
import re
import unicodedata
from typing import Any

import sympy as sp

from ..errors import ModelError, did_you_mean
from .expressions import float_value, parse_expression

__all__ = ["toml_problem", "control_characters", "unknown_keys", "is_number", "is_expr", "Checker", "read_simulation",
           "describe", "short_value"]


def toml_problem(message: str, text: str) -> str:
    """The TOML parser's message plus the offending line with a caret."""
    out = f"not valid TOML: {message}"
    m = re.search(r"at line (\d+), column (\d+)", message)
    if m:
        line_no, col = int(m.group(1)), int(m.group(2))
        lines = text.splitlines()
        if 1 <= line_no <= len(lines):
            line = lines[line_no - 1].replace("\t", " ")
            out += f"\n    line {line_no}: {line}\n    {' ' * (len(str(line_no)) + 7 + col - 1)}^"
    return out + ("\n    (TOML: strings in double quotes, a key with a prime in quotes as "
                  "\"x'\" = 1.0, tables as [name], arrays of tables as [[constraints]])")


def control_characters(value: Any, where: str = "") -> list[str]:
    """Strings with control characters (terminal escape sequences, a bell, a carriage
    return...): printed back, they would act on the user's terminal.  A description may span
    lines (newlines and tabs are allowed there)."""
    if isinstance(value, dict):
        return [p for k, v in value.items()
                for p in control_characters(v, f"{where} {k}" if where.endswith("]") else
                                             f"{where}.{k}" if where else f"[{k}]")]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in control_characters(v, f"{where}[{i}]")]
    if not isinstance(value, str):
        return []
    allowed = "\n\t" if re.split(r"[ .]", where)[-1] in ("description", "source") else ""
    bad = sorted({c for c in value if unicodedata.category(c) == "Cc" and c not in allowed})
    if not bad:
        return []
    return [f"{where}: contains the control character(s) {', '.join(repr(c) for c in bad)}; "
            "remove them (only plain text is allowed in a model file's strings"
            + (", and newlines and tabs in a description)" if not allowed else ")")]


def unknown_keys(keys, allowed, where: str) -> list[str]:
    out = []
    for k in keys:
        if k not in allowed:
            out.append(f"{where}: unknown key '{k}'{did_you_mean(str(k), allowed)}; allowed: "
                       + ", ".join(sorted(allowed)))
    return out


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def is_expr(value: Any) -> bool:
    return isinstance(value, str) or is_number(value)


class Checker:
    """Type checks of model-file values; every problem is appended to ``problems``."""

    def __init__(self, problems: list[str]):
        self.problems = problems
        self.parameters: dict[str, float] = {}   # numeric values, for numbers given as expressions
        self.parameter_names: set[str] = set()

    def boolean(self, table: dict, key: str, where: str, default: bool = False) -> bool:
        value = table.get(key, default)
        if not isinstance(value, bool):
            self.problems.append(f"{where}: {key} must be true or false (got {value!r})")
            return default
        return value

    def number(self, table: dict, key: str, where: str, default, low=None, high=None,
               positive: bool = False):
        if key not in table:
            return default
        value = table[key]
        if isinstance(value, str):   # an expression in the parameters, evaluated now
            try:
                expr = parse_expression(value, {n: sp.Symbol(n) for n in self.parameter_names},
                                        f"{where}: {key}")
                if any(s.name not in self.parameters for s in expr.free_symbols):
                    return default   # a parameter without a value: reported with the parameters
                value = float_value(expr, f"{where}: {key}", self.parameters)
            except ModelError as exc:
                self.problems += exc.problems
                return default
            except TypeError:   # not a real number
                value = math.nan
        ok = is_number(value) and math.isfinite(value)
        if ok and positive and not value > 0:
            ok = False
        if ok and low is not None and value < low or ok and high is not None and value > high:
            ok = False
        if not ok:
            rng = (f" in [{low}, {high}]" if low is not None and high is not None
                   else " > 0" if positive else "")
            self.problems.append(f"{where}: {key} must be a number{rng}, or an expression in the "
                                 f"parameters (got {table[key]!r})")
            return default
        return value

    def expr(self, table: dict, key: str, where: str) -> bool:
        value = table.get(key)
        if not is_expr(value):
            self.problems.append(f"{where}: {key} must be an expression in quotes or a number "
                                 f"(got {describe(value)})")
            return False
        return True

    def expr_list(self, table: dict, key: str, where: str, sizes=None, allow_scalar=False) -> bool:
        value = table.get(key)
        if allow_scalar and is_expr(value):
            value = [value]
        if not isinstance(value, list) or not all(is_expr(v) for v in value):
            self.problems.append(f"{where}: {key} must be a list of expressions, e.g. "
                                 f"{key} = [\"0\", \"1\"] (got {describe(value)})")
            return False
        if sizes and len(value) not in sizes:
            self.problems.append(f"{where}: {key} must have {' or '.join(map(str, sizes))} "
                                 f"entries (got {len(value)})")
            return False
        return True

    def matrix(self, table: dict, key: str, where: str, size=None) -> bool:
        value = table.get(key)
        if not (isinstance(value, list) and all(isinstance(r, list) and all(is_expr(v) for v in r)
                                                for r in value)):
            self.problems.append(f"{where}: {key} must be a list of rows (lists of expressions), "
                                 f"e.g. [[\"1\", \"0\"], [\"0\", \"1\"]] (got {describe(value)})")
            return False
        if size is not None and (len(value) != size or any(len(r) != size for r in value)):
            self.problems.append(f"{where}: {key} must be {size}x{size} (one row and column per "
                                 "coordinate)")
            return False
        return True

    def name(self, table: dict, where: str) -> bool:
        value = table.get("name")
        if not isinstance(value, str):
            self.problems.append(f"{where}: name must be a string in quotes (got {describe(value)})")
            return False
        return True


def describe(value: Any) -> str:
    if value is None:
        return "nothing"
    kind = {bool: "a boolean", int: "a number", float: "a number", str: "a string",
            list: "a list", dict: "a table"}.get(type(value), type(value).__name__)
    return f"{kind} {short_value(value)}"


def short_value(value: Any) -> str:
    r = repr(value)
    return r if len(r) <= 50 else r[:47] + "..."


def read_simulation(sim: dict, check: Checker, problems: list[str]) -> tuple[Any, dict]:
    """``(t0, settings)`` of the ``[simulation]`` table *sim* (the keyword arguments of
    :class:`~nonideal.modeling.declarations.SimulationSettings`)."""
    t0 = check.number(sim, "t0", "[simulation]", 0.0)
    settings = {}
    for key in ("t_end", "max_step"):
        if key in sim:
            value = check.number(sim, key, "[simulation]", None, positive=key == "max_step")
            if value is not None:
                settings[key] = float(value)
    for key in ("rtol", "atol"):
        if key in sim:
            value = check.number(sim, key, "[simulation]", None, positive=True)
            if value is not None and key == "rtol" and not 2.3e-14 <= float(value) < 1:
                problems.append(f"[simulation] rtol: must be at least 2.3e-14 (100 times the "
                                f"machine precision, the finest the integrators resolve) and below 1 "
                                f"(got {float(value):g})")
            elif value is not None:
                settings[key] = float(value)
    for key in ("method", "split"):
        if key in sim:
            if isinstance(sim[key], str):
                settings[key] = sim[key]
            else:
                problems.append(f"[simulation] {key}: must be a string (got {describe(sim[key])})")
    if "split_weights" in sim:
        settings["split_weights"] = split_weights(sim["split_weights"], check, problems)
    if "singular" in sim:
        if sim["singular"] in ("smooth", "stop"):
            settings["singular"] = sim["singular"]
        else:
            problems.append("[simulation] singular: must be \"smooth\" (go on through a singular "
                            "configuration of the constraints on the smooth branch) or \"stop\" "
                            f"(got {describe(sim['singular'])})")
    if "grid" in sim:
        grid = sim["grid"]
        if isinstance(grid, int) and not isinstance(grid, bool) and 2 <= grid <= 200_000:
            settings["grid"] = grid
        else:
            problems.append("[simulation] grid: must be an integer from 2 to 200000, the number of "
                            f"uniform output times (e.g. grid = 2001; got {describe(grid)})")
    if "every_step" in sim:
        if isinstance(sim["every_step"], bool):
            settings["every_step"] = sim["every_step"]
        else:
            problems.append("[simulation] every_step: must be true (output at every accepted step) or "
                            f"false (on the grid) (got {describe(sim['every_step'])})")
    return t0, settings


def split_weights(table: Any, check: Checker, problems: list[str]) -> dict[str, tuple]:
    """``[simulation] split_weights = {name = c, contact = [c_normal, c_tangential]}``: numbers
    or expressions in the parameters (their values checked with the model's names)."""
    if not isinstance(table, dict):
        problems.append(f"[simulation] split_weights: must be a table, e.g. split_weights = "
                        f"{{wall = 1.0, floor = [1.0, 2.0]}} (got {describe(table)})")
        return {}
    out = {}
    for name, value in table.items():
        items = value if isinstance(value, list) else [value]
        where = f"[simulation] split_weights {name}"
        numbers = [check.number({"weight": v}, "weight", where, None, positive=True) for v in items]
        out[name] = tuple(float(v) if v is not None else float("nan") for v in numbers)
    return out
