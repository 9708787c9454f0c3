"""Compiled numerics of many coordinates: the matrices of a compact kernel by their nonzero
entries, and compiled functions built in chunks.

* :data:`SPARSE_MIN_N` -- from this many coordinates :class:`~nonideal.numeric.kernel.Kernel`
  compiles ``M``, ``G`` and ``B`` as vectors of their nonzero entries (:class:`SparsePattern`);
* :class:`Chunked` -- a SymEngine ``Lambdify`` of many outputs over many inputs, built in
  chunks over the inputs each reads (:data:`CHUNK_MIN_WORK`).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_matrix

__all__ = ["SPARSE_MIN_N", "SparsePattern", "CHUNK_MIN_WORK", "CHUNK_SIZE", "Chunked"]


SPARSE_MIN_N = 500
"""From this many coordinates :class:`Kernel` compiles ``M``, ``G`` and ``B`` as the vectors
of their nonzero entries (:class:`SparsePattern`) and the numeric stage keeps them sparse:
the dense layout of 10 000 particles alone would be 30 000^2 doubles (7.2 GB), and filling
and gathering an n x n buffer costs O(n^2) per evaluation.  Below it the dense layout (one
LAPACK call) is faster and the results of small models stay those of the dense path."""


class SparsePattern:
    """The nonzero positions of a matrix output compiled as a vector of its entries, in
    row-major order (so the vector is the ``data`` of a CSR matrix).

    Parameters
    ----------
    shape : (int, int)
    positions : list of (int, int)
        Sorted row-major, no repeats.
    """

    def __init__(self, shape: tuple[int, int], positions):
        self.shape = shape
        ij = np.array(positions, dtype=np.intp).reshape(-1, 2)
        self.rows, self.cols = ij[:, 0], ij[:, 1]
        self.indptr = np.concatenate(([0], np.cumsum(np.bincount(self.rows, minlength=shape[0]))))

    def matrix(self, values) -> csr_matrix:
        """The CSR matrix with the entries *values* (copied)."""
        return csr_matrix((np.array(values, dtype=float), self.cols.copy(), self.indptr.copy()),
                          shape=self.shape)



CHUNK_MIN_WORK = 20_000_000
"""Above this product of outputs and inputs a Lambdify is split into chunks of
:data:`CHUNK_SIZE` outputs, each over only the inputs it reads: SymEngine's build time grows
with outputs x inputs (10 000 particles, 60 000 inputs and 40 000 outputs: 25 s in one piece;
in chunks it grows with the size)."""

CHUNK_SIZE = 2048


class Chunked:
    """Several Lambdify over consecutive chunks of the outputs, each over its own inputs; called
    like one (``unsafe_real(x, out)``, and on a batch of input rows)."""

    def __init__(self, inputs, exprs, optimize: bool, build):
        position = {s: i for i, s in enumerate(inputs)}
        self.size = len(exprs)
        self.parts = []
        for lo in range(0, len(exprs), CHUNK_SIZE):
            chunk = exprs[lo:lo + CHUNK_SIZE]
            used = sorted({position[s] for e in chunk for s in e.free_symbols if s in position})
            if not used:   # constants only: one dummy input
                used = [0]
            fn = build([inputs[i] for i in used], chunk, optimize)
            self.parts.append((slice(lo, lo + len(chunk)), np.array(used, dtype=np.intp), fn))

    def unsafe_real(self, x: np.ndarray, out: np.ndarray) -> None:
        for sl, used, fn in self.parts:
            fn.unsafe_real(np.ascontiguousarray(x[used]), out[sl])

    def __call__(self, X: np.ndarray) -> np.ndarray:
        out = np.empty((len(X), self.size))
        for sl, used, fn in self.parts:
            out[:, sl] = np.asarray(fn(np.ascontiguousarray(X[:, used])), dtype=float).reshape(len(X), -1)
        return out
