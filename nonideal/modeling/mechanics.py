"""Models from ``sympy.physics.mechanics`` objects.

Users who already describe a system with ``ReferenceFrame``, ``Point``, ``Particle``,
``RigidBody``, ``dynamicsymbols`` and load tuples get a :class:`~nonideal.model.Model` without
rewriting it: positions are read with ``Point.pos_from(origin)`` in the inertial ``frame``,
orientations with ``frame.dcm(body.frame)``, central inertia tensors in the body's frame, and
loads (``Force``/``Torque`` objects or the classic ``(Point, Vector)`` / ``(ReferenceFrame,
Vector)`` tuples) become forces at points and torques on rigid bodies, i.e. generalized forces
by virtual work.  Velocities and accelerations are never taken from the points: the model is
built from positions and orientations alone, and :mod:`nonideal.equations.dynamics` derives the rest.

Coordinates, initial values and constraint expressions may use ``dynamicsymbols``: ``q1(t)``
is the coordinate ``q1``, ``q1'(t)`` its velocity ``q1'``.

The frames of the rigid bodies and the points of the bodies (and any ``ReferenceFrame`` or
``Point`` passed in ``frames=`` / ``points=``) become the model's declared frames and points
(:class:`~nonideal.modeling.frames.Frame` given by its matrix in the inertial frame,
:class:`~nonideal.modeling.points.Point` by its position from the origin) under their SymPy
names, so expressions may use them: ``dot(vel(P), N.x)``, ``omega(B)`` (a name that is not an
identifier, reserved or taken twice is left out).

Examples
--------
>>> import sympy as sp
>>> import sympy.physics.mechanics as me
>>> from nonideal import model_from_mechanics
>>> q = me.dynamicsymbols("q")
>>> m, l, g = sp.symbols("m l g")
>>> N, O = me.ReferenceFrame("N"), me.Point("O")
>>> P = O.locatenew("P", l * (sp.sin(q) * N.x - sp.cos(q) * N.y))
>>> model = model_from_mechanics(
...     "pendulum", [q], N, O, [me.Particle("bob", P, m)],
...     loads=[(P, -m * g * N.y)], parameters={"m": 1.0, "l": 0.5, "g": 9.81},
...     initial={q: 0.3, q.diff(): 0.0})
>>> model.coordinates
('q',)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import sympy as sp
from sympy.core.function import AppliedUndef

from .bodies import Force, Particle, PlanarBody, RigidBody, Torque
from ..errors import ModelError
from .frames import Frame
from .kinematics import RESERVED_KINEMATIC_NAMES
from .model import Model
from .points import Point
from .symbols import is_identifier

__all__ = ["model_from_mechanics", "bodies_from_mechanics", "loads_from_mechanics", "coordinate_name",
           "frames_points_from_mechanics"]


def _me():
    import sympy.physics.mechanics as me

    return me


def coordinate_name(q: Any) -> str:
    """The coordinate name of a string or of a ``dynamicsymbols`` function ``q(t)``; a first
    (second) time derivative gives ``q'`` (``q''``)."""
    if isinstance(q, str):
        return q
    if isinstance(q, sp.Derivative) and isinstance(q.expr, AppliedUndef):
        order = sum(int(c) for _, c in q.variable_count)
        return q.expr.func.__name__ + "'" * order
    if isinstance(q, AppliedUndef):
        return q.func.__name__
    if isinstance(q, sp.Symbol):
        return q.name
    raise ModelError(f"coordinate {q!r}: expected a name or a dynamicsymbols function q(t)")


def _components(vector: Any, frame: Any, where: str) -> tuple[sp.Expr, ...]:
    me = _me()
    if isinstance(vector, me.Vector) or vector == 0:
        v = vector if isinstance(vector, me.Vector) else me.Vector(0)
        return tuple(v.to_matrix(frame))
    raise ModelError(f"{where}: expected a sympy.physics.mechanics Vector, got {type(vector).__name__}")


def _position(point: Any, origin: Any, frame: Any, where: str) -> tuple[sp.Expr, ...]:
    try:
        r = point.pos_from(origin)
    except ValueError as exc:
        raise ModelError(
            f"{where}: point '{point.name}' has no position relative to the origin "
            f"'{origin.name}' ({exc}); locate it with Point.locatenew or set_pos"
        ) from None
    return _components(r, frame, where)


def _central_inertia(body: Any, frame: Any) -> sp.Matrix:
    """Central inertia tensor of a sympy RigidBody in its own frame (the body may declare its
    inertia about another point: the parallel-axis term is removed)."""
    me = _me()
    dyadic, about = body.inertia
    r = body.masscenter.pos_from(about)
    central = dyadic - me.inertia_of_point_mass(body.mass, r, frame) if r != 0 else dyadic
    return central.to_matrix(body.frame)


def bodies_from_mechanics(frame: Any, origin: Any, bodies: Iterable[Any]) -> tuple:
    """Our :class:`~nonideal.bodies.Particle` / :class:`~nonideal.bodies.RigidBody` from
    ``sympy.physics.mechanics`` particles and rigid bodies.

    Parameters
    ----------
    frame : sympy.physics.mechanics.ReferenceFrame
        The inertial frame: positions and rotation matrices are expressed in it.
    origin : sympy.physics.mechanics.Point
        A point fixed in ``frame``.
    bodies : iterable of Particle, RigidBody (sympy's), or of ours (passed through)

    Returns
    -------
    tuple of nonideal.bodies.Particle, nonideal.bodies.RigidBody
    """
    me = _me()
    out = []
    for b in bodies:
        where = f"body '{getattr(b, 'name', '?')}'"
        if isinstance(b, me.RigidBody):
            pos = _position(b.masscenter, origin, frame, where)
            inertia = _central_inertia(b, frame)
            rotation = frame.dcm(b.frame)
            out.append(RigidBody(b.name, b.mass, inertia.tolist(), pos, rotation.tolist()))
        elif isinstance(b, me.Particle):
            out.append(Particle(b.name, b.mass, _position(b.point, origin, frame, where)))
        elif isinstance(b, (Particle, PlanarBody, RigidBody)):  # ours: passed through
            out.append(b)
        else:
            raise ModelError(f"{where}: not a sympy.physics.mechanics Particle or RigidBody "
                             f"(got {type(b).__name__})")
    return tuple(out)


def loads_from_mechanics(frame: Any, origin: Any, loads: Iterable[Any],
                         bodies: Iterable[Any] = ()) -> tuple:
    """Our :class:`~nonideal.bodies.Force` / :class:`~nonideal.bodies.Torque` from sympy loads.

    Parameters
    ----------
    frame, origin
        As in :func:`bodies_from_mechanics`.
    loads : iterable
        ``sympy.physics.mechanics.Force(point, vector)`` / ``Torque(frame, vector)`` objects or
        the tuples ``(Point, Vector)`` / ``(ReferenceFrame, Vector)`` used by ``KanesMethod``;
        our own :class:`~nonideal.bodies.Force` / :class:`~nonideal.bodies.Torque` pass through.
    bodies : iterable of sympy RigidBody
        A torque acts on the rigid body whose frame it names.

    Returns
    -------
    tuple of nonideal.bodies.Force, nonideal.bodies.Torque
    """
    me = _me()
    by_frame = {id(b.frame): b.name for b in bodies if isinstance(b, me.RigidBody)}
    out = []
    for k, load in enumerate(loads):
        where = f"load {k + 1}"
        if isinstance(load, (Force, Torque)):  # ours: passed through
            out.append(load)
            continue
        try:
            location, vector = load
        except (TypeError, ValueError):
            raise ModelError(f"{where}: expected (Point, Vector) or (ReferenceFrame, Vector), "
                             f"got {load!r}") from None
        if isinstance(location, me.Point):
            out.append(Force(f"force_{location.name}_{k + 1}",
                             _position(location, origin, frame, where), _components(vector, frame, where)))
        elif isinstance(location, me.ReferenceFrame):
            body = by_frame.get(id(location))
            if body is None:
                raise ModelError(f"{where}: the torque acts on frame '{location.name}', which is not "
                                 f"the frame of a RigidBody of this model; attach it to a body")
            out.append(Torque(f"torque_{body}_{k + 1}", _components(vector, frame, where), body=body))
        else:
            raise ModelError(f"{where}: the load's location must be a Point or a ReferenceFrame, "
                             f"got {type(location).__name__}")
    return tuple(out)


def frames_points_from_mechanics(frame: Any, origin: Any, bodies: Iterable[Any], frames: Iterable[Any] = (),
                                 points: Iterable[Any] = ()) -> tuple[tuple, tuple]:
    """Our :class:`Frame` and :class:`Point` declarations of the SymPy frames of the rigid
    bodies and the points of the bodies, plus *frames* and *points* (SymPy objects, or ours,
    passed through): each frame by its rotation matrix in *frame* (``frame.dcm(B)``: columns,
    B's unit vectors), each point by its position from *origin* in *frame*'s axes."""
    me = _me()
    out_frames, out_points, taken = [], [], {frame.name, origin.name}
    sym_frames = [b.frame for b in bodies if isinstance(b, me.RigidBody)] + list(frames)
    sym_points = [b.masscenter if isinstance(b, me.RigidBody) else b.point for b in bodies
                  if isinstance(b, (me.RigidBody, me.Particle))] + list(points)

    def usable(name) -> bool:
        ok = is_identifier(name) and name not in RESERVED_KINEMATIC_NAMES and name not in taken
        taken.add(name)
        return ok
    for f in sym_frames:
        if isinstance(f, Frame):
            out_frames.append(f)
        elif isinstance(f, me.ReferenceFrame) and f is not frame and usable(f.name):
            out_frames.append(Frame(f.name, matrix=frame.dcm(f).tolist()))
    for p in sym_points:
        if isinstance(p, Point):
            out_points.append(p)
        elif isinstance(p, me.Point) and p is not origin and usable(p.name):
            out_points.append(Point(p.name, _position(p, origin, frame, f"point '{p.name}'")))
    return tuple(out_frames), tuple(out_points)


def model_from_mechanics(name: str, coordinates: Sequence[Any], frame: Any, origin: Any,
                         bodies: Iterable[Any], loads: Iterable[Any] = (),
                         gravity: Any = None, initial: Mapping[Any, Any] | None = None,
                         **model_fields: Any) -> Model:
    """A :class:`~nonideal.model.Model` from ``sympy.physics.mechanics`` objects.

    Parameters
    ----------
    name : str
    coordinates : sequence of str or dynamicsymbols
    frame, origin
        The inertial frame and a point fixed in it.
    bodies : iterable of sympy Particle / RigidBody (ours are accepted too)
    loads : iterable of sympy loads (see :func:`loads_from_mechanics`)
    gravity : sympy Vector or sequence, optional
        Uniform gravity (e.g. ``-g*N.z``); its potential is added to the model's.
    initial : mapping, optional
        Keys may be names (``"q1"``, ``"q1'"``) or dynamicsymbols (``q1``, ``q1.diff()``).
    **model_fields
        Any other :class:`~nonideal.model.Model` field (``parameters``, ``constraints``,
        ``contacts``, ``potential``, ``forces``, ``simulation`` ...).
    """
    me = _me()
    sympy_bodies = list(bodies)
    names = tuple(coordinate_name(q) for q in coordinates)
    if isinstance(gravity, me.Vector):
        gravity = _components(gravity, frame, "gravity")
    init = {coordinate_name(k): v for k, v in (initial or {}).items()}
    frames, points = frames_points_from_mechanics(frame, origin, sympy_bodies, model_fields.pop("frames", ()),
                                                  model_fields.pop("points", ()))
    return Model(
        name=name,
        coordinates=names,
        frames=frames,
        points=points,
        bodies=bodies_from_mechanics(frame, origin, sympy_bodies),
        loads=loads_from_mechanics(frame, origin, loads, sympy_bodies),
        gravity=gravity,
        initial=init,
        **model_fields,
    )
