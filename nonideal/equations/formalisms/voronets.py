"""Voronets' equations: the nonholonomic constraints solved for the dependent velocities,
every coordinate kept; Chaplygin's equations as the special case.

The ideal constraints, linear in the velocities (holonomic ones at velocity level), are solved
for the dependent velocities (``D``; the independent ``I`` chosen as by ``[forms]
independent``):

    q'_D = sum_{i in I} a_Di(q, t) q'_i + a_D0(q, t).

With ``Theta(q, q'_I, t) = T`` with these substituted and ``P_D = (dT/dq'_D)`` likewise, the
equations for each independent ``i`` are (Voronets 1901, in Neimark & Fufaev 1967, ch. III
sec. 4 (4.3); rheonomic terms added)

    d/dt dTheta/dq'_i - dTheta/dq_i - sum_D a_Di dTheta/dq_D + sum_D P_D beta_Di
        = Q_i + sum_D a_Di Q_D,

    beta_Di = -d(a_Di)/dt + sum_{l in I} (da_Dl/dq_i + sum_E a_Ei da_Dl/dq_E) q'_l
              + da_D0/dq_i + sum_E a_Ei da_D0/dq_E,

``d(a_Di)/dt`` the derivative along the motion.  The dependent coordinates stay in the
equations (they are not cyclic in general); their accelerations follow from the constraints:
``R`` has the rows ``a_Di`` (unit rows for ``I``), ``r_D = d/dt(a_D q'_I + a_D0)`` without the
``q''_I`` terms.  Non-ideal constraints keep their multipliers as in Maggi's form.

**Chaplygin's equations** (Chaplygin 1897) hold when the system is a Chaplygin system: ``T``,
the constraints' coefficients ``a``, ``a_0`` and the generalized forces do not depend on the
dependent coordinates.  Then the ``dTheta/dq_D`` and ``a_Ei d/dq_E`` terms vanish and

    d/dt dTheta/dq'_i - dTheta/dq_i + sum_D P_D sum_{l in I} (da_Dl/dq_i - da_Di/dq_l) q'_l
        + sum_D P_D (da_D0/dq_i - da_Di/dt) = Q_i + sum_D a_Di Q_D,

a closed system in ``q_I`` alone.  A system that is not of Chaplygin's kind is refused
(:class:`FormNotApplicable`) naming the coordinate and what depends on it.

Code names: ``a`` (``A[D,i]``), ``a_0``, ``Theta``, ``P_D`` as above; ``A = d2Theta/dq'_I^2``,
``c`` the rest of the left-hand side, ``Q_f = Q_I + a^T Q_D``.

Sources: P. V. Voronets, Mat. Sb. 22 (1901) 659-686; S. A. Chaplygin, Mat. Sb. 20 (1897);
Ju. I. Neimark & N. A. Fufaev, *Dynamics of nonholonomic systems* (1967), ch. III.
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from ..eom import EquationsOfMotion
from ...errors import FormNotApplicable
from .base import Formalism, partition, project_rows, split_rows, symbolic_solve, vanishing
from .quasi import ADJUGATE_MAX, Reduced, fold_trig, velocity_rows

__all__ = ["Voronets", "Chaplygin"]


class Voronets(Formalism):
    name = "voronets"
    title = "Voronets equations (dependent velocities eliminated, all coordinates kept)"
    citation = ("Voronets 1901; Neimark & Fufaev 1967, ch. III: d/dt dTheta/dq'_i - dTheta/dq_i "
                "- a_Di dTheta/dq_D + P_D beta_Di = Q_i + a_Di Q_D")
    chaplygin = False

    def derive(self, dyn, rows, independent):
        ideal, kept = split_rows(rows)
        n = dyn.n
        coords = dyn.model.coordinates
        G, g = velocity_rows(dyn, ideal, self.name)
        dep, ind = partition(dyn, ideal, independent)
        m, k = len(dep), len(ind)
        if m:
            K = [[G[i][j] for j in dep] for i in range(m)]
            Y = [[-G[i][j] for j in ind] + [-g[i]] for i in range(m)]
            size = count_ops([x for row in K + Y for x in row])
            X = symbolic_solve(K, Y, max(4000, 4 * size))
            if X is None:
                raise FormNotApplicable(
                    f"the {self.name} form needs the dependent velocities written explicitly, and "
                    "they are too large to write; use shulgin (auxiliary coefficients) or maggi")
        else:
            X = []
        a = {dep[d]: [X[d][c] for c in range(k)] for d in range(m)}
        a0 = {dep[d]: X[d][k] for d in range(m)}
        if self.chaplygin:
            self._check_chaplygin(dyn, dep, a, a0)
        qd = dyn.qd
        elim = {qd[D]: sum((a[D][c] * qd[ind[c]] for c in range(k)), se.Integer(0)) + a0[D] for D in dep}
        T = se.sympify(dyn.T)
        Theta = T.subs(elim)
        P = {D: se.diff(T, qd[D]).subs(elim) for D in dep}
        Q = [se.sympify(x) for x in dyn.Q]
        lhs, rhs = [], []
        for c, i in enumerate(ind):
            e = dyn.dt(se.diff(Theta, qd[i])) - se.diff(Theta, dyn.q[i])
            if not self.chaplygin:
                e -= sum((a[D][c] * se.diff(Theta, dyn.q[D]) for D in dep), se.Integer(0))
            for D in dep:
                e += P[D] * self._beta(dyn, D, c, ind, dep, a, a0)
            lhs.append(e.subs(elim))
            rhs.append((Q[i] + sum((a[D][c] * Q[D] for D in dep), se.Integer(0))).subs(elim))
        acc = [dyn.qdd[i] for i in ind]
        fold = fold_trig if n <= ADJUGATE_MAX else (lambda x: x)   # large systems: as derived
        zero_acc = {x: se.Integer(0) for x in dyn.qdd}
        A = se.zeros(k, k)
        cvec = se.zeros(k, 1)
        Qf = se.zeros(k, 1)
        for r in range(k):
            for s in range(k):
                A[r, s] = fold(se.diff(lhs[r], acc[s]))
            cvec[r, 0] = fold(lhs[r].subs(zero_acc))
            Qf[r, 0] = fold(rhs[r])
        V = se.zeros(n, k)
        w = se.zeros(n, 1)
        for c, i in enumerate(ind):
            V[i, c] = 1
        for D in dep:
            for c in range(k):
                V[D, c] = a[D][c]
            w[D, 0] = dyn.dt(elim[qd[D]], with_acceleration=False).subs(elim)
        Gk, gam, B = project_rows(kept, Reduced(V, w), n)
        notes = []
        if ideal:
            notes.append("independent velocities: " + ", ".join(coords[j] + "'" for j in ind)
                         + "; eliminated: " + ", ".join(coords[D] + "'" for D in dep)
                         + " by " + ", ".join(r.name for r in ideal))
        extras = {}
        if m and count_ops(list(elim.values())) <= 200:
            extras["dependent velocities"] = "; ".join(f"{coords[D]}' = {fold(elim[qd[D]])}" for D in dep)
        if count_ops([Theta]) <= 300:
            extras["Theta"] = fold(Theta)
        return EquationsOfMotion(
            form=self.name, title=self.title, citation=self.citation, model=dyn.model,
            unknowns=tuple(coords[j] + "''" for j in ind),
            multipliers=tuple(f"lambda_{r.name}" for r in kept),
            constraint_names=tuple(r.name for r in kept), rows=tuple(rows),
            independent=tuple(coords[j] for j in ind), A_=A, c_=cvec, Qf_=Qf, B_=B, G_=Gk, gamma_=gam,
            R_=V, r_=w, extras_=extras, notes=tuple(notes), eliminated=tuple(r.name for r in ideal),
        )

    def _beta(self, dyn, D, c, ind, dep, a, a0):
        """Voronets' coefficient ``beta_Di`` (the module docstring), ``i = ind[c]``."""
        q, qd = dyn.q, dyn.qd
        i = ind[c]
        if self.chaplygin:
            out = se.diff(a0[D], q[i]) - se.diff(a[D][c], dyn.t)
            for l_, l in enumerate(ind):
                out += (se.diff(a[D][l_], q[i]) - se.diff(a[D][c], q[l])) * qd[l]
            return out
        out = -dyn.dt(a[D][c], with_acceleration=False)
        for l_, l in enumerate(ind):
            term = se.diff(a[D][l_], q[i]) + sum((a[E][c] * se.diff(a[D][l_], q[E]) for E in dep), se.Integer(0))
            out += term * qd[l]
        out += se.diff(a0[D], q[i]) + sum((a[E][c] * se.diff(a0[D], q[E]) for E in dep), se.Integer(0))
        return out

    def _check_chaplygin(self, dyn, dep, a, a0):
        coords = dyn.model.coordinates
        parts = [("the kinetic energy depends", [se.sympify(dyn.T)])]
        parts.append(("the constraints' coefficients of the independent velocities depend",
                      [x for D in dep for x in a[D]]))
        parts.append(("the constraints' free terms depend", [a0[D] for D in dep]))
        parts.append(("the generalized forces (potential included) depend", [se.sympify(x) for x in dyn.Q]))
        for D in dep:
            qD = dyn.q[D]
            for what, exprs in parts:
                derivs = [se.diff(e, qD) for e in exprs if qD in se.sympify(e).free_symbols]
                if not derivs:
                    continue
                if not all(vanishing(dyn, [[d] for d in derivs])):
                    raise FormNotApplicable(
                        f"the chaplygin form needs a Chaplygin system: {what} on the "
                        f"eliminated coordinate '{coords[D]}' (the dependent velocities eliminated are "
                        f"{', '.join(coords[E] + chr(39) for E in dep)}); use voronets, which keeps "
                        "that dependence, or choose other independent coordinates in [forms] independent")


class Chaplygin(Voronets):
    name = "chaplygin"
    title = "Chaplygin equations (Chaplygin system: eliminated coordinates absent)"
    citation = ("Chaplygin 1897; Neimark & Fufaev 1967, ch. III: d/dt dTheta/dq'_i - dTheta/dq_i "
                "+ P_D (da_Dl/dq_i - da_Di/dq_l) q'_l = Q_i + a_Di Q_D")
    chaplygin = True
