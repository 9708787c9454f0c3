"""The Gibbs--Appell equations: derivatives of the acceleration energy in the independent accelerations.

With the ideal constraints solved for the dependent velocities (``reduce_velocities``), every
acceleration compatible with the constraints is ``q'' = V p' + w``, where ``p'`` are the
accelerations of the independent coordinates (symbols named like their ``q''``).  The
acceleration energy ``S`` of the kernel (genuine ``sum m a^2/2 + ...`` from the bodies, or
from Appell's identity ``dS/dq'' = d/dt dT/dq' - dT/dq`` for a kinetic energy given as an
expression) becomes, after this substitution, ``S'(p')`` -- the acceleration energy "composed
with the constraints" of Manglieva & Beknazarov 2022 -- and the equations are

    dS'/dp'_j = Pi_j + sum_k B_jk mu_k,          Pi = V^T Q,

for the independent ``j``.  ``S'`` is quadratic in ``p'``: ``A`` is its Hessian and ``c`` its
gradient at ``p' = 0``, both obtained by differentiating ``S'`` (SymEngine), not by
projecting the mass matrix.  Ideal constraints (holonomic, linear or nonlinear nonholonomic
by Chetaev's rule) disappear; non-ideal ones (servo, quasi-ideal, sliding friction) keep
their multipliers and rows ``G V p' + G w + gamma = 0`` exactly as in Maggi's form
(``project_rows``).

With declared ``[speeds]`` the quasi-velocities are the speeds (Appell's own use for a rigid
body: the body components of its angular velocity): ``q'' = Phi p' + r`` with the partial
velocities ``Phi`` of :func:`~.quasi.partial_velocities`, ``S'(p')`` written in the speeds and
``Pi = Phi^T Q`` -- a rigid body prints Euler's equations.  When ``Phi`` is too large to write
explicitly, the accelerations of the independent coordinates are taken as above.

Code names: ``S`` in ``extras`` is ``S'`` (printed when small), ``A = d2S'/dp'2``,
``c = dS'/dp'|_{p'=0}``, ``Q_f = Pi = V^T Q`` (generalized forces of the quasi-velocities).

Sources: P. Appell, C. R. Acad. Sci. 129 (1899) 317-320, 423-427, 459-460 and J. reine angew.
Math. 121 (1900) 310-319; J. W. Gibbs (1879); Manglieva & Beknazarov 2022, (1.65) (there with
the friction forces ``(R^r_j)'``; here the non-ideal rows).
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from ..eom import EquationsOfMotion
from .base import Formalism, project_rows, reduce_velocities, split_rows, transpose_times
from .folding import foldable
from .quasi import ADJUGATE_MAX, Reduced, fold_matrix, norm_reducer, partial_velocities

__all__ = ["Appell", "reduced_acceleration_energy"]

PRINT_MAX_OPS = 300  # S' is kept in extras (and printed) only below this size (count_ops)


def reduced_acceleration_energy(dyn, red):
    """``S'(p')``: the kernel's acceleration energy with ``q''_d = sum_c V_dc p'_c + w_d``.

    The independent accelerations are their own ``p'`` (``V`` has unit rows there and ``w``
    zeros), so only the dependent ones are substituted.
    """
    p = [dyn.qdd[j] for j in red.independent]
    subs = {}
    for d in red.dependent:
        acc = sum((red.V[d, c] * p[c] for c in range(len(p)) if red.V[d, c] != 0), se.Integer(0))
        subs[dyn.qdd[d]] = acc + red.w[d, 0]
    S = se.sympify(dyn.S)
    return S.subs(subs) if subs else S


class Appell(Formalism):
    name = "appell"
    title = "Gibbs-Appell equations (acceleration energy)"
    citation = ("Appell 1899, 1900; Gibbs 1879; Manglieva & Beknazarov 2022, (1.65): "
                "dS'/dp'_j = Q'_j (+ reactions of the non-ideal constraints)")

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        if dyn.model.speeds:
            pv = partial_velocities(dyn, ideal, independent, self.name, self.speed_order)
            if pv.subs:   # explicit: the equations in the declared speeds
                return self._in_speeds(dyn, rows, ideal, kept, pv)
        red = reduce_velocities(dyn, ideal, independent)
        n, k = dyn.n, len(red.independent)
        p = [dyn.qdd[j] for j in red.independent]
        S = reduced_acceleration_energy(dyn, red)
        grad = [se.diff(S, pj) for pj in p]
        zero = {pj: se.Integer(0) for pj in p}
        c = se.zeros(k, 1)
        A = se.zeros(k, k)
        for i in range(k):
            c[i, 0] = grad[i].subs(zero)
            for j in range(i, k):
                A[i, j] = se.diff(grad[i], p[j])
                A[j, i] = A[i, j]
        Qf = transpose_times(red.V, dyn.Q, n, k)
        if red.explicit:   # high trigonometric powers that cancel folded (small systems only)
            A, c, Qf = (fold_matrix(M_, norm_reducer(dyn.model), n) for M_ in (A, c, Qf))
        G, gamma, B = project_rows(kept, red, n)
        coords = dyn.model.coordinates
        notes = ["quasi-accelerations p' = " + ", ".join(coords[j] + "''" for j in red.independent)
                 + " (accelerations of the independent coordinates)"]
        if ideal:
            notes.append("S' = S with the dependent accelerations "
                         + ", ".join(coords[d] + "''" for d in red.dependent)
                         + " eliminated by the constraints " + ", ".join(r.name for r in ideal))
        if kept:
            notes.append("multipliers kept for the non-ideal constraints " + ", ".join(r.name for r in kept))
        extras = {}
        if count_ops([S]) <= PRINT_MAX_OPS:
            extras["S"] = S
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in red.independent),
            multipliers=tuple(f"lambda_{r.name}" for r in kept),
            constraint_names=tuple(r.name for r in kept), rows=tuple(rows),
            independent=tuple(coords[j] for j in red.independent),
            A_=A, c_=c, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=red.V, r_=red.w,
            auxiliaries=red.auxiliaries, extras_=extras, notes=tuple(notes),
            eliminated=tuple(r.name for r in ideal),
        )

    def _in_speeds(self, dyn, rows, ideal, kept, pv):
        """The Gibbs--Appell equations in the declared speeds (see the module docstring)."""
        basis, Phi, r = pv.basis, pv.Phi, pv.r
        n, k = dyn.n, basis.k
        p = basis.accelerations()
        subs = {dyn.qdd[i]: sum((Phi[i, c] * p[c] for c in range(k) if Phi[i, c] != 0), se.Integer(0)) + r[i, 0]
                for i in range(n)}
        S = se.sympify(dyn.S).subs(subs).subs(pv.subs)
        grad = [se.diff(S, pj) for pj in p]
        zero = {pj: se.Integer(0) for pj in p}
        A, c = se.zeros(k, k), se.zeros(k, 1)
        for i in range(k):
            c[i, 0] = grad[i].subs(zero)
            for j in range(i, k):
                A[i, j] = A[j, i] = se.diff(grad[i], p[j])
        Qf = transpose_times(Phi, dyn.Q, n, k)
        G, gamma, B = project_rows(kept, Reduced(Phi, r), n)
        reduce = norm_reducer(dyn.model)
        # expanded first: S in the speeds carries products that cancel term by term (a fold of
        # the unexpanded expression would exceed its size budget)
        A, c, Qf, R, rr, G, gamma, B = [fold_matrix(M_.subs(pv.subs).applyfunc(se.expand) if foldable(M_, n, reduce)
                                                    else M_.subs(pv.subs), reduce, n)
                                        for M_ in (A, c, Qf, Phi, r, G, gamma, B)]
        notes = [basis.note() + " (the quasi-velocities; p' their derivatives)"]
        if ideal:
            notes.append("eliminated (no part along the partial velocities): " + ", ".join(r_.name for r_ in ideal))
        if kept:
            notes.append("multipliers kept for the non-ideal constraints " + ", ".join(r_.name for r_ in kept))
        extras = {}
        S_shown = fold_matrix(se.Matrix([[S - S.subs(zero)]]), reduce, n)[0, 0]   # up to terms without p'
        if count_ops([S_shown]) <= PRINT_MAX_OPS:
            extras["S"] = S_shown
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=basis.unknowns, multipliers=tuple(f"lambda_{r_.name}" for r_ in kept),
            constraint_names=tuple(r_.name for r_ in kept), rows=tuple(rows), independent=basis.names,
            A_=A, c_=c, Qf_=Qf, B_=B, G_=G, gamma_=gamma, R_=R, r_=rr,
            auxiliaries=basis.auxiliaries(), extras_=extras, notes=tuple(notes),
            eliminated=tuple(r_.name for r_ in ideal), speeds=basis.names,
        )
