"""Lagrange's equations of the first kind (with multipliers), in the model's own coordinates.

    d/dt dT/dq' - dT/dq = Q + sum_k B_k lambda_k,        G q'' + gamma = 0

Every constraint keeps its multiplier ``lambda_k`` and its reaction direction ``B_k``
(``B_k = df_k/dq`` for an ideal holonomic constraint, ``d(phi_k)/dq'`` for an ideal
nonholonomic one by Chetaev's rule, the given direction for a servo-constraint,
``adj(A) df/dq`` for a quasi-ideal one, whose multiplier is then ``mu`` with the paper's
``lambda = det(A) mu``).  In redundant (e.g. Cartesian) coordinates these are
the equations of Manglieva & Beknazarov 2022, (1.18)/(1.53) and of Yushkov 1999, ch. I section 2; in generalized
coordinates with nonholonomic constraints they are Routh's equations with multipliers.

Code names: ``A = M`` (mass matrix), ``c = h`` (velocity terms of the Lagrange operator),
``Q_f = Q`` (active forces, ``-dV/dq`` included).
"""

from __future__ import annotations

import symengine as se

from ..dynamics import ConstraintRow, Dynamics
from ..eom import EquationsOfMotion
from .base import Formalism

__all__ = ["Lagrange1"]


def lagrange1_equations(dyn: Dynamics, rows: list[ConstraintRow]):
    """``(A, c, Q_f, B, G, gamma)`` of Lagrange I for *rows*."""
    n, m = dyn.n, len(rows)
    B = se.zeros(n, m)
    G = se.zeros(m, n)
    gamma = se.zeros(m, 1)
    for i, r in enumerate(rows):
        for j in range(n):
            B[j, i] = r.B[j]
            G[i, j] = r.G[j]
        gamma[i, 0] = r.gamma
    Q = se.Matrix(dyn.Q)
    return dyn.M, dyn.h, Q, B, G, gamma


def mass_pattern(dyn: Dynamics) -> dict[int, list[int]]:
    """The nonzero columns of each row of the mass matrix, ``{i: [j, ...]}``."""
    pattern: dict[int, list[int]] = {}
    for i, j in sorted(dyn.mass_entries):
        pattern.setdefault(i, []).append(j)
    return pattern


class Lagrange1(Formalism):
    name = "lagrange1"
    title = "Lagrange equations of the first kind (with multipliers)"
    citation = ("Yushkov 1999, ch. I sec. 2; Manglieva & Beknazarov 2022, (1.18), (1.53), (2.8); "
                "Chetaev's rule for nonlinear nonholonomic constraints")

    def derive(self, dyn, rows, independent):
        A, c, Q, B, G, gamma = lagrange1_equations(dyn, rows)
        n = dyn.n
        names = tuple(f"lambda_{r.name}" for r in rows)
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(s.name for s in dyn.qdd), multipliers=names,
            constraint_names=tuple(r.name for r in rows), rows=tuple(rows),
            independent=tuple(dyn.model.coordinates),
            A_=A, c_=c, Qf_=Q, B_=B, G_=G, gamma_=gamma, R_=se.eye(n), r_=se.zeros(n, 1),
            structure_={"A_": mass_pattern(dyn)},
        )
