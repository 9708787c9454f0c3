"""Canonical symbols and the SymPy <-> SymEngine bridge.

Glossary (one name per concept, everywhere in the code):

====================  ===========================================================
``t``                 time
``q``                 generalized coordinates, SymPy symbols named ``x``
``qd``                velocities, symbols named ``x'``  (LaTeX ``\\dot{x}``)
``qdd``               accelerations, symbols named ``x''`` (LaTeX ``\\ddot{x}``)
``n_q``               number of coordinates
``n_dof``             number of independent velocities (degrees of freedom)
``M``                 mass matrix, ``d2T/dqd2``
``F``                 forcing: generalized active forces minus the velocity terms
                      of the Lagrange operator, so that ``M qdd = F + B lambda_``
``G``, ``gamma``      constraints at acceleration level ``G qdd + gamma = 0``
``B``                 reaction directions (``G.T`` for ideal constraints)
``lambda_``           multipliers (one per scalar constraint equation)
``V``, ``w``          velocity basis and particular acceleration,
                      ``qdd = V pdot + w`` on the constraint manifold
``S``                 acceleration energy (Gibbs--Appell)
``N``, ``U``          normal force and slip velocity of a contact
====================  ===========================================================

All internal symbols carry no assumptions, so that SymPy and SymEngine round trips keep
identity (a SymPy ``Symbol('x', real=True)`` is a different object from ``Symbol('x')``).
The heavy symbolic work runs in SymEngine (differentiation is 30-250x faster than SymPy);
users see SymPy objects, converted on demand.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Iterable, Mapping
from functools import cmp_to_key

import symengine as se
import sympy as sp

__all__ = [
    "t",
    "coordinate_symbols",
    "velocity_name",
    "acceleration_name",
    "multiplier_symbol",
    "to_se",
    "to_sp",
    "latex_names",
]

t = sp.Symbol("t")
t_se = se.Symbol("t")

_IDENT = re.compile(r"^[A-Za-z_][A-Za-z_0-9]*$")


def velocity_name(name: str) -> str:
    return name + "'"


def acceleration_name(name: str) -> str:
    return name + "''"


def coordinate_symbols(names: Iterable[str]) -> tuple[tuple[sp.Symbol, ...], ...]:
    """Return ``(q, qd, qdd)`` tuples of SymPy symbols for coordinate *names*."""
    names = list(names)
    q = tuple(sp.Symbol(n) for n in names)
    qd = tuple(sp.Symbol(velocity_name(n)) for n in names)
    qdd = tuple(sp.Symbol(acceleration_name(n)) for n in names)
    return q, qd, qdd


def multiplier_symbol(constraint_name: str, index: int | None = None) -> sp.Symbol:
    """The multiplier of a (possibly vector) constraint: ``lambda_name`` or ``lambda_name_i``."""
    base = f"lambda_{constraint_name}"
    return sp.Symbol(base if index is None else f"{base}_{index}")


def to_se(expr):
    """SymPy (or number, or nested list) -> SymEngine."""
    if isinstance(expr, (list, tuple)):
        return [to_se(e) for e in expr]
    if isinstance(expr, sp.MatrixBase):
        return se.Matrix(expr.tolist()) if expr.shape[0] else se.zeros(0, expr.shape[1])
    return se.sympify(expr)


def to_sp(expr, memo: dict | None = None):
    """SymEngine (or nested list/Matrix) -> SymPy, without re-canonicalizing.

    SymEngine's expressions are already canonical, and SymPy's constructors would spend most
    of the conversion re-flattening and re-sorting them (and converting every shared
    subexpression once per occurrence).  The tree is therefore rebuilt node by node, each
    distinct SymEngine node once (*memo*, which callers converting several related
    expressions may share), with the arguments sorted in SymPy's canonical order and the
    node created directly.  SymPy's evaluating constructors are used only where SymPy's
    canonical form differs from SymEngine's (``-(x + y)`` is ``-x - y`` in SymPy, a sum of
    sums is flattened, ``E**x`` is ``exp(x)``), and for function nodes, so the result
    equals what ``sympy.sympify`` builds in the cases that occur in the equations of motion
    (pendulum, knife chain: all entries structurally equal).

    Parameters
    ----------
    expr : se.Basic, se.DenseMatrix, number, or nested list/tuple of them
    memo : dict, optional
        SymEngine node -> SymPy node, filled as a side effect.

    Returns
    -------
    sympy.Basic, sympy.Matrix, or list

    Examples
    --------
    >>> import symengine as se
    >>> x, y = se.symbols("x y")
    >>> to_sp(-(x + 2*y)), to_sp(-(x + 2*y)*se.cos(x))
    (-x - 2*y, -(x + 2*y)*cos(x))
    """
    if memo is None:
        memo = {}
    if isinstance(expr, (list, tuple)):
        return [to_sp(e, memo) for e in expr]
    if isinstance(expr, se.DenseMatrix):
        rows, cols = expr.shape
        return sp.Matrix(rows, cols, [_convert(e, memo) for e in expr])
    if not isinstance(expr, se.Basic):
        return sp.sympify(expr)
    return _convert(expr, memo)


_CANONICAL_ORDER = cmp_to_key(sp.Basic.compare)   # the key of SymPy's Add/Mul.flatten


def _convert(root, memo: dict):
    """Post-order conversion of one SymEngine tree (explicit stack: deep trees are fine)."""
    stack = [root]
    while stack:
        node = stack[-1]
        if node in memo:
            stack.pop()
            continue
        args = node.args
        pending = [a for a in args if a not in memo]
        if pending:
            stack.extend(pending)
            continue
        stack.pop()
        memo[node] = _node(node, [memo[a] for a in args])
    return memo[root]


def _node(node, args: list):
    """The SymPy node for a SymEngine *node* whose arguments are already converted."""
    if not args:
        return node._sympy_()          # symbols, numbers, constants
    if isinstance(node, se.Add):
        if any(a.is_Add for a in args):
            return sp.Add(*args)       # a term became a sum (-(x + y) -> -x - y): flatten
        args.sort(key=_CANONICAL_ORDER)
        return sp.Add._from_args(args, is_commutative=True)
    if isinstance(node, se.Mul):
        args.sort(key=_CANONICAL_ORDER)
        if (len(args) == 2 and args[0].is_Rational and args[1].is_Add) or any(a.is_Mul for a in args):
            return sp.Mul(*args)       # SymPy distributes a number over a sum
        return sp.Mul._from_args(args, is_commutative=True)
    if isinstance(node, se.Pow):
        base, exponent = args
        if base.is_number:
            return sp.Pow(base, exponent)   # E**x -> exp(x), 2**(1/2) -> sqrt(2)
        return sp.Pow(base, exponent, evaluate=False)
    function = getattr(sp, type(node).__name__, None)
    if isinstance(node, se.Function) and isinstance(function, type) and issubclass(function, sp.Function):
        return function(*args)
    return node._sympy_()              # anything else: SymEngine's own (evaluating) conversion


def _latex_base(name: str) -> str:
    greek = {
        "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa",
        "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi",
        "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Phi", "Psi", "Omega",
        "varphi", "vartheta",
    }
    m = re.match(r"^([A-Za-z]+?)(_?)(\d*)$", name)
    if m and (m.group(1) in greek or len(m.group(1)) == 1):
        head = "\\" + m.group(1) if m.group(1) in greek else m.group(1)
        return head + (f"_{{{m.group(3)}}}" if m.group(3) else "")
    if "_" in name:
        head, _, tail = name.partition("_")
        return _latex_base(head) + "_{" + tail.replace("_", r"\_") + "}"
    return r"\mathrm{" + name + "}" if len(name) > 1 else name


def latex_names(symbols: Iterable[sp.Symbol]) -> Mapping[sp.Symbol, str]:
    """LaTeX names for coordinates, their derivatives and multipliers: ``x''`` -> ``\\ddot{x}``."""
    out = {}
    for s in symbols:
        name = s.name
        if name.endswith("''"):
            out[s] = r"\ddot{" + _latex_base(name[:-2]) + "}"
        elif name.endswith("'"):
            out[s] = r"\dot{" + _latex_base(name[:-1]) + "}"
        elif name.startswith("lambda_"):
            out[s] = r"\lambda_{" + name[len("lambda_"):].replace("_", r"\_") + "}"
        else:
            out[s] = _latex_base(name)
    return out


def is_identifier(name: str) -> bool:
    """A valid model name: a Python identifier that is not a keyword (``lambda`` is not)."""
    return bool(_IDENT.match(name)) and not keyword.iskeyword(name)
