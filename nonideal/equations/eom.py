"""One result type for every formalism: :class:`EquationsOfMotion`.

Every form (``lagrange1``, ``lagrange2``, ``maggi``, ``appell``, ``shulgin``, ``servo``) fills
the same structure.  With ``a`` the form's unknown accelerations (all ``q''`` for Lagrange I,
the independent ones for the reduced forms) and ``mu`` the multipliers the form keeps::

    A a + c = Q_f + B mu          (k equations: inertia terms = forces + reactions)
    G a + gamma = 0               (one row per kept constraint)
    q'' = R a + r                 (back to all coordinates)

Reduced forms eliminate the ideal constraints; non-ideal ones (servo, quasi-ideal, sliding
friction) keep their multipliers.  Auxiliary quantities (dependent-velocity coefficients that
would be expensive to write explicitly) appear as symbols defined by linear systems in
``auxiliaries``; the numerics solve those systems numerically.

Internally the matrices are SymEngine; the public properties return SymPy objects, converted
on first access.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import symengine as se
import sympy as sp

from ..modeling.symbols import latex_names, to_sp
from .readable import Printer

__all__ = ["EquationsOfMotion", "Auxiliary"]


@dataclass(frozen=True)
class Auxiliary:
    """Auxiliary symbols ``X`` defined by a linear system ``K X = Y`` (solved numerically).

    Attributes
    ----------
    symbols : se.DenseMatrix, shape (m, p)
    K : se.DenseMatrix, shape (m, m)
    Y : se.DenseMatrix, shape (m, p)
    meaning : str
    """

    symbols: Any
    K: Any
    Y: Any
    meaning: str


@dataclass(frozen=True, eq=False)
class EquationsOfMotion:
    """Equations of motion of a model in one classical form.

    Attributes
    ----------
    form : str
        ``"lagrange1"``, ``"lagrange2"``, ``"maggi"``, ``"appell"``, ``"shulgin"``.
    title, citation : str
        Name of the form and where it comes from.
    model : Model
    unknowns : tuple of str
        Names of the unknown accelerations ``a`` (``"x''"``...).
    multipliers : tuple of str
        Names of the multipliers kept in the equations.
    constraint_names : tuple of str
        Constraint (or contact row) each multiplier belongs to.
    rows : tuple
        The :class:`~nonideal.equations.dynamics.ConstraintRow` objects the equations were derived for.
    independent : tuple of str
        Coordinates whose accelerations are the unknowns (reduced forms) -- or all.
    notes : tuple of str
        Remarks printed with the equations (eliminations, branch choices, misprints).
    structure_ : dict
        Known nonzero pattern of a matrix, ``{"A_": {i: [j, ...]}}`` (the columns of row ``i``
        that may be nonzero; a row not listed is empty), from a form that knows it (Lagrange
        I: the mass matrix of many bodies is sparse).  Printing visits only those entries
        (reading the n^2 entries of a SymEngine matrix one by one costs ~5 us each); a matrix
        not listed is read entry by entry.
    speeds : tuple of str
        The generalized speeds the equations are written in (the quasi-velocity forms), printed
        as velocities; their values are computed from the state (an auxiliary).
    """

    form: str
    title: str
    citation: str
    model: Any
    unknowns: tuple[str, ...]
    multipliers: tuple[str, ...]
    constraint_names: tuple[str, ...]
    rows: tuple[Any, ...]
    independent: tuple[str, ...]
    A_: Any
    c_: Any
    Qf_: Any
    B_: Any
    G_: Any
    gamma_: Any
    R_: Any
    r_: Any
    auxiliaries: tuple[Auxiliary, ...] = ()
    extras_: dict[str, Any] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    eliminated: tuple[str, ...] = ()
    structure_: dict[str, Any] = field(default_factory=dict)
    speeds: tuple[str, ...] = ()

    def columns(self, name: str, i: int) -> range | list[int]:
        """The columns of row *i* of matrix *name* (``"A_"``...) that may be nonzero."""
        pattern = self.structure_.get(name)
        if pattern is None:
            return range(getattr(self, name).shape[1])
        return pattern.get(i, [])

    # ---------------------------------------------------------------- shapes
    @property
    def k(self) -> int:
        """Number of unknown accelerations."""
        return len(self.unknowns)

    # ---------------------------------------------------------------- SymPy views
    @cached_property
    def _memo(self) -> dict:
        """SymEngine -> SymPy nodes converted so far (the views share subexpressions)."""
        return {}

    def _sp(self, expr):
        return to_sp(expr, self._memo)

    @cached_property
    def mass_matrix(self) -> sp.Matrix:
        """``A``, shape (k, k)."""
        return self._sp(self.A_)

    @cached_property
    def inertial_terms(self) -> sp.Matrix:
        """``c``: velocity-dependent inertia terms on the left, shape (k, 1)."""
        return self._sp(self.c_)

    @cached_property
    def generalized_forces(self) -> sp.Matrix:
        """``Q_f``: active generalized forces on the right, shape (k, 1)."""
        return self._sp(self.Qf_)

    @cached_property
    def forcing(self) -> sp.Matrix:
        """``b = Q_f - c`` so that ``A a = b + B mu``, shape (k, 1)."""
        return self._sp(self.Qf_ - self.c_)

    @cached_property
    def reaction_matrix(self) -> sp.Matrix:
        """``B``, shape (k, n_mult)."""
        return self._sp(self.B_)

    @cached_property
    def constraint_jacobian(self) -> sp.Matrix:
        """``G``, shape (n_mult, k)."""
        return self._sp(self.G_)

    @cached_property
    def constraint_bias(self) -> sp.Matrix:
        """``gamma``, shape (n_mult, 1)."""
        return self._sp(self.gamma_)

    @cached_property
    def acceleration_map(self) -> tuple[sp.Matrix, sp.Matrix]:
        """``(R, r)`` with ``q'' = R a + r``."""
        return self._sp(self.R_), self._sp(self.r_)

    @property
    def unknown_symbols(self) -> list[sp.Symbol]:
        return [sp.Symbol(n) for n in self.unknowns]

    @property
    def multiplier_symbols(self) -> list[sp.Symbol]:
        return [sp.Symbol(n) for n in self.multipliers]

    @cached_property
    def extras(self) -> dict[str, Any]:
        """Form-specific symbolic objects (``S`` for Appell, ``T*`` for Shulgin...), SymPy."""
        out = {}
        for key, value in self.extras_.items():
            out[key] = self._sp(value) if not isinstance(value, str) else value
        return out

    def equations(self) -> list[sp.Eq]:
        """The equations as SymPy ``Eq``: dynamics rows then constraint rows."""
        a = sp.Matrix(self.unknown_symbols)
        mu = sp.Matrix(self.multiplier_symbols)
        A, c, Qf = self.mass_matrix, self.inertial_terms, self.generalized_forces
        eqs = []
        for i in range(self.k):
            lhs = sum((A[i, j] * a[j] for j in range(self.k)), sp.Integer(0)) + c[i]
            rhs = Qf[i]
            if mu.shape[0]:
                rhs += sum((self.reaction_matrix[i, j] * mu[j] for j in range(mu.shape[0])), sp.Integer(0))
            eqs.append(sp.Eq(lhs, rhs, evaluate=False))
        G, gamma = self.constraint_jacobian, self.constraint_bias
        for i in range(G.shape[0]):
            lhs = sum((G[i, j] * a[j] for j in range(self.k)), sp.Integer(0)) + gamma[i]
            eqs.append(sp.Eq(lhs, 0, evaluate=False))
        return eqs

    # ---------------------------------------------------------------- printing
    @cached_property
    def printer(self) -> Printer:
        """The :class:`~nonideal.equations.readable.Printer` of these equations."""
        def latex_of(name: str) -> str:
            s = sp.Symbol(name)
            return latex_names([s])[s]

        return Printer(self.model.coordinates, self.unknowns, self.multipliers, latex_of, speeds=self.speeds)

    @cached_property
    def _sides(self) -> list[tuple[dict, dict]]:
        """(lhs, rhs) polynomials of every equation, the identities folded: ``A a + c`` =
        ``Q_f + B mu``, then ``G a + gamma`` = 0."""
        P = self.printer
        out = []
        for i in range(self.k):
            lhs: dict = {}
            for j in self.columns("A_", i):
                P.add_into(lhs, P.poly(self.A_[i, j]), self.unknowns[j])
            P.add_into(lhs, P.poly(self.c_[i]))
            rhs: dict = {}
            P.add_into(rhs, P.poly(self.Qf_[i]))
            for j, m in enumerate(self.multipliers):
                P.add_into(rhs, P.poly(self.B_[i, j]), m)
            out.append((P.fold(lhs), P.fold(rhs)))
        for i in range(self.G_.shape[0]):
            lhs = {}
            for j, a in enumerate(self.unknowns):
                P.add_into(lhs, P.poly(self.G_[i, j]), a)
            P.add_into(lhs, P.poly(self.gamma_[i]))
            lhs = P.fold(lhs)
            if lhs and all(c < 0 for c in lhs.values()):
                lhs = {m: -c for m, c in lhs.items()}     # "= 0": written with plus signs
            out.append((lhs, {}))
        return out

    def readable(self, latex: bool = False) -> list[str]:
        """The equations as a mechanician writes them, one string ``lhs = rhs`` each (LaTeX:
        ``lhs &= rhs``): accelerations, then products of velocities, then forces and
        multipliers, with ``sin^2 + cos^2``, angle sums and common factors folded
        (:mod:`nonideal.equations.readable`; exact identities only, no ``simplify``)."""
        P = self.printer
        sep = " &= " if latex else " = "
        return [P.side(lhs, latex) + sep + P.side(rhs, latex) for lhs, rhs in self._sides]

    def _readable_value(self, value, latex: bool = False) -> str:
        """An extra (``T``, ``S``, a matrix ``V``...) in the readable style."""
        P = self.printer
        if isinstance(value, str):
            return value
        if isinstance(value, (se.DenseMatrix, sp.MatrixBase)):
            rows = [[P.expression(x, latex) for x in row] for row in
                    (value.tolist() if hasattr(value, "tolist") else value)]
            if latex:
                return r"\begin{pmatrix}" + r" \\ ".join(" & ".join(r) for r in rows) + r"\end{pmatrix}"
            return "Matrix([" + ", ".join("[" + ", ".join(r) + "]" for r in rows) + "])"
        try:
            return P.expression(value, latex)
        except (TypeError, ValueError, RuntimeError):   # pragma: no cover - not an expression
            return str(value)

    def _symbols_for_print(self):
        syms = set()
        for eq in self.equations():
            syms |= eq.free_symbols
        return syms

    def as_text(self, simplify: bool = False) -> str:
        """Plain text, one equation per line, in the readable form of :meth:`readable`
        (``simplify`` runs SymPy's ``trigsimp`` on the raw equations instead: slow, it grows
        exponentially with the number of angles)."""
        lines = [f"{self.title}  [{self.form}]", f"  source: {self.citation}"]
        lines += [f"  note: {n}" for n in self.notes]
        for key, value in self.extras_.items():
            lines.append(f"  {key} = {self._readable_value(value)}")
        for aux in self.auxiliaries:
            lines.append(f"  auxiliary: {aux.meaning}")
        lines.append("  unknowns: " + ", ".join(self.unknowns))
        if self.multipliers:
            lines.append("  multipliers: " + ", ".join(self.multipliers))
        if simplify:
            for eq in self.equations():
                lines.append(f"  {sp.sstr(sp.trigsimp(eq.lhs))} = {sp.sstr(sp.trigsimp(eq.rhs))}")
        else:
            lines += ["  " + line for line in self.readable()]
        return "\n".join(lines)

    def as_latex(self, simplify: bool = False) -> str:
        """LaTeX (an ``align*`` environment) in textbook notation (``\\ddot{x}``, ``\\lambda``),
        in the readable form (``simplify``: SymPy's ``trigsimp`` of the raw equations)."""
        if simplify:
            names = latex_names(self._symbols_for_print() | {sp.Symbol(n) for n in self.unknowns})
            rows = [sp.latex(sp.trigsimp(eq.lhs), symbol_names=names) + " &= "
                    + sp.latex(sp.trigsimp(eq.rhs), symbol_names=names) for eq in self.equations()]
        else:
            rows = self.readable(latex=True)
        head = f"% {self.title} ({self.form}); {self.citation}\n"
        for key, value in self.extras_.items():
            if not isinstance(value, str):
                head += f"% {key} = " + self._readable_value(value, latex=True) + "\n"
        return head + "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"

    def _repr_latex_(self) -> str:
        """Jupyter: the equations, typeset."""
        return "$$\\begin{aligned}\n" + " \\\\\n".join(self.readable(latex=True)) + "\n\\end{aligned}$$"

    def _repr_html_(self) -> str:
        """Jupyter: the form, its source and the equations (typeset by MathJax)."""
        from html import escape

        notes = "".join(f"<li>{escape(n)}</li>" for n in self.notes)
        return (f"<div><b>{escape(self.title)}</b> [{escape(self.form)}] of "
                f"<i>{escape(self.model.name)}</i><br><small>{escape(self.citation)}</small>"
                + (f"<ul>{notes}</ul>" if notes else "") + "<br>" + self._repr_latex_() + "</div>")

    def to_dict(self) -> dict[str, Any]:
        """Machine-readable form: every expression in the readable style of :meth:`readable`
        (SymPy syntax, primes for the time derivatives)."""
        P = self.printer

        def matrix(m, name=None) -> list:
            if name not in self.structure_:
                return [[P.expression(m[i, j]) for j in range(m.shape[1])] for i in range(m.shape[0])]
            zero = P.expression(se.Integer(0))
            rows = [[zero] * m.shape[1] for _ in range(m.shape[0])]
            for i, row in enumerate(rows):
                for j in self.columns(name, i):
                    row[j] = P.expression(m[i, j])
            return rows

        def column(m) -> list:
            return [P.expression(m[i, 0]) for i in range(m.shape[0])]

        return {
            "form": self.form,
            "title": self.title,
            "citation": self.citation,
            "model": self.model.name,
            "unknowns": list(self.unknowns),
            "multipliers": list(self.multipliers),
            "constraints": list(self.constraint_names),
            "eliminated": list(self.eliminated),
            "independent": list(self.independent),
            "notes": list(self.notes),
            "mass_matrix": matrix(self.A_, "A_"),
            "inertial_terms": column(self.c_),
            "generalized_forces": column(self.Qf_),
            "reaction_matrix": matrix(self.B_),
            "constraint_jacobian": matrix(self.G_),
            "constraint_bias": column(self.gamma_),
            "equations": self.readable(),
            "latex": self.as_latex(),
            "extras": {k: self._readable_value(v) for k, v in self.extras_.items()},
            "auxiliaries": [a.meaning for a in self.auxiliaries],
        }

    def __repr__(self) -> str:
        return (f"EquationsOfMotion(form={self.form!r}, model={self.model.name!r}, "
                f"unknowns={list(self.unknowns)}, multipliers={list(self.multipliers)})")


def empty(rows: int, cols: int):
    """A SymEngine zero matrix that also works for zero rows or columns."""
    return se.zeros(rows, cols)
