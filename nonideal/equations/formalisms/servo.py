"""Béghin's equations for systems with servo-constraints (Appell 1911, servo-constraints).

A servo-constraint (Béghin 1922) is realized by reactions "of the second kind": control forces
along given directions ``D`` (``reaction = [...]`` in the model file), which do no work on the
displacements with ``D^T dq = 0`` -- the j extra conditions.  The kinetic energy and the active
forces are computed *without* the servo-constraints; then, with the ideal ("contact")
constraints eliminated by the possible velocities ``q' = V p + w`` (their multipliers Λ, M, ...
drop out, Suslov--Jourdain),

    V^T (M q'' + h - Q) = V^T D u,                                          (10)

together with the constraint equations and the r servo-constraints (3).  Eliminating the j
controls ``u`` from (10) leaves the ``n_dof - j`` control-free equations (12)

    E_l(q'', q', q, t) = 0,      l = 1 .. n_dof - j,

which with the r servo-constraints determine the motion when r = j (Béghin's count: r > j
impossible, r < j indeterminate).  The form's equations are (10) with the controls kept as
multipliers (so it solves like Maggi's form and gives the same accelerations); the control-free
equations (12) are listed as ``control_free_<l>`` (fraction-free elimination, the pivot on a
structurally non-zero entry of the projected control directions).  Without servo-constraints
(j = 0) the equations are Maggi's.

Code names: ``A = V^T M V`` (reduced mass matrix), ``c = V^T (M w + h)``, ``Q_f = V^T Q``,
``B = V^T D`` (projected control directions and other non-ideal reactions).
"""

from __future__ import annotations

from dataclasses import replace

import symengine as se

from .base import Formalism
from .maggi import Maggi

__all__ = ["Servo"]


def _eliminate(rows: list, cols: list[list]) -> list:
    """Fraction-free elimination of the unknowns whose coefficient columns are *cols* from the
    equations *rows* (``rows[i] + sum_c cols[c][i] u_c = 0``): returns the equations free of
    them (one fewer per eliminated unknown with a non-zero pivot)."""
    rows = list(rows)
    cols = [list(c) for c in cols]
    for c in range(len(cols)):
        pivot = next((i for i, x in enumerate(cols[c]) if se.expand(x) != 0), None)
        if pivot is None:
            continue
        p = cols[c][pivot]
        new_rows, new_cols = [], [[] for _ in cols]
        for i in range(len(rows)):
            if i == pivot:
                continue
            f = cols[c][i]
            new_rows.append(p * rows[i] - f * rows[pivot] if f != 0 else rows[i])
            for d in range(len(cols)):
                new_cols[d].append(p * cols[d][i] - f * cols[d][pivot] if f != 0 else cols[d][i])
        rows, cols = new_rows, new_cols
    return rows


class Servo(Formalism):
    name = "servo"
    title = "Béghin's equations with servo-constraints (reactions of the second kind)"
    citation = "Béghin 1922; Appell 1911, servo-constraints, eqs. (10), (12)"

    def derive(self, dyn, rows, independent):
        eom = Maggi().derive(dyn, rows, independent)
        servo = [j for j, r in enumerate(rows_kept(eom)) if r.reaction_kind == "servo"]
        k = eom.k
        a = [se.Symbol(u) for u in eom.unknowns]
        residual = [sum((eom.A_[i, j] * a[j] for j in range(k)), se.Integer(0)) + eom.c_[i, 0] - eom.Qf_[i, 0]
                    for i in range(k)]
        other = [j for j in range(len(eom.multipliers)) if j not in servo]
        mu = [se.Symbol(m) for m in eom.multipliers]
        for i in range(k):
            residual[i] -= sum((eom.B_[i, j] * mu[j] for j in other), se.Integer(0))
        cols = [[-eom.B_[i, j] for i in range(k)] for j in servo]
        free = _eliminate(residual, cols)
        extras = dict(eom.extras_)
        for ell, e in enumerate(free, 1):
            extras[f"control_free_{ell}"] = se.expand(e) if len(str(e)) < 4000 else e
        r = len(servo)
        names = [eom.constraint_names[j] for j in servo]
        notes = list(eom.notes)
        if servo:
            notes.append(f"servo-constraints {', '.join(names)} (r = {r}) with j = {r} control "
                         f"directions: determinate (Béghin: r = j); the {len(free)} control-free "
                         "equations (12) are listed as control_free_*; the controls are the "
                         "multipliers " + ", ".join(eom.multipliers[j] for j in servo))
        else:
            notes.append("no servo-constraint: Béghin's equations are Maggi's")
        reach = getattr(dyn, "servo_reach", {})
        for name in names:
            if name in reach and reach[name].order > 2:
                notes.append(f"the control of '{name}' acts through the dynamics: its row is the "
                             f"condition of dynamics, the program differentiated to order "
                             f"{reach[name].order} (Yushkov 1999, ch. IV)")
        return replace(eom, form=self.name, title=self.title, citation=self.citation,
                       extras_=extras, notes=tuple(notes))


def rows_kept(eom):
    """The rows whose multipliers the reduced form keeps, in the order of its multipliers."""
    by_name = {r.name: r for r in eom.rows}
    return [by_name[n] for n in eom.constraint_names]
