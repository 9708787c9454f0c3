"""Characteristic polynomial, Routh--Hurwitz conditions, verdict and Kalman controllability
of a linear system ``x' = A x + B u`` (numeric, or symbolic in named parameters).

The Hurwitz matrix of ``a0 s^n + a1 s^(n-1) + ... + an`` (``a0 > 0``) has entries
``H_ij = a_(2j - i)`` (1-based, ``a_k = 0`` outside ``0..n``); all roots have negative real
parts iff the minors ``Delta_1 .. Delta_n`` are positive (Hurwitz 1895), equivalently
(Liénard & Chipart 1914) iff all ``a_k > 0`` and ``Delta_(n-1), Delta_(n-3), ... > 0`` --
the form used for the conditions in symbolic parameters.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import sympy as sp

from .linear_system import clean

__all__ = ["analyse", "routh_reduction", "zero_cluster", "null_directions", "hurwitz_minors", "routh_hurwitz_conditions", "even_conditions", "controllability",
           "verdict_of"]

S = sp.Symbol("s")


def _nice(x: float) -> sp.Expr:
    """A float with 10 significant digits (integers stay integers)."""
    if abs(x - round(x)) <= 1e-10 * max(1.0, abs(x)):
        return sp.Integer(int(round(x)))
    return sp.Float(float(f"{x:.10g}"), 10)


def hurwitz_minors(coeffs: Sequence) -> list:
    """Hurwitz minors ``Delta_1 .. Delta_n`` of the polynomial with coefficients ``a0 .. an``."""
    a = list(coeffs)
    n = len(a) - 1

    def at(k):
        return a[k] if 0 <= k <= n else 0

    H = sp.Matrix(n, n, lambda i, j: at(2 * (j + 1) - (i + 1)))
    return [sp.factor(sp.simplify(H[:k, :k].det())) if k else 1 for k in range(1, n + 1)]


def routh_hurwitz_conditions(coeffs: Sequence, minors: Sequence) -> list:
    """Liénard--Chipart conditions ``a_k > 0``, ``Delta_(n-1) > 0, Delta_(n-3) > 0, ...`` with the
    ones that hold identically removed (a ``False`` stays: the system can never be stable)."""
    n = len(coeffs) - 1
    out = []
    exprs = [sp.factor(c) for c in coeffs[1:]]
    exprs += [minors[k - 1] for k in range(n - 1, 0, -2) if k >= 2]
    seen = set()
    for e in exprs:
        rel = _positive(e)
        if rel is sp.true:
            continue
        key = str(rel)
        if key not in seen:
            seen.add(key)
            out.append(rel)
    return out


def clean_eigenvalues(eig) -> np.ndarray:
    """Sorted (largest real part first), round-off parts (below 1e-12 of the largest) zeroed."""
    eig = np.asarray(eig, complex)
    if eig.size:
        tol = 1e-12 * max(1.0, float(np.abs(eig).max()))
        eig = np.where(np.abs(eig.real) < tol, 0.0, eig.real) + 1j * np.where(np.abs(eig.imag) < tol, 0.0, eig.imag)
    return np.array(sorted(eig, key=lambda z: (-z.real, -z.imag)), complex)


ZERO_SAFETY = 1e3       # rounding of A taken as ZERO_SAFETY * eps * ||A|| (conditioning margin)


def zero_cluster(A: np.ndarray, eig: np.ndarray) -> tuple[int, float]:
    """The number ``k`` of eigenvalues of *A* that are one zero eigenvalue of multiplicity ``k``
    split by rounding, and the largest of their moduli.

    A k-fold defective zero eigenvalue (a Jordan chain, e.g. the lateral position and the
    heading of a vehicle running straight) is moved by a perturbation ``delta`` of ``A`` by
    about ``(delta ||A||^(k-1))^(1/k)``, the k-th root of the rounding: with
    ``delta = ZERO_SAFETY eps ||A||`` a double zero comes out as ``+-sqrt(eps) ||A||``, not 0.
    Their sum (the trace of the invariant block) is perturbed by ``delta`` only.  So the ``k``
    eigenvalues of smallest modulus are a k-fold zero when each is below
    ``(ZERO_SAFETY eps)^(1/k) ||A||`` and their sum below ``k ZERO_SAFETY eps ||A||``; the
    largest such ``k`` is returned (0: none).  A genuine small eigenvalue alone (a capsize
    mode near its critical speed) keeps its value: one eigenvalue is a zero only within the
    rounding itself.  A zero eigenvalue makes ``A`` singular: when the smallest singular
    value of ``A`` is above the rounding there is none (the conjugate pairs ``+-i w`` of a
    stiff conservative system, frequencies from 7 to 800, also sum to zero and lie below the
    k-th root for large k)."""
    A = np.asarray(A, float)
    eig = np.asarray(eig, complex)
    if eig.size == 0:
        return 0, 0.0
    norm = float(np.linalg.norm(A, 2)) if A.size else 0.0
    if norm == 0.0:
        return eig.size, 0.0
    eps = np.finfo(float).eps * ZERO_SAFETY
    if float(np.linalg.svd(A, compute_uv=False).min()) > eps * norm:
        return 0, 0.0
    order = np.argsort(np.abs(eig))
    for k in range(eig.size, 0, -1):
        part = eig[order[:k]]
        if (np.abs(part).max() <= eps ** (1.0 / k) * norm
                and abs(part.sum()) <= k * eps * norm):
            return k, float(np.abs(part).max())
    return 0, 0.0


def null_directions(A: np.ndarray, k: int, variables: Sequence[str]) -> list:
    """Names of the variables a k-fold zero eigenvalue moves: those with a sizeable component in
    the null space of ``A^k`` (the eigenvector and its Jordan chain)."""
    A = np.asarray(A, float)
    if k == 0 or not len(variables):
        return []
    _, _, Vt = np.linalg.svd(np.linalg.matrix_power(A, k))
    basis = Vt[-k:].T
    weight = np.linalg.norm(basis, axis=1)
    return [v for v, w in zip(variables, weight) if w > 0.1 * weight.max()]


def verdict_of(eigenvalues: np.ndarray, equilibrium: bool = True) -> tuple[str, str]:
    """("asymptotically stable" | "unstable" | "critical", why) by the first approximation.

    In the critical case Lagrange--Dirichlet's theorem is named only for an *equilibrium*
    (about a steady motion -- a top spinning above its pivot -- the potential energy has no
    minimum to speak of: the motion is gyroscopically stabilized or not)."""
    if eigenvalues.size == 0:
        return "critical", "no perturbation variables are left"
    tol = 1e-9 * max(1.0, float(np.abs(eigenvalues).max()))
    worst = eigenvalues[np.argmax(eigenvalues.real)]
    text = f"{worst.real:.6g}" + (f" {'+' if worst.imag >= 0 else '-'} {abs(worst.imag):.6g}i" if abs(worst.imag) > tol else "")
    if worst.real > tol:
        return "unstable", (f"the eigenvalue {text} has a positive real part: unstable by the "
                            "first approximation (Lyapunov)")
    if worst.real < -tol:
        return "asymptotically stable", (f"every eigenvalue has a negative real part (the largest is {text}); "
                                         "the Hurwitz minors are positive: asymptotically stable by the "
                                         "first approximation (Lyapunov)")
    on_axis = int(np.sum(np.abs(eigenvalues.real) <= tol))
    return "critical", (f"{on_axis} eigenvalue(s) on the imaginary axis and none to the right: Lyapunov's "
                        "critical case, the first approximation does not decide"
                        + (" (a conservative system at a strict minimum of its potential energy is "
                           "stable by Lagrange--Dirichlet)" if equilibrium else ""))


def analyse(A: np.ndarray, A_symbolic: sp.Matrix | None = None, symbolic: Sequence[str] = (),
            variables: Sequence[str] = (), equilibrium: bool = True) -> dict:
    """Eigenvalues, characteristic polynomial (in ``s``), Hurwitz minors, conditions, verdict
    (*equilibrium*: about an equilibrium, else a steady or programmed motion).

    Eigenvalues that are one multiple zero eigenvalue split by rounding (:func:`zero_cluster`)
    are reported as zeros; the verdict says so and names the *variables* they move."""
    A = np.asarray(A, float)
    eig = np.linalg.eigvals(A) if A.size else np.zeros(0, complex)
    k, spread = zero_cluster(A, eig)
    note = ""
    if k:
        order = np.argsort(np.abs(eig))
        eig = eig.copy()
        eig[order[:k]] = 0.0
        if k > 1 or spread > 0:
            moved = null_directions(A, k, variables)
            note = (f"; {'a zero eigenvalue' if k == 1 else f'a {k}-fold zero eigenvalue'} (computed "
                    f"within {spread:.2g} of 0: the rounding of a multiple zero eigenvalue, "
                    f"(eps ||A||)^(1/{k}) with ||A|| = {np.linalg.norm(A, 2):.3g}, taken as 0)"
                    + (f", moving {', '.join(moved)}: a neighbouring motion (a family of motions "
                       "the perturbation moves to), not a growth" if moved else ""))
    eig = clean_eigenvalues(eig)
    if A_symbolic is not None and A_symbolic.rows:
        poly = sp.Poly(A_symbolic.charpoly(S).as_expr(), S)
        coeffs = [sp.factor(sp.simplify(c)) for c in poly.all_coeffs()]
    elif A.size:
        coeffs = [_nice(c) for c in np.real(np.poly(A))]
    else:
        coeffs = [sp.Integer(1)]
    polynomial = sum((c * S ** (len(coeffs) - 1 - i) for i, c in enumerate(coeffs)), sp.Integer(0))
    coeffs = [_integral_floats(c) for c in coeffs]
    polynomial = _integral_floats(polynomial)
    minors = hurwitz_minors(coeffs) if len(coeffs) > 1 else []
    even = len(coeffs) > 1 and all(sp.simplify(c) == 0 for c in coeffs[1::2])
    if A_symbolic is None:
        conditions = []
    elif even:
        conditions = even_conditions(coeffs)
    else:
        conditions = routh_hurwitz_conditions(coeffs, minors)
    conditions = [_integral_floats(c) for c in conditions]
    verdict, reason = verdict_of(eig, equilibrium)
    reason += note
    # the odd powers vanish: P(s) = Z(s^2) (even degree) or s Z(s^2) (odd degree: a zero root)
    form = "Z(s^2)" if (len(coeffs) - 1) % 2 == 0 else "s Z(s^2)"
    if even and verdict == "critical":
        reason += (("; the polynomial is even in s" if form == "Z(s^2)" else
                    "; the polynomial is s times an even polynomial, P(s) = s Z(s^2) (a zero root)")
                   + f" (no dissipation): the {'' if form == 'Z(s^2)' else 'other '}roots are on the imaginary axis iff the roots "
                   "of Z(z), z = s^2, are real and negative (gyroscopic stability, Kelvin--Chetaev)")
    meaning = ("" if A_symbolic is None else
               f"roots on the imaginary axis, simple (no dissipation: P(s) = {form}, the "
               "roots of Z real, negative, distinct)" if even else "asymptotic stability (Lienard--Chipart)")
    return {"eigenvalues": eig, "polynomial": polynomial, "coefficients": coeffs, "hurwitz": minors,
            "conditions": conditions, "conditions_meaning": meaning, "verdict": verdict, "reason": reason}


def _positive(expr) -> sp.Basic:
    """``expr > 0`` with the factors that cannot change its sign dropped: positive numbers and
    even powers (a condition ``x^2 > 0`` only excludes ``x = 0``).  ``True``/``False`` when
    nothing is left."""
    expr = sp.factor(sp.sympify(expr))
    if not expr.free_symbols:
        return sp.sympify(bool(expr > 0))
    sign, keep = 1, []
    for f in sp.Mul.make_args(expr):
        base, exp = f.as_base_exp()
        if f.is_number:
            sign *= 1 if f > 0 else -1
        elif exp.is_Integer and int(exp) % 2 == 0:
            continue
        else:
            keep.append(f)
    if not keep:
        return sp.sympify(sign > 0)
    rest = sp.Mul(*keep)
    return sp.simplify(rest > 0) if sign > 0 else sp.simplify(rest < 0)


def _integral_floats(e):
    """Floats with integer values (1.0) written as integers."""
    e = sp.sympify(e)
    return e.xreplace({f: sp.Integer(int(f)) for f in e.atoms(sp.Float) if float(f).is_integer()})


def even_conditions(coeffs: Sequence) -> list:
    """For ``P(s) = Z(s^2)`` (no odd powers): every root on the imaginary axis and simple iff the
    roots of ``Z(z)`` are real, negative and distinct: the coefficients of ``Z`` positive and
    (degree 2) its discriminant positive -- Maievski's condition for the sleeping top."""
    z = list(coeffs[::2])
    out = []
    for c in z[1:]:
        rel = _positive(c)
        if rel is not sp.true:
            out.append(rel)
    if len(z) == 3:
        rel = _positive(sp.expand(z[1] ** 2 - 4 * z[0] * z[2]))
        if rel is not sp.true:
            out.append(rel)
    return out


def controllability(A: np.ndarray, B: np.ndarray) -> dict:
    """Kalman's rank of ``[B, AB, ..., A^(n-1) B]``: ``{"rank", "n"}``."""
    A, B = np.asarray(A, float), np.asarray(B, float)
    n = A.shape[0]
    if n == 0 or B.size == 0:
        return {"rank": 0, "n": n}
    blocks, cur = [], B
    for _ in range(n):
        blocks.append(cur)
        cur = A @ cur
    W = np.hstack(blocks)
    sv = np.linalg.svd(W, compute_uv=False)
    rank = int(np.sum(sv > 1e-9 * sv.max())) if sv.size and sv.max() > 0 else 0
    return {"rank": rank, "n": n}


def routh_reduction(A: np.ndarray, A_sym, pos: int):
    """``(A, A_sym)`` restricted to the level of the first integral that the velocity at *pos*
    carries, or None.

    A steady motion with a held cyclic velocity ``w`` is one of a family (another ``w``, another
    steady motion): ``A`` has a simple zero eigenvalue whose left null vector ``c`` --
    ``c . x' = 0``, the linearized first integral (the cyclic momentum, Routh) -- weighs on
    ``w``.  On ``c . x = 0`` (perturbations that keep the integral), ``w = -c_rest . x_rest /
    c_w``: the reduced matrix is ``A_rest,rest - A_rest,w c_rest / c_w`` with the eigenvalues of
    ``A`` but that zero.  A decoupled ``w`` (its row and column zero) is the case ``c = e_w``."""
    n = A.shape[0]
    if n < 2:
        return None
    _, sv, Vt = np.linalg.svd(A.T)
    norm = max(1.0, float(sv[0]))
    if sv[-1] > 1e-9 * norm or sv[-2] <= 1e-6 * norm:       # not one simple zero
        return None
    c = Vt[-1]
    if abs(c[pos]) <= 0.1 * float(np.abs(c).max()):
        return None
    rest = [i for i in range(n) if i != pos]
    reduced = clean(A[np.ix_(rest, rest)] - np.outer(A[rest, pos], c[rest] / c[pos]))
    if A_sym is None:
        return reduced, None
    try:
        (cs,) = A_sym.T.nullspace(simplify=True)
    except (ValueError, NotImplementedError):
        return None
    if sp.simplify(cs[pos]) == 0:
        return None
    col = A_sym.extract(rest, [pos])
    row = sp.Matrix([[cs[i] / cs[pos] for i in rest]])
    return reduced, (A_sym.extract(rest, rest) - col * row).applyfunc(sp.simplify)
