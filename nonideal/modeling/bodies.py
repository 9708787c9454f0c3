"""Bodies and loads: the kinetic energy and generalized forces assembled from geometry.

A model's kinetic energy can be written directly (``kinetic = "..."``) or assembled from
bodies whose positions are functions of the coordinates and time:

* :class:`Particle` -- a point mass at ``position`` (2 or 3 components);
* :class:`PlanarBody` -- a rigid body in the plane: mass, central moment of inertia,
  centre-of-mass position (2 components) and rotation angle;
* :class:`RigidBody` -- a rigid body in space: mass, central inertia tensor in body axes,
  centre-of-mass position (3 components) and rotation matrix (body -> world).

Loads become generalized forces by virtual work:

* :class:`Force` -- a force (world components, may depend on velocities and time) applied at
  a point ``Q_j = F . dr/dq_j``;
* :class:`Torque` -- a torque about the normal of the plane applied to a body rotating by
  ``angle`` (``Q_j = tau d(angle)/dq_j``), or, with three components, a spatial torque applied
  to a :class:`RigidBody` (``Q_j = tau . d(omega)/d(qd_j)``).

Fields accept strings (parsed safely) or SymPy expressions; the :class:`~nonideal.model.Model`
normalizes them.  These are plain value objects; the symbolic work happens in
:mod:`nonideal.equations.dynamics`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Particle", "PlanarBody", "RigidBody", "Force", "Torque"]


@dataclass(frozen=True)
class Particle:
    """A point mass.

    Parameters
    ----------
    name : str
    mass : str or sympy.Expr
    position : sequence of 2 or 3 expressions in the coordinates and time
    point : str, optional
        Instead of ``position``: a declared point (:class:`~nonideal.modeling.points.Point`);
        the model fills ``position`` from it.
    """

    name: str
    mass: Any
    position: tuple[Any, ...] | None = None
    point: str | None = None

    def __post_init__(self):
        if self.position is not None:
            object.__setattr__(self, "position", tuple(self.position))


@dataclass(frozen=True)
class PlanarBody:
    """A rigid body moving in a plane.

    Parameters
    ----------
    name : str
    mass : expression
    inertia : expression
        Moment of inertia about the centre of mass, normal to the plane.
    position : sequence of 2 expressions
        Centre of mass.
    angle : expression
        Rotation angle of the body (counter-clockwise).
    """

    name: str
    mass: Any
    inertia: Any
    position: tuple[Any, ...]
    angle: Any

    def __post_init__(self):
        object.__setattr__(self, "position", tuple(self.position))


@dataclass(frozen=True)
class RigidBody:
    """A rigid body in space.

    Parameters
    ----------
    name : str
    mass : expression
    inertia : 3x3 nested sequence of expressions
        Central inertia tensor in body axes.
    position : sequence of 3 expressions
        Centre of mass in world axes.
    rotation : 3x3 nested sequence of expressions
        Rotation matrix R (body -> world): world components = R @ body components.
    frame, center : str, optional
        Instead of ``position`` and ``rotation``: a declared frame fixed in the body (its
        inertia is in the frame's axes) and a declared point, the centre of mass.  The model
        fills ``position``, ``rotation`` and ``omega`` from them.
    omega : sequence of 3 expressions, optional
        The angular velocity in the body's axes (filled from ``frame``; otherwise the
        dynamics derives it from ``rotation``).

    Examples
    --------
    >>> RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]], frame="B", center="G").frame
    'B'
    """

    name: str
    mass: Any
    inertia: tuple[tuple[Any, ...], ...]
    position: tuple[Any, ...] | None = None
    rotation: tuple[tuple[Any, ...], ...] | None = None
    frame: str | None = None
    center: str | None = None
    omega: tuple[Any, ...] | None = None

    def __post_init__(self):
        if self.position is not None:
            object.__setattr__(self, "position", tuple(self.position))
        object.__setattr__(self, "inertia", tuple(tuple(r) for r in self.inertia))
        if self.rotation is not None:
            object.__setattr__(self, "rotation", tuple(tuple(r) for r in self.rotation))
        if self.omega is not None:
            object.__setattr__(self, "omega", tuple(self.omega))


@dataclass(frozen=True)
class Force:
    """A force applied at a point; becomes ``Q_j = F . dr/dq_j``.

    Parameters
    ----------
    name : str
    point : sequence of 2 or 3 expressions (position of the point of application)
    force : sequence of the same length (world components; may depend on q, q', t)
    """

    name: str
    point: tuple[Any, ...]
    force: tuple[Any, ...]

    def __post_init__(self):
        object.__setattr__(self, "point", tuple(self.point))
        object.__setattr__(self, "force", tuple(self.force))


@dataclass(frozen=True)
class Torque:
    """A torque.

    Planar: ``angle`` is the rotation angle of the body it acts on and ``torque`` a scalar;
    ``Q_j = torque * d(angle)/dq_j``.  Spatial: ``body`` names a :class:`RigidBody` and
    ``torque`` has three world components; ``Q_j = torque . d(omega)/d(q'_j)``.
    """

    name: str
    torque: Any
    angle: Any = None
    body: str | None = None

    def __post_init__(self):
        if isinstance(self.torque, (list, tuple)):
            object.__setattr__(self, "torque", tuple(self.torque))


BODY_TYPES = (Particle, PlanarBody, RigidBody)
LOAD_TYPES = (Force, Torque)
