"""Maggi's equations: the dynamics projected on the possible velocities.

With independent velocities ``p`` (the velocities of the independent coordinates) and the
velocity basis ``V`` (``G V = 0``), ``q'' = V p' + w`` on the constraint manifold and

    V^T (M q'' + h - Q) = V^T B_kept mu,     i.e.    (V^T M V) p' + V^T (M w + h) = V^T Q + ...

The ideal constraints disappear (``V^T G^T = 0``, Suslov--Jourdain); non-ideal ones (servo,
quasi-ideal, sliding friction) keep their multipliers and equations ``G V p' + G w + gamma = 0``.
Valid for linear and nonlinear (Chetaev) nonholonomic constraints: ``V`` spans the null space
of ``d(phi)/dq'``.  ``w`` is obtained from the acceleration-level constraints, so ``V`` is
never differentiated.

Source: G. Maggi (1896); Yushkov 1999, ch. II sec. 2 (Maggi equations from Newton's law).
"""

from __future__ import annotations

import symengine as se

from ..eom import EquationsOfMotion
from .base import (
    Formalism,
    project_rows,
    quadratic_form,
    reduce_velocities,
    split_rows,
    transpose_times,
)

__all__ = ["Maggi"]


class Maggi(Formalism):
    name = "maggi"
    title = "Maggi equations (projection on the possible velocities)"
    citation = "Maggi 1896; Yushkov 1999, ch. II sec. 2"

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        red = reduce_velocities(dyn, ideal, independent)
        n, k = dyn.n, len(red.independent)
        A, MV = quadratic_form(red.V, dyn.M, n, k)
        Mw_h = se.zeros(n, 1)
        for i in range(n):
            Mw_h[i, 0] = dyn.h[i] + sum((dyn.M[i, j] * red.w[j, 0] for j in range(n) if red.w[j, 0] != 0),
                                        se.Integer(0))
        c = transpose_times(red.V, Mw_h, n, k)
        Qf = transpose_times(red.V, dyn.Q, n, k)
        G, gamma, B = project_rows(kept, red, n)
        coords = dyn.model.coordinates
        notes = []
        if ideal:
            notes.append("independent velocities: " + ", ".join(coords[j] + "'" for j in red.independent)
                         + "; eliminated: " + ", ".join(r.name for r in ideal))
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in red.independent),
            multipliers=tuple(f"lambda_{r.name}" for r in kept),
            constraint_names=tuple(r.name for r in kept), rows=tuple(rows),
            independent=tuple(coords[j] for j in red.independent),
            A_=A, c_=c, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=red.V, r_=red.w,
            auxiliaries=red.auxiliaries, extras_={"V": red.V}, notes=tuple(notes),
            eliminated=tuple(r.name for r in ideal),
        )
