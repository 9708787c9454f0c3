"""Equations a mechanician can read, fast: targeted rewriting instead of ``simplify``.

The symbolic dynamics (:mod:`nonideal.equations.dynamics`) builds the equations of motion as SymEngine expressions in whatever
shape the derivation left them (``m*(l**2*sin(q)**2 + l**2*cos(q)**2)*q''``).  This module
prints them the way a textbook writes them::

    m1*l1**2*q1'' + m2*l1*l2*cos(q1 - q2)*q2'' + m2*l1*l2*sin(q1 - q2)*q2'**2 = -g*l1*(m1 + m2)*sin(q1)

in three steps, none of which calls SymPy's ``simplify``/``trigsimp`` (whose cost grows
exponentially with the number of angles):

1. **Expand** each expression (SymEngine) into a sum of monomials in the parameters,
   coordinates, velocities, accelerations, multipliers and the functions ``sin``/``cos`` of
   linear combinations of symbols (anything else is kept as an opaque factor).
2. **Fold** on the monomial dictionary, to a fixed point: the Pythagorean identity
   ``k sin(u)^2 X + k cos(u)^2 X -> k X`` (also ``tan^2 + 1 = 1/cos^2``: ``X`` may hold negative
   powers) and the angle sums ``cos a cos b + sin a sin b -> cos(a - b)``,
   ``sin a cos b - cos a sin b -> sin(a - b)`` (and ``a + b`` with the other signs).
3. **Group and factor**: every equation is printed as its accelerations, then the products of
   velocities, then the multipliers, then the remaining (force) terms, each with its
   coefficient; common monomial factors (of a whole side, of a coefficient) are pulled out
   and the coefficients' parameter sums are kept in parentheses ``(m2 + m3)``.

The rewriting is exact (identities only), so the printed text parses back to the same
expressions -- the tests check that at random states.
"""

from __future__ import annotations

import re
from fractions import Fraction
from math import gcd
from typing import Any, Callable, Iterable

import symengine as se

from .typeset import Typesetting

__all__ = ["Printer", "Poly"]

_NUMBER_TYPES = (se.Integer, se.Rational)
_TRIG = {"sin": se.sin, "cos": se.cos}

# A factor is a hashable tuple: ("s", name) a symbol, ("sin", lin) / ("cos", lin) with lin a
# canonical linear combination ((name, Fraction), ...), ("f", expr) any other SymEngine atom.
# A monomial is a tuple of (factor, power) sorted by the printer's order; a polynomial is a
# dict monomial -> coefficient (Fraction, or float when the model has floating numbers).

Poly = dict


def _natural(name: str):
    return tuple(int(p) if p.isdigit() else p for p in re.split(r"(\d+)", name))


def _num(value) -> int | Fraction | float:
    if isinstance(value, se.Integer):
        return int(value)
    if isinstance(value, se.Rational):
        p, q = str(value).split("/")
        return Fraction(int(p), int(q))
    return float(value)


def _exact(c) -> bool:
    return isinstance(c, (int, Fraction))


def _norm(c):
    """Fractions with denominator 1 as ints (cheaper to hash and multiply)."""
    if isinstance(c, Fraction) and c.denominator == 1:
        return c.numerator
    return c


def _is_zero(c) -> bool:
    return c == 0 or (isinstance(c, float) and abs(c) < 1e-300)


def _close(a, b) -> bool:
    if _exact(a) and _exact(b):
        return a == b
    return abs(a - b) <= 1e-12 * max(abs(a), abs(b))


class Printer(Typesetting):
    """Expansion, folding, grouping and printing in the vocabulary of one model.

    Parameters
    ----------
    coordinates : iterable of str
        Coordinate names in the model's order (they order the angles: ``cos(q1 - q2)``).
    unknowns : iterable of str
        The unknown accelerations (``"x''"``), grouped first.
    multipliers : iterable of str
        Multiplier names, grouped after the velocity products.
    latex_of : callable str -> str, optional
        LaTeX spelling of a symbol name (``"x''"`` -> ``\\ddot{x}``).
    speeds : iterable of str, optional
        Generalized speeds: ordered and grouped like velocities.
    """

    def __init__(self, coordinates: Iterable[str], unknowns: Iterable[str] = (),
                 multipliers: Iterable[str] = (), latex_of: Callable[[str], str] | None = None,
                 speeds: Iterable[str] = ()):
        self.coordinates = list(coordinates)
        self.unknowns = list(unknowns)
        self.multipliers = list(multipliers)
        cindex = {c: i for i, c in enumerate(self.coordinates)}
        self._rank: dict[str, tuple] = {}
        for c, i in cindex.items():
            self._rank[c] = (3, i)
            self._rank[c + "'"] = (6, i)
            self._rank[c + "''"] = (7, i)
        for j, u in enumerate(speeds):   # generalized speeds group with the velocities
            self._rank[u] = (6, len(cindex) + j)
        for j, a in enumerate(self.unknowns):
            self._rank.setdefault(a, (7, len(cindex) + j))
        for j, m in enumerate(self.multipliers):
            self._rank[m] = (8, j)
        self._rank["t"] = (2, 0)
        self._latex_of = latex_of or (lambda name: name)
        self._latex: dict[str, str] = {}
        self._keys: dict[Any, tuple] = {}
        self._se_cache: dict[Any, Poly] = {}
        self._fcache: dict[Any, tuple] = {}
        self._lcache: dict[Any, Any] = {}
        self._holders: dict[Any, Any] = {}     # opaque subexpression -> placeholder symbol
        self._held: dict[str, Any] = {}        # placeholder name -> opaque subexpression

    def _lx(self, name: str) -> str:
        out = self._latex.get(name)
        if out is None:
            out = self._latex[name] = self._latex_of(name)
        return out

    # ------------------------------------------------------------------ ordering
    def symbol_rank(self, name: str) -> tuple:
        r = self._rank.get(name)
        if r is None:
            if name.endswith("'"):
                r = (6, 10**6, _natural(name))
            else:
                r = (1, 0, _natural(name))   # parameters and other symbols
            self._rank[name] = r
        return r

    def key(self, factor) -> tuple:
        k = self._keys.get(factor)
        if k is None:
            kind = factor[0]
            if kind == "s":
                k = self.symbol_rank(factor[1])
            elif kind in ("sin", "cos"):
                k = (5, tuple(self.symbol_rank(n) for n, _ in factor[1]), kind,
                     tuple(float(c) for _, c in factor[1]))
            elif not factor[1].free_symbols:
                k = (0, 1, str(factor[1]))          # a number such as sqrt(2), pi
            else:
                k = (4, 0, str(factor[1]))
            self._keys[factor] = k
        return k

    def monomial(self, powers: dict) -> frozenset:
        return frozenset((f, p) for f, p in powers.items() if p != 0)

    def ordered(self, m) -> list:
        """The factors of a monomial in printing order."""
        return sorted(m, key=lambda fp: self.key(fp[0]))

    # ------------------------------------------------------------------ parsing
    def _linear(self, arg) -> tuple | None:
        """``arg`` as a canonical linear combination of symbols, or None (cached)."""
        try:
            return self._lcache[arg]
        except KeyError:
            out = self._lcache[arg] = self._linear_of(arg)
            return out

    def _linear_of(self, arg) -> tuple | None:
        terms: dict[str, Fraction] = {}
        for t in (arg.args if isinstance(arg, se.Add) else (arg,)):
            if isinstance(t, se.Symbol):
                terms[t.name] = terms.get(t.name, 0) + 1
            elif isinstance(t, se.Mul) and len(t.args) == 2 and isinstance(t.args[0], _NUMBER_TYPES) \
                    and isinstance(t.args[1], se.Symbol):
                terms[t.args[1].name] = terms.get(t.args[1].name, 0) + _num(t.args[0])
            else:
                return None
        return tuple(sorted(((n, _norm(c)) for n, c in terms.items() if c != 0),
                            key=lambda nc: self.symbol_rank(nc[0])))

    def _trig(self, kind: str, lin: tuple) -> tuple[int, tuple]:
        """(sign, factor) of sin/cos of *lin* with the leading coefficient made positive."""
        if lin and lin[0][1] < 0:
            lin = tuple((n, -c) for n, c in lin)
            return (-1 if kind == "sin" else 1), (kind, lin)
        return 1, (kind, lin)

    def _factor(self, node) -> tuple[Any, int, int]:
        """(sign, factor, power) of one factor of a monomial (cached per node)."""
        out = self._fcache.get(node)
        if out is None:
            out = self._fcache[node] = self._factor_of(node)
        return out

    def _factor_of(self, node) -> tuple[Any, int, int]:
        power = 1
        if isinstance(node, se.Pow):
            base, exponent = node.args
            if isinstance(exponent, se.Integer):
                node, power = base, int(exponent)
            elif isinstance(exponent, se.Rational) and not isinstance(base, se.Number):
                node, power = base, _num(exponent)
                if not isinstance(base, (se.Symbol, se.Add, se.Mul)):
                    return 1, ("f", base), power
            else:
                return 1, ("f", node), 1
        if isinstance(node, se.Symbol):
            original = self._held.get(node.name)
            if original is not None:
                return 1, ("f", original), power
            return 1, ("s", node.name), power
        name = type(node).__name__
        if name in _TRIG and isinstance(power, int):
            lin = self._linear(node.args[0])
            if lin is not None and lin:
                sign, factor = self._trig(name, lin)
                return sign ** power, factor, power
        return 1, ("f", node), power

    def _protect(self, expr):
        """*expr* with its opaque parts -- the bases of roots and inverse powers of sums, the
        functions other than sin/cos of linear arguments -- replaced by placeholder symbols, so
        that the expansion keeps them as written (``sqrt((x - x1)**2 + (y - y1)**2)``, not its
        expanded radicand)."""
        table = {}
        for p in expr.atoms(se.Pow):
            base, exponent = p.args
            if isinstance(base, (se.Add, se.Mul)) and not (isinstance(exponent, se.Integer) and int(exponent) > 0):
                table[base] = self._placeholder(base)
        for f in expr.atoms(se.Function):
            if type(f).__name__ in _TRIG and self._linear(f.args[0]):
                continue
            table[f] = self._placeholder(f)
        return expr.subs(table) if table else expr

    def _placeholder(self, original):
        symbol = self._holders.get(original)
        if symbol is None:
            symbol = se.Symbol(f"_opaque{len(self._holders)}")
            self._holders[original] = symbol
            self._held[symbol.name] = original
        return symbol

    def poly(self, expr) -> Poly:
        """The expanded polynomial of a SymEngine (or SymPy) expression."""
        if not isinstance(expr, se.Basic):
            expr = se.sympify(expr)
        cached = self._se_cache.get(expr)
        if cached is not None:
            return cached
        out: Poly = {}
        expanded = se.expand(self._protect(expr))
        for term in (expanded.args if isinstance(expanded, se.Add) else (expanded,)):
            coeff: Any = 1
            powers: dict = {}
            for node in (term.args if isinstance(term, se.Mul) else (term,)):
                if isinstance(node, se.Number) and not isinstance(node, se.Pow):
                    try:
                        coeff = coeff * _num(node)
                    except (TypeError, ValueError):
                        powers[("f", node)] = powers.get(("f", node), 0) + 1
                    continue
                sign, factor, power = self._factor(node)
                coeff = coeff * sign
                powers[factor] = powers.get(factor, 0) + power
            if _is_zero(coeff):
                continue
            m = self.monomial(powers)
            out[m] = _norm(out.get(m, 0) + coeff)
            if _is_zero(out[m]):
                del out[m]
        self._se_cache[expr] = out
        return out

    def add_into(self, target: Poly, poly: Poly, symbol: str | None = None) -> None:
        """``target += poly * symbol`` (in place)."""
        extra = ("s", symbol)
        for m, c in poly.items():
            if symbol is not None:
                powers = dict(m)
                powers[extra] = powers.get(extra, 0) + 1
                m = self.monomial(powers)
            self._add(target, m, c)

    # ------------------------------------------------------------------ folding
    def fold(self, poly: Poly) -> Poly:
        """The trigonometric identities applied to a fixed point (see the module docstring)."""
        poly = dict(poly)
        for _ in range(50):
            if not (self._pythagoras(poly) or self._angle_sums(poly)):
                break
        return poly

    def _shift(self, m: tuple, changes: dict) -> tuple:
        powers = dict(m)
        for f, d in changes.items():
            powers[f] = powers.get(f, 0) + d
        return self.monomial(powers)

    def _add(self, poly: Poly, m: tuple, c) -> None:
        v = _norm(poly.get(m, 0) + c)
        if _is_zero(v) or (isinstance(v, float) and abs(v) < 1e-14 * abs(c)):
            poly.pop(m, None)
        else:
            poly[m] = v

    def _combine(self, poly, m1, m2, k1, k2, target_same, target_opposite) -> bool:
        """Replace k1 m1 + k2 m2 by k target when k1 = +-k2 (or the common part when the
        coefficients have the same sign and differ)."""
        if _close(k1, k2) and target_same is not None:
            del poly[m1], poly[m2]
            sign, m = target_same
            self._add(poly, m, sign * k1)
            return True
        if _close(k1, -k2) and target_opposite is not None:
            del poly[m1], poly[m2]
            sign, m = target_opposite
            self._add(poly, m, sign * k1)
            return True
        return False

    def _pythagoras(self, poly: Poly) -> bool:
        changed = False
        for m in list(poly):
            if m not in poly:
                continue
            for f, p in m:
                if f[0] != "sin" or p < 2:
                    continue
                cos = ("cos", f[1])
                partner = self._shift(m, {f: -2, cos: 2})
                if partner not in poly:
                    continue
                k1, k2 = poly[m], poly[partner]
                base = self._shift(m, {f: -2})
                if _close(k1, k2):
                    del poly[m], poly[partner]
                    self._add(poly, base, k1)
                elif (k1 > 0) == (k2 > 0):          # common part: k s^2 + k' c^2, |k| < |k'|
                    small = k1 if abs(k1) < abs(k2) else k2
                    self._add(poly, m, -small)
                    self._add(poly, partner, -small)
                    self._add(poly, base, small)
                else:
                    continue
                changed = True
                break
        return changed

    def _angle(self, kind: str, a: tuple, b: tuple, plus: bool) -> tuple[int, tuple] | None:
        terms: dict[str, Any] = dict(a)
        for n, c in b:
            terms[n] = terms.get(n, 0) + (c if plus else -c)
        lin = tuple(sorted(((n, _norm(c)) for n, c in terms.items() if c != 0),
                           key=lambda nc: self.symbol_rank(nc[0])))
        if not lin:
            return None
        return self._trig(kind, lin)

    def _angle_sums(self, poly: Poly) -> bool:
        changed = False
        for m in list(poly):
            if m not in poly:
                continue
            trig = [(f, p) for f, p in m if f[0] in ("sin", "cos")]
            done = False
            for i, (fa, _) in enumerate(trig):
                for fb, _ in trig[i + 1:]:
                    a, b = fa[1], fb[1]
                    if a == b:
                        continue
                    sa, ca, sb, cb = ("sin", a), ("cos", a), ("sin", b), ("cos", b)
                    k1 = poly[m]
                    if fa[0] == "cos" and fb[0] == "cos":
                        # k1 cos a cos b + k2 sin a sin b
                        partner = self._shift(m, {ca: -1, cb: -1, sa: 1, sb: 1})
                        if partner not in poly:
                            continue
                        rest = {ca: -1, cb: -1}
                        same = self._angle("cos", a, b, False)      # cos(a - b)
                        opp = self._angle("cos", a, b, True)        # cos(a + b)
                    elif fa[0] == "sin" and fb[0] == "cos":
                        # k1 sin a cos b + k2 cos a sin b
                        partner = self._shift(m, {sa: -1, cb: -1, ca: 1, sb: 1})
                        if partner not in poly:
                            continue
                        rest = {sa: -1, cb: -1}
                        same = self._angle("sin", a, b, True)       # sin(a + b)
                        opp = self._angle("sin", a, b, False)       # sin(a - b)
                    elif fa[0] == "cos" and fb[0] == "sin":
                        # k1 cos a sin b + k2 sin a cos b
                        partner = self._shift(m, {ca: -1, sb: -1, sa: 1, cb: 1})
                        if partner not in poly:
                            continue
                        rest = {ca: -1, sb: -1}
                        same = self._angle("sin", a, b, True)       # sin(a + b)
                        opp = self._angle("sin", b, a, False)       # sin(b - a)
                    else:
                        continue
                    k2 = poly[partner]
                    targets = []
                    for t in (same, opp):
                        if t is None:                                # cos(0) = 1, sin(0) = 0
                            targets.append(None)
                            continue
                        sign, factor = t
                        targets.append((sign, self._shift(m, {**rest, factor: 1})))
                    if same is None and fa[0] == "cos":              # a = -b: cos a cos b + sin a sin b
                        targets[0] = (1, self._shift(m, rest))
                    if self._combine(poly, m, partner, k1, k2, targets[0], targets[1]):
                        changed = done = True
                        break
                if done:
                    break
        return changed

    # ------------------------------------------------------------------ factoring
    def content(self, poly: Poly) -> tuple[Any, tuple]:
        """(number, monomial) common to every term: rational gcd (negative when every term
        is), the smallest positive powers common to all (denominators stay with their terms)."""
        coeffs = list(poly.values())
        if all(isinstance(c, int) for c in coeffs):
            num = 0
            for c in coeffs:
                num = gcd(num, c)
            number: Any = num or 1
        elif all(_exact(c) for c in coeffs):
            num = 0
            den = 1
            for c in coeffs:
                c = Fraction(c)
                num = gcd(num, c.numerator)
                den = den * c.denominator // gcd(den, c.denominator)
            number = _norm(Fraction(num, den)) if num else 1
        else:
            number = 1
        if all(c < 0 for c in coeffs):
            number = -number
        monomials = iter(poly)
        common = {f: p for f, p in next(monomials) if p > 0}
        for m in monomials:
            if not common:
                break
            powers = dict(m)
            for f in list(common):
                q = powers.get(f, 0)
                if q > 0:
                    if q < common[f]:
                        common[f] = q
                else:
                    del common[f]
        return number, self.monomial(common)

    def denominator(self, poly: Poly) -> frozenset:
        """The negative powers common to every term (largest, i.e. the common denominator)."""
        common = None
        for m in poly:
            neg = {f: p for f, p in m if p < 0}
            if common is None:
                common = neg
            else:
                common = {f: max(p, neg[f]) for f, p in common.items() if f in neg}
            if not common:
                return frozenset()
        return self.monomial(common or {})

    def divide(self, poly: Poly, number, mono: tuple) -> Poly:
        out = {}
        exact = _exact(number)
        for m, c in poly.items():
            if mono:
                powers = dict(m)
                for f, p in mono:
                    powers[f] = powers.get(f, 0) - p
                m = frozenset((f, p) for f, p in powers.items() if p)
            if number == 1:
                out[m] = c
            elif exact and _exact(c):
                out[m] = _norm(Fraction(c) / number)
            else:
                out[m] = c / float(number)
        return out
