"""Normalization of the ``[[contacts]]``: the gap, the slip rows, the friction law, the impact
law and the friction torques (``spin``/``spin_friction``, ``rolling``/``rolling_friction``),
every problem reported by name (a part of :mod:`nonideal.modeling.normalize`)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import sympy as sp

from .contacts import TORQUES, Contact, CoulombContensou, Newton, Plastic, is_infinite, normalize_friction
from .shapes import Point, spin_and_rolling
from .shapes.geometry import fold
from .shapes.reading import shape_contact
from .symbols import is_identifier
from .values import derivative_order, identically_zero, parameter_values

__all__ = ["normalize_contacts", "torque_keys"]


def torque_keys(table: dict, check, where: str) -> dict | None:
    """The friction torque keys of a model file's ``[[contacts]]`` table (``spin``, ``rolling``,
    ``spin_friction``, ``rolling_friction``) as :class:`Contact` keyword arguments, their types
    checked by *check* (a :class:`~nonideal.modeling.filechecks.Checker`); None after a problem."""
    if "spin" in table and not check.expr(table, "spin", where):
        return None
    if "rolling" in table and not check.expr_list(table, "rolling", where, (1, 2), allow_scalar=True):
        return None
    if not all(check.expr(table, key, where) for key in ("spin_friction", "rolling_friction") if key in table):
        return None
    rolling = table.get("rolling")
    return dict(spin=table.get("spin"), rolling=tuple(rolling) if isinstance(rolling, list) else rolling,
                spin_friction=table.get("spin_friction"), rolling_friction=table.get("rolling_friction"))


def normalize_contacts(self) -> None:
    """The contacts of the model *self* (a :class:`~nonideal.modeling.normalize.Normalizer`)
    normalized: gap, slip rows, friction law, impact law, friction torques."""
    m = self.m
    out, names = [], {c.name for c in m.constraints}
    for ct in m.contacts:
        where = f"contact '{ct.name}'"
        if not isinstance(ct.name, str) or not is_identifier(ct.name):
            self.problems.append(f"{where}: name must be an identifier")
            continue
        if ct.name in names:
            owner = next((c.name for c in m.contacts if c is not ct and ct.name in
                          (f"{c.name}_{key}" for key, length in TORQUES if getattr(c, length) is not None)), None)
            self.problems.append(f"{where}: name already used by a constraint or contact" + (
                f" (the friction torque of contact '{owner}' is reported under that name)" if owner else ""))
            continue
        names.add(ct.name)
        if ct.geometry is None and (ct.shape is not None or ct.body is not None or ct.gap is None):
            ct = shape_contact(ct, where, m, lambda v, w: self.expr(v, w, 0), self.problems)
            if ct is None:
                continue
        gap = self.smooth(self.expr(ct.gap, f"{where}: gap", 2), f"{where}: gap")
        if gap is None:
            continue
        if derivative_order(gap, m.coordinates) > 0:
            self.problems.append(
                f"{where}: the gap must be a function of the coordinates and time only "
                "(it contains velocities)"
            )
            continue
        if identically_zero(gap) or not (gap.free_symbols & set(m.q)):
            self.problems.append(
                f"{where}: the gap does not depend on the coordinates, so no normal force "
                "can be identified; write the normal distance, e.g. gap = \"y\""
            )
            continue
        slips = []
        if not 1 <= len(ct.slip) <= 2:
            self.problems.append(f"{where}: slip must have 1 or 2 components (got {len(ct.slip)})")
            continue
        for i, s in enumerate(ct.slip):
            e = _velocity_row(self, s, f"{where}: slip[{i}]", "the tangential velocity of the contact point")
            if e is not None:
                slips.append(e)
        if len(slips) != len(ct.slip):
            continue
        friction = normalize_friction(self, ct.friction, where)
        impact = ct.impact
        if not isinstance(impact, (Plastic, Newton)):
            self.problems.append(f"{where}: impact must be Plastic() or Newton(e)")
            continue
        if not 0.0 <= float(impact.restitution) <= 1.0:
            self.problems.append(f"{where}: restitution must lie in [0, 1] (got {impact.restitution})")
            continue
        if friction is None:
            continue
        if isinstance(friction, CoulombContensou):
            pivoting = _pivoting(self, ct, where, len(slips))
            if pivoting is None:
                continue
            slips.append(friction.radius * pivoting)     # the third slip row: rho omega_n
            ct = replace(ct, spin=None)
        extra = _torques(self, ct, where, names)
        if extra is None:
            continue
        out.append(Contact(ct.name, gap, tuple(slips), friction, impact, bool(ct.bilateral),
                           ct.body, ct.shape, ct.surface, ct.geometry, **extra))
    self.set("contacts", tuple(out))
    # the multipliers are printed as lambda_<constraint>: a parameter or coordinate of that
    # name would read like a multiplier in every equation
    for kind, given in (("[parameters]", m.parameters), ("[coordinates] q:", m.coordinates)):
        for name in given:
            if isinstance(name, str) and name.startswith("lambda_") and name[7:] in names:
                self.problems.append(
                    f"{kind} '{name}' is the name of the multiplier of constraint or contact "
                    f"'{name[7:]}' in the equations; rename it")

def _velocity_row(self, value: Any, where: str, meaning: str):
    """A slip or angular-velocity row: an expression linear in the velocities, with at least one
    velocity and no acceleration (None and a problem recorded otherwise)."""
    m = self.m
    e = self.smooth(self.expr(value, where, 2), where)
    if e is None:
        return None
    if derivative_order(e, m.coordinates) == 2:
        self.problems.append(f"{where} must not contain accelerations")
        return None
    if any(sp.diff(e, a, b) != 0 for a in m.qd for b in m.qd if a in e.free_symbols):
        self.problems.append(f"{where} = {e} is not linear in the velocities; it is W(q,t) q' + w0")
        return None
    if not (e.free_symbols & set(m.qd)):
        self.problems.append(f"{where} = {e} contains no velocity; it must be {meaning}")
        return None
    return e


_MEANING = {"spin": "the relative spin angular velocity of the bodies about the contact normal",
            "rolling": "the relative rolling angular velocity of the bodies (its components about "
                       "axes of the tangent plane)"}


def _pivoting(self, ct, where: str, n_slip: int):
    """The angular velocity about the normal of a Coulomb-Contensou contact: derived for a contact
    from geometry, the ``spin`` key otherwise; None with the problem recorded."""
    if ct.spin_friction is not None:
        self.problems.append(f"{where}: friction = \"contensou\" already gives the pivoting torque of the "
                             "contact patch; remove spin_friction")
        return None
    if n_slip != 2:
        self.problems.append(f"{where}: friction = \"contensou\" needs a contact in space, with two slip "
                             f"components (got {n_slip}); use friction = \"coulomb\" for a planar contact")
        return None
    if ct.geometry is not None:
        if ct.spin is not None:
            self.problems.append(f"{where}: spin is derived from the shape and the surface; remove it")
            return None
        row = fold(spin_and_rolling(ct.geometry)[0])
    elif ct.spin is None:
        self.problems.append(f"{where}: friction = \"contensou\" needs the angular velocity about the "
                             "normal: give spin = \"...\" (linear in the velocities) or declare the "
                             "contact by body and shape")
        return None
    else:
        row = _velocity_row(self, ct.spin, f"{where}: spin", _MEANING["spin"])
    if row is not None and sp.expand(row) == 0:
        self.problems.append(f"{where}: body '{ct.body}' cannot pivot on the surface with these "
                             "coordinates (the spin vanishes); use friction = \"coulomb\"")
        return None
    return row


def _torques(self, ct, where: str, names: set) -> dict | None:
    """``spin``/``spin_friction`` and ``rolling``/``rolling_friction`` of a contact, checked and
    parsed (None when a problem was recorded)."""
    out, ok = {}, True
    for rows_key, length_key in TORQUES:
        rows, length = getattr(ct, rows_key), getattr(ct, length_key)
        if rows is None and length is None:
            continue
        if ct.geometry is not None:     # a contact from geometry: the angular velocity is derived
            rows = _derived(self, ct, where, rows_key, length_key, rows)
            if rows is None:
                ok = False
                continue
        if length is None:
            self.problems.append(f"{where}: {rows_key} is given without {length_key}; it is read only by "
                                 f"{length_key} (a length): add {length_key} = \"...\" or remove {rows_key}")
            ok = False
            continue
        if rows is None:
            self.problems.append(
                f"{where}: {length_key} needs {_MEANING[rows_key]}; give {rows_key} = "
                + ("\"...\" (one expression" if rows_key == "spin" else "[\"...\", \"...\"] (one or two expressions")
                + ", linear in the velocities) or remove " + length_key)
            ok = False
            continue
        if ct.bilateral:
            self.problems.append(f"{where}: {length_key} on a bilateral contact is not supported (the torque "
                                 f"bound uses N >= 0); remove {length_key} or bilateral")
            ok = False
            continue
        name = f"{ct.name}_{rows_key}"
        if name in names:
            self.problems.append(f"{where}: {length_key} is reported as '{name}', a name already used by a "
                                 "constraint or contact; rename one of them")
            ok = False
            continue
        items = (rows,) if rows_key == "spin" else tuple(rows)
        if rows_key == "spin" and not isinstance(rows, (str, sp.Expr, int, float)):
            self.problems.append(f"{where}: spin must be one expression (the angular velocity about the "
                                 "normal), not a list")
            ok = False
            continue
        if not 1 <= len(items) <= 2:
            self.problems.append(f"{where}: rolling must have 1 or 2 components (got {len(items)})")
            ok = False
            continue
        parsed = [_velocity_row(self, e, f"{where}: {rows_key}" + (f"[{i}]" if rows_key == "rolling" else ""),
                                _MEANING[rows_key]) for i, e in enumerate(items)]
        if is_infinite(length):
            self.problems.append(f"{where}: {length_key} = inf would forbid the motion entirely: write "
                                 f"{rows_key} = 0 as a nonholonomic [[constraints]] entry instead")
            ok = False
            continue
        value = self.expr(length, f"{where}: {length_key}", 0)
        if value is not None and not value.free_symbols & set(self.m.q):
            number = value.xreplace(parameter_values(self.m.parameters))
            if number.is_number and float(number) < 0:
                self.problems.append(f"{where}: {length_key} = {float(number):g} is negative; it is a "
                                     "length >= 0 (the torque bound is length * N)")
                value = None
        if value is None or any(e is None for e in parsed):
            ok = False
            continue
        names.add(name)
        out[rows_key] = parsed[0] if rows_key == "spin" else tuple(parsed)
        out[length_key] = value
    return out if ok else None


def _derived(self, ct, where: str, rows_key: str, length_key: str, given):
    """The spin (one expression) or the rolling components along the surface's tangents t1, t2
    of a contact from geometry (:func:`~nonideal.modeling.shapes.spin_and_rolling`); None with
    the problem recorded."""
    if given is not None:
        self.problems.append(f"{where}: {rows_key} is derived from the shape and the surface; remove it")
        return None
    if isinstance(ct.shape, Point):
        self.problems.append(f"{where}: {length_key} on a point contact (shape type \"point\"): a point has no "
                             f"contact patch to resist {'pivoting' if rows_key == 'spin' else 'rolling'}; "
                             f"remove {length_key}, or give the body a shape with a radius (sphere, "
                             "ellipsoid, paraboloid, disk)")
        return None
    spin, rolling = spin_and_rolling(ct.geometry)
    if rows_key == "spin":
        rows = [fold(spin)]
    else:
        rows = [fold((tk.T * rolling)[0]) for tk in ct.geometry.tangents]
        rows = [w for w in rows if sp.expand(w) != 0]   # a component the coordinates cannot produce
    if not rows or all(sp.expand(w) == 0 for w in rows):
        self.problems.append(f"{where}: body '{ct.body}' cannot {'pivot' if rows_key == 'spin' else 'roll'} "
                             f"on the surface with these coordinates ({rows_key} vanishes); remove {length_key}")
        return None
    return rows[0] if rows_key == "spin" else tuple(rows)
