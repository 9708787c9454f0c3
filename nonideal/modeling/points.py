"""Points: the declaration (:class:`Point`) of a point by its position from another point.

``[[points]] name, position = [..], frame = "B", from = "P"``: the point lies at ``position``
(components in the axes of ``frame``, default the fixed frame ``N``) from the point ``from``
(default ``O``, the origin of N).  A point whose position components are constants in a
frame's axes is fixed in that frame.  Velocities and accelerations in N are derived by
:class:`~nonideal.modeling.kinematics.Kinematics` (the two-point and one-point theorems).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .frames import FIXED, ORIGIN

__all__ = ["Point"]


@dataclass(frozen=True)
class Point:
    """A point at ``position`` (in ``frame``'s axes) from the point ``origin``.

    Parameters
    ----------
    name : str
    position : sequence of 3 expressions
        Components in the axes of ``frame``.
    frame : str
        Default ``"N"``.
    origin : str
        The point the position is measured from (the key ``from`` of a model file); default
        ``"O"``, the origin of N.

    Examples
    --------
    >>> Point("G", ("0", "0", "l"), frame="B").origin
    'O'
    """

    name: str
    position: tuple[Any, ...]
    frame: str = FIXED
    origin: str = ORIGIN

    def __post_init__(self):
        if isinstance(self.position, (list, tuple)):
            object.__setattr__(self, "position", tuple(self.position))
