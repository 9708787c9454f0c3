"""The stall of an integration at a vanishing two-component slip, named.

Under the exact Coulomb law a contact that slides in two tangential directions stops in finite
time; as its slip ``U`` vanishes, its direction may turn ever faster (the friction force,
``-mu N U/|U|``, turns with it), and the solution's higher derivatives grow like inverse
powers of the time left.  Below :data:`~nonideal.numeric.contact_kernel.SLIP_FLOOR` of the
speeds the friction acts along the slip's reference, so the slip passes through zero smoothly
and its stop is located as any event; a slip that the steps cannot bring to zero, hovering
below :data:`SLIP_LEVEL` of the speeds for many tiny steps, is stopped there
(:func:`~nonideal.simulation.guards.arrest`).  Should an integration still stall at a slip
that hovers at the level of rounding, this module says so, rather than the generic
explanation of a right-hand side that is not smooth.
"""

from __future__ import annotations

import numpy as np

from ..errors import IntegrationFailed
from ..modes.motion import Motion
from ..modes.types import SLIDE
from ..numeric.contact_kernel import SLIP_LEVEL
from ..numeric.kernel import max_abs

__all__ = ["slip_stall"]

def slip_stall(sim, ode, mode) -> None:
    """Raise :class:`~nonideal.errors.IntegrationFailed` naming the sliding contact of *mode*
    whose two-component slip is vanishing at the solver's state *ode*, if there is one."""
    solver = sim.solver
    if solver.ck is None:
        return
    motion = Motion(solver, mode, float(ode.t), np.asarray(ode.y, dtype=float))
    speed = 1.0 + max_abs(motion.qd)
    for c, (name, cs) in enumerate(mode.contacts):
        if cs.state != SLIDE or solver.ck.dims[c] < 2:
            continue
        slip = float(np.linalg.norm(motion.slip(c)))
        if slip <= SLIP_LEVEL * speed:
            source = None if sim.model.source == "<api>" else sim.model.source
            raise IntegrationFailed(
                ode.t, mode.label(),
                f"the slip of the sliding contact '{name}' is vanishing (|U| = {slip:.3g}) while "
                "its direction turns: the exact Coulomb law in two tangential directions stops "
                "it in finite time, and here the steps could not reach that instant (the slip "
                "stays at the level of rounding; another rtol, or native=False/True, takes other "
                "steps; friction = \"regularized\" with a small eps resolves the stop smoothly)", source)
