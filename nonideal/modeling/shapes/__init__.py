"""Contacts from geometry: shapes fixed in rigid bodies touching planes.

One module per shape (:mod:`.sphere`, :mod:`.ellipsoid`, :mod:`.paraboloid`, :mod:`.disk`,
:mod:`.point`) behind the interface of :mod:`.base`; the surface in :mod:`.surface`; the gap,
slip and angular velocities of a contact in :mod:`.geometry`; the uniqueness of the support
points watched along a motion in :mod:`.watch`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ...errors import did_you_mean
from .base import Parse, Shape, read_fields
from .disk import Disk
from .ellipsoid import Ellipsoid
from .geometry import ContactGeometry, angular_velocity, contact_geometry, spin_and_rolling
from .paraboloid import Paraboloid
from .point import Point
from .sphere import Sphere
from .surface import Plane

__all__ = ["Shape", "Sphere", "Ellipsoid", "Paraboloid", "Disk", "Point", "Plane", "SHAPES",
           "SURFACES", "ContactGeometry", "contact_geometry", "angular_velocity",
           "spin_and_rolling", "read_shape", "read_surface"]

SHAPES: dict[str, type[Shape]] = {cls.TYPE: cls for cls in (Sphere, Ellipsoid, Paraboloid, Disk, Point)}
SURFACES: dict[str, type] = {"plane": Plane}


def _read(kinds: dict, value: Any, where: str, parse: Parse, problems: list[str], what: str):
    if isinstance(value, tuple(kinds.values())):
        data = {k: v for k, v in value.__dict__.items() if v is not None}
        kind = type(value)
    elif isinstance(value, Mapping):
        name = value.get("type", "plane" if what == "surface" else None)
        if not isinstance(name, str) or name not in kinds:
            listed = ", ".join(f'"{k}"' for k in kinds)
            problems.append(f"{where}: {what} type {name!r} unknown{did_you_mean(str(name), kinds)}; "
                            f"use one of {listed}")
            return None
        kind, data = kinds[name], dict(value)
    else:
        problems.append(f"{where}: {what} must be a table such as "
                        + ('{type = "sphere", radius = "r"}' if what == "shape"
                           else '{type = "plane", normal = [0, 0, 1]}')
                        + f" (got {type(value).__name__})")
        return None
    fields = read_fields(kind, data, where, parse, problems)
    return None if fields is None else kind(**fields)


def read_shape(value: Any, where: str, parse: Parse, problems: list[str]) -> Shape | None:
    """A :class:`Shape` from a mapping (``{"type": "sphere", "radius": "r"}``) or a shape
    object, every key parsed with *parse*; ``None`` with *problems* appended if it is wrong."""
    return _read(SHAPES, value, where, parse, problems, "shape")


def read_surface(value: Any, where: str, parse: Parse, problems: list[str]) -> Plane | None:
    """A :class:`Plane` from a mapping or a :class:`Plane` (``None``: the plane z = 0)."""
    if value is None:
        return Plane()
    return _read(SURFACES, value, where, parse, problems, "surface")
