"""Kane's equations in the generalized speeds: ``F_r + F_r* = 0``.

With the independent speeds ``p`` (the model's ``[speeds]``, or the independent velocities)
and the partial velocities ``Phi_p`` (:mod:`.quasi`: ``q' = Phi_p p + phi0`` on the
constraints, ``q'' = Phi_p p' + r``), Kane's equations for ``r = 1..k`` are

    F_r + F_r* = 0,     F_r = sum_j Phi_jr Q_j,     F_r* = -sum_j Phi_jr (M q'' + h)_j,

where ``Q`` are the generalized active forces (``-dV/dq`` included) and ``M q'' + h`` is the
Lagrange operator ``d/dt dT/dq' - dT/dq`` -- the generalized inertia forces of the bodies,
``sum m a . dv/dq'_j`` (Kane & Levinson 1985, sec. 5.4 (F_r) and 5.6 (F_r*); ch. 6 for the
dynamical equations, and sec. 4.4 for the nonholonomic partial velocities).  Dependent speeds
(the constraints' own combinations of the velocities) never appear: the ideal constraints'
reactions have no part along the partial velocities.  Non-ideal constraints (servo,
quasi-ideal, sliding friction) keep their multipliers as in Maggi's form.

Code names: ``A = Phi_p^T M Phi_p`` (the coefficients of the speed derivatives in ``-F_r*``),
``c = Phi_p^T (M r + h)``, ``Q_f = F_r``, ``R = Phi_p``, ``r`` as above; the unknowns are the
speed derivatives ``p'``.  Everything is written in the speeds; the speeds themselves are
evaluated from the state.  When ``Phi_p`` would be too large to write explicitly its entries
are auxiliary symbols solved numerically (the equations then stay in the velocities).

Source: T. R. Kane & D. A. Levinson, *Dynamics: Theory and Applications*, McGraw-Hill 1985.
"""

from __future__ import annotations

import symengine as se

from ..eom import EquationsOfMotion
from .base import Formalism, project_rows, quadratic_form, split_rows, transpose_times
from .folding import ADJUGATE_MAX, foldable
from .quasi import Reduced, fold_matrix, norm_reducer, partial_velocities

__all__ = ["Kane"]


class Kane(Formalism):
    name = "kane"
    title = "Kane's equations (generalized speeds)"
    citation = ("Kane & Levinson 1985, ch. 5-6: F_r + F_r* = 0, F_r = Phi_p^T Q, "
                "F_r* = -Phi_p^T (M q'' + h) (Phi_p: partial velocities)")

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        pv = partial_velocities(dyn, ideal, independent, self.name, self.speed_order)
        basis, Phi, r, subs, aux = pv.basis, pv.Phi, pv.r, pv.subs, pv.auxiliaries
        n, k = dyn.n, basis.k
        A, _ = quadratic_form(Phi, dyn.M, n, k)
        Mr_h = se.zeros(n, 1)
        for i in range(n):
            Mr_h[i, 0] = dyn.h[i] + sum((dyn.M[i, j] * r[j, 0] for j in range(n) if r[j, 0] != 0), se.Integer(0))
        c = transpose_times(Phi, Mr_h, n, k)
        Qf = transpose_times(Phi, dyn.Q, n, k)
        G, gamma, B = project_rows(kept, Reduced(Phi, r), n)
        if subs:
            reduce = norm_reducer(dyn.model)
            # a large system that is still folded (Euler parameters, small entries) is expanded first:
            # its powers of |e|^2 cancel term by term
            big = [M_.subs(subs) for M_ in (A, c, Qf, Phi, r, G, gamma, B)]
            A, c, Qf, Phi, r, G, gamma, B = [
                fold_matrix(M_.applyfunc(se.expand) if n > ADJUGATE_MAX and foldable(M_, n, reduce) else M_, reduce, n)
                for M_ in big]
            aux = basis.auxiliaries()
        notes = [basis.note()]
        if ideal:
            notes.append("eliminated (no part along the partial velocities): "
                         + ", ".join(r_.name for r_ in ideal))
        extras = {}
        from ..dynamics import count_ops
        if subs and count_ops(list(Phi)) <= 200:
            extras["partial velocities Phi_p"] = Phi
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=basis.unknowns, multipliers=tuple(f"lambda_{r_.name}" for r_ in kept),
            constraint_names=tuple(r_.name for r_ in kept), rows=tuple(rows),
            independent=basis.names, A_=A, c_=c, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=Phi, r_=r,
            auxiliaries=aux, extras_=extras, notes=tuple(notes),
            eliminated=tuple(r_.name for r_ in ideal), speeds=basis.names if basis.declared else (),
        )
