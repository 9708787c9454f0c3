"""The Boltzmann--Hamel equations: Lagrange's equations in quasi-velocities with Hamel's
(transpositional) coefficients.

With the speeds ``u = W q' + w`` (:mod:`.quasi`: the independent speeds ``p`` and the
constraints' own combinations ``sigma``, zero on the motion), ``q' = Phi u + phi0`` and
``T*(q, u, t) = T(q, Phi u + phi0, t)``, the equations for the independent speeds are

    d/dt dT*/du_r - sum_j Phi_jr dT*/dq_j + sum_k dT*/du_k (sum_s gamma^k_rs u_s + gamma^k_r0) = Pi_r,

    gamma^k_rs = sum_ij (dW_kj/dq_i - dW_ki/dq_j) Phi_jr Phi_is,
    gamma^k_r0 = sum_j Phi_jr (dW_kj/dt - dw_k/dq_j) + sum_ij (dW_kj/dq_i - dW_ki/dq_j) Phi_jr phi0_i,

``Pi_r = sum_j Phi_jr Q_j``; ``sigma = 0`` after the differentiation.  Derivation: multiply
Lagrange's equations by ``Phi_jr`` and use ``dT/dq'_j = sum_k dT*/du_k W_kj``,
``W Phi = I``; the ideal constraints' reactions drop out (``G Phi_p = 0``).  The Hamel
coefficients are the components of the transpositional relations
``d(delta pi_k) - delta(d pi_k) = sum gamma^k_rs delta pi_r d pi_s`` (Hamel 1904; Boltzmann 1902;
Yushkov 1999, ch. IV).  Non-ideal constraints keep their multipliers (as in Maggi's form).

Code names: ``u`` the speeds (declared ``[speeds]``, else the independent velocities),
``Phi``, ``phi0`` as above, ``A = d2T*/dp'^2``, ``c`` the rest of the left-hand side,
``Q_f = Pi``, ``extras["gamma"]`` the nonzero Hamel coefficients on the motion (small systems).

Sources: L. Boltzmann, Sitzungsber. Akad. Wiss. Wien 111 (1902); G. Hamel, Z. Math. Phys. 50
(1904); Yushkov 1999, ch. IV.
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from .base import Formalism
from .quasi import fold_trig, norm_reducer, quasi_equations

__all__ = ["BoltzmannHamel", "hamel_coefficients"]


def hamel_coefficients(dyn, ql):
    """``{(k, r, s): gamma^k_rs}`` (``s = None`` for ``gamma^k_r0``) for the independent ``r, s``
    and every speed ``k`` of the full set, on the motion; zeros left out."""
    n, kk = dyn.n, ql.basis.k
    W, w, Phi, phi0 = ql.basis.W, ql.basis.w, ql.Phi, ql.phi0
    out = {}
    reduce = norm_reducer(dyn.model) or (lambda x: x)
    for k in range(n):
        # curl[j][i] = dW_kj/dq_i - dW_ki/dq_j
        curl = [[se.diff(W[k, j], dyn.q[i]) - se.diff(W[k, i], dyn.q[j]) for i in range(n)] for j in range(n)]
        for r in range(kk):
            for s in list(range(kk)) + [None]:
                acc = se.Integer(0)
                for j in range(n):
                    if Phi[j, r] == 0:
                        continue
                    if s is None:
                        acc += Phi[j, r] * (se.diff(W[k, j], dyn.t) - se.diff(w[k, 0], dyn.q[j]))
                        vec = phi0
                        col = 0
                    else:
                        vec, col = Phi, s
                    for i in range(n):
                        if curl[j][i] != 0 and vec[i, col] != 0:
                            acc += curl[j][i] * Phi[j, r] * vec[i, col]
                if acc != 0:
                    acc = fold_trig(reduce(acc))
                    if acc != 0:
                        out[(k, r, s)] = acc
    return out


class BoltzmannHamel(Formalism):
    name = "boltzmann_hamel"
    title = "Boltzmann-Hamel equations (quasi-velocities, Hamel coefficients)"
    citation = ("Boltzmann 1902; Hamel 1904; Yushkov 1999, ch. IV: d/dt dT*/du_r - Phi_r . dT*/dq "
                "+ sum dT*/du_k gamma^k_rs u_s = Pi_r")

    def derive(self, dyn, rows, independent):
        return quasi_equations(self, dyn, rows, independent, hamel_coefficients, _term, _describe)


def _term(ql, gamma, r):
    """``sum_k dT*/du_k (sum_s gamma^k_rs u_s + gamma^k_r0)``."""
    speeds = ql.basis.symbols
    return sum((ql.dT[kk] * g * (speeds[s] if s is not None else 1)
                for (kk, rr, s), g in gamma.items() if rr == r), se.Integer(0))


def _describe(ql, gamma, labels):
    names = ql.basis.names
    shown = {f"gamma^{labels[kk]}_{names[r]},{names[s] if s is not None else 0}": g
             for (kk, r, s), g in gamma.items()}
    extras = {}
    if shown and count_ops(list(shown.values())) <= 300:
        extras["Hamel coefficients"] = "; ".join(f"{key} = {val}" for key, val in shown.items())
    return extras, ["T* = T with q' = Phi u + phi0 (u: the speeds and the constraints' "
                    "combinations sigma, zero on the motion)"]
