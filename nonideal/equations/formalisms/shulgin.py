"""Shulgin's equations in redundant coordinates, with Voronets' terms for nonholonomic and
rheonomic constraints.

All coordinates ``x`` are kept; the ideal constraints, linear in the velocities (holonomic ones
at velocity level ``G x' + df/dt = 0``, nonholonomic ones ``G x' + c = 0``), are solved for the
dependent velocities (``a``: dependent, ``i, j``: independent)

    x_a' = sum_j A_aj x_j' + A_a0                                          (1.61)

and ``T* = T`` with these substituted.  With Shulgin's operators

    E_j = d/dx_j + sum_a A_aj d/dx_a,          E_0 = d/dt + sum_a A_a0 d/dx_a,

and ``p_b = (dT/dx_b')*`` (``*``: dependent velocities substituted) the equations are, for
each independent ``j``,

    d/dt dT*/dx_j' - E_j(T*) - sum_b p_b W_bj = Q_j + sum_a A_aj Q_a   (+ non-ideal reactions)
    W_bj = sum_i (E_i(A_bj) - E_j(A_bi)) x_i' + E_0(A_bj) - E_j(A_b0),

where ``d/dt`` is taken along the constrained motion (``d/dt f = E_0 f + sum_i x_i' E_i f``).
Derivation: ``dT*/dx_j' = (dT/dx_j')* + sum_b A_bj p_b`` and
``E_j(T*) = (dT/dx_j)* + sum_a A_aj (dT/dx_a)* + sum_b p_b (sum_i E_j(A_bi) x_i' + E_j(A_b0))``,
so the left-hand side minus the ``W`` terms is ``L_j + sum_a A_aj L_a`` (``L`` the Lagrange
operator of ``T``): Maggi's equation, i.e. the general equation of dynamics (1.62) with the
dependent variations eliminated.  The ``W_bj`` (Voronets' terms) vanish identically when the
constraints are integrable (holonomic, scleronomic or rheonomic); they are then dropped (tested
numerically at generic points) and the equations are exactly (1.64), with ``A_a0`` added for
rheonomic constraints.  Manglieva & Beknazarov 2022 print (1.61) without ``A_a0`` (scleronomic only), refers to
(1.43) for the constraints (1.58) and writes the dependent velocities as ``x_q``; the
equations here are derived, not copied.

Unknowns: the accelerations of the independent coordinates (the only accelerations in the
equations, from ``d/dt dT*/dx_j'``).  ``A = d2T*/dx_j'dx_i'``, ``c`` = the rest of the left-hand
side (velocity terms, with the Voronets terms), ``Q_f = Q_j + sum_a A_aj Q_a`` (``-dV/dx``
included), all with the dependent velocities eliminated.  ``R`` (back to every ``x''``) has the
rows ``A_aj`` (unit rows for the independent coordinates), ``r`` the dependent accelerations
that (1.61) gives along the motion, ``w_a = E_0(x_a'*) + sum_i x_i' E_i(x_a'*)`` (``x_a'*`` the
right-hand side of (1.61)).  Non-ideal constraints (servo, quasi-ideal, sliding friction) keep
their multipliers, projected as in Maggi's form.  Without ideal constraints nothing is
eliminated: ``T* = T``, ``E_j = d/dx_j``, and (1.64) is Lagrange's equations of ``T`` -- ``A``
and ``c`` are then the kernel's ``M`` and ``h`` (built from the bodies, not by differentiating
``T`` again).

The coefficients ``A_aj``, ``A_a0`` are written explicitly when the dependent block of the
constraints solves within a size budget (:func:`coefficients`).  Beyond it -- e.g. a chain of
knife edges, whose k-th dependent velocity written out contains all the earlier ones and
doubles with every link -- they are auxiliary symbols ``A[a,j]``, ``A0[a]`` defined by the
constraints, ``G_D [A | A_0] = -[G_I | b]``, and their partial derivatives symbols
``dA[a,j]/dx`` defined by the derivative of that system; ``T*``, the operators ``E_j``, ``E_0``
(by the chain rule through the coefficients) and Voronets' terms are formed as above, so the
equations keep Shulgin's form and grow polynomially.

Applies to constraints linear in the velocities; otherwise :class:`FormNotApplicable` points
to ``maggi`` or ``appell``.

Sources: M. F. Shulgin, *On some differential equations of analytical dynamics and their
integration*, Tashkent 1958; Manglieva & Beknazarov 2022, (1.61)-(1.64); P. V. Voronets,
*On the equations of motion of nonholonomic systems*, Mat. Sb. 22 (1901).
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from ..eom import Auxiliary, EquationsOfMotion
from ...errors import FormNotApplicable
from .base import (
    Formalism,
    Reduction,
    symbolic_solve,
    partition,
    project_rows,
    split_rows,
    transpose_times,
    vanishing,
)

__all__ = ["Shulgin", "Coefficients", "coefficients"]

PRINT_MAX_OPS = 300   # T* is kept in extras (and printed) only below this size (count_ops)
NOTE_MAX_OPS = 200    # dependent-velocity relations are printed only below this size
EXPLICIT_FACTOR, EXPLICIT_FLOOR = 2, 30   # budget of the explicit A_aj, A_a0 (operations)


def _check_linear(dyn, rows) -> None:
    qd = set(dyn.qd)
    for r in rows:
        if r.order == 2:
            raise FormNotApplicable(
                f"shulgin: constraint '{r.name}' is of second order (it contains accelerations); "
                "Shulgin's equations need velocity-level constraints: use --form maggi or "
                "--form appell (or lagrange1)")
        if r.order == 1 and any(set(se.sympify(g).free_symbols) & qd for g in r.G):
            raise FormNotApplicable(
                f"shulgin: the nonholonomic constraint '{r.name}' ({r.velocity} = 0) is not linear in "
                "the velocities, so the dependent velocities are not x_a' = A x_j' + A_0; use "
                "--form maggi or --form appell (Chetaev's rule), or lagrange1")


def _velocity_bias(dyn, r):
    """``b`` of the velocity-level constraint ``G x' + b = 0``."""
    if r.order == 0:
        return se.diff(r.position, dyn.t)
    return se.sympify(r.velocity).subs({v: se.Integer(0) for v in dyn.qd})


class Coefficients:
    """Shulgin's coefficients (1.61) ``x_a' = sum_j A_aj x_j' + A_a0`` and his operators
    ``E_j = d/dx_j + sum_a A_aj d/dx_a``, ``E_0 = d/dt + sum_a A_a0 d/dx_a``.

    Attributes
    ----------
    dependent, independent : list of int
        Coordinate indices (``a`` and ``j``).
    A : dict int -> list
        ``A[a][c]`` is ``A_aj`` for the c-th independent coordinate ``j``.
    A0 : dict int -> se.Basic
    auxiliaries : tuple of Auxiliary
        Empty when the coefficients are explicit expressions.  Otherwise ``A_aj`` and
        ``A_a0`` are symbols ``A[a,j]``, ``A0[a]`` and *partials* maps each of them to its
        partial derivatives (symbols ``dA[a,j]/dx``, by coordinate or ``t``); the operators
        apply the chain rule through them.
    """

    def __init__(self, dyn, dependent, independent, A, A0, partials=None, auxiliaries=()):
        self.q, self.qd, self.t = dyn.q, dyn.qd, dyn.t
        self.dependent, self.independent = dependent, independent
        self.A, self.A0, self.auxiliaries = A, A0, auxiliaries
        # (variable, {a: coefficient of d/dx_a}) of E_j for each independent j, and of E_0
        self._ops = [(self.q[j], {a: A[a][c] for a in dependent if A[a][c] != 0})
                     for c, j in enumerate(independent)]
        self._op0 = (self.t, {a: A0[a] for a in dependent if A0[a] != 0})
        # the operators applied to the coefficient symbols themselves (first derivatives)
        partials = partials or {}
        self._chain = [{s: self._combine(d, op) for s, d in partials.items()} for op in self._ops]
        self._chain0 = {s: self._combine(d, self._op0) for s, d in partials.items()}

    def _combine(self, derivatives: dict, op):
        variable, coefficients = op
        out = derivatives.get(variable, se.Integer(0))
        for a, coefficient in coefficients.items():
            if self.q[a] in derivatives:
                out += coefficient * derivatives[self.q[a]]
        return out

    def _apply(self, f, op, chain: dict):
        variable, coefficients = op
        f = se.sympify(f)
        free = f.free_symbols
        out = se.diff(f, variable) if variable in free else se.Integer(0)
        for a, coefficient in coefficients.items():
            if self.q[a] in free:
                out += coefficient * se.diff(f, self.q[a])
        for s in free & chain.keys():
            out += se.diff(f, s) * chain[s]
        return out

    def E(self, f, c: int):
        """Shulgin's operator ``E_j`` for the c-th independent coordinate (of a function of
        ``x``, ``t``, the velocities and the coefficients, not of their derivatives)."""
        return self._apply(f, self._ops[c], self._chain[c])

    def E0(self, f):
        """``E_0 = d/dt + sum_a A_a0 d/dx_a``."""
        return self._apply(f, self._op0, self._chain0)

    def rate(self, f):
        """``d/dt`` along the constrained motion without the acceleration terms:
        ``E_0 f + sum_j x_j' E_j f``."""
        return self.E0(f) + sum((self.E(f, c) * self.qd[j] for c, j in enumerate(self.independent)),
                                se.Integer(0))

    @property
    def velocities(self) -> dict:
        """``{x_a': sum_j A_aj x_j' + A_a0}`` for the dependent ``a`` (1.61)."""
        return {self.qd[a]: sum((self.A[a][c] * self.qd[j] for c, j in enumerate(self.independent)
                                 if self.A[a][c] != 0), se.Integer(0)) + self.A0[a]
                for a in self.dependent}


def coefficients(dyn, rows, independent) -> Coefficients:
    """Solve the velocity-level *rows* for the dependent velocities (1.61).

    The dependent block ``G_D`` is inverted symbolically within a budget of
    ``max(EXPLICIT_FLOOR, EXPLICIT_FACTOR * size of the input)`` operations -- Shulgin's
    operators differentiate the coefficients, so explicit ones that grow (a chain whose k-th
    dependent velocity contains all the earlier ones) make the equations grow faster still.
    Beyond it the coefficients are auxiliary symbols (:func:`_implicit`).

    Returns
    -------
    Coefficients
    """
    dep, ind = partition(dyn, rows, independent)
    if not dep:
        return Coefficients(dyn, dep, ind, {}, {})
    k = len(ind)
    bias = [_velocity_bias(dyn, r) for r in rows]
    rheonomic = any(b != 0 for b in bias)
    K = [[r.G[a] for a in dep] for r in rows]
    Y = [[-r.G[j] for j in ind] + ([-b] if rheonomic else []) for r, b in zip(rows, bias)]
    size = count_ops([x for row in K + Y for x in row])
    X = symbolic_solve(K, Y, max(EXPLICIT_FLOOR, EXPLICIT_FACTOR * size))
    partials, aux = {}, ()
    if X is None:
        X, partials, aux = _implicit(dyn, dep, ind, K, Y)
    A = {a: X[i][:k] for i, a in enumerate(dep)}
    A0 = {a: X[i][k] if rheonomic else se.Integer(0) for i, a in enumerate(dep)}
    return Coefficients(dyn, dep, ind, A, A0, partials, aux)


def _implicit(dyn, dep, ind, K, Y):
    """The coefficients ``X = [A | A_0]`` as symbols defined by ``G_D X = -[G_I | b]`` (*K*,
    *Y*) and their partial derivatives by the derivatives of that system,
    ``G_D dX/dx = -d[G_I | b]/dx - (dG_D/dx) X``, for every coordinate ``x`` (and ``t``) the
    constraints depend on: one block-triangular system, solved numerically.

    Returns
    -------
    X : list of lists of se.Symbol
    partials : dict
        Symbol of X -> {variable: symbol of its partial derivative}.
    auxiliaries : tuple of one Auxiliary
    """
    coords = dyn.model.coordinates
    k, m, p = len(ind), len(dep), len(Y[0])
    names = [[f"A[{coords[a]},{coords[j]}]" for j in ind] + ([f"A0[{coords[a]}]"] if p > k else [])
             for a in dep]
    X = [[se.Symbol(name) for name in row] for row in names]
    free = set().union(*(se.sympify(x).free_symbols for row in K + Y for x in row))
    variables = [v for v in dyn.q + [dyn.t] if v in free]
    L, zero = len(variables), se.Integer(0)
    K_big = [list(row) + [zero] * (m * L) for row in K]
    Y_big = [list(row) for row in Y]
    symbols = [list(row) for row in X]
    partials = {x: {} for row in X for x in row}
    for s, v in enumerate(variables, 1):
        for i in range(m):
            K_big.append([se.diff(K[i][j], v) for j in range(m)] + [zero] * (m * (s - 1)) + list(K[i])
                         + [zero] * (m * (L - s)))
            Y_big.append([se.diff(y, v) for y in Y[i]])
            symbols.append([se.Symbol(f"d{names[i][c]}/d{v}") for c in range(p)])
            for c in range(p):
                partials[X[i][c]][v] = symbols[-1][c]
    meaning = ("Shulgin's coefficients A[a,j]" + (", A0[a]" if p > k else "") + " solve "
               "G_D [A | A0] = -[G_I | b] and their derivatives dA[a,j]/dx the derivative of that "
               "system, G_D dA/dx = -dG_I/dx - (dG_D/dx) A (solved numerically)")
    return X, partials, (Auxiliary(se.Matrix(symbols), se.Matrix(K_big), se.Matrix(Y_big), meaning),)


class Shulgin(Formalism):
    name = "shulgin"
    title = "Shulgin's equations in redundant coordinates (Voronets' terms for nonholonomic constraints)"
    citation = ("Shulgin 1958; Manglieva & Beknazarov 2022, (1.61)-(1.64) (A_a0 added for rheonomic "
                "constraints); Voronets 1901")

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        _check_linear(dyn, ideal)
        co = coefficients(dyn, ideal, independent)
        qd, n = dyn.qd, dyn.n
        dep, ind = co.dependent, co.independent
        k = len(ind)
        vsub = co.velocities
        V = se.zeros(n, k)
        w = se.zeros(n, 1)
        for c, j in enumerate(ind):
            V[j, c] = 1
        for a in dep:
            for c in range(k):
                V[a, c] = co.A[a][c]
            w[a, 0] = co.rate(vsub[qd[a]])  # x_a'' = sum_j A_aj x_j'' + w_a along the motion
        red = Reduction(dep, ind, V, w, co.auxiliaries)
        T = se.sympify(dyn.T)
        voronets = {}
        if not dep:
            # T* = T and E_j = d/dx_j: (1.64) is Lagrange's equations for T, whose velocity
            # terms d/dt dT/dx_j' - dT/dx_j (without accelerations) the kernel holds as h
            Tstar, mass, c_vec = T, dyn.M, dyn.h
        else:
            Tstar = T.subs(vsub)
            P = [se.diff(Tstar, qd[j]) for j in ind]
            mass = se.zeros(k, k)
            for a in range(k):
                for b in range(a, k):
                    mass[a, b] = se.diff(P[a], qd[ind[b]])
                    mass[b, a] = mass[a, b]
            # Voronets' terms W_bj, dropped where they vanish identically
            terms = {}
            for b in dep:
                for c in range(k):
                    parts = []
                    for i in range(k):
                        parts.append(co.E(co.A[b][c], i) * qd[ind[i]])
                        parts.append(-co.E(co.A[b][i], c) * qd[ind[i]])
                    parts += [co.E0(co.A[b][c]), -co.E(co.A0[b], c)]
                    terms[b, c] = [x for x in parts if x != 0]
            keys = list(terms)
            zero = vanishing(dyn, [terms[key] for key in keys], auxiliaries=co.auxiliaries)
            voronets = {key: sum(terms[key], se.Integer(0)) for key, z in zip(keys, zero) if not z}
            p = {b: se.diff(T, qd[b]).subs(vsub) for b in {key[0] for key in voronets}}
            c_vec = se.zeros(k, 1)
            for c in range(k):
                # d/dt along the constrained motion, without the acceleration terms (those are A a)
                lhs = co.rate(P[c]) - co.E(Tstar, c)
                for b in dep:
                    if (b, c) in voronets:
                        lhs -= p[b] * voronets[b, c]
                c_vec[c, 0] = lhs  # free of dependent velocities: T*, A, A_0 and p_b are
        Qf = transpose_times(V, dyn.Q, n, k)
        G, gamma, B = project_rows(kept, red, n)
        if vsub:
            Qf = Qf.subs(vsub)
            G, gamma, B = G.subs(vsub), gamma.subs(vsub), B.subs(vsub)
        notes = self._notes(dyn, ideal, kept, co, voronets)
        extras = {"T*": Tstar} if count_ops([Tstar]) <= PRINT_MAX_OPS else {}
        coords = dyn.model.coordinates
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in ind),
            multipliers=tuple(f"lambda_{r.name}" for r in kept),
            constraint_names=tuple(r.name for r in kept), rows=tuple(rows),
            independent=tuple(coords[j] for j in ind),
            A_=mass, c_=c_vec, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=V, r_=w,
            auxiliaries=co.auxiliaries, extras_=extras, notes=tuple(notes),
            eliminated=tuple(r.name for r in ideal),
        )

    @staticmethod
    def _notes(dyn, ideal, kept, co, voronets):
        coords = dyn.model.coordinates
        notes = []
        if not ideal:
            notes.append("no ideal constraint to eliminate: E_j = d/dx_j, T* = T (Lagrange II in "
                         "the model's coordinates)")
        else:
            notes.append("independent velocities: " + ", ".join(coords[j] + "'" for j in co.independent)
                         + "; dependent velocities eliminated by " + ", ".join(r.name for r in ideal))
            vsub = co.velocities
            for a in co.dependent:
                rel = vsub[dyn.qd[a]]
                if count_ops([rel]) <= NOTE_MAX_OPS:
                    notes.append(f"{coords[a]}' = {rel}")
            if co.auxiliaries:
                notes.append("the coefficients A[a,j] are too large to write explicitly: auxiliary "
                             "symbols, as are their derivatives dA[a,j]/dx in E_j")
            if voronets:
                dep = sorted({coords[b] for b, _ in voronets})
                notes.append("Voronets' terms kept (non-integrable constraints), for the dependent "
                             "velocities of " + ", ".join(dep))
            else:
                notes.append("Voronets' terms vanish identically (integrable constraints): "
                             "equations (1.64)")
        if kept:
            notes.append("multipliers kept for the non-ideal constraints " + ", ".join(r.name for r in kept))
        return notes
