"""Numbers as the text outputs show them: rounding noise (a value below ``1e-12`` of its scale,
the scale at least 1) is shown as ``0`` -- not ``-2.46e-32`` or ``-0`` -- since the computation
cannot resolve it.  The JSON outputs keep the raw values."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

__all__ = ["clean", "number", "numbers", "html_table", "NOISE"]

#: relative size below which a value is rounding noise
NOISE = 1e-12


def clean(value: float, scale: float | None = None) -> float:
    """*value*, or ``0.0`` when it is rounding noise against *scale* (default: its own size,
    at least 1)."""
    value = float(value)
    ref = max(1.0, abs(value) if scale is None else abs(float(scale)))
    return 0.0 if abs(value) <= NOISE * ref else value


def number(value: float, scale: float | None = None, digits: int = 10, sign: bool = False) -> str:
    """``f"{value:.{digits}g}"`` with rounding noise as ``0`` (``sign``: a space for plus)."""
    v = clean(value, scale)
    if v == 0.0:
        return " 0" if sign else "0"
    return f"{v: .{digits}g}" if sign else f"{v:.{digits}g}"


def numbers(values: Iterable[float], scale: float | None = None, digits: int = 8) -> str:
    """``[a, b, ...]``; the scale defaults to the largest magnitude among the values."""
    arr = np.atleast_1d(np.asarray(list(values), dtype=float))
    if scale is None:
        scale = float(np.max(np.abs(arr))) if arr.size else 1.0
    return "[" + ", ".join(number(v, scale, digits) for v in arr) + "]"


def html_table(header: Iterable[str], rows: Iterable[Iterable[Any]], caption: str = "") -> str:
    """An HTML table for the notebooks' displays (``_repr_html_``): cells escaped, floats
    written with :func:`number`, a missing value (None, NaN) as an empty cell.

    Examples
    --------
    >>> html_table(["x", "y"], [["a", 1.5]])
    '<table><tr><th>x</th><th>y</th></tr><tr><td>a</td><td>1.5</td></tr></table>'
    """
    from html import escape

    def cell(v) -> str:
        if v is None or (isinstance(v, float) and v != v):
            return ""
        if isinstance(v, (float, np.floating)):
            return number(float(v))
        return escape(str(v))

    head = "".join(f"<th>{escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{cell(v)}</td>" for v in r) + "</tr>" for r in rows)
    cap = f"<caption>{escape(caption)}</caption>" if caption else ""
    return f"<table>{cap}<tr>{head}</tr>{body}</table>"
