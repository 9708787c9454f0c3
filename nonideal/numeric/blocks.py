"""Block structure of a symmetric matrix: solves and definiteness tests by independent blocks.

A system of many bodies that each move their own coordinates (free particles, particles
coupled only by forces) has a block-diagonal mass matrix: the coordinates fall into groups
that no entry of ``M`` couples.  Factoring each block costs O(sum k_b^3) instead of O(n_q^3)
(1000 free particles: 3000 blocks of one coordinate, microseconds instead of ~1 s per dense
Cholesky factorization).  The blocks come from the nonzero pattern of the symbolic matrix
(:attr:`~nonideal.equations.dynamics.Dynamics.mass_entries`), so they are the same at every
state.

* :func:`blocks_of` -- the groups of coordinates (connected components of the pattern);
* :class:`BlockSolver` -- ``M x = b`` by Cholesky per block, blocks of equal size batched;
* :func:`definite_above` -- whether every eigenvalue of a symmetric matrix exceeds a bound.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

__all__ = ["blocks_of", "BlockSolver", "definite_above", "BLOCKS_MIN_N"]

BLOCKS_MIN_N = 64
"""Below this many coordinates a mass matrix is factored whole (one LAPACK call is faster
than gathering blocks, and the results of small models stay those of the dense path)."""


def blocks_of(n: int, pattern: Iterable[tuple[int, int]]) -> list[np.ndarray]:
    """The groups of coordinates that no entry of the pattern couples.

    Parameters
    ----------
    n : int
        Size of the (square) matrix.
    pattern : iterable of (int, int)
        Positions ``(i, j)`` of its nonzero entries.

    Returns
    -------
    list of ndarray of int
        Sorted index arrays, one per block, in order of their first index; a coordinate
        without any entry is a block of its own.

    Examples
    --------
    >>> [b.tolist() for b in blocks_of(4, [(0, 0), (1, 3), (3, 1), (2, 2)])]
    [[0], [1, 3], [2]]
    """
    ij = np.array(list(pattern), dtype=np.intp).reshape(-1, 2)
    return _components(n, ij[:, 0], ij[:, 1])


def _components(n: int, rows: np.ndarray, cols: np.ndarray) -> list[np.ndarray]:
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    groups = np.split(order, cuts)
    groups.sort(key=lambda g: g[0])
    return groups


class BlockSolver:
    """``M x = b`` for a symmetric positive definite ``M`` with the block structure *blocks*.

    The blocks of equal size are gathered into one stacked array and factored by one batched
    Cholesky call (NumPy), so the cost is a few NumPy calls per block size.

    Parameters
    ----------
    n : int
    blocks : list of ndarray of int
        From :func:`blocks_of`.
    """

    def __init__(self, n: int, blocks: list[np.ndarray]):
        self.n = n
        self.blocks = blocks
        by_size: dict[int, list[np.ndarray]] = {}
        for b in blocks:
            by_size.setdefault(len(b), []).append(b)
        #: per block size k: the (count, k) index array of its blocks
        self.groups = [np.array(v, dtype=np.intp) for _, v in sorted(by_size.items())]

    def solve(self, M: np.ndarray, b: np.ndarray) -> np.ndarray | None:
        """``x`` with ``M x = b`` (*M* dense, shape (n, n); only its blocks are read), or
        None when a block is not positive definite (the caller then takes the dense path,
        which explains a singular matrix)."""
        x = np.empty(self.n)
        for idx in self.groups:
            k = idx.shape[1]
            rhs = b[idx]
            if k == 1:
                d = M[idx[:, 0], idx[:, 0]]
                if not np.all(d > 0):
                    return None
                x[idx[:, 0]] = rhs[:, 0] / d
                continue
            A = M[idx[:, :, None], idx[:, None, :]]
            try:
                L = np.linalg.cholesky(A)
            except np.linalg.LinAlgError:
                return None
            y = np.linalg.solve(L, rhs[:, :, None])
            x[idx] = np.linalg.solve(np.swapaxes(L, 1, 2), y)[:, :, 0]
        if not np.all(np.isfinite(x)):
            return None
        return x


def definite_above(A: np.ndarray, tol: float) -> bool:
    """Whether every eigenvalue of the symmetric matrix *A* exceeds *tol*: the Cholesky
    factorization of ``A - tol I`` exists (block by block when *A* has independent blocks).
    O(n^3) only for a dense *A*; a sufficient test that spares the eigen-decomposition of
    a regular matrix.

    Examples
    --------
    >>> definite_above(np.diag([2.0, 1.0]), 0.5), definite_above(np.diag([2.0, 0.1]), 0.5)
    (True, False)
    """
    n = A.shape[0]
    if n == 0:
        return True
    if n >= BLOCKS_MIN_N:
        blocks = _components(n, *np.nonzero(A))
        if len(blocks) > 1:
            shifted = A.copy()
            shifted[np.diag_indices(n)] -= tol
            return BlockSolver(n, blocks).solve(shifted, np.zeros(n)) is not None
    try:
        np.linalg.cholesky(A - tol * np.eye(n))
    except np.linalg.LinAlgError:
        return False
    return True
