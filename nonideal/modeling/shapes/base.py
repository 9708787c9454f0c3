"""The interface every contact shape implements, and the reading of its keys.

A shape is a convex surface fixed in a rigid body, described in the body's axes about its own
``center`` (a point fixed in the body, given in body axes from the body's centre; default the
body's centre).  Touching a plane of unit normal ``n`` (pointing from the plane into the side
where the body is), the **support point** is the point of the shape farthest along ``-n``: the
point that minimizes ``n . x`` over the shape.  Every shape gives it in closed form as a
function of ``n_b = R^T n`` (the normal in body axes), and says where that point is not unique
(:meth:`Shape.validity`: an expression that must be positive).

Checklist for a new shape (one module in this folder):

1. a frozen dataclass subclassing :class:`Shape` with its keys as fields (expressions) and
   ``center``; ``TYPE`` (the model file's ``type``) and ``SIZES`` (key -> number of
   components, 1 for a scalar);
2. :meth:`Shape.support` -- the support point in body axes relative to ``center``, closed form
   in ``n_b`` (no ``simplify``);
3. :meth:`Shape.validity` -- ``None`` when the support point is unique for every ``n_b``, else
   ``(expression > 0 where unique, what to say where it is not)``;
4. :meth:`Shape.check` -- problems with the values (a radius that is not positive, ...);
5. register it in ``SHAPES`` (``__init__.py``) and document its keys in docs/MODEL_FORMAT.md.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import sympy as sp

from ...errors import did_you_mean

__all__ = ["Shape", "read_fields"]

Parse = Callable[[Any, str], "sp.Expr | None"]


@dataclass(frozen=True)
class Shape:
    """Base class of the contact shapes (see the module's checklist)."""

    TYPE: ClassVar[str] = ""
    SIZES: ClassVar[dict[str, int]] = {}

    def support(self, n_b: sp.Matrix) -> sp.Matrix:
        """The support point in body axes relative to ``center`` (3x1), given the unit normal
        of the plane in body axes ``n_b`` (3x1)."""
        raise NotImplementedError

    def depth(self, n_b: sp.Matrix) -> sp.Expr:
        """``n_b . support(n_b)``: minus the support function, the signed distance from the
        plane through ``center`` to the support point (each shape gives its short form)."""
        return (n_b.T * self.support(n_b))[0]

    def offset_in(self, R: sp.Matrix) -> sp.Matrix:
        """``center`` in N axes (``R @ center``)."""
        c = getattr(self, "center", None)
        return sp.zeros(3, 1) if c is None else R * sp.Matrix(c)

    def support_in(self, n: sp.Matrix, R: sp.Matrix) -> sp.Matrix:
        """The support point relative to the body's centre, in N axes, given the plane's unit
        normal *n* (N axes) and the body's rotation *R* (body -> N)."""
        return R * (self.offset + self.support(R.T * n))

    def validity(self, n_b: sp.Matrix) -> tuple[sp.Expr, str] | None:
        """``(expression, explanation)``: the support point is unique where the expression is
        positive; ``None`` when it is unique for every orientation."""
        return None

    def check(self, values: Mapping[sp.Symbol, float], where: str) -> list[str]:
        """Problems with the dimensions at the parameter values *values*."""
        return []

    @property
    def offset(self) -> sp.Matrix:
        """``center`` as a column (body axes, from the body's centre)."""
        c = getattr(self, "center", None)
        return sp.zeros(3, 1) if c is None else sp.Matrix(c)

    def as_dict(self) -> dict[str, Any]:
        """The keys as written in a model file (for printing and JSON)."""
        out: dict[str, Any] = {"type": self.TYPE}
        for f in fields(self):
            v = getattr(self, f.name)
            if v is not None:
                out[f.name] = [str(x) for x in v] if isinstance(v, tuple) else str(v)
        return out


def positive(values: Mapping[sp.Symbol, float], expr: sp.Expr, where: str, key: str) -> list[str]:
    """A dimension that must be a positive number at the parameter values."""
    try:
        value = float(sp.sympify(expr).xreplace(values))
    except (TypeError, ValueError):
        return [f"{where}: {key} = {expr} is not a number at the parameter values; use "
                "parameters and numbers only"]
    if not value > 0:
        return [f"{where}: {key} = {expr} = {value:g} must be positive"]
    return []


def read_fields(cls: type, data: Mapping[str, Any], where: str, parse: Parse,
                problems: list[str]) -> dict[str, Any] | None:
    """The fields of shape or surface *cls* read from *data* (a mapping as in a model file):
    each key present, of the right size, parsed with *parse*; unknown keys and missing keys
    reported (with the fix).  ``center`` is optional (3 components)."""
    sizes = dict(cls.SIZES)
    optional = dict(getattr(cls, "OPTIONAL", {"center": 3}))
    known = {"type", *sizes, *optional}
    ok = True
    for key in data:
        if key not in known:
            problems.append(f"{where}: unknown key '{key}'{did_you_mean(str(key), known)} for a "
                            f"{cls.TYPE} (its keys: {', '.join(sorted(known - {'type'}))})")
            ok = False
    missing = [k for k in sizes if k not in data]
    if missing:
        example = ", ".join(f"{k} = {'[..]' if sizes[k] > 1 else '...'}" for k in sizes)
        problems.append(f"{where}: a {cls.TYPE} needs {', '.join(missing)} "
                        f"(write {{type = \"{cls.TYPE}\", {example}}})")
        return None
    out: dict[str, Any] = {}
    for key, size in {**sizes, **optional}.items():
        if key not in data:
            continue
        value = data[key]
        if size == 1:
            if isinstance(value, (list, tuple)):
                problems.append(f"{where}: {key} is one expression, not a list")
                ok = False
                continue
            e = parse(value, f"{where}: {key}")
            ok &= e is not None
            out[key] = e
        else:
            if not isinstance(value, (list, tuple)) or len(value) != size:
                got = len(value) if isinstance(value, (list, tuple)) else "one value"
                problems.append(f"{where}: {key} must have {size} components (got {got})")
                ok = False
                continue
            items = [parse(v, f"{where}: {key}[{i}]") for i, v in enumerate(value)]
            ok &= all(e is not None for e in items)
            out[key] = tuple(items)
    return out if ok else None
