"""Contacts with Coulomb friction, friction laws and impact laws -- small value objects.

A :class:`Contact` is declared by

* a **gap** ``g(q, t) >= 0`` -- the normal distance, so that its multiplier ``N`` is the
  physical normal force (or, with ``bilateral=True``, an equation ``g = 0`` whose multiplier
  may take either sign: a slider in a rough guide, friction then uses ``|N|``);
* one or two **slip** velocities ``U = W(q, t) q' + w0`` (physical tangential velocities of
  the contact point, linear in the velocities);
* a **friction law** -- :class:`Coulomb` (exact, the default), :class:`IdealRolling`
  (``mu = inf``: no slip while the gap is closed, whatever the tangential force),
  :class:`RegularizedCoulomb` (smooth sign, for comparison), :class:`LinearizedCoulomb`
  (the epsilon-linear law of Kalinin & Novozhilov) or :class:`CoulombContensou` (Coulomb's
  law over a small circular contact patch: sliding and pivoting coupled, Contensou 1963);
* an **impact law** for when the gap closes -- :class:`Plastic` (default) or
  :class:`Newton` with a restitution coefficient.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from .values import parameter_values

__all__ = [
    "normalize_friction",
    "Contact",
    "Coulomb",
    "TORQUES",
    "torques",
    "IdealRolling",
    "is_infinite",
    "read_infinite",
    "RegularizedCoulomb",
    "LinearizedCoulomb",
    "CoulombContensou",
    "Plastic",
    "Newton",
]


@dataclass(frozen=True)
class Coulomb:
    """Coulomb's law: ``|F| <= mu_static N`` while sticking, ``F = -mu N U/|U|`` while sliding.

    ``mu`` and ``mu_static`` are expressions (``mu_static`` defaults to ``mu``).
    """

    mu: Any
    mu_static: Any = None

    @property
    def exact(self) -> bool:
        return True


@dataclass(frozen=True)
class IdealRolling:
    """Ideal rolling while in contact (Coulomb's law with ``mu = mu_static = inf``).

    While the gap is closed the slip velocity is held at zero by an ideal nonholonomic
    constraint (Chetaev) whose multiplier, the friction force, is unbounded: the contact never
    slides.  The gap is unilateral as for any contact: the contact lifts off when its normal
    force reaches zero, and a closing gap is an impact (the tangential impulse of sticking,
    unbounded too).  No slip states, no slip events, no friction work.  A model file writes it
    ``mu = "inf"`` (or the TOML number ``inf``).

    Examples
    --------
    >>> IdealRolling().mu
    oo
    """

    @property
    def mu(self) -> sp.Expr:
        return sp.oo

    @property
    def mu_static(self) -> sp.Expr:
        return sp.oo

    @property
    def exact(self) -> bool:
        return True


def is_infinite(value: Any) -> bool:
    """Whether a friction coefficient as written means infinity (ideal rolling): the string
    ``"inf"`` (or ``"infinity"``, ``"oo"``, any case, optionally ``+``), a float ``inf`` or
    SymPy's ``oo``.

    Examples
    --------
    >>> is_infinite("inf"), is_infinite(float("inf")), is_infinite("mu"), is_infinite(1e9)
    (True, True, False, False)
    """
    if isinstance(value, str):
        return value.strip().lower().lstrip("+") in ("inf", "infinity", "oo")
    if isinstance(value, float):
        return math.isinf(value) and value > 0
    return value is sp.oo


def read_infinite(law: Any, where: str) -> tuple[Any, str | None]:
    """A friction law with an infinite coefficient read as :class:`IdealRolling` (``Coulomb``
    with ``mu = inf``), or the problem of a combination that has no meaning (a finite
    ``mu_static`` with ``mu = inf``, ``mu_static = inf`` alone, a regularized law with
    ``mu = inf``); other laws are returned as they are.

    Examples
    --------
    >>> read_infinite(Coulomb("inf"), "contact 'c'")
    (IdealRolling(), None)
    >>> read_infinite(Coulomb(0.3), "contact 'c'")
    (Coulomb(mu=0.3, mu_static=None), None)
    """
    if isinstance(law, Coulomb) and is_infinite(law.mu):
        if law.mu_static is not None and not is_infinite(law.mu_static):
            return None, (f"{where}: mu = inf (ideal rolling) with a finite mu_static = "
                          f"{law.mu_static!r}; the static coefficient is at least the kinetic one: "
                          "remove mu_static")
        return IdealRolling(), None
    if isinstance(law, Coulomb) and law.mu_static is not None and is_infinite(law.mu_static):
        return None, (f"{where}: mu_static = inf with a finite mu = {law.mu!r}; a contact that never "
                      "slips is written mu = \"inf\" (ideal rolling), without mu_static")
    if isinstance(law, (RegularizedCoulomb, LinearizedCoulomb, CoulombContensou)) and is_infinite(law.mu):
        return None, (f"{where}: mu = inf needs the exact law (friction = \"coulomb\"): a regularized "
                      "law with infinite mu has no meaning; for ideal rolling remove friction and eps")
    return law, None


@dataclass(frozen=True)
class RegularizedCoulomb:
    """Smooth friction ``F = -mu N U / sqrt(|U|^2 + eps^2)`` (what users write by hand).

    No sticking mode: the contact always slides; ``eps`` (m/s) sets the smoothing.
    """

    mu: Any
    eps: float

    @property
    def exact(self) -> bool:
        return False


@dataclass(frozen=True)
class LinearizedCoulomb:
    """The epsilon-linear law of Kalinin & Novozhilov (Kalinin & Novozhilov):
    ``F = -mu N U/eps`` for ``|U| <= eps``, ``-mu N U/|U|`` outside.

    As ``eps -> 0`` its solutions tend to the sticking (nonholonomic) motion when sticking is
    realizable (Tikhonov's theorem).
    """

    mu: Any
    eps: float

    @property
    def exact(self) -> bool:
        return False


@dataclass(frozen=True)
class CoulombContensou:
    """Coulomb's law integrated over a circular contact patch of radius ``radius`` under uniform
    pressure (Contensou 1963; Zhuravlev 1998): every point of the patch slides at
    ``v + omega_n x r`` against the local Coulomb traction ``-mu p (v + omega_n x r)/|..|``, and
    the patch's resultant is a friction force and a pivoting torque about the normal,

        F = -mu N f(d) v/|v|,   M = -mu N radius m(d) omega_n/|omega_n|,   d = |v|/(radius |omega_n|),

    with f, m exact one-dimensional integrals (:func:`nonideal.numeric.contensou.contensou`):
    f(0) = 0, f(1) = 8/(3 pi), f -> 1 and m(0) = 2/3, m -> 1/(4 d) as d -> oo.  While the body
    pivots the sliding force is continuous in the slip (it falls linearly to zero as
    ``-mu N v/(radius omega_n)``), so the slip of a spinning top need not stop -- the coupling that
    turns a tippe top over (Leine & Glocker 2003).  No sticking mode: where the slip and the
    pivoting both vanish the law is set-valued and the run stops with that diagnosis.

    The contact's slip gets a third row, ``radius * omega_n`` (the pivoting as a velocity), whose
    "friction force" times ``radius`` is the torque ``M``.
    """

    mu: Any
    radius: Any

    @property
    def exact(self) -> bool:
        return False


@dataclass(frozen=True)
class Plastic:
    """Plastic impact: the normal velocity of the contact becomes zero."""

    restitution: float = 0.0


@dataclass(frozen=True)
class Newton:
    """Newton's impact law: the normal velocity reverses, scaled by ``restitution`` in [0, 1]."""

    restitution: float = 0.5


@dataclass(frozen=True)
class Contact:
    """A contact with friction.

    Parameters
    ----------
    name : str
    gap : expression in the coordinates and time
        ``>= 0``; the normal distance (its multiplier is the normal force).  Not given for a
        contact from geometry (``body`` and ``shape``).
    slip : sequence of 1 or 2 expressions
        Tangential slip velocities, linear in the velocities (not given with ``shape``).
    friction : Coulomb, IdealRolling, RegularizedCoulomb, LinearizedCoulomb or CoulombContensou
        ``Coulomb(math.inf)`` (or ``Coulomb("inf")``) is read as :class:`IdealRolling`.
    impact : Plastic or Newton
    bilateral : bool
        The gap is held at zero by a two-sided guide (no separation; friction uses ``|N|``).
    body : str, optional
        A contact from geometry: the name of the rigid body carrying ``shape``.
    shape : Shape or mapping, optional
        :class:`~nonideal.modeling.shapes.Sphere`, ``Ellipsoid``, ``Paraboloid``, ``Disk``,
        ``Point`` or a mapping as in a model file (``{"type": "sphere", "radius": "r"}``); the
        library derives the gap and the two slip components
        (:func:`~nonideal.modeling.shapes.contact_geometry`).
    surface : Plane or mapping, optional
        The plane touched (default: z = 0 of N, normal +z).  After normalization a contact
        from geometry carries ``geometry`` (:class:`~nonideal.modeling.shapes.ContactGeometry`:
        normal, support point, angular velocities) besides the derived ``gap`` and ``slip``.
    spin : expression, optional
        The relative spin angular velocity of the bodies about the contact normal (linear in
        the velocities); needed by ``spin_friction`` (derived for a contact from geometry).
    rolling : sequence of 1 or 2 expressions, optional
        The relative rolling angular velocity (its components about axes of the tangent plane,
        linear in the velocities); needed by ``rolling_friction``.
    spin_friction, rolling_friction : expression, optional
        Lengths ``l``: the pivoting torque about the normal (rolling-resistance torque in the
        tangent plane) is bounded by ``l N`` while the spin (rolling) angular velocity is zero
        and equals ``-l N w/|w|`` while it is not -- Coulomb's law on the angular velocity,
        each torque with its own sticking and exact switching, independent of the sliding
        friction and of each other (:func:`torques`).

    Examples
    --------
    >>> Contact("floor", body="ball", shape={"type": "sphere", "radius": "r"}, friction=Coulomb("mu")).slip
    ()
    """

    name: str
    gap: Any = None
    slip: tuple[Any, ...] = ()
    friction: Any = field(default_factory=lambda: Coulomb(0))
    impact: Any = field(default_factory=Plastic)
    bilateral: bool = False
    body: str | None = None
    shape: Any = None
    surface: Any = None
    geometry: Any = field(default=None, compare=False, repr=False)
    spin: Any = None
    rolling: tuple[Any, ...] | None = None
    spin_friction: Any = None
    rolling_friction: Any = None

    def __post_init__(self):
        slip = () if self.slip is None else self.slip
        if isinstance(slip, (str, int, float)) or not hasattr(slip, "__iter__"):
            slip = (slip,)
        object.__setattr__(self, "slip", tuple(slip))
        rolling = self.rolling
        if rolling is not None and (isinstance(rolling, (str, int, float)) or not hasattr(rolling, "__iter__")):
            object.__setattr__(self, "rolling", (rolling,))
        elif rolling is not None:
            object.__setattr__(self, "rolling", tuple(rolling))


TORQUES = (("spin", "spin_friction"), ("rolling", "rolling_friction"))
"""The friction torques of a contact: (angular velocity key, length key)."""


def torques(contact: Contact) -> list[tuple[str, tuple[Any, ...], Any]]:
    """The friction torques of *contact*: ``(name, angular velocity rows, length)`` for each of
    ``spin_friction`` (name ``<contact>_spin``) and ``rolling_friction``
    (``<contact>_rolling``) it gives.

    Examples
    --------
    >>> c = Contact("floor", "z", ("x'",), spin="w", spin_friction="l")
    >>> torques(c)
    [('floor_spin', ('w',), 'l')]
    """
    out = []
    for rows_key, length_key in TORQUES:
        length = getattr(contact, length_key)
        if length is None:
            continue
        rows = getattr(contact, rows_key)
        rows = (rows,) if rows_key == "spin" else rows
        out.append((f"{contact.name}_{rows_key}", tuple(rows), length))
    return out


def normalize_friction(norm, law: Any, where: str):
    """The friction law of a contact with its coefficients parsed and checked (None after a
    problem, appended to ``norm.problems``); *norm* is the model's Normalizer."""

    pvals = parameter_values(norm.m.parameters)

    def coefficient(value: Any, key: str):
        e = norm.expr(value, f"{where}: {key}", 0)
        if e is None:
            return None
        if not e.free_symbols & set(norm.m.q):
            v = e.xreplace(pvals)
            if v.is_number and float(v) < 0:
                norm.problems.append(f"{where}: {key} = {float(v):g} is negative; a friction "
                                     "coefficient is >= 0")
                return None
        return e

    law, problem = read_infinite(law, where)  # mu = inf: ideal rolling, or a problem
    if problem or isinstance(law, IdealRolling):
        norm.problems += [problem] if problem else []
        return None if problem else law
    if isinstance(law, Coulomb):
        mu = coefficient(law.mu, "mu")
        # mu_static defaults to mu: a problem of mu is not reported again under a key the
        # user did not write
        mus = coefficient(law.mu_static, "mu_static") if law.mu_static is not None else mu
        if mu is None or mus is None:
            return None
        return Coulomb(mu, mus)
    if isinstance(law, CoulombContensou):
        mu = coefficient(law.mu, "mu")
        radius = norm.expr(law.radius, f"{where}: patch_radius", 0)
        if mu is None or radius is None:
            return None
        v = radius.xreplace(pvals)
        if radius.free_symbols & set(norm.m.q) or (v.is_number and not float(v) > 0):
            norm.problems.append(f"{where}: patch_radius must be a positive constant (the radius of "
                                 f"the contact patch in m; got {law.radius})")
            return None
        return CoulombContensou(mu, radius)
    if isinstance(law, (RegularizedCoulomb, LinearizedCoulomb)):
        mu = coefficient(law.mu, "mu")
        if mu is None:
            return None
        if not float(law.eps) > 0:
            norm.problems.append(f"{where}: eps must be > 0 (got {law.eps})")
            return None
        return type(law)(mu, float(law.eps))
    norm.problems.append(
        f"{where}: friction must be Coulomb, IdealRolling, RegularizedCoulomb, LinearizedCoulomb or "
        "CoulombContensou"
    )
    return None
