"""Typesetting of the readable equations: monomials, sums and equation sides as text or LaTeX
(the printing half of :class:`~nonideal.equations.readable.Printer`; the expansion, folding
and factoring are in :mod:`nonideal.equations.readable`)."""

from __future__ import annotations

from fractions import Fraction

import symengine as se

__all__ = ["Typesetting"]

Poly = dict   # monomial (frozenset of (factor, power)) -> coefficient


class Typesetting:
    """Mixin of :class:`~nonideal.equations.readable.Printer`: everything that turns its
    polynomials into strings."""

    # ------------------------------------------------------------------ printing
    def _fmt_number(self, c, latex: bool) -> str:
        if isinstance(c, int):
            return str(c)
        if isinstance(c, Fraction):
            if c.denominator == 1:
                return str(c.numerator)
            if latex:
                return r"\frac{%d}{%d}" % (c.numerator, c.denominator)
            return f"{c.numerator}/{c.denominator}"
        if c == 0:
            return "0"
        if float(c).is_integer() and abs(c) < 1e15:
            return repr(float(c))
        return repr(float(c))

    def _fmt_factor(self, f, p: int, latex: bool) -> str:
        kind = f[0]
        if kind == "s":
            base = self._lx(f[1]) if latex else f[1]
            if latex and p != 1:
                if base.startswith("\\dot") or base.startswith("\\ddot") or "_" in base:
                    base = "{" + base + "}"
        elif kind in ("sin", "cos"):
            arg = self._fmt_lin(f[1], latex)
            if latex:
                head = "\\" + kind + (f"^{{{p}}}" if p != 1 else "")
                return head + r"\left(" + arg + r"\right)"
            base = f"{kind}({arg})"
        else:
            base = self._fmt_atom(f[1], latex)
        if p == 1:
            return base
        if isinstance(p, Fraction):
            if p == Fraction(1, 2):
                if latex:
                    return r"\sqrt{" + self._strip(base, latex) + "}"
                return "sqrt(" + self._strip(base, latex) + ")"
            if latex:
                return f"{base}^{{{p.numerator}/{p.denominator}}}"
            return f"{base}**({p.numerator}/{p.denominator})"
        if latex:
            return f"{base}^{{{p}}}"
        return f"{base}**{p}"

    @staticmethod
    def _strip(text: str, latex: bool) -> str:
        if latex and text.startswith(r"\left(") and text.endswith(r"\right)"):
            return text[6:-7]
        if not latex and text.startswith("(") and text.endswith(")"):
            return text[1:-1]
        return text

    def _fmt_atom(self, expr, latex: bool) -> str:
        if latex:
            import sympy as sp

            from ..modeling.symbols import to_sp

            e = to_sp(expr)
            names = {s: self._lx(s.name) for s in e.free_symbols}
            text = sp.latex(e, symbol_names=names)
            return text if isinstance(expr, (se.Symbol, se.Function)) else r"\left(" + text + r"\right)"
        text = str(expr)
        if isinstance(expr, (se.Add, se.Mul)):
            return "(" + text + ")"
        return text

    def _fmt_lin(self, lin: tuple, latex: bool) -> str:
        out = ""
        for i, (n, c) in enumerate(lin):
            name = self._lx(n) if latex else n
            mag = abs(c)
            term = name if mag == 1 else (self._fmt_number(mag, latex) + ("" if latex else "*") + name)
            if i == 0:
                out = ("-" if c < 0 else "") + term
            else:
                out += (" - " if c < 0 else " + ") + term
        return out

    def _fmt_mono(self, m: tuple, latex: bool, inner: str | None = None) -> str:
        """A monomial without its number; *inner* (a parenthesized sum) is placed before the
        state-dependent factors."""
        m = self.ordered(m)
        num = [(f, p) for f, p in m if p > 0]
        den = [(f, -p) for f, p in m if p < 0]
        params = [(f, p) for f, p in num if self.key(f)[0] <= 1]
        state = [(f, p) for f, p in num if self.key(f)[0] > 1]
        sep = " " if latex else "*"
        parts = [self._fmt_factor(f, p, latex) for f, p in params]
        if inner is not None:
            parts.append(inner)
        parts += [self._fmt_factor(f, p, latex) for f, p in state]
        top = sep.join(parts)
        if not den:
            return top
        bottom = sep.join(self._fmt_factor(f, p, latex) for f, p in den)
        if latex:
            return r"\frac{" + (top or "1") + "}{" + bottom + "}"
        if len(den) > 1:
            bottom = "(" + bottom + ")"
        return (top or "1") + "/" + bottom

    def _signed(self, c, body: str, latex: bool) -> tuple[bool, str]:
        """(negative, text) of c * body, the sign apart."""
        neg = c < 0
        mag = -c if neg else c
        if body == "":
            return neg, self._fmt_number(mag, latex)
        if mag == 1:
            return neg, body
        if latex:
            return neg, self._fmt_number(mag, latex) + " " + body
        if isinstance(mag, int) and body.startswith("1/"):
            return neg, f"{mag}{body[1:]}"
        if isinstance(mag, Fraction):
            head = "" if mag.numerator == 1 else f"{mag.numerator}*"
            return neg, f"{head}{body}/{mag.denominator}"
        return neg, self._fmt_number(mag, latex) + "*" + body

    @staticmethod
    def _join(terms: list[tuple[bool, str]], latex: bool) -> str:
        if not terms:
            return "0"
        out = ""
        for i, (neg, text) in enumerate(terms):
            if i == 0:
                out = ("-" if neg else "") + text
            else:
                out += (" - " if neg else " + ") + text
        return out

    def _state_part(self, m: tuple) -> tuple[tuple, tuple]:
        params = frozenset((f, p) for f, p in m if self.key(f)[0] <= 1 and p > 0)
        return params, m - params

    def _sum_terms(self, poly: Poly, latex: bool) -> list[tuple[bool, str]]:
        """Terms of a polynomial, grouped the way that gives fewer terms: by their
        state-dependent part, each coefficient (a polynomial in the parameters) factored --
        ``-g*l1*(m1 + m2)*sin(q1)`` -- or by their parameters and denominator, each numerator
        (a polynomial in the state) in parentheses -- ``m1*mu_2*(y - y1)/(x1 - x)``."""
        by_state: dict[frozenset, Poly] = {}
        by_params: dict[frozenset, Poly] = {}
        for m, c in poly.items():
            params, state = self._state_part(m)
            by_state.setdefault(state, {})[params] = c
            den = frozenset((f, p) for f, p in state if p < 0)
            by_params.setdefault(params | den, {})[state - den] = c
        order = lambda s: tuple(self.key(f) + (p,) for f, p in self.ordered(s))  # noqa: E731
        if len(by_params) < len(by_state):
            return [self._product(by_params[k], k, latex) for k in sorted(by_params, key=order)]
        return [self._product(by_state[k], k, latex) for k in sorted(by_state, key=order)]

    def _product(self, coeff: Poly, state: tuple, latex: bool) -> tuple[bool, str]:
        """c(params) * state-monomial, with c factored."""
        if len(coeff) == 1:
            (m, c), = coeff.items()
            return self._signed(c, self._fmt_mono(self.monomial({**dict(m), **dict(state)}), latex), latex)
        number, common = self.content(coeff)
        rest = self.divide(coeff, number, common)
        inner_terms = []
        for m in sorted(rest, key=lambda m: tuple(self.key(f) + (-p,) for f, p in self.ordered(m))):
            inner_terms.append(self._signed(rest[m], self._fmt_mono(m, latex), latex))
        inner = self._join(inner_terms, latex)
        inner = (r"\left(" + inner + r"\right)") if latex else "(" + inner + ")"
        head = self.monomial({**dict(common), **dict(state)})
        if not head and number == 1:
            return False, inner[len(r"\left("):-len(r"\right)")] if latex else inner[1:-1]
        body = self._fmt_mono(head, latex, inner=inner)
        return self._signed(number, body, latex)

    def text(self, poly: Poly, latex: bool = False) -> str:
        """A polynomial, folded, grouped and factored."""
        return self._join(self._sum_terms(poly, latex), latex)

    def expression(self, expr, latex: bool = False) -> str:
        """Readable text (or LaTeX) of one SymEngine/SymPy expression."""
        return self.text(self.fold(self.poly(expr)), latex)

    # ------------------------------------------------------------------ equations
    def side(self, poly: Poly, latex: bool = False) -> str:
        """One side of an equation: its common factor, then accelerations, products of
        velocities, multipliers and the rest, each with its (factored) coefficient."""
        if not poly:
            return "0"
        number, common = self.content(poly)
        if len(poly) == 1:
            return self.text(poly, latex)
        if len({self._state_part(m)[1] for m in poly}) == 1:
            return self.text(poly, latex)       # one state-dependent part: c(params)*part
        if not common and abs(number) == 1:
            number = 1                          # a lone minus sign is not pulled out
        rest = self.divide(poly, number, common)
        groups: dict[tuple, Poly] = {}
        for m, c in rest.items():
            gkey, factor, coeff_m = self._group_of(m)
            groups.setdefault((gkey, factor), {})[coeff_m] = c
        terms = []
        for (gkey, factor) in sorted(groups, key=lambda g: g[0]):
            coeff = groups[(gkey, factor)]
            if gkey[0] == 9:                    # the forces: grouped by state part
                terms += self._sum_terms(coeff, latex)
                continue
            fmono = self._fmt_mono(factor, latex)
            if len(coeff) == 1:
                (m, c), = coeff.items()
                terms.append(self._signed(c, self._fmt_mono(m | factor, latex), latex))
                continue
            den = self.denominator(coeff)
            if den:
                coeff = self.divide(coeff, 1, den)
            sub = self._sum_terms(coeff, latex)
            if len(sub) == 1 and not den:
                neg, t = sub[0]
                if not self._grouped(t, latex):
                    t = (r"\left(" + t + r"\right)") if latex else "(" + t + ")"
                terms.append((neg, t + (" " if latex else "*") + fmono))
            elif len(sub) == 1 and self._grouped(sub[0][1], latex):
                neg, t = sub[0]
                terms.append((neg, self._fmt_mono(factor | den, latex, inner=t)))
            else:
                inner = self._join(sub, latex)
                inner = (r"\left(" + inner + r"\right)") if latex else "(" + inner + ")"
                terms.append((False, self._fmt_mono(factor | den, latex, inner=inner)))
        body = self._join(terms, latex)
        if number == 1 and not common:
            return body
        if len(terms) > 1 or terms[0][0] or not self._grouped(body, latex):   # (one term may be a sum)
            body = (r"\left(" + body + r"\right)") if latex else "(" + body + ")"
        head = self._fmt_mono(common, latex)
        core = (head + (" " if latex else "*") + body) if head else body
        neg, t = self._signed(number, core, latex)
        return ("-" if neg else "") + t

    @staticmethod
    def _grouped(text: str, latex: bool) -> bool:
        """Whether *text* is a product (no sum at its top level)."""
        if " + " not in text and " - " not in text:
            return True
        depth = 0
        opening, closing = (r"\left(", r"\right)") if latex else ("(", ")")
        i = 0
        while i < len(text):
            if text.startswith(opening, i):
                depth += 1
                i += len(opening)
                continue
            if text.startswith(closing, i):
                depth -= 1
                i += len(closing)
                continue
            if depth == 0 and text[i] in "+-" and i > 0 and text[i - 1] == " ":
                return False
            i += 1
        return True

    def _group_of(self, m: tuple):
        """(group key, group monomial, remaining monomial) of one term."""
        acc = [(f, p) for f, p in m if f[0] == "s" and self.key(f)[0] == 7]
        vel = [(f, p) for f, p in m if f[0] == "s" and self.key(f)[0] == 6]
        mul = [(f, p) for f, p in m if f[0] == "s" and self.key(f)[0] == 8]
        if len(acc) == 1 and acc[0][1] == 1:
            group = acc
            gkey = (0, self.key(acc[0][0]))
        elif acc:
            group, gkey = [], (9,)
        elif mul and len(mul) == 1 and mul[0][1] == 1:
            group = mul
            gkey = (10, self.key(mul[0][0]))
        elif vel:
            group = vel
            gkey = (1, sum(p for _, p in vel), tuple(self.key(f) + (-p,) for f, p in self.ordered(vel)))
        else:
            group, gkey = [], (9,)
        gset = frozenset(group)
        return gkey, gset, m - gset
