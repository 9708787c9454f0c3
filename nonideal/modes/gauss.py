"""Generalized Gauss principle for systems with friction (Manglieva & Beknazarov 2022, section 2.2).

An independent numerical route to the accelerations, following Manglieva & Beknazarov's construction
rather than the saddle-point solve of the other forms:

1. the constraint forces ``lambda`` do not depend on friction: they are those of Gauss's
   problem without friction, ``min Z0 = 1/2 (q'' - M^-1 F)^T M (q'' - M^-1 F)`` subject to
   ``G q'' + gamma = 0`` (the ideal constraints, touching contacts' normal rows and sticking
   contacts' rows);
2. the *friction law of the system* turns ``lambda`` into the physical normal forces of the
   sliding contacts: ``lambda = (I - sum_c K_c s_c sigma_c mu_c e_c^T) N`` with
   ``K = (G M^-1 G^T)^-1 G M^-1 W^T`` (singular = Painleve's paradox), hence the friction
   forces ``F_c = -sigma_c mu_c N_c s_c`` and the friction part of the reaction
   ``R_tau = P sum_c W_c^T F_c``, ``P = I - G^T (G M^-1 G^T)^-1 G M^-1``;
3. the actual accelerations minimize Gauss's constraint with the friction forces included,
   ``Z = 1/2 (q'' - M^-1 (F + R_tau))^T M (q'' - M^-1 (F + R_tau))`` (2.21), subject to the
   same constraints.

Both quadratic programs are solved by the null-space method (QR of ``G^T``): a different
algorithm from the LU of the saddle-point matrix used elsewhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import qr

from ..errors import FormNotApplicable, PainleveParadox

__all__ = ["GaussResult", "gauss_accelerations", "gauss_minimize", "gauss_measure"]


@dataclass
class GaussResult:
    """Accelerations by the generalized Gauss principle and the pieces of the construction."""

    qdd: np.ndarray
    lam: np.ndarray               # constraint forces (friction independent), one per row
    normal: dict                  # physical normal force of each sliding contact
    friction_part: np.ndarray     # R_tau, shape (n_q,)
    Z: float                      # Gauss's measure at the minimum


def gauss_minimize(M: np.ndarray, force: np.ndarray, G: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """``argmin 1/2 (a - M^-1 f)^T M (a - M^-1 f)`` s.t. ``G a + gamma = 0`` (null-space method)."""
    m = G.shape[0]
    if m == 0:
        return np.linalg.solve(M, force)
    Q, R, piv = qr(G.T, pivoting=True)
    rank = int(np.sum(np.abs(np.diag(R)) > 1e-12 * max(1.0, abs(R[0, 0]))))
    Y, Z = Q[:, :rank], Q[:, rank:]
    # particular solution a_p = Y y with G Y y = -gamma (least squares in the range)
    a_p = Y @ np.linalg.lstsq(G @ Y, -gamma, rcond=None)[0]
    if Z.shape[1] == 0:
        return a_p
    # minimize over a = a_p + Z xi:  (Z^T M Z) xi = Z^T (f - M a_p)
    xi = np.linalg.solve(Z.T @ M @ Z, Z.T @ (force - M @ a_p))
    return a_p + Z @ xi


def gauss_measure(M: np.ndarray, force: np.ndarray, qdd: np.ndarray) -> float:
    """Gauss's constraint ``1/2 (a - M^-1 f)^T M (a - M^-1 f)``.  With coordinates without
    inertia (M singular, the accelerations still unique through the constraints) the
    least-squares M^-1 f is used: the measure is defined up to the massless directions, which
    it does not weigh."""
    try:
        free = np.linalg.solve(M, force)
    except np.linalg.LinAlgError:
        free = np.linalg.lstsq(M, force, rcond=None)[0]
    d = qdd - free
    return float(0.5 * d @ M @ d)


def _gauss_with_controls(M, F, G, gamma, B, controlled, t) -> GaussResult:
    """Gauss's principle with servo / quasi-ideal constraints (Yushkov 1999, ch. III: the force
    that enforces a program).  The controls ``u`` act along the given columns ``B_c``; for any u
    the motion minimizes Gauss's constraint with the force ``F + B_c u`` under the ideal rows,
    so ``q''(u) = a_0 + A u`` (one null-space solve per column); u is then the solution of the
    programs ``G_c q''(u) + gamma_c = 0`` (least norm if they leave it undetermined)."""
    ideal = [k for k in range(G.shape[0]) if k not in controlled]
    Gi, gi = G[ideal], gamma[ideal]
    Bc = B[:, controlled]
    a0 = gauss_minimize(M, F, Gi, gi)
    A = np.column_stack([gauss_minimize(M, Bc[:, j], Gi, np.zeros(len(ideal)))
                         for j in range(Bc.shape[1])])
    Gc, gc = G[controlled], gamma[controlled]
    u, *_ = np.linalg.lstsq(Gc @ A, -(Gc @ a0 + gc), rcond=None)
    qdd = a0 + A @ u
    force = F + Bc @ u
    lam = np.zeros(G.shape[0])
    lam[controlled] = u
    if ideal:
        lam[ideal] = np.linalg.lstsq(Gi.T, M @ qdd - force, rcond=None)[0]
    return GaussResult(qdd, lam, {}, np.zeros(len(F)), gauss_measure(M, force, qdd))


def gauss_accelerations(solver, t: float, q: np.ndarray, qd: np.ndarray, mode) -> GaussResult:
    """Accelerations at a state by the generalized Gauss principle (see the module docstring).

    Raises
    ------
    FormNotApplicable
        For servo / quasi-ideal constraints together with sliding contacts.
    PainleveParadox
        When the friction law of the system cannot be inverted.
    """
    from .types import SLIDE, SMOOTH

    kernel, ck = solver.kernel, solver.ck
    x = solver.input(t, q, qd)
    out = kernel.dynamics(x)
    cout = {k: np.array(v) if isinstance(v, np.ndarray) else v for k, v in ck(x).items()} if ck else None
    M, F = kernel.dense(out, "M"), out["F"].copy()
    layout = solver.layout(mode)
    sliding = [(c, cs) for c, (_, cs) in enumerate(mode.contacts) if cs.state in (SLIDE, SMOOTH)]
    controlled = [k for k, r in enumerate(layout)
                  if r.kind == "constraint" and kernel.rows[r.index].reaction_kind != "ideal"]
    if controlled and sliding:
        raise FormNotApplicable(
            "gauss: servo / quasi-ideal constraints together with sliding contacts are not "
            "covered by the generalized Gauss principle here -- use lagrange1")
    if layout:
        G, gamma, B = solver.assemble(mode, layout, out, cout)
    else:
        G, gamma = np.zeros((0, solver.n)), np.zeros(0)
    if controlled:
        return _gauss_with_controls(M, F, G, gamma, B, controlled, t)
    # 1. friction-free Gauss problem -> constraint forces
    a0 = gauss_minimize(M, F, G, gamma)
    lam = np.linalg.lstsq(G.T, M @ a0 - F, rcond=None)[0] if layout else np.zeros(0)
    if not sliding:
        return GaussResult(a0, lam, {}, np.zeros(solver.n), gauss_measure(M, F, a0))
    # 2. friction law of the system: lambda = A N  ->  N
    Minv_GT = np.linalg.solve(M, G.T)
    D = G @ Minv_GT
    A = np.eye(len(layout))
    shapes = {}
    for c, cs in sliding:
        o, d = ck.offsets[c], ck.dims[c]
        W = cout["W"][o:o + d]
        s = solver.friction_shape(c, cs, cout["U"][o:o + d])
        shapes[c] = (W, s)
        j = next(k for k, r in enumerate(layout) if r.kind == "normal" and r.index == c)
        Kc = np.linalg.solve(D, G @ np.linalg.solve(M, W.T @ s))
        A[:, j] -= cs.sigma * cout["mu"][c] * Kc
    try:
        N_vec = np.linalg.solve(A, lam)
    except np.linalg.LinAlgError:
        raise PainleveParadox("the friction law of the system cannot be inverted: the normal "
                              "forces of the sliding contacts are not determined by the "
                              "constraint forces (Painleve's paradox)", t) from None
    friction = np.zeros(solver.n)
    normal = {}
    for c, cs in sliding:
        j = next(k for k, r in enumerate(layout) if r.kind == "normal" and r.index == c)
        W, s = shapes[c]
        Fc = -cs.sigma * cout["mu"][c] * N_vec[j] * s
        friction += W.T @ Fc
        normal[ck.names[c]] = float(N_vec[j])
    # friction part of the split: P (sum W^T F)
    R_tau = friction - G.T @ np.linalg.solve(D, G @ np.linalg.solve(M, friction))
    # 3. Gauss with the friction forces included
    qdd = gauss_minimize(M, F + R_tau, G, gamma)
    return GaussResult(qdd, lam, normal, R_tau, gauss_measure(M, F + R_tau, qdd))
