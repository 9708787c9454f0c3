"""What a notebook shows of a :class:`~nonideal.analysis.stability.linearize.Linearization`:
the verdict and its reason, the state, ``A`` typeset, the characteristic polynomial and a
table of the eigenvalues (numbers rounded as the text report rounds them)."""

from __future__ import annotations

from html import escape

import numpy as np
import sympy as sp

from ...numeric.display import clean, html_table, number

__all__ = ["linearization_html", "linearization_latex"]


def linearization_latex(lin) -> str:
    """``p(s) = 0`` and the set of its roots, as display math."""
    poly = lin.characteristic_polynomial
    rows = [(sp.latex(poly) if isinstance(poly, sp.Basic) else str(poly)) + " &= 0"]
    if len(lin.eigenvalues):
        rows.append(r"s &\in \{" + ",\\ ".join(_tex_complex(z) for z in lin.eigenvalues) + r"\}")
    return "$$\\begin{aligned}\n" + " \\\\\n".join(rows) + "\n\\end{aligned}$$"


def linearization_html(lin) -> str:
    """The verdict first, then the state, the variables, ``A``, the polynomial and the
    eigenvalues."""
    A = lin.A_symbolic if lin.A_symbolic is not None else sp.Matrix(np.asarray(lin.A, dtype=float))
    state = ", ".join(f"{escape(k)} = {number(v)}" for k, v in lin.q.items())
    moving = ", ".join(f"{escape(k)}' = {number(v)}" for k, v in lin.qdot.items() if v)
    about = "steady motion" if lin.about == "steady" else "equilibrium"
    eig = html_table(["eigenvalue", "real part", "imaginary part"],
                     [[k + 1, float(z.real), float(z.imag)] for k, z in enumerate(lin.eigenvalues)])
    conditions = (f"<br>{escape(lin.conditions_meaning)} iff "
                  + ", ".join(f"${sp.latex(c)}$" for c in lin.conditions)) if lin.conditions else ""
    return (f"<div><b>{escape(lin.model)}</b>, {about} {state}{', ' + moving if moving else ''}: "
            f"<b>{escape(lin.verdict)}</b> -- {escape(lin.reason)}<br>"
            f"variables: {escape(', '.join(lin.variables))}"
            + (f"; eliminated: {escape(', '.join(lin.dependent))}" if lin.dependent else "")
            + (f"; ignorable: {escape(', '.join(lin.ignorable))}" if lin.ignorable else "")
            + f"<br>$$A = {sp.latex(A.applyfunc(_tex_entry))}$$"
            + linearization_latex(lin) + conditions + eig + "</div>")


def _tex_complex(z: complex) -> str:
    re_, im = number(z.real, abs(z)), number(abs(z.imag), abs(z))
    if im == "0":
        return re_
    return (f"{re_} {'-' if z.imag < 0 else '+'} {im}\\,i" if re_ != "0"
            else f"{'-' if z.imag < 0 else ''}{im}\\,i")


def _tex_entry(x):
    """A numeric entry of A rounded as printed (10 digits; rounding noise as 0)."""
    if isinstance(x, sp.Float) or (isinstance(x, sp.Number) and not x.is_Rational):
        return sp.Float(float(f"{clean(float(x)):.10g}"), 10)
    return x
