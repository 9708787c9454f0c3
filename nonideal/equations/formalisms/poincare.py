"""The Poincaré--Chetaev--Rumyantsev equations in quasi-velocities, with the structure
coefficients of the speeds' vector fields.

The speeds (:mod:`.quasi`: the independent ``p``, the constraints' combinations ``sigma``)
define the vector fields ``X_a = sum_j Phi_ja d/dq_j`` (the columns of ``Phi = W^-1``) and, for
a rheonomic system, ``X_0 = d/dt + sum_j phi0_j d/dq_j``; ``q' = sum_a u_a X_a + X_0``.  Their
commutators define the structure coefficients (functions of ``q, t`` in general: Chetaev's
extension of Poincaré's Lie-group case, Rumyantsev's nonholonomic one)

    [X_a, X_b] = sum_k c^k_ab X_k,      [X_0, X_b] = sum_k c^k_0b X_k,
    c^k_ab = sum_m W_km sum_l (Phi_la dPhi_mb/dq_l - Phi_lb dPhi_ma/dq_l),

and with ``T*(q, u, t) = T(q, Phi u + phi0, t)`` the equations for the independent speeds are

    d/dt dT*/du_r - X_r(T*) - sum_{s,k} c^k_sr u_s dT*/du_k - sum_k c^k_0r dT*/du_k = Pi_r,

``Pi_r = sum_j Phi_jr Q_j`` (``-dV/dq`` included: ``X_r(V)`` is its potential part), ``sigma = 0``
after the differentiation.  The sums over ``k`` include the constraints' combinations: the
commutators of the independent fields leave the constraint distribution (the nonholonomic
terms).  ``c^k_rs = gamma^k_rs`` of Boltzmann--Hamel (:mod:`.hamel`); here they are computed
from the commutators of ``Phi``'s columns, not from the derivatives of ``W``.

Code names: ``X_a`` the columns of ``Phi``, ``c^k_ab`` in ``extras["structure coefficients"]``
(the nonzero ones with ``a < b`` on the motion, printed for small systems), ``A = d2T*/dp'^2``,
``c`` the rest of the left-hand side, ``Q_f = Pi``.

Sources: H. Poincaré, C. R. Acad. Sci. 132 (1901) 369-371; N. G. Chetaev (1927, 1928);
V. V. Rumyantsev (1994); Yushkov 1999, ch. IV sec. 4 and appendices B, F.
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from .base import Formalism
from .quasi import fold_trig, norm_reducer, quasi_equations

__all__ = ["PoincareChetaev", "structure_coefficients"]


def structure_coefficients(dyn, ql, on_motion: bool = True):
    """``{(k, a, b): c^k_ab}`` for the independent ``b`` and ``a`` over the independent speeds
    and ``None`` (the time field ``X_0``); ``k`` over the full set; zeros left out."""
    n, kk = dyn.n, ql.basis.k
    W, Phi, phi0 = ql.basis.W, ql.Phi, ql.phi0

    def field(a):
        return [phi0[m, 0] for m in range(n)] if a is None else [Phi[m, a] for m in range(n)]

    def bracket(a, b):
        Xa, Xb = field(a), field(b)
        out = []
        for m in range(n):
            e = se.Integer(0)
            if a is None:
                e += se.diff(Xb[m], dyn.t)
            for l in range(n):
                if Xa[l] != 0 and Xb[m] != 0:
                    e += Xa[l] * se.diff(Xb[m], dyn.q[l])
                if Xb[l] != 0 and Xa[m] != 0:
                    e -= Xb[l] * se.diff(Xa[m], dyn.q[l])
            out.append(e)
        return out

    out = {}
    reduce = norm_reducer(dyn.model) or (lambda x: x)
    for b in range(kk):
        for a in list(range(kk)) + [None]:
            if a == b:
                continue
            br = bracket(a, b)
            if all(x == 0 for x in br):
                continue
            for k in range(n):
                c = sum((W[k, m] * br[m] for m in range(n) if W[k, m] != 0 and br[m] != 0), se.Integer(0))
                if c != 0:
                    c = fold_trig(reduce(c))
                    if c != 0:
                        out[(k, a, b)] = c
    return out


class PoincareChetaev(Formalism):
    name = "poincare_chetaev"
    title = "Poincaré-Chetaev-Rumyantsev equations (quasi-velocities, structure coefficients)"
    citation = ("Poincaré 1901; Chetaev 1927; Rumyantsev 1994; Yushkov 1999, ch. IV sec. 4, app. B, F: "
                "d/dt dT*/du_r - X_r(T*) - sum c^k_sr u_s dT*/du_k = Pi_r")

    def derive(self, dyn, rows, independent):
        return quasi_equations(self, dyn, rows, independent, structure_coefficients, _term, _describe)


def _term(ql, coeff, r):
    """``- sum_{s,k} c^k_sr u_s dT*/du_k - sum_k c^k_0r dT*/du_k``."""
    speeds = ql.basis.symbols
    return -sum((c * (speeds[a] if a is not None else 1) * ql.dT[kk]
                 for (kk, a, b), c in coeff.items() if b == r), se.Integer(0))


def _describe(ql, coeff, labels):
    names = ql.basis.names
    shown = {f"c^{labels[kk]}_{names[a] if a is not None else 0},{names[b]}": val.subs(ql.on_motion)
             for (kk, a, b), val in coeff.items() if a is None or a < b}
    extras = {}
    if shown and count_ops(list(shown.values())) <= 400:
        extras["structure coefficients"] = "; ".join(f"{key} = {val}" for key, val in shown.items()) \
            + " (c^k_ba = -c^k_ab)"
    elif not shown:
        extras["structure coefficients"] = "all zero (the speeds' vector fields commute)"
    return extras, ["X_a: the columns of Phi, q' = Phi u + phi0; T* = T in the speeds"]
