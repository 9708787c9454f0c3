"""A contact from geometry read into its gap and slip: the body found and checked, the shape
and surface read, their values checked, the geometry derived."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import sympy as sp

from ...errors import did_you_mean
from ..bodies import RigidBody
from ..symbols import t
from . import contact_geometry, read_shape, read_surface

__all__ = ["shape_contact"]


def shape_contact(ct, where: str, model, parse: Callable[[Any, str], Any], problems: list[str]):
    """*ct* (a :class:`~nonideal.modeling.contacts.Contact` with ``body`` and ``shape``) with
    ``gap``, ``slip`` and ``geometry`` derived from the body's rotation and centre; ``None``
    with every problem appended to *problems*.

    *model* is the model being normalized (its bodies, parameters and coordinates already
    normalized), *parse(value, where)* reads an expression (SymPy, or ``None`` with the problem
    noted)."""
    bodies = {b.name: b for b in model.bodies}
    values = {sp.Symbol(k): float(v) for k, v in model.parameter_values.items()}
    if ct.shape is None:
        problems.append(f"{where}: " + (f"body = '{ct.body}' without shape; add shape = {{type = "
                                        "\"sphere\", radius = ...}} (or another shape), or remove body "
                                        "and give gap and slip" if ct.body is not None else
                                        "give gap = \"...\" (>= 0) and slip = [\"...\"], or body and "
                                        "shape (a contact from geometry)"))
        return None
    if ct.gap is not None or ct.slip:
        problems.append(f"{where}: give either gap and slip or body and shape, not both (the shape "
                        "derives the gap and slip)")
        return None
    if ct.body is None:
        problems.append(f"{where}: shape needs body = \"...\" (the rigid body it is fixed in)")
        return None
    body = bodies.get(ct.body)
    if body is None:
        problems.append(f"{where}: body '{ct.body}' is not a body of this model"
                        + did_you_mean(str(ct.body), bodies))
        return None
    if not isinstance(body, RigidBody):
        problems.append(f"{where}: body '{ct.body}' is a {type(body).__name__}; a shape is fixed in a "
                        "rigid body (type = \"rigid\" with inertia, position and rotation); for a "
                        "point mass write gap and slip")
        return None
    allowed = set(model.parameter_symbols) | {t}
    found: list[str] = []

    def checked(value, w):
        e = parse(value, w)
        if e is not None and not e.free_symbols <= allowed:
            extra = sorted(str(x) for x in e.free_symbols - allowed)
            found.append(f"{w}: {', '.join(extra)} -- a shape's dimensions and a surface's placement "
                         "are numbers or parameters (a moving surface's velocity and omega may "
                         "depend on t)")
            return None
        return e

    given = _named_center(ct.shape, body, model, f"{where}: shape", problems)
    if given is None:
        return None
    shape = read_shape(given, f"{where}: shape", checked, found)
    surface = read_surface(ct.surface, f"{where}: surface", checked, found)
    if shape is not None and surface is not None:
        found += shape.check(values, f"{where}: shape")
        found += surface.check(values, f"{where}: surface")
        for key in ("radius", "semi_axes", "curvature_radii", "axis", "center"):
            given = getattr(shape, key, None)
            if given is not None and t in sp.Matrix(list(given) if isinstance(given, tuple) else [given]).free_symbols:
                found.append(f"{where}: shape {key} depends on t; a shape is fixed in its body")
        for key in ("normal", "point"):
            if t in sp.Matrix(list(getattr(surface, key))).free_symbols:
                found.append(f"{where}: surface {key} depends on t; the plane moves only in its own "
                             "plane (velocity, omega)")
    if found or shape is None or surface is None:
        problems += found
        return None
    omega = getattr(body, "omega", None)   # body axes, when the body is given by a frame
    geometry = contact_geometry(shape, surface, body.rotation, body.position, model.q, model.qd, t,
                                omega=None if omega is None else sp.Matrix(body.rotation) * sp.Matrix(omega))
    # a component the coordinates cannot produce (a planar model's sideways slip) is left out
    slip = tuple(u for u in geometry.slip if sp.expand(u) != 0)
    if not slip:
        problems.append(f"{where}: the contact point of body '{ct.body}' cannot move along the "
                        "surface with these coordinates (both slip components vanish); declare a "
                        "constraint instead")
        return None
    return replace(ct, gap=geometry.gap, slip=slip, shape=shape, surface=surface, geometry=geometry)


def _named_center(shape, body, model, where: str, problems: list[str]):
    """*shape* with a ``center`` that names a point (``center = "O"``) replaced by that point's
    components in the body's axes from its centre of mass, ``R^T (pos(O) - pos(G))`` -- which
    must not change as the body moves (a point fixed in the body)."""
    from dataclasses import is_dataclass

    from .geometry import fold

    name = shape.get("center") if isinstance(shape, dict) else getattr(shape, "center", None)
    if not isinstance(name, str):
        return shape
    kin = model.__dict__.get("_kinematics")
    known = kin.names_of("point") if kin is not None else []
    if name not in known:
        problems.append(f"{where}: center '{name}' is not a point of the model{did_you_mean(name, known)}; "
                        "declare it in [[points]] (fixed in the body) or give center = [x, y, z] in "
                        "the body's axes from its centre of mass")
        return None
    R = sp.Matrix(body.rotation)
    offset = sp.Matrix(kin.pos(name).components) - sp.Matrix(list(body.position))
    local = (R.T * offset).applyfunc(fold)
    if any(e.free_symbols & (set(model.q) | {t}) for e in local):
        problems.append(f"{where}: center '{name}' moves in the body of '{body.name}' (its position in "
                        f"the body's axes is {list(local)}); a shape's centre is a point fixed in its body")
        return None
    center = tuple(local)
    return {**shape, "center": list(center)} if isinstance(shape, dict) else (
        replace(shape, center=center) if is_dataclass(shape) else shape)
