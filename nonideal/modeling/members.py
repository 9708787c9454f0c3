"""Elastic members: a beam or a rod of the system whose deformation is expanded in
Bubnov–Galerkin shape functions whose amplitudes become generalized coordinates.

A member is a uniform straight Euler–Bernoulli beam (bending), a rod (longitudinal
vibration) or a shaft (torsion) along the x axis of a frame, from a point of the system
(``[[members]] frame``, ``origin``; by default the fixed frame ``N`` and its origin ``O``).
Its deformation is ``w(x, t) = sum_k a_k(t) phi_k(x / L)`` with ``N`` admissible functions
``phi_k`` (they satisfy the geometric boundary conditions: deflection and slope at a clamped
end, deflection at a pinned one, the displacement at a fixed end of a rod); the amplitudes
``a_k`` are the coordinates ``<name>_1 ... <name>_N``.  The library forms the member's kinetic
and potential energies by exact integration over the length (SymPy), so the member enters every
form of the equations (Lagrange I and II, Kane, Appell, ...) as any body does.  Lagrange's
equations of the energies so formed are the Bubnov–Galerkin equations of the member (the
generalized Gauss principle applied to the approximating family: Yushkov 1999, appendix E), and
the natural frequencies of the linearization are Rayleigh–Ritz upper bounds that decrease as
``N`` grows (Meirovitch 1967, ch. 5; 2001, §8.5).

Energies (mu = mass per length, ``V``, ``W`` velocity of the origin and angular velocity of
the frame, ``e1`` the member's axis, ``e2`` the deflection direction; a point of a beam is at
``r(x) = P + (x + u_c) e1 + w e2`` with the shortening ``u_c = -1/2 int_0^x w'^2 ds``)::

    T = 1/2 int mu |v(x)|^2 dx        (beam: to second order in a, a')
    V = 1/2 int EI w''^2 dx - int mu g . r(x) dx

The shortening gives the rotating beam its centrifugal stiffening (Kane, Ryan & Banerjee 1987)
and a hanging or standing beam its stiffening or softening by its own weight; the beam's
energy is exact to second order in the amplitudes, so its linearization is exact for the
Galerkin model (the large-deflection equations are not a target).  A rod ``r(x) = P + (x + u)
e1`` and a shaft (twist ``theta`` about e1, polar inertia ``rho J`` per length: ``T = 1/2 int
rho J (W . e1 + theta')^2 dx``) are exact.

Shapes: ``"polynomial"`` (``xi^p0 (1 - xi)^p1 P_(k-1)(2 xi - 1)``, ``p`` = 2 clamped, 1 pinned
or fixed, 0 free, ``P_j`` Legendre's polynomials: the polynomials of degree ``< p0 + p1 + N``
with the end conditions, in a basis far better conditioned than the monomials; rigid motions
included where the ends allow them) or ``"modes"`` (the exact
modes of the uniform member with the same ends where they are trigonometric: every rod and
shaft, the pinned–pinned beam).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import sympy as sp
from sympy.simplify.fu import TR8

from ..errors import did_you_mean
from .symbols import is_identifier

__all__ = ["Member", "MEMBER_KINDS", "END_CONDITIONS", "SHAPES", "MemberExpansion", "shape_functions",
           "member_matrices", "read_members", "MEMBER_KEYS"]

MEMBER_KINDS = ("beam", "rod", "shaft")
END_CONDITIONS = {"beam": ("clamped", "pinned", "free"), "rod": ("fixed", "free"),
                  "shaft": ("fixed", "free")}
SHAPES = ("polynomial", "modes")
#: the stiffness each kind takes (the key of a model file)
STIFFNESS = {"beam": "bending_stiffness", "rod": "axial_stiffness", "shaft": "torsional_stiffness"}
#: [[members]]: the stiffness key names the kind's stiffness (EI, EA, GJ)
MEMBER_KEYS = {"name", "kind", "length", "mass_per_length", "inertia_per_length", "bending_stiffness",
               "axial_stiffness", "torsional_stiffness", "ends", "modes", "shape", "frame", "origin",
               "deflection", "points", "description"}
#: the highest number of shape functions: monomials beyond it make the mass matrix too
#: ill-conditioned for double precision eigenvalues
MAX_MODES = 16
#: the order of zero of the polynomial shapes at an end
_ZERO_ORDER = {"clamped": 2, "pinned": 1, "fixed": 1, "free": 0}
XI = sp.Symbol("xi", real=True)


@dataclass(frozen=True)
class Member:
    """An elastic member of the system (see the module docstring).

    Parameters
    ----------
    name : str
        Its amplitudes are the coordinates ``<name>_1 ... <name>_<modes>``.
    kind : {"beam", "rod", "shaft"}
    length : expression in the parameters
    stiffness : expression in the parameters
        EI (beam), EA (rod) or GJ (shaft).
    ends : (str, str)
        The conditions at ``x = 0`` and ``x = L``: ``"clamped"``, ``"pinned"``, ``"free"``
        (beam), ``"fixed"``, ``"free"`` (rod, shaft).  An end at ``x = 0`` is attached to
        ``origin`` in ``frame``.
    modes : int
        The number N of shape functions (1 to 16).
    mass_per_length : expression, optional
        rho A: required for a beam and a rod; for a shaft, the mass of its axis (rigid).
    inertia_per_length : expression, optional
        rho J, the polar moment of inertia per length (shaft).
    shape : {"polynomial", "modes"}
    frame : str
        The frame whose x axis the member lies along (default ``"N"``).
    origin : str
        The point where ``x = 0`` (default ``"O"``).
    deflection : {"y", "z"}
        The axis of ``frame`` a beam deflects along.
    points : mapping name -> expression
        Material points of the member at a distance ``x`` (expression in the parameters)
        from the origin: points of the model usable as ``[[points]]`` are (``pos(tip)``,
        ``vel(tip)``, a particle at ``point = "tip"``).
    description : str

    Examples
    --------
    >>> Member("beam", "beam", "L", "EI", ("clamped", "free"), 3, mass_per_length="rho_A").coordinates
    ('beam_1', 'beam_2', 'beam_3')
    """

    name: str
    kind: str
    length: Any
    stiffness: Any
    ends: tuple[str, str]
    modes: int
    mass_per_length: Any = None
    inertia_per_length: Any = None
    shape: str = "polynomial"
    frame: str = "N"
    origin: str = "O"
    deflection: str = "y"
    points: Mapping[str, Any] = field(default_factory=dict)
    description: str = ""

    def __post_init__(self):
        if isinstance(self.ends, list):
            object.__setattr__(self, "ends", tuple(self.ends))
        object.__setattr__(self, "points", dict(self.points or {}))

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The amplitudes' names."""
        n = self.modes if isinstance(self.modes, int) and not isinstance(self.modes, bool) else 0
        return tuple(f"{self.name}_{k}" for k in range(1, n + 1))

    def problems(self) -> list[str]:
        """What is wrong with the declaration's structure (empty when nothing)."""
        where = f"member '{self.name}'"
        out = []
        if not isinstance(self.name, str) or not is_identifier(self.name):
            return [f"member {self.name!r}: name must be an identifier (letters, digits, _)"]
        if self.kind not in MEMBER_KINDS:
            return [f"{where}: kind '{self.kind}' unknown{did_you_mean(str(self.kind), MEMBER_KINDS)}; "
                    f"choose one of {', '.join(MEMBER_KINDS)}"]
        allowed = END_CONDITIONS[self.kind]
        if not (isinstance(self.ends, tuple) and len(self.ends) == 2):
            out.append(f"{where}: ends must be two conditions [at x = 0, at x = L], each one of "
                       f"{', '.join(allowed)} (got {self.ends!r})")
        else:
            for end in self.ends:
                if end not in allowed:
                    out.append(f"{where}: end condition '{end}' is not one of a {self.kind}'s "
                               f"({', '.join(allowed)}){did_you_mean(str(end), allowed)}")
        if not isinstance(self.modes, int) or isinstance(self.modes, bool) or not 1 <= self.modes <= MAX_MODES:
            out.append(f"{where}: modes must be a whole number from 1 to {MAX_MODES} (got {self.modes!r}); "
                       "more shape functions make the mass matrix too ill-conditioned for double precision")
        if self.shape not in SHAPES:
            out.append(f"{where}: shape '{self.shape}' unknown{did_you_mean(str(self.shape), SHAPES)}; "
                       f"choose one of {', '.join(SHAPES)}")
        if self.kind in ("beam", "rod") and self.mass_per_length is None:
            out.append(f"{where}: a {self.kind} needs mass_per_length (rho A)")
        if self.kind == "shaft" and self.inertia_per_length is None:
            out.append(f"{where}: a shaft needs inertia_per_length (rho J, the polar moment of "
                       "inertia per unit length)")
        if self.kind != "shaft" and self.inertia_per_length is not None:
            out.append(f"{where}: inertia_per_length belongs to a shaft (torsion); a {self.kind} "
                       "takes mass_per_length")
        if self.deflection not in ("y", "z") or (self.kind != "beam" and self.deflection != "y"):
            out.append(f"{where}: deflection must be \"y\" or \"z\" (the axis of frame '{self.frame}' "
                       "a beam deflects along; a rod and a shaft lie along x)")
        for key in ("frame", "origin"):
            if not isinstance(getattr(self, key), str):
                out.append(f"{where}: {key} must be a name (got {getattr(self, key)!r})")
        for p in self.points:
            if not isinstance(p, str) or not is_identifier(p):
                out.append(f"{where}: points: {p!r} is not a valid point name")
        if not out and self.shape == "modes":
            try:
                shape_functions(self.kind, self.ends, self.modes, self.shape)
            except ValueError as exc:
                out.append(f"{where}: {exc}")
        return out


def shape_functions(kind: str, ends: tuple[str, str], n: int, shape: str) -> list[sp.Expr]:
    """The N admissible functions of ``xi = x / L`` on [0, 1] (see the module docstring).

    Examples
    --------
    >>> shape_functions("beam", ("clamped", "free"), 2, "polynomial")
    [xi**2, 2*xi**3 - xi**2]
    >>> shape_functions("rod", ("fixed", "free"), 2, "modes")
    [sin(pi*xi/2), sin(3*pi*xi/2)]
    """
    if shape == "polynomial":
        p0, p1 = _ZERO_ORDER[ends[0]], _ZERO_ORDER[ends[1]]
        return [sp.expand(XI ** p0 * (1 - XI) ** p1 * sp.legendre(k, 2 * XI - 1)) for k in range(n)]
    pi, k = sp.pi, range(1, n + 1)
    if kind == "beam":
        if ends == ("pinned", "pinned"):
            return [sp.sin(j * pi * XI) for j in k]
        raise ValueError(f"the exact modes of a beam {ends[0]} and {ends[1]} are not trigonometric "
                         "(only the pinned-pinned beam's are); use shape = \"polynomial\"")
    return {("fixed", "free"): [sp.sin((2 * j - 1) * pi * XI / 2) for j in k],
            ("free", "fixed"): [sp.cos((2 * j - 1) * pi * XI / 2) for j in k],
            ("fixed", "fixed"): [sp.sin(j * pi * XI) for j in k],
            ("free", "free"): [sp.cos((j - 1) * pi * XI) for j in k]}[tuple(ends)]


def _integral(f) -> sp.Expr:
    """``int_0^1 f dxi``, exact: a polynomial by its coefficients, a trigonometric product
    by the product-to-sum formulas and the integrals of ``xi^n cos(a xi)``, ``xi^n sin(a xi)``
    (a few distinct ones, each computed once)."""
    if isinstance(f, sp.Poly):
        return f.integrate().eval(1)
    total = sp.Integer(0)
    for term in sp.Add.make_args(sp.expand(TR8(sp.expand(f)))):
        c, g = term.as_independent(XI, as_Add=False)
        total += c * _elementary(g)
    return sp.nsimplify(total) if total.is_Rational else total


@lru_cache(maxsize=None)
def _elementary(g: sp.Expr) -> sp.Expr:
    """``int_0^1 xi^n f(a xi)`` for ``f`` = 1, cos or sin (by parts, recursively)."""
    n, f, a = 0, None, sp.Integer(0)
    for factor, power in g.as_powers_dict().items():
        if factor == XI:
            n = int(power)
        elif isinstance(factor, (sp.cos, sp.sin)) and power == 1 and f is None:
            f, a = type(factor), sp.cancel(factor.args[0] / XI)
        elif factor != 1:
            return sp.integrate(g, (XI, 0, 1))
    return _by_parts(n, f, a)


def _by_parts(n: int, f, a) -> sp.Expr:
    if f is None or a == 0:
        return sp.Rational(1, n + 1) if f in (None, sp.cos) else sp.Integer(0)
    if f is sp.cos:
        return sp.sin(a) / a - (n * _by_parts(n - 1, sp.sin, a) / a if n else 0)
    return -sp.cos(a) / a + (n * _by_parts(n - 1, sp.cos, a) / a if n else 1 / a)


def _primitive(f) -> sp.Expr:
    """``int_0^xi f`` as a function of ``xi``."""
    if isinstance(f, sp.Poly):
        return f.integrate().as_expr()
    s = sp.Symbol("s", real=True)
    return sp.integrate(f.subs(XI, s), (s, 0, XI))


def member_matrices(kind: str, phis: list[sp.Expr]) -> dict[str, sp.Matrix]:
    """The dimensionless integrals over ``xi`` in [0, 1], exact:

    ``m = int phi phi^T``, ``k = int phi'' phi''^T`` (beam) or ``int phi' phi'^T`` (rod,
    shaft), ``c = int phi``, ``d = int xi phi``, ``g0 = int (1 - xi) phi' phi'^T``,
    ``g1 = int (1 - xi^2)/2 phi' phi'^T`` (the beam's shortening).

    Examples
    --------
    >>> member_matrices("beam", [XI**2])["k"]
    Matrix([[4]])
    """
    n = len(phis)
    if all(p.is_polynomial(XI) for p in phis):
        phis = [sp.Poly(p, XI, domain="QQ") for p in phis]
        one, xi = sp.Poly(1, XI, domain="QQ"), sp.Poly(XI, XI, domain="QQ")
        d1 = [p.diff(XI) for p in phis]
    else:
        one, xi = sp.Integer(1), XI
        d1 = [sp.diff(p, XI) for p in phis]
    dk = [sp.diff(p, XI) for p in d1] if kind == "beam" else d1
    sym = lambda f: sp.Matrix(n, n, lambda i, j: _integral(f(i, j)) if i <= j else 0)  # noqa: E731
    out = {"m": sym(lambda i, j: phis[i] * phis[j]), "k": sym(lambda i, j: dk[i] * dk[j])}
    if kind == "beam":
        out["g0"] = sym(lambda i, j: (one - xi) * d1[i] * d1[j])
        out["g1"] = sym(lambda i, j: (one - xi * xi) * d1[i] * d1[j] * sp.Rational(1, 2))
    for key, M in list(out.items()):
        out[key] = M + M.T - sp.diag(*[M[i, i] for i in range(n)])
    out["c"] = sp.Matrix([_integral(p) for p in phis])
    out["d"] = sp.Matrix([_integral(xi * p) for p in phis])
    return out


def _quad(a, M, b) -> sp.Expr:
    return sp.Add(*[M[i, j] * a[i] * b[j] for i in range(len(a)) for j in range(len(b)) if M[i, j] != 0])


def _lin(c, a) -> sp.Expr:
    return sp.Add(*[ci * ai for ci, ai in zip(c, a)])


class MemberExpansion:
    """The members of a model turned into coordinates, points and energies, in three steps
    of the normalization (:class:`~nonideal.modeling.normalize.Normalizer` calls them): the
    coordinates before the parameters are read, the points before the kinematics, the energies
    with the other energies."""

    def __init__(self, members, problems: list[str]):
        self.problems = problems
        self.members: list[Member] = []
        self.data: dict[str, dict] = {}
        names: set[str] = set()
        for m in members:
            if isinstance(m, Mapping):
                m = Member(**m)
            if not isinstance(m, Member):
                problems.append(f"members: {m!r} is not a Member")
                continue
            more = m.problems()
            if m.name in names:
                more.append(f"member '{m.name}': duplicate member name")
            names.add(m.name)
            problems.extend(more)
            if not more:
                self.members.append(m)

    # -- step 1
    def coordinates(self, coordinates: tuple[str, ...]) -> tuple[str, ...]:
        """The model's coordinates followed by every member's amplitudes."""
        out = list(coordinates)
        for m in self.members:
            for c in m.coordinates:
                if c in out:
                    self.problems.append(f"member '{m.name}': its amplitude '{c}' is also a coordinate "
                                         "of [coordinates]; remove it there (a member adds its own)")
                else:
                    out.append(c)
        return tuple(out)

    def initial(self, initial: Mapping[str, Any]) -> dict[str, Any]:
        """Undeformed and at rest relative to its base unless ``[initial]`` says otherwise."""
        out = dict(initial)
        for m in self.members:
            for c in m.coordinates:
                out.setdefault(c, 0)
                out.setdefault(c + "'", 0)
        return out

    # -- step 2
    def points(self, norm) -> list:
        """The members' material points as :class:`~nonideal.modeling.points.Point` (with the
        parameters read), and each member's constants."""
        from .points import Point

        out = []
        values = {sp.Symbol(k): p.value for k, p in norm.m.parameters.items()}
        frames = ["N", *(getattr(f, "name", "") for f in norm.m.frames)]
        points = ["O", *(getattr(p, "name", "") for p in norm.m.points), *(p for m in self.members for p in m.points)]
        for m in self.members:
            where = f"member '{m.name}'"
            for key, value, known, table in (("frame", m.frame, frames, "[[frames]]"),
                                              ("origin", m.origin, points, "[[points]]")):
                if value not in known:
                    self.problems.append(f"{where}: {key} '{value}' is not declared{did_you_mean(value, known)}; "
                                         f"declare it in {table}")
            if m.frame not in frames or m.origin not in points:
                continue
            length = self._constant(norm, m.length, f"{where}: length")
            if length is not None and not float(length.xreplace(values)) > 0:
                self.problems.append(f"{where}: length must be positive (got {float(length.xreplace(values)):g})")
                length = None
            stiff = self._constant(norm, m.stiffness, f"{where}: {STIFFNESS[m.kind]}")
            mu = self._constant(norm, m.mass_per_length, f"{where}: mass_per_length") \
                if m.mass_per_length is not None else sp.Integer(0)
            rho_j = self._constant(norm, m.inertia_per_length, f"{where}: inertia_per_length") \
                if m.inertia_per_length is not None else sp.Integer(0)
            for what, e in ((STIFFNESS[m.kind], stiff), ("mass_per_length", mu),
                            ("inertia_per_length", rho_j)):
                if e is not None and float(e.xreplace(values)) < 0:
                    self.problems.append(f"{where}: {what} must not be negative")
            if None in (length, stiff, mu, rho_j):
                continue
            phis = shape_functions(m.kind, m.ends, m.modes, m.shape)
            q = [sp.Symbol(c) for c in m.coordinates]
            self.data[m.name] = dict(L=length, stiff=stiff, mu=mu, rho_j=rho_j, phis=phis, q=q,
                                     qd=[sp.Symbol(c + "'") for c in m.coordinates],
                                     mats=member_matrices(m.kind, phis))
            for pname, loc in m.points.items():
                x = self._constant(norm, loc, f"{where}: points.{pname}")
                if x is None:
                    continue
                if not 0 <= float(x.xreplace(values)) <= float(length.xreplace(values)):
                    self.problems.append(f"{where}: points.{pname} = {loc} lies outside the member "
                                         f"(0 <= x <= length)")
                    continue
                xi = x / length
                w = sp.Add(*[a * p.subs(XI, xi) for a, p in zip(q, phis)])
                axial = [x, 0, 0]
                if m.kind == "beam":
                    dphi = [sp.Poly(sp.diff(p, XI), XI, domain="QQ") if p.is_polynomial(XI) else sp.diff(p, XI)
                            for p in phis]
                    s = [[_primitive(dphi[i] * dphi[j]) for j in range(len(q))] for i in range(len(q))]
                    uc = -sp.Add(*[q[i] * q[j] * s[i][j].subs(XI, xi) for i in range(len(q))
                                   for j in range(len(q))]) / (2 * length)
                    axial[0] = x + uc
                    axial[1 if m.deflection == "y" else 2] = w
                elif m.kind == "rod":
                    axial[0] = x + w
                out.append(Point(pname, tuple(sp.sympify(c) for c in axial), m.frame, m.origin))
        return out

    def _constant(self, norm, value, where: str):
        e = norm.expr(value, where, 0)
        if e is None:
            return None
        live = e.free_symbols - set(norm.m.parameter_symbols)
        if live:
            self.problems.append(f"{where}: must be a constant (parameters only; got "
                                 f"{', '.join(sorted(map(str, live)))})")
            return None
        return e

    # -- step 3
    def energies(self, norm) -> tuple[sp.Expr, sp.Expr]:
        """``(T, V)`` of every member (see the module docstring)."""
        T, V = sp.Integer(0), sp.Integer(0)
        g = tuple(norm.m.gravity or ())
        g = tuple(g) + (sp.Integer(0),) * (3 - len(g)) if g else ()
        for m in self.members:
            if m.name not in self.data:
                continue
            dT, dV = self._energy(norm, m, self.data[m.name], g)
            T += dT
            V += dV
        return T, V

    def _energy(self, norm, m: Member, d: dict, g: tuple) -> tuple[sp.Expr, sp.Expr]:
        where = f"member '{m.name}'"
        L, mu, q, qd, M = d["L"], d["mu"], d["q"], d["qd"], d["mats"]
        F, P = m.frame, m.origin
        e1, e2 = f"{F}.x", f"{F}.{m.deflection}"
        moving = not (F == "N" and P == "O")

        def s(text: str, order: int = 1) -> sp.Expr:
            e = norm.expr(text, f"{where}: {text}", order)
            return e if e is not None else sp.Integer(0)

        W1, W2 = f"cross(omega({F}), {e1})", f"cross(omega({F}), {e2})"
        rigid_T = sp.Integer(0)
        if moving:   # the member moving as a rigid body with its frame
            rigid_T = mu * (L * s(f"dot(vel({P}), vel({P}))") + L ** 2 * s(f"dot(vel({P}), {W1})")
                            + L ** 3 / 3 * s(f"dot({W1}, {W1})")) / 2
        gdot = (lambda text: sp.Add(*[gk * s(f"dot({text}, N.{ax})", 0) for gk, ax in zip(g, "xyz") if gk != 0])) \
            if g else (lambda text: sp.Integer(0))
        rigid_V = -mu * (L * gdot(f"pos({P})") + L ** 2 / 2 * gdot(e1)) if moving or g else sp.Integer(0)
        if m.kind == "shaft":
            rj = d["rho_j"]
            c = L * M["c"]
            spin = s(f"dot(omega({F}), {e1})") if moving else sp.Integer(0)
            T = rigid_T + rj * (L * spin ** 2 + 2 * spin * _lin(c, qd) + L * _quad(qd, M["m"], qd)) / 2
            V = rigid_V + d["stiff"] / L * _quad(q, M["k"], q) / 2
            return T, V
        Mm, c, dd = mu * L * M["m"], mu * L * M["c"], mu * L ** 2 * M["d"]
        if m.kind == "rod":
            K = d["stiff"] / L * M["k"]
            T = rigid_T + _quad(qd, Mm, qd) / 2
            if moving:
                T += (s(f"dot(vel({P}), {W1})") * _lin(c, q) + s(f"dot({W1}, {W1})") * (2 * _lin(dd, q) + _quad(q, Mm, q)) / 2
                      + s(f"dot(vel({P}), {e1})") * _lin(c, qd))
            V = rigid_V + _quad(q, K, q) / 2 - _lin(c, q) * gdot(e1)
            return T, V
        K = d["stiff"] / L ** 3 * M["k"]
        G0, G1 = mu * M["g0"], mu * L * M["g1"]
        T = rigid_T + _quad(qd, Mm, qd) / 2
        if moving:
            T += (_lin(c, q) * s(f"dot(vel({P}), {W2})") + _lin(c, qd) * s(f"dot(vel({P}), {e2})")
                  + _lin(dd, q) * s(f"dot({W1}, {W2})") + _lin(dd, qd) * s(f"dot({W1}, {e2})")
                  + _quad(q, Mm, q) * s(f"dot({W2}, {W2})") / 2
                  - _quad(q, G0, q) * s(f"dot(vel({P}), {W1})") / 2
                  - _quad(q, G0, qd) * s(f"dot(vel({P}), {e1})")
                  - _quad(q, G1, q) * s(f"dot({W1}, {W1})") / 2)
        V = rigid_V + _quad(q, K, q) / 2 - _lin(c, q) * gdot(e2) + _quad(q, G0, q) * gdot(e1) / 2
        return T, V


def read_members(tables: list, check, problems: list[str]) -> tuple:
    """``[[members]]`` as :class:`~nonideal.modeling.members.Member` declarations (the types of
    the values checked here, their meaning by the model)."""
    from .filechecks import describe, unknown_keys

    out = []
    for k, b in enumerate(tables):
        where = f"[[members]] #{k + 1}" + (f" '{b.get('name')}'" if "name" in b else "")
        problems.extend(unknown_keys(b, MEMBER_KEYS, where))
        ok = check.name(b, where)
        kind = b.get("kind")
        if kind not in STIFFNESS:
            problems.append(f"{where}: kind must be one of {', '.join(STIFFNESS)} (got {describe(kind)})"
                            + did_you_mean(str(kind), STIFFNESS))
            continue
        for key in ("length", STIFFNESS[kind], "modes", "ends"):
            if key not in b:
                problems.append(f"{where}: missing {key}")
                ok = False
        for key in set(STIFFNESS.values()) - {STIFFNESS[kind]}:
            if key in b:
                problems.append(f"{where}: {key} is not a {kind}'s stiffness; a {kind} takes "
                                f"{STIFFNESS[kind]}")
                ok = False
        for key in ("length", STIFFNESS[kind], "mass_per_length", "inertia_per_length"):
            ok &= check.expr(b, key, where) if key in b else True
        for key in ("kind", "shape", "frame", "origin", "deflection"):
            if key in b and not isinstance(b[key], str):
                problems.append(f"{where}: {key} must be a string (got {describe(b[key])})")
                ok = False
        if "ends" in b and not (isinstance(b["ends"], list) and all(isinstance(e, str) for e in b["ends"])):
            problems.append(f"{where}: ends must be a list of two strings [at x = 0, at x = length], "
                            f"e.g. [\"clamped\", \"free\"] (got {describe(b['ends'])})")
            ok = False
        pts = b.get("points", {})
        if not isinstance(pts, dict):
            problems.append(f"{where}: points must be a table name = distance from the origin, e.g. "
                            f"points = {{ tip = \"L\" }} (got {describe(pts)})")
            ok = False
        else:
            ok &= all([check.expr(pts, p, f"{where}: points") for p in pts])
        if ok:
            out.append(Member(b["name"], kind, b["length"], b[STIFFNESS[kind]], tuple(b["ends"]), b["modes"],
                              b.get("mass_per_length"), b.get("inertia_per_length"), b.get("shape", "polynomial"),
                              b.get("frame", "N"), b.get("origin", "O"), b.get("deflection", "y"), pts,
                              b.get("description", "")))
    return tuple(out)
