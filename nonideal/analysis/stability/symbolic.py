"""The first approximation in symbolic parameters (``stability --symbolic``): ``A`` and ``B``
with the named parameters kept as symbols, in exact arithmetic.

The parameters not kept enter as exact numbers (``9.81 -> 981/100``); a derived parameter
(``A = "m*r^2/4"``) that depends on a kept one enters by its definition
(:func:`~nonideal.analysis.stability.linear_system.parameter_substitution`).  The state -- found
by Newton in floating point -- enters by the expressions given for it (``--at``, ``[initial]``)
where they hold, else as numbers; the rounding residue that such numbers leave in a
cancellation is dropped (:func:`without_residue`).
"""

from __future__ import annotations

import numpy as np
import symengine as se
import sympy as sp

from ...errors import ModelError, NotAnEquilibrium
from ...modeling.model import Model
from .linear_system import LinearKernel, parameter_substitution, saddle, solve, state_matrices

__all__ = ["symbolic_matrices", "without_residue", "exact_state_value", "RESIDUE"]


def symbolic_matrices(k: LinearKernel, model, t0, q, v, given, part, symbolic, values, kept, rated):
    """A and B in the *symbolic* parameters, in exact arithmetic (the other parameters as exact
    numbers, derived ones that depend on a symbolic one by their definitions: see
    :func:`parameter_substitution`).  The state: the expressions given in --at, else the
    model's initial values when they are expressions in the parameters and equal the state,
    else the numbers -- refused when a symbolic parameter then enters nowhere."""
    names_q = list(model.coordinates)
    names_v = [c + "'" for c in names_q]
    subs = {sp.Symbol(name): val for name, val in values.items()}
    fixed = parameter_substitution(model, symbolic)
    fixed_s = {sp.Symbol(name): e for name, e in fixed.items()}
    initial = {key: sp.sympify(val) for key, val in model.initial.items()
               if key not in given and isinstance(val, sp.Basic) and val.free_symbols}
    from_numbers = []

    def entry(name, num):
        out = exact_state_value(num)
        for source in (given, initial):
            expr = source.get(name)
            if expr is not None and abs(float(expr.xreplace(subs)) - num) <= 1e-9 * (1 + abs(num)):
                out = expr.xreplace(fixed_s)
                break
        if out != 0 and not out.free_symbols:
            from_numbers.append(name)
        return out

    qs = [entry(c, x) for c, x in zip(names_q, q)]
    vs = [entry(c, x) for c, x in zip(names_v, v)]
    n, r = k.n, k.r
    b0 = k.symbolic(t0, qs, vs, [0] * n, [0] * r, fixed)
    K = saddle(b0, False)
    rhs = -sp.Matrix.vstack(b0["E"], b0["C"])
    sol = solve(K, rhs, False, "the motion is undetermined at this state", model)
    a = [sp.simplify(x) for x in sol[:n]]
    lam = [sp.simplify(x) for x in sol[n:]]
    rates = [vs[j] for j in kept] + [a[j] for j in rated]
    rng = np.random.default_rng(3)
    syms = [sp.Symbol(s_) for s_ in symbolic]
    for _ in range(2):
        trial = dict(subs)
        for s_ in syms:
            trial[s_] = subs[s_] * (1 + 0.1 * rng.standard_normal())
        bad = [float(abs(sp.N(sp.sympify(x).xreplace(trial)))) for x in rates]
        if bad and max(bad) > 1e-8 * max(1.0, max(abs(float(y)) for y in trial.values())):
            raise NotAnEquilibrium(
                f"--symbolic {', '.join(symbolic)}: the state moves with these parameters (at "
                f"other values of them the residual rates are up to {max(bad):.3g}); give the "
                "state in --at as expressions in them (e.g. \"phi=acos(g/(l*w^2))\") or make "
                "them numeric", _src(model))
    b = k.symbolic(t0, qs, vs, a, lam, fixed)
    A, B = state_matrices(b, part, n, False, model)
    A, B = (m.applyfunc(lambda e: without_residue(e, subs)) for m in (A, B))
    used = {str(x) for e in k.flat for x in se.sympify(e).free_symbols}
    used |= {str(x) for name, e in fixed.items() if name in used for x in e.free_symbols}
    absent = [name for name in symbolic if sp.Symbol(name) not in A.free_symbols and name not in used]
    if absent and from_numbers:
        # a parameter may enter only through the state (a spin w given as phi' = 5): kept
        # numeric, the conditions would silently not be in it
        dependent = [names_q[j] for j in part.coords_D] + [names_v[j] for j in part.vel_D]
        shown = [name for name in from_numbers if name not in dependent] or from_numbers
        example = shown[0]
        where = ", ".join(f"{name} = {exact_state_value(x)}" for name, x in
                          zip(names_q + names_v, list(q) + list(v)) if name in shown)
        raise ModelError(
            f"--symbolic {', '.join(absent)}: {'it does' if len(absent) == 1 else 'they do'} not "
            f"appear in A at this state, whose values are numbers ({where}); if the state depends "
            f"on {', '.join(absent)}, give it in --at as expressions in "
            f"{'it' if len(absent) == 1 else 'them'} (e.g. --at \"{example}={absent[0]}\"), "
            f"else drop {'it' if len(absent) == 1 else 'them'} from --symbolic", _src(model))
    return A, B


#: a term with a floating-point coefficient below this fraction of its expression's size at the
#: parameters' values is the rounding of a cancellation (a state found by Newton in floating
#: point), not a term: ``1.73e-22*A**2`` beside terms of order 1
RESIDUE = 1e-12


def without_residue(expr, values: dict) -> sp.Expr:
    """*expr* with the rounding residue of floating-point state values removed: in its
    numerator and denominator (expanded), the terms with a Float coefficient whose value at the
    parameters' *values* is below :data:`RESIDUE` of the sum of the terms' magnitudes there.
    Exact terms are never dropped."""
    expr = sp.sympify(expr)
    if not expr.atoms(sp.Float) or not expr.free_symbols:
        return expr
    num, den = sp.fraction(sp.together(expr))

    dropped = []

    def clean_part(part):
        terms = sp.Add.make_args(sp.expand(part))
        try:
            sizes = [abs(complex(sp.N(t.xreplace(values)))) for t in terms]
        except (TypeError, ValueError):
            return part
        total = sum(sizes)
        keep = [t for t, z in zip(terms, sizes)
                if not (t.atoms(sp.Float) and z <= RESIDUE * total)]
        dropped.extend(t for t in terms if t not in keep)
        return sp.Add(*keep)

    num, den = clean_part(num), clean_part(den)
    return num / den if dropped else expr


def exact_state_value(num: float) -> sp.Expr:
    """A state value as a SymPy number: 0, an integer, a simple multiple of pi, else a Float."""
    if abs(num) < 1e-9:
        return sp.Integer(0)
    guess = sp.nsimplify(num, [sp.pi], tolerance=1e-10)
    if sp.count_ops(guess) <= 4 and abs(float(guess) - num) <= 1e-9 * (1 + abs(num)):
        return guess
    return sp.Float(num)


def _src(model: Model):
    return None if model.source == "<api>" else model.source
