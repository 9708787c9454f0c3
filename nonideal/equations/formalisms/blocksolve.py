"""Solving the speed matrix ``W X = Y`` block by block (the velocities in the speeds).

``W`` stacks the declared speeds and the constraints; for a body described by a point and a
frame its rows fall into independent groups -- the body's angular velocity components and the
norm of Euler parameters read only the parameters' rates, the velocity of a point reads the
point's coordinates and, through a contact, the rates of the orientation.  Eliminating across
the groups (Gaussian elimination on the whole 7 x 7 matrix of a top on a plane) divides by
pivots such as ``2 e0 + 2 e1^2/e0`` that cancel only after a simplification nobody can
afford; solving the groups in turn keeps each inverse small and exact.

The groups are the strongly connected components of the rows' dependency graph under a perfect
matching of rows to columns (the block triangular form of Duff & Reid 1978): row ``i`` depends
on row ``k`` when it has an entry in the column matched to ``k``.  Components are solved in
topological order, each by ``adj(B)/det(B)`` with the determinant reduced (unit Euler
parameters, trigonometric identities) when it has at most :data:`ADJUGATE_MAX` rows, else by
Gaussian elimination.
"""

from __future__ import annotations

import symengine as se

from ..dynamics import count_ops
from .base import symbolic_solve
from .folding import ADJUGATE_MAX

__all__ = ["adjugate_solve", "block_solve"]


def adjugate_solve(W: list[list], Y: list[list], reduce) -> list[list] | None:
    """``X = adj(W) Y / det(W)`` with the determinant factored and *reduce*-d (SymPy); None when
    the determinant vanishes identically."""
    import sympy as sp

    n = len(W)

    def reparse(expr):
        names = {str(x): sp.Symbol(str(x)) for x in se.sympify(expr).free_symbols}
        return sp.sympify(str(expr), locals=names)

    Ws = sp.Matrix(n, n, lambda i, j: reparse(W[i][j]) if W[i][j].free_symbols else sp.sympify(W[i][j]))
    det = sp.trigsimp(sp.factor(reparse(reduce(se.sympify(Ws.det(method="berkowitz"))))))
    if det == 0:
        return None
    adj = Ws.adjugate(method="berkowitz")
    adj_se = [[reduce(se.sympify(sp.expand(adj[i, j]))) for j in range(n)] for i in range(n)]
    d = se.sympify(det)
    p = len(Y[0]) if Y else 0
    return [[sum((adj_se[i][l] * Y[l][c] for l in range(n) if adj_se[i][l] != 0 and Y[l][c] != 0),
                 se.Integer(0)) / d for c in range(p)] for i in range(n)]


def _matching(W: list[list]) -> list[int] | None:
    """A perfect matching row -> column of the nonzero pattern (augmenting paths), or None."""
    n = len(W)
    col_of, row_of = [-1] * n, [-1] * n

    def augment(i, seen):
        for j in range(n):
            if W[i][j] != 0 and j not in seen:
                seen.add(j)
                if row_of[j] < 0 or augment(row_of[j], seen):
                    col_of[i], row_of[j] = j, i
                    return True
        return False

    for i in range(n):
        if not augment(i, set()):
            return None
    return col_of


def _components(W: list[list], col_of: list[int]) -> list[list[int]]:
    """Strongly connected components of the row graph, dependencies first (Tarjan)."""
    n = len(W)
    row_of = {j: i for i, j in enumerate(col_of)}
    succ = [[row_of[j] for j in range(n) if W[i][j] != 0 and row_of[j] != i] for i in range(n)]
    index, low, on, stack, out = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in succ[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    for v in range(n):
        if v not in index:
            visit(v)
    return out          # Tarjan emits a component after every component it depends on


def block_solve(W: list[list], Y: list[list], reduce, budget: int) -> list[list] | None:
    """``X`` with ``W X = Y`` solved component by component (module docstring); None when ``W``
    has one block only, no structural perfect matching, or a block exceeds *budget*."""
    n = len(W)
    col_of = _matching(W)
    if col_of is None:
        return None
    blocks = _components(W, col_of)
    if len(blocks) < 2:
        return None
    p = len(Y[0]) if Y else 0
    X: list = [None] * n
    for rows in blocks:
        cols = [col_of[i] for i in rows]
        B = [[W[i][j] for j in cols] for i in rows]
        rhs = [[Y[i][c] - sum((W[i][j] * X[j][c] for j in range(n) if j not in cols and W[i][j] != 0),
                              se.Integer(0)) for c in range(p)] for i in rows]
        sol = adjugate_solve(B, rhs, reduce) if len(rows) <= ADJUGATE_MAX else None
        if sol is None:
            sol = symbolic_solve(B, rhs, budget)
        if sol is None or count_ops([x for row in sol for x in row]) > budget:
            return None
        for k, j in enumerate(cols):
            X[j] = [reduce(x) for x in sol[k]]
    return X
