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
* :func:`definite_above` -- whether every eigenvalue of a symmetric matrix exceeds a bound
  (dense, or ``scipy.sparse``: :func:`definite_above_sparse`);
* :class:`SparseSaddle` -- the saddle-point matrix ``[[M, B], [G, 0]]`` of many coordinates as
  a ``scipy.sparse`` CSC matrix of fixed pattern, gathered from a flat buffer and factored by
  SuperLU (:func:`scipy.sparse.linalg.splu`);
* :func:`dependent_rows` -- which rows of a sparse ``G`` repeat the others, component by
  component.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from scipy.sparse import coo_matrix, csc_matrix, issparse
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

__all__ = ["blocks_of", "BlockSolver", "definite_above", "definite_above_sparse", "SparseSaddle",
           "dependent_rows", "row_groups", "BLOCKS_MIN_N"]

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
        self._gather = None

    @classmethod
    def of_pattern(cls, n: int, rows: np.ndarray, cols: np.ndarray) -> "BlockSolver":
        """The solver of a matrix given by the vector of its entries at ``(rows, cols)``
        (:meth:`solve_entries`)."""
        solver = cls(n, _components(n, rows, cols))
        where = {(int(i), int(j)): k for k, (i, j) in enumerate(zip(rows.tolist(), cols.tolist()))}
        zero = len(rows)   # the position of a structural zero: an appended 0.0
        solver._gather = [np.array([[[where.get((int(a), int(b)), zero) for b in blk] for a in blk]
                                    for blk in idx], dtype=np.intp).reshape(len(idx), idx.shape[1], idx.shape[1])
                          for idx in solver.groups]
        return solver

    def solve_entries(self, values: np.ndarray, b: np.ndarray, shift: float = 0.0) -> np.ndarray | None:
        """``x`` with ``(M - shift I) x = b``, *M* given by the vector *values* of its entries at
        the pattern of :meth:`of_pattern`; None when a block is not positive definite."""
        ext = np.append(np.asarray(values, dtype=float), 0.0)
        x = np.empty(self.n)
        for idx, gather in zip(self.groups, self._gather):
            A = ext[gather]
            if shift:
                A = A - shift * np.eye(idx.shape[1])
            x_blk = _cholesky_solve(A, b[idx])
            if x_blk is None:
                return None
            x[idx] = x_blk
        if not np.all(np.isfinite(x)):
            return None
        return x

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
            x_blk = _cholesky_solve(M[idx[:, :, None], idx[:, None, :]], rhs)
            if x_blk is None:
                return None
            x[idx] = x_blk
        if not np.all(np.isfinite(x)):
            return None
        return x


def _cholesky_solve(A: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """Batched ``A_b x_b = rhs_b`` by Cholesky (*A* shape (count, k, k), *rhs* (count, k)),
    or None when a block is not positive definite."""
    if A.shape[1] == 1:
        d = A[:, 0, 0]
        if not np.all(d > 0):
            return None
        return rhs / A[:, 0, :]
    try:
        L = np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        return None
    y = np.linalg.solve(L, rhs[:, :, None])
    return np.linalg.solve(np.swapaxes(L, 1, 2), y)[:, :, 0]


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


def definite_above_sparse(A, tol: float) -> bool:
    """:func:`definite_above` of a ``scipy.sparse`` symmetric matrix: Cholesky of ``A - tol I``
    block by block (the connected components of its pattern), never an n x n array unless a
    single block is that large."""
    A = A.tocoo()
    n = A.shape[0]
    if n == 0:
        return True
    keep = A.data != 0
    rows, cols = A.row[keep], A.col[keep]
    solver = BlockSolver.of_pattern(n, rows, cols)
    return solver.solve_entries(A.data[keep], np.zeros(n), shift=tol) is not None


class SparseSaddle:
    """A square matrix of fixed sparsity pattern whose entries are gathered from a flat buffer:
    the saddle-point matrix ``[[M, B], [G, 0]]`` of a mode with many coordinates.

    Parameters
    ----------
    s : int
        Size.
    rows, cols : ndarray of int
        Positions of the entries (no repeats).
    src : ndarray of int
        Where each entry sits in the buffer.

    Notes
    -----
    The entries are put into compressed-column order once (:attr:`position` maps an entry
    given at construction to its place in the data); each evaluation is one gather and one
    SuperLU factorization (O(nnz) fill for the chains and particle systems of mechanics,
    against O(s^3) for the dense LU).
    """

    def __init__(self, s: int, rows: np.ndarray, cols: np.ndarray, src: np.ndarray):
        order = np.lexsort((rows, cols))
        self.s = s
        self.src = np.ascontiguousarray(src[order])
        self.indices = np.ascontiguousarray(rows[order])
        self.indptr = np.concatenate(([0], np.cumsum(np.bincount(cols[order], minlength=s)))).astype(np.intp)
        #: position in the CSC data of each entry as given
        self.position = np.empty_like(order)
        self.position[order] = np.arange(len(order))

    def data(self, z: np.ndarray) -> np.ndarray:
        """The entries, gathered from the buffer *z* (a fresh array, CSC order)."""
        return z[self.src]

    def matrix(self, data: np.ndarray) -> csc_matrix:
        return csc_matrix((data, self.indices, self.indptr), shape=(self.s, self.s))

    @staticmethod
    def factor(K: csc_matrix, r: np.ndarray):
        """``(x, lu)`` with ``K x = r`` (``lu`` a SuperLU object: ``lu.solve``), or None when
        ``K`` is singular or the solution is not finite."""
        try:
            lu = splu(K)
        except RuntimeError:   # "Factor is exactly singular"
            return None
        x = lu.solve(r)
        if not np.all(np.isfinite(x)):
            return None
        return x, lu


def dependent_rows(G, tol: float) -> list[int]:
    """Rows of the sparse (or dense) *G* that are combinations of the earlier ones, decided
    per connected component of the rows (rows sharing a column), so that many bodies with a
    constraint each cost O(m) small rank tests, not one O(m^2 n) decomposition."""
    G = G.tocsr() if issparse(G) else csc_matrix(np.asarray(G, dtype=float)).tocsr()
    m, n = G.shape
    if m == 0:
        return []
    coo = G.tocoo()
    keep = coo.data != 0
    r, c = coo.row[keep], coo.col[keep]
    # rows and columns as the nodes of one graph: a row is joined to its columns
    groups = _components(m + n, np.concatenate((r, m + c)), np.concatenate((m + c, r)))
    out: list[int] = []
    for g in groups:
        rows_g = np.sort(g[g < m])
        if len(rows_g) == 0:
            continue
        cols_g = np.sort(g[g >= m] - m)
        block = G[rows_g][:, cols_g].toarray()
        kept: list[int] = []
        if np.linalg.matrix_rank(block, tol=tol) == len(rows_g):
            continue
        for j in range(len(rows_g)):
            if np.linalg.matrix_rank(block[kept + [j]], tol=tol) == len(kept) + 1:
                kept.append(j)
            else:
                out.append(int(rows_g[j]))
    return sorted(out)


def row_groups(n: int, g_rows: np.ndarray, g_cols: np.ndarray, m_rows: np.ndarray, m_cols: np.ndarray,
               rows: list[int]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The constraint rows *rows* split into groups that neither share a coordinate nor are
    coupled through the mass matrix, so that ``G M^-1 G^T`` is block diagonal by group.

    Parameters
    ----------
    n : int
        Number of coordinates.
    g_rows, g_cols : ndarray of int
        Nonzero pattern of ``G`` (kernel row, coordinate).
    m_rows, m_cols : ndarray of int
        Nonzero pattern of ``M``.
    rows : list of int
        The kernel rows concerned.

    Returns
    -------
    list of (ndarray, ndarray)
        Per group: positions in *rows*, and the coordinates of the group (sorted).
    """
    where = {r: k for k, r in enumerate(rows)}
    pick = np.array([r in where for r in g_rows.tolist()], dtype=bool)
    k = len(rows)
    node_r = np.array([where[r] for r in g_rows[pick].tolist()], dtype=np.intp)
    a = np.concatenate((node_r, k + m_rows))
    b = np.concatenate((k + g_cols[pick], k + m_cols))
    out = []
    for g in _components(k + n, a, b):
        pos = np.sort(g[g < k])
        if len(pos):
            out.append((pos, np.sort(g[g >= k] - k)))
    return out
