"""Stage 5 -- the hybrid simulation: the loop around the ODE solver that restarts at each mode
change (:mod:`~nonideal.simulation.hybrid`), the events (:mod:`~nonideal.simulation.events`) and
the immutable result (:class:`~nonideal.simulation.trajectory.Trajectory`)."""

from .hybrid import Simulation, simulate
from .trajectory import Trajectory

__all__ = ["Simulation", "simulate", "Trajectory"]
