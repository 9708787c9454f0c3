"""The uniqueness of the support points watched along a motion.

A contact from geometry has a unique support point only where its shape's validity expression
(:meth:`~nonideal.modeling.shapes.base.Shape.validity`) is positive: a thin disk's rim has
``1 - (n_b . a)^2 = sin^2`` of its tilt from lying flat, a paraboloid the component ``n_b . e_z``
of the plane's normal along its axis.  The start is checked when the initial state is completed;
a motion that starts regular can still reach such a state -- a coin that falls flat on its face,
a rattleback tipped over the rim of its paraboloid.  There the support point jumps (the rim's
touching point to the opposite side), the gap has a kink and the contact force no definite
point of application: integrating on would carry a singular contact as if it were regular.

:class:`SupportWatch` evaluates the validity of every such contact at the states the simulation
accepts (the end of every step and every sample) and raises
:class:`~nonideal.errors.SingularMotion` (exit code 3) at the first one where it has fallen to
:data:`LEVEL`, naming the contact, the time, the state and the reason.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import sympy as sp

from ...errors import SingularMotion
from ..symbols import t as time

__all__ = ["SupportWatch", "LEVEL"]

LEVEL = 1e-8
"""The validity at which a support point counts as no longer unique along a motion: for a disk,
``sin^2`` of the tilt from flat, a tilt of 1e-4 rad -- where the rim's touching point moves over
the body ten thousand times faster than the tilt changes and the steps collapse.  (The initial
state is refused only at 1e-12, where it is singular to rounding.)"""


class SupportWatch:
    """The validity of the contacts' support points, compiled; :meth:`check` refuses a state
    where one of them is no longer unique.

    Parameters
    ----------
    model : Model
        The normalized model (its ``contacts`` with ``geometry``).
    params : sequence of float
        The parameter values, in the order of ``model.parameter_values``.
    """

    def __init__(self, model, params: Sequence[float]):
        self.model = model
        self.watched: list[tuple[object, object, str]] = []
        values = {sp.Symbol(str(k)): float(v) for k, v in zip(model.parameter_values, params)}
        args = [time, *model.q]
        for c in model.contacts:
            geometry = getattr(c, "geometry", None)
            if geometry is None or geometry.validity is None:
                continue
            expr, why = geometry.validity
            expr = sp.sympify(expr).xreplace(values)
            self.watched.append((c, sp.lambdify(args, expr, "numpy"), why))

    def __bool__(self) -> bool:
        return bool(self.watched)

    def check(self, t: float, q: Sequence[float]) -> None:
        """Raise :class:`~nonideal.errors.SingularMotion` when a support point is no longer
        unique at time *t* and coordinates *q* (the first entries of a state are enough)."""
        if not self.watched:
            return
        q = [float(v) for v in q[:len(self.model.q)]]
        for contact, f, why in self.watched:
            value = float(f(float(t), *q))
            if value > LEVEL:
                continue
            state = dict(zip(self.model.coordinates, q))
            at = ", ".join(f"{n} = {v:.6g}" for n, v in state.items())
            raise SingularMotion(
                f"contact '{contact.name}' (shape {contact.shape.TYPE} of body '{contact.body}') "
                f"loses its unique support point along the motion at t = {float(t):.10g} ({at}; "
                f"uniqueness measure {value:.3g} <= {LEVEL:g}): {why}. The motion is not "
                "continued through it; end the run before t or model the flat contact otherwise",
                float(t), state, details={"contact": contact.name, "validity": value})
