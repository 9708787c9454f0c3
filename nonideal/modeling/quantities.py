"""Quantities with units where the user writes them: ``alpha = "30 deg"``, ``m = "250 g"``,
``w = "120 rpm"`` in ``[parameters]``, converted to the model's base units.

A quantity is a number, a space and a unit (``"30 deg"``; ``"30°"`` too).  A small table of common units, not a units library: a model file must read the same wherever
nonideal runs, with no optional package deciding whether it parses.  The base units are the
model's ``[units]`` (``length``, ``mass``, ``time``, ``angle``), SI (m, kg, s, rad) where it
names none; angles always in radians (the trigonometric functions take them).  A unit is a product of the table's symbols with integer powers, one ``/``
dividing by what follows it (``kg m^2``, ``m/s^2``, ``N m``, ``rad/s``, ``1/s``,
``W/(N m)^2``).  Nothing is evaluated: the text is read token by token.

:func:`degree_warnings` finds the other mistake -- an angle written in degrees with no unit
(``theta0 = 30`` where ``30 deg`` was meant) -- when it changes whether a contact touches at
t0.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import sympy as sp

__all__ = ["UNITS", "Quantity", "parse_quantity", "parse_unit", "base_units", "base_unit_of", "unit_label", "with_units",
           "degree_warnings"]

# dimension exponents (length, mass, time, angle)
_L, _M, _T, _A = (1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)


def _dim(length=0, mass=0, time=0, angle=0):
    return (length, mass, time, angle)


#: symbol -> (factor to SI, dimension exponents (length, mass, time, angle))
UNITS: dict[str, tuple[float, tuple[int, int, int, int]]] = {
    "m": (1.0, _L), "mm": (1e-3, _L), "cm": (1e-2, _L), "dm": (0.1, _L), "km": (1e3, _L),
    "um": (1e-6, _L), "µm": (1e-6, _L), "in": (0.0254, _L), "ft": (0.3048, _L),
    "kg": (1.0, _M), "g": (1e-3, _M), "mg": (1e-6, _M), "lb": (0.45359237, _M),
    "s": (1.0, _T), "ms": (1e-3, _T), "min": (60.0, _T), "h": (3600.0, _T),
    "rad": (1.0, _A), "mrad": (1e-3, _A), "deg": (math.pi / 180, _A), "degree": (math.pi / 180, _A),
    "degrees": (math.pi / 180, _A), "°": (math.pi / 180, _A), "rev": (2 * math.pi, _A),
    "rpm": (2 * math.pi / 60, _dim(time=-1, angle=1)), "Hz": (1.0, _dim(time=-1)),
    "N": (1.0, _dim(1, 1, -2)), "kN": (1e3, _dim(1, 1, -2)), "mN": (1e-3, _dim(1, 1, -2)),
    "J": (1.0, _dim(2, 1, -2)), "kJ": (1e3, _dim(2, 1, -2)), "W": (1.0, _dim(2, 1, -3)),
    "kW": (1e3, _dim(2, 1, -3)), "Pa": (1.0, _dim(-1, 1, -2)), "kPa": (1e3, _dim(-1, 1, -2)),
    "MPa": (1e6, _dim(-1, 1, -2)), "GPa": (1e9, _dim(-1, 1, -2)),
    "1": (1.0, _dim()), "%": (0.01, _dim()),
}

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})(?:\s+([A-Za-z°µ%(][^=]*?)|\s*([°%]))\s*$")
_TOKEN = re.compile(r"\s*(\*\*|[()*/^·]|[+-]?\d+|[A-Za-z°µ%]+)")


@dataclass(frozen=True)
class Quantity:
    """A number with its unit as written, e.g. ``Quantity(30.0, "deg")``."""

    number: float
    unit: str
    factor: float                      # to SI
    dimension: tuple[int, int, int, int]

    def in_base(self, base: "dict[str, str | None] | None" = None) -> float:
        """The value in the base units *base* (``{"length": "cm", ...}``; SI where None).

        Examples
        --------
        >>> round(parse_quantity("30 deg").in_base(), 12)
        0.523598775598
        >>> parse_quantity("250 g").in_base({"mass": "g"})
        250.0
        """
        return self.number * self.factor / base_factor(self.dimension, base)

    @property
    def text(self) -> str:
        return f"{self.number:g} {self.unit}"


def base_factor(dimension, base=None) -> float:
    """The SI value of one base unit of *dimension* (1 for SI base units)."""
    out = 1.0
    for kind, power in zip(("length", "mass", "time", "angle"), dimension):
        if power:
            name = (base or {}).get(kind)
            if name:
                factor, dim = UNITS.get(name, (None, None))
                if factor is None or dim != {"length": _L, "mass": _M, "time": _T, "angle": _A}[kind]:
                    raise ValueError(f"the model's base unit of {kind} {name!r} is not one the "
                                     f"table converts to ({', '.join(k for k, v in UNITS.items() if v[1] == {'length': _L, 'mass': _M, 'time': _T, 'angle': _A}[kind])})")
                out *= factor ** power
    return out


def parse_unit(text: str) -> tuple[float, tuple[int, int, int, int]]:
    """``(factor to SI, dimension)`` of a unit such as ``"kg m^2"`` or ``"m/s^2"``.

    Raises
    ------
    ValueError
        An unknown symbol (with the nearest known ones) or a malformed unit.

    Examples
    --------
    >>> parse_unit("kN m")
    (1000.0, (2, 1, -2, 0))
    >>> parse_unit("W/(N m)^2")
    (1.0, (-2, -1, 1, 0))
    """
    tokens, pos = [], 0
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m:
            raise ValueError(f"cannot read the unit {text!r} at {text[pos:]!r}")
        tokens.append(m.group(1))
        pos = m.end()
    factor, dim, rest = _product(tokens, text)
    if rest:
        raise ValueError(f"cannot read the unit {text!r} at {' '.join(rest)!r}")
    return factor, dim


def _product(tokens, text):
    factor, dim = 1.0, (0, 0, 0, 0)
    divide = False
    while tokens and tokens[0] != ")":
        tok = tokens[0]
        if tok in ("*", "·"):
            tokens = tokens[1:]
            continue
        if tok == "/":
            if divide:
                raise ValueError(f"the unit {text!r} divides twice; write it as a/(b c)")
            divide, tokens = True, tokens[1:]
            continue
        f, d, tokens = _factor(tokens, text)
        sign = -1 if divide else 1
        factor *= f ** sign
        dim = tuple(a + sign * b for a, b in zip(dim, d))
        if divide:      # "/" divides by the factor that follows it
            divide = None
    return factor, dim, tokens


def _factor(tokens, text):
    tok, tokens = tokens[0], tokens[1:]
    if tok == "(":
        f, d, tokens = _product(tokens, text)
        if not tokens or tokens[0] != ")":
            raise ValueError(f"the unit {text!r} misses a ')'")
        tokens = tokens[1:]
    elif tok in UNITS:
        f, d = UNITS[tok]
    else:
        from difflib import get_close_matches

        near = get_close_matches(tok, UNITS, n=3)
        raise ValueError(f"unknown unit {tok!r} in {text!r}"
                         + (f" (did you mean {' or '.join(repr(n) for n in near)}?)" if near
                            else f"; the units known are {', '.join(UNITS)}"))
    if tokens and tokens[0] in ("^", "**"):
        if len(tokens) < 2 or not re.fullmatch(r"[+-]?\d+", tokens[1]):
            raise ValueError(f"the unit {text!r}: a power is an integer, e.g. m^2")
        p = int(tokens[1])
        if abs(p) > 12:
            raise ValueError(f"the unit {text!r}: a power of a unit is at most 12 in magnitude")
        f, d, tokens = f ** p, tuple(p * x for x in d), tokens[2:]
    return f, d, tokens


def parse_quantity(text) -> Quantity | None:
    """The quantity written in *text* (``"30 deg"``, ``"250 g"``, ``"9.81 m/s^2"``), or None
    when *text* is not a number followed by a unit (an expression in other parameters).

    Raises
    ------
    ValueError
        A number followed by something that is not a unit of the table.
    """
    if not isinstance(text, str):
        return None
    m = _QUANTITY.match(text)
    if not m:
        return None
    unit = m.group(2) or m.group(3)
    factor, dim = parse_unit(unit)
    number = float(m.group(1))
    if not math.isfinite(number) or not math.isfinite(number * factor):
        raise ValueError(f"{text!r}: the number overflows")
    return Quantity(number, unit, factor, dim)


def degree_warnings(model) -> list[str]:
    """Angles that look written in degrees with no unit, where it matters: a number above
    2 pi in magnitude that the model uses as an angle -- a parameter in the argument of a
    trigonometric function, or the initial value of a coordinate that is an angle -- such
    that a contact open at t0 (gap > 0) would touch (gap <= 0) were the number in degrees.
    One message per contact, naming the number, the contact and both gaps.
    """
    from .units import coordinate_kinds

    if not model.contacts:
        return []
    values = dict(model.parameter_values)
    try:
        initial = dict(model.numeric_initial())
    except Exception:   # an initial state that does not evaluate is reported elsewhere
        return []
    given = {n for n, p in model.parameters.items() if getattr(p, "given", "")}
    trig = (sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)
    exprs = [model.kinetic, model.potential, *[c.gap for c in model.contacts],
             *[c.expr for c in model.constraints]]
    for b in model.bodies:
        exprs += [*getattr(b, "position", ()), getattr(b, "angle", None) or 0]
    angle_params = set()
    for e in exprs:
        for f in sp.sympify(e).atoms(*trig):
            angle_params |= {s.name for s in f.args[0].free_symbols if s.name in values}
    suspects = {("parameter", n): values[n] for n in angle_params
                if abs(values[n]) > 2 * math.pi and n not in given}
    large = [c for c in model.coordinates if c in initial and abs(initial[c]) > 2 * math.pi]
    kinds = coordinate_kinds(model) if large else {}
    suspects.update({("coordinate", c): initial[c] for c in large if kinds.get(c) == "angle"})
    if not suspects:
        return []
    q = {sp.Symbol(c): initial[c] for c in model.coordinates if c in initial}
    p = {sp.Symbol(n): v for n, v in values.items()}
    out = []
    for contact in model.contacts:
        gap = sp.sympify(contact.gap).subs(sp.Symbol("t"), model.t0 or 0)
        for (kind, name), v in suspects.items():
            symbol = sp.Symbol(name)
            if symbol not in gap.free_symbols and not (kind == "parameter" and _through_initial(model, name)):
                continue
            as_given = _number(gap, {**p, **q})
            if kind == "parameter":
                in_degrees = _number(gap, {**p, symbol: math.radians(v), **_initial_with(model, name, math.radians(v))})
            else:
                in_degrees = _number(gap, {**p, **q, symbol: math.radians(v)})
            scale = max(1.0, abs(as_given or 0.0))
            if as_given is None or in_degrees is None:
                continue
            if as_given > 1e-9 * scale and in_degrees <= 1e-9 * scale:
                where = f"[parameters] {name}" if kind == "parameter" else f"[initial] {name}"
                out.append(f"{where} = {v:g} is used as an angle in radians and is more than 2 pi; "
                           f"with it contact '{contact.name}' is open at t0 (gap {as_given:.6g}), "
                           f"while {v:g} deg would close it (gap "
                           f"{0 if abs(in_degrees) <= 1e-12 * scale else in_degrees:.3g}): if the angle "
                           f"is in degrees, write \"{v:g} deg\"")
    return out


def _through_initial(model, name: str) -> bool:
    return any(sp.Symbol(name) in sp.sympify(e).free_symbols for e in model.initial.values()
               if not isinstance(e, (int, float)))


def _initial_with(model, name: str, value: float) -> dict:
    """The initial coordinates with the parameter *name* set to *value*."""
    from .expressions import float_value

    values = {**model.parameter_values, name: value}
    out = {}
    for c in model.coordinates:
        if c in model.initial:
            try:
                out[sp.Symbol(c)] = float_value(sp.sympify(model.initial[c]), f"[initial] {c}", values)
            except Exception:
                pass
    return out


def _number(expr, subs) -> float | None:
    try:
        value = complex(sp.sympify(expr).xreplace(subs).evalf())
    except (TypeError, ValueError):
        return None
    return value.real if abs(value.imag) < 1e-12 else None


_KINDS = ("length", "mass", "time", "angle")
_SI = {"length": "m", "mass": "kg", "time": "s", "angle": "rad"}


def base_units(units) -> dict[str, str | None]:
    """The base units of a model's ``[units]`` (a :class:`~nonideal.modeling.units.Units`, the
    raw table or None): ``{"length": ..., "mass": ..., "time": ...}``, None where not declared
    (SI then).  Angles are always in radians, whatever ``[units] angle`` labels them."""
    if units is None:
        return {}
    kinds = ("length", "mass", "time")     # angles: always radians (the functions take them)
    if isinstance(units, dict) or hasattr(units, "get"):
        return {k: units.get(k) for k in kinds if isinstance(units.get(k), str)}
    return {k: getattr(units, k, None) for k in kinds}


def unit_label(dimension, base=None) -> str:
    """The unit of *dimension* in the base units, e.g. ``"m/s^2"``, ``"rad"``, ``"1"``."""
    up, down = [], []
    for kind, power in zip(_KINDS, dimension):
        if power:
            name = (base or {}).get(kind) or _SI[kind]
            (up if power > 0 else down).append(name + (f"^{abs(power)}" if abs(power) != 1 else ""))
    text = " ".join(up) or "1"
    if down:
        text += "/" + (down[0] if len(down) == 1 else "(" + " ".join(down) + ")")
    return text


def base_unit_of(unit: str, units=None) -> str:
    """The model's base unit of the quantity *unit* measures (``"deg"`` -> ``"rad"``; ``"cm"``
    -> ``"m"``, or the ``[units]`` length), or *unit* itself when the table does not know it:
    a value given in base units (``--set``, ``--vary``) keeps its label and is not converted.
    """
    try:
        _, dim = parse_unit(unit)
    except ValueError:
        return unit
    return unit_label(dim, base_units(units if isinstance(units, dict) else None))


def with_units(p, base, where: str, problems: list[str]):
    """*p* (a :class:`~nonideal.modeling.declarations.Parameter`) with its value in the base
    units: a quantity ``"30 deg"`` converted, or a number whose ``unit`` the table knows
    converted when the factor is not 1 (``{value = 30, unit = "deg"}``); its ``unit`` is then
    the base unit and ``given`` the quantity as written.  A unit the table does not know stays
    a label, as before.  A problem is appended to *problems* for a quantity that cannot be
    read."""
    from dataclasses import replace

    if p.given:
        return p
    try:
        quantity = parse_quantity(p.value)
    except ValueError:      # reported where the values are resolved
        return p
    try:
        if quantity is None and p.unit and isinstance(p.value, (int, float)) \
                and not isinstance(p.value, bool):
            try:
                factor, dim = parse_unit(p.unit)
            except ValueError:
                return p       # a unit the table does not know: a label
            if factor / base_factor(dim, base) == 1.0:
                return p
            quantity = Quantity(float(p.value), p.unit, factor, dim)
        if quantity is None:
            return p
        return replace(p, value=quantity.in_base(base), unit=unit_label(quantity.dimension, base),
                       given=quantity.text)
    except ValueError as exc:
        problems.append(f"{where}: {exc}")
        return p
