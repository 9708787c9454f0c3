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
rheonomic constraints.  Seed 000 prints (1.61) without ``A_a0`` (scleronomic only), refers to
(1.43) for the constraints (1.58) and writes the dependent velocities as ``x_q``; the
equations here are derived, not copied.

Unknowns: the accelerations of the independent coordinates (the only accelerations in the
equations, from ``d/dt dT*/dx_j'``).  ``A = d2T*/dx_j'dx_i'``, ``c`` = the rest of the left-hand
side (velocity terms, with the Voronets terms), ``Q_f = Q_j + sum_a A_aj Q_a`` (``-dV/dx``
included), all with the dependent velocities eliminated.  ``R, r`` (back to every ``x''``) are
Maggi's ``V, w``.  Non-ideal constraints (servo, quasi-ideal, sliding friction) keep their
multipliers, projected as in Maggi's form.

Applies to constraints linear in the velocities whose dependent block is solved explicitly;
otherwise :class:`FormNotApplicable` points to ``maggi`` or ``appell``.

Sources: M. F. Shulgin, *On some differential equations of analytical dynamics and their
integration*, Tashkent 1958; Manglieva & Beknazarov 2022, (1.61)-(1.64); P. V. Voronets,
*On the equations of motion of nonholonomic systems*, Mat. Sb. 22 (1901).
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from ..eom import EquationsOfMotion
from ..errors import FormNotApplicable
from .base import (Formalism, _symbolic_solve, project_rows, reduce_velocities, split_rows,
                   transpose_times, vanishing)

__all__ = ["Shulgin"]

PRINT_MAX_OPS = 300   # T* is kept in extras (and printed) only below this size (count_ops)
NOTE_MAX_OPS = 200    # dependent-velocity relations are printed only below this size


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


class Shulgin(Formalism):
    name = "shulgin"
    title = "Shulgin's equations in redundant coordinates (Voronets' terms for nonholonomic constraints)"
    citation = ("Shulgin 1958; Manglieva & Beknazarov 2022, (1.61)-(1.64) (A_a0 added for rheonomic "
                "constraints); Voronets 1901")

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        _check_linear(dyn, ideal)
        # Shulgin needs the coefficients A_aj explicitly: a larger budget than the other forms
        red = reduce_velocities(dyn, ideal, independent, factor=12, floor=4000)
        if red.auxiliaries:
            raise FormNotApplicable(
                "shulgin: the constraints " + ", ".join(r.name for r in ideal) + " cannot be solved "
                "for the dependent velocities in closed form within the size budget (the explicit "
                "coefficients A_aj would blow up); Shulgin's operators E_j need them explicitly: use "
                "--form maggi or --form appell")
        q, qd, t = dyn.q, dyn.qd, dyn.t
        n = dyn.n
        dep, ind = red.dependent, red.independent
        k = len(ind)
        # A_aj are the dependent rows of V; A_a0 solves the same dependent block for -b
        A = {d: [red.V[d, c] for c in range(k)] for d in dep}
        A0 = {d: se.Integer(0) for d in dep}
        if dep:
            K = [[r.G[d] for d in dep] for r in ideal]
            Y = [[-_velocity_bias(dyn, r)] for r in ideal]
            if any(y[0] != 0 for y in Y):
                size = count_ops([x for row in K for x in row] + [y[0] for y in Y])
                X = _symbolic_solve(K, Y, max(4000, 12 * size))
                if X is None:
                    raise FormNotApplicable(
                        "shulgin: the rheonomic terms A_a0 of the constraints "
                        + ", ".join(r.name for r in ideal) + " are too large to write explicitly; "
                        "use --form maggi or --form appell")
                A0 = {d: X[i][0] for i, d in enumerate(dep)}
        vsub = {qd[d]: sum((A[d][c] * qd[ind[c]] for c in range(k) if A[d][c] != 0), se.Integer(0)) + A0[d]
                for d in dep}

        def E(f, c):
            out = se.diff(f, q[ind[c]])
            for d in dep:
                if A[d][c] != 0:
                    out += A[d][c] * se.diff(f, q[d])
            return out

        def E0(f):
            out = se.diff(f, t)
            for d in dep:
                if A0[d] != 0:
                    out += A0[d] * se.diff(f, q[d])
            return out

        T = se.sympify(dyn.T)
        Tstar = T.subs(vsub) if vsub else T
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
                    parts.append(E(A[b][c], i) * qd[ind[i]])
                    parts.append(-E(A[b][i], c) * qd[ind[i]])
                parts += [E0(A[b][c]), -E(A0[b], c)]
                terms[b, c] = [x for x in parts if x != 0]
        keys = list(terms)
        zero = vanishing(dyn, [terms[key] for key in keys]) if keys else []
        voronets = {key: sum(terms[key], se.Integer(0)) for key, z in zip(keys, zero) if not z}
        p = {b: se.diff(T, qd[b]).subs(vsub) for b in {key[0] for key in voronets}}
        c_vec = se.zeros(k, 1)
        for c in range(k):
            # d/dt along the constrained motion, without the acceleration terms (those are A a)
            rate = E0(P[c]) + sum((E(P[c], i) * qd[ind[i]] for i in range(k)), se.Integer(0))
            lhs = rate - E(Tstar, c)
            for b in dep:
                if (b, c) in voronets:
                    lhs -= p[b] * voronets[b, c]
            c_vec[c, 0] = lhs  # free of dependent velocities: T*, A, A_0 and p_b are
        Qf = transpose_times(red.V, dyn.Q, n, k)
        G, gamma, B = project_rows(kept, red, n)
        if vsub:
            Qf = Qf.subs(vsub)
            G, gamma, B = G.subs(vsub), gamma.subs(vsub), B.subs(vsub)
        notes = self._notes(dyn, ideal, kept, red, vsub, voronets)
        extras = {"T*": Tstar} if count_ops([Tstar]) <= PRINT_MAX_OPS else {}
        coords = dyn.model.coordinates
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in ind),
            multipliers=tuple(f"lambda_{r.name}" for r in kept),
            constraint_names=tuple(r.name for r in kept), rows=tuple(rows),
            independent=tuple(coords[j] for j in ind),
            A_=mass, c_=c_vec, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=red.V, r_=red.w,
            extras_=extras, notes=tuple(notes), eliminated=tuple(r.name for r in ideal),
        )

    @staticmethod
    def _notes(dyn, ideal, kept, red, vsub, voronets):
        coords = dyn.model.coordinates
        notes = []
        if not ideal:
            notes.append("no ideal constraint to eliminate: E_j = d/dx_j, T* = T (Lagrange II in "
                         "the model's coordinates)")
        else:
            notes.append("independent velocities: " + ", ".join(coords[j] + "'" for j in red.independent)
                         + "; dependent velocities eliminated by " + ", ".join(r.name for r in ideal))
            for d in red.dependent:
                rel = vsub[dyn.qd[d]]
                if count_ops([rel]) <= NOTE_MAX_OPS:
                    notes.append(f"{coords[d]}' = {rel}")
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
