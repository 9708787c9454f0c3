"""Coordinate partitioning of reduced forms: which velocities are dependent.

A reduced form (Maggi, Appell, Shulgin, Lagrange II) solves the constraints for *dependent*
velocities; near a configuration where that choice is singular, the exchange factors
``X = G_D^-1 G_I`` grow and another choice is better conditioned ("maxvol" partitioning).
"""

from __future__ import annotations

import numpy as np

__all__ = ["REPARTITION_GAIN", "better_partition", "exchange_factors"]


#: re-partition when exchanging one dependent for one independent coordinate would multiply
#: |det G_D| by more than this (the partition is then far from the best one at this state)
REPARTITION_GAIN = 4.0


def better_partition(Gi: np.ndarray, dep: list[int], gain: float = REPARTITION_GAIN) -> list[int] | None:
    """A better-conditioned choice of dependent coordinates for the rows ``Gi`` (m, n), or
    ``None`` when the current choice *dep* is good enough (every ``|X_ij| <= gain``).

    With ``X = G_D^-1 G_I`` the entry ``|X_ij|`` is the factor by which ``|det G_D|`` changes
    when dependent coordinate i and independent coordinate j are exchanged (Cramer's rule), and
    ``q'_D = -X q'_I`` on the constraint manifold: a large entry means the dependent velocities
    are large multiples of the independent ones and the reduced form loses digits to
    cancellation (the choice becomes singular where the motion has no component along an
    independent coordinate).  The current choice is kept while every ``|X_ij| <= gain``;
    otherwise exchanges of the largest entry are made until all are <= 1.05 (a locally
    maximal-volume choice, as in "maxvol" coordinate partitioning), so switching back needs
    the entries to grow again by ~``gain`` (hysteresis).
    """
    m, n = Gi.shape
    if m == 0:
        return None
    dep = list(dep)
    X = exchange_factors(Gi, dep)
    if X is not None and (X.size == 0 or float(np.max(np.abs(X))) <= gain):
        return None
    if X is None:
        from scipy.linalg import qr

        _, _, piv = qr(Gi, pivoting=True)
        dep = sorted(int(j) for j in piv[:m])
        X = exchange_factors(Gi, dep)
        if X is None:
            return dep
    for _ in range(4 * n):
        if X.size == 0:
            break
        i, j = np.unravel_index(int(np.argmax(np.abs(X))), X.shape)
        if abs(X[i, j]) <= 1.05:
            break
        ind = [c for c in range(n) if c not in dep]
        dep[i] = ind[j]
        dep.sort()
        X = exchange_factors(Gi, dep)
        if X is None:
            break
    return dep


def exchange_factors(Gi: np.ndarray, dep: list[int]) -> np.ndarray | None:
    """``G_D^-1 G_I`` (rows: dependent coordinates in the order of *dep*), ``None`` when
    ``G_D`` is singular or not square."""
    m, n = Gi.shape
    if len(dep) != m:
        return None
    ind = [c for c in range(n) if c not in dep]
    try:
        X = np.linalg.solve(Gi[:, dep], Gi[:, ind])
    except np.linalg.LinAlgError:
        return None
    return X if np.all(np.isfinite(X)) else None
