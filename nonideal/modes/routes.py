"""The routes by which :class:`~nonideal.modes.solver.ModeSolver` solves the motion at a state,
chosen once by the form's name (as PyDy picks its code generator once), so that the hot path
reads a route's properties instead of testing form names.

=============  ==============================================================================
route          how the accelerations and multipliers are found
=============  ==============================================================================
saddle point   Lagrange I: ``[[M, -B], [G, 0]] [q''; lambda] = [F; -gamma]`` assembled by index
               from the compiled kernels (:mod:`~nonideal.modes.system`); multipliers direct
reduced form   Maggi, Gibbs--Appell, Shulgin: the form derived per mode structure and compiled;
               the ideal multipliers recovered afterwards; dependent velocities re-chosen near
               a singular partition (:mod:`~nonideal.modes.partition`)
charts         Lagrange II: a reduced form on a chart of the holonomic constraints, the chart
               changed along the motion (:mod:`~nonideal.modes.charts`)
Gauss          the generalized Gauss principle with the system's friction law, an independent
               null-space solver (:mod:`~nonideal.modes.gauss`)
=============  ==============================================================================
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Route", "route_for", "SADDLE_POINT", "REDUCED_FORM", "CHARTS", "GAUSS"]


@dataclass(frozen=True)
class Route:
    """A way of solving the motion at a state (a value object; see the module's table)."""

    name: str
    #: the mode's saddle-point system of Lagrange I (the fast path)
    saddle_point: bool = False
    #: a symbolic form derived per mode structure (multipliers of ideal rows recovered)
    derived: bool = False
    #: Lagrange II charts of the holonomic constraints, changed along the motion
    charts: bool = False
    #: re-choose the dependent velocities of a reduced form near a singular partition
    repartition: bool = False
    #: the generalized Gauss principle (numerical, no symbolic form)
    gauss: bool = False


SADDLE_POINT = Route("saddle point", saddle_point=True)
REDUCED_FORM = Route("reduced form", derived=True, repartition=True)
CHARTS = Route("charts", derived=True, charts=True)
GAUSS = Route("Gauss", gauss=True)
#: the quasi-velocity forms: their unknowns are speeds, not coordinates to re-partition
SPEEDS = Route("quasi-velocity form", derived=True)

_BY_FORM = {"lagrange1": SADDLE_POINT, "lagrange2": CHARTS, "gauss": GAUSS,
            "kane": SPEEDS, "boltzmann_hamel": SPEEDS, "poincare_chetaev": SPEEDS}


def route_for(form: str) -> Route:
    """The route of a form: Lagrange I's saddle point, Lagrange II's charts, the Gauss
    principle, or (every other form: Maggi, Appell, Shulgin) a derived reduced form."""
    return _BY_FORM.get(form, REDUCED_FORM)
