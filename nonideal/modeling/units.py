"""Units of a model, for labels and outputs only: the library never converts units.

A model file may declare its base units and the kind of each coordinate::

    [units]
    length = "m"
    mass = "kg"
    time = "s"
    coordinates = { phi1 = "angle", rho = "length" }

From them :class:`Units` derives the units of velocities, accelerations, generalized forces,
contact forces and energy (``N``, ``J``, ``N m`` when the base units are SI).  Which
coordinates are angles is decided by :func:`coordinate_kinds`: the declaration first, then the
model itself (the angle of a planar body or of a torque, the argument of a trigonometric
function; a coordinate that is a body's or a contact's position is a length), then the kinetic
energy (``I phi'^2/2`` with ``I`` a moment of inertia: an angle; ``m x'^2/2``: a length), and
the name (``phi``, ``theta``, ``psi``...) only when nothing else decides.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from ..errors import did_you_mean

__all__ = ["Units", "units_of", "coordinate_kinds", "KINDS", "units_report"]

#: kinds of coordinates
KINDS = ("angle", "length")
#: units that make a coordinate an angle when it is declared with them
ANGLE_UNITS = ("rad", "radian", "radians", "deg", "degree", "degrees")
_KEYS = ("length", "mass", "time", "angle", "coordinates")
_ANGLE_NAMES = re.compile(r"^(phi|varphi|theta|vartheta|psi|alpha|beta|gamma|delta|chi|omega|"
                          r"eta|xi|zeta|kappa|epsilon|tau|angle|ang|yaw|pitch|roll)_?[0-9a-z]?$", re.I)
_INERTIA_NAMES = re.compile(r"^[IJ](_?[0-9a-z]{0,3})$")
_MASS_NAMES = re.compile(r"^[mM](_?[0-9]{0,2})$")


@dataclass(frozen=True)
class Units:
    """The model's declared units (None: not declared, "model units" in labels).

    Attributes
    ----------
    length, mass, time : str or None
    angle : str
        ``"rad"`` unless declared.
    coordinates : mapping name -> str
        A coordinate's kind (``"angle"``, ``"length"``) or its unit.
    """

    length: str | None = None
    mass: str | None = None
    time: str | None = None
    angle: str = "rad"
    coordinates: Mapping[str, str] = field(default_factory=dict)

    def __hash__(self) -> int:
        return hash((self.length, self.mass, self.time, self.angle, tuple(sorted(self.coordinates.items()))))

    @property
    def declared(self) -> bool:
        return any(v is not None for v in (self.length, self.mass, self.time)) or bool(self.coordinates)

    @property
    def si(self) -> bool:
        return (self.length, self.mass, self.time) == ("m", "kg", "s")

    def force(self) -> str | None:
        """Unit of a force (a contact's normal and friction forces)."""
        if self.si:
            return "N"
        return _compose(self, {"mass": 1, "length": 1, "time": -2})

    def energy(self) -> str | None:
        if self.si:
            return "J"
        return _compose(self, {"mass": 1, "length": 2, "time": -2})

    def torque(self) -> str | None:
        if self.si:
            return "N m"
        return _compose(self, {"mass": 1, "length": 2, "time": -2})

    def of(self, kind: str, name: str | None = None) -> str | None:
        """Unit of a coordinate of *kind* (its declared unit for a kind of its own)."""
        if kind == "angle":
            return self.angle
        if kind == "length":
            return self.length
        return self.coordinates.get(name) if name else None

    def rate(self, unit: str | None, order: int = 1) -> str | None:
        """``unit/time^order`` (None when either is not declared)."""
        if unit is None or self.time is None:
            return None
        return f"{unit}/{self.time}" + (f"^{order}" if order > 1 else "")

    def generalized_force(self, kind: str, name: str | None = None) -> str | None:
        """Unit of the generalized force of a coordinate: a force, a torque for an angle,
        energy per unit otherwise."""
        if kind == "length":
            return self.force()
        if kind == "angle":
            return self.torque()
        unit, energy = self.of(kind, name), self.energy()
        return None if unit is None or energy is None else f"{energy}/{unit}"


def _compose(units: Units, powers: dict[str, int]) -> str | None:
    num, den = [], []
    for key, p in powers.items():
        u = getattr(units, key)
        if u is None:
            return None
        text = u if abs(p) == 1 else f"{u}^{abs(p)}"
        (num if p > 0 else den).append(text)
    return " ".join(num) + ("/" + " ".join(den) if den else "")


def units_of(value: Any, coordinates, where: str = "[units]") -> tuple[Units, list[str]]:
    """:class:`Units` from *value* (a Units, a mapping with the keys of the ``[units]`` table,
    or None) and the problems found (unknown keys and coordinates, values that are not text)."""
    if value is None:
        return Units(), []
    if isinstance(value, Units):
        value = {k: getattr(value, k) for k in _KEYS}
    if not isinstance(value, Mapping):
        return Units(), [f"{where}: must be a table, e.g. length = \"m\", mass = \"kg\", time = \"s\""]
    problems = []
    for key in value:
        if key not in _KEYS:
            problems.append(f"{where}: unknown key '{key}'{did_you_mean(str(key), _KEYS)}; allowed: "
                            + ", ".join(_KEYS))
    base = {}
    for key in ("length", "mass", "time", "angle"):
        v = value.get(key)
        if v is not None and not (isinstance(v, str) and v.strip()):
            problems.append(f"{where}: {key} must be a unit in quotes, e.g. {key} = "
                            f"\"{ {'length': 'm', 'mass': 'kg', 'time': 's', 'angle': 'rad'}[key]}\" (got {v!r})")
        elif v is not None:
            base[key] = v.strip()
    coords = value.get("coordinates") or {}
    if not isinstance(coords, Mapping):
        problems.append(f"{where}: coordinates must be a table, e.g. coordinates = {{phi = \"angle\", "
                        f"x = \"length\"}} (got {coords!r})")
        coords = {}
    kinds = {}
    for name, kind in coords.items():
        if name not in coordinates:
            problems.append(f"{where} coordinates: '{name}' is not a coordinate"
                            f"{did_you_mean(str(name), coordinates)}")
        elif not (isinstance(kind, str) and kind.strip()):
            problems.append(f"{where} coordinates: {name} must be \"angle\", \"length\" or a unit "
                            f"in quotes (got {kind!r})")
        else:
            kinds[name] = kind.strip()
    return Units(**base, coordinates=kinds), problems


def _declared_kind(units: Units, text: str) -> str:
    if text in KINDS:
        return text
    if text == units.angle or text.lower() in ANGLE_UNITS:
        return "angle"
    if units.length is not None and text == units.length:
        return "length"
    return "other"


def coordinate_kinds(model) -> dict[str, str]:
    """``"angle"``, ``"length"`` or ``"other"`` (a declared unit of its own) for every
    coordinate of *model* (see the module docstring for the order of the evidence).

    Examples
    --------
    >>> from nonideal import gallery
    >>> coordinate_kinds(gallery.load("friction-speed-regulator"))
    {'phi1': 'angle', 'phi2': 'angle', 'phi': 'angle', 'rho': 'length'}
    """
    names = list(model.coordinates)
    units = getattr(model, "units", None) or Units()
    kinds: dict[str, str] = {n: _declared_kind(units, k) for n, k in units.coordinates.items()}
    symbols = {sp.Symbol(n): n for n in names}

    def decide(found, kind):
        for n in found:
            kinds.setdefault(n, kind)

    # the model's own geometry: angles of bodies and torques, arguments of trigonometric functions
    exprs = [model.kinetic, model.potential, *_forces(model)]
    for b in model.bodies:
        if getattr(b, "angle", None) is not None:
            decide(_coords(b.angle, symbols), "angle")
        exprs += [*getattr(b, "position", ()), *(x for row in (getattr(b, "rotation", None) or ()) for x in row)]
    for ld in model.loads:
        if getattr(ld, "angle", None) is not None:
            decide(_coords(ld.angle, symbols), "angle")
    exprs += [c.expr for c in model.constraints] + [c.gap for c in model.contacts]
    exprs += [u for c in model.contacts for u in c.slip]
    trig = (sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)
    for e in exprs:
        for f in sp.sympify(e).atoms(*trig):
            decide(_coords(f.args[0], symbols), "angle")
    # a coordinate that is itself a position (a term c*x with a number c): a length
    for e in [x for b in model.bodies for x in getattr(b, "position", ())] + [c.gap for c in model.contacts]:
        for term in sp.Add.make_args(sp.expand(sp.sympify(e))):
            coeff, rest = term.as_coeff_Mul()
            if rest in symbols:
                decide([symbols[rest]], "length")
    # the kinetic energy: I q'^2/2 (a moment of inertia) or m q'^2/2 (a mass)
    _kinetic_kinds(model, symbols, kinds, units)
    for n in names:
        if n not in kinds:
            kinds[n] = "angle" if _ANGLE_NAMES.match(n) else "length"
    return {n: kinds[n] for n in names}


def _kinetic_kinds(model, symbols, kinds, units) -> None:
    """Kinds from the coefficient ``a`` of ``q'^2`` in the kinetic energy (*kinds* filled where
    not yet decided): ``a = I`` (a moment of inertia) or ``a = m l^2`` (a mass times two
    lengths or coordinates): an angle; ``a = m``: a length."""
    inertias = {sp.sympify(b.inertia) for b in model.bodies
                if getattr(b, "inertia", None) is not None and not isinstance(b.inertia, (list, tuple))}
    masses = {sp.sympify(b.mass) for b in model.bodies if getattr(b, "mass", None) is not None}
    unit_of = {n: _squash(getattr(p, "unit", "") or "") for n, p in model.parameters.items()}
    mass_unit, length_unit = _squash(units.mass or "kg"), _squash(units.length or "m")

    def is_inertia(s):
        u = unit_of.get(s.name, "")
        if u:
            return u in (f"{mass_unit}{length_unit}2", f"{length_unit}2{mass_unit}")
        return s in inertias or bool(_INERTIA_NAMES.match(s.name))

    def is_mass(s):
        u = unit_of.get(s.name, "")
        if u:
            return u == mass_unit
        return s in masses or bool(_MASS_NAMES.match(s.name))

    T = sp.expand(sp.sympify(model.kinetic) * 2)
    for s, n in symbols.items():
        if n in kinds:
            continue
        a = T.coeff(sp.Symbol(n + "'"), 2)
        if a == 0:
            continue
        powers = {}
        for f in sp.Mul.make_args(sp.factor(a)):
            base, exp = f.as_base_exp()
            if base.is_Symbol and exp.is_Integer:
                powers[base] = int(exp)
            elif not f.is_number:
                powers = {}
                break
        if not powers:
            continue
        heavy = [b for b in powers if b.name not in symbols.values() and (is_mass(b) or is_inertia(b))]
        if len(heavy) != 1 or powers[heavy[0]] != 1:
            continue
        rest = sum(e for b, e in powers.items() if b != heavy[0])
        if is_inertia(heavy[0]) and rest == 0:
            kinds[n] = "angle"
        elif is_mass(heavy[0]):
            if rest == 0:
                kinds[n] = "length"
            elif rest == 2:
                kinds[n] = "angle"


def _squash(unit: str) -> str:
    return re.sub(r"[\s*·.^]", "", unit.lower().replace("²", "2"))


def _coords(expr, symbols) -> list[str]:
    return [symbols[s] for s in sp.sympify(expr).free_symbols if s in symbols]


def _forces(model) -> list:
    f = model.forces
    if isinstance(f, Mapping):
        return list(f.values())
    return list(f) if isinstance(f, (list, tuple)) else []


def units_report(model) -> dict[str, Any]:
    """The units of a trajectory's quantities (``simulate --json``: key ``units``); None where
    the model does not declare what they need (``[units]``).

    Returns
    -------
    dict
        ``declared``, ``time``, ``kinds`` (angle/length/other per coordinate), ``q``, ``qdot``,
        ``qddot``, ``generalized_force`` (per coordinate), ``force`` (contact normal and friction
        forces), ``energy``, ``contacts`` (``normal``, ``friction``, ``gap``, ``slip``).
    """
    units = getattr(model, "units", None) or Units()
    kinds = coordinate_kinds(model)
    q = {n: units.of(k, n) for n, k in kinds.items()}
    return {
        "declared": units.declared,
        "time": units.time,
        "kinds": kinds,
        "q": q,
        "qdot": {n: units.rate(u) for n, u in q.items()},
        "qddot": {n: units.rate(u, 2) for n, u in q.items()},
        "generalized_force": {n: units.generalized_force(k, n) for n, k in kinds.items()},
        "force": units.force(),
        "energy": units.energy(),
        "contacts": {"normal": units.force(), "friction": units.force(), "gap": units.length,
                     "slip": units.rate(units.length)},
    }
