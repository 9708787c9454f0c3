"""nonideal -- analytical dynamics of mechanical systems with ideal and non-ideal constraints.

Describe a system once (:class:`Model`, or a TOML model file) and get its equations of motion
in the classical forms (:func:`derive`), the reactions at a state (:func:`evaluate`) and an
exact hybrid simulation (:func:`simulate`).
"""

from .bodies import Force, Particle, PlanarBody, RigidBody, Torque
from .contacts import Contact, Coulomb, LinearizedCoulomb, Newton, Plastic, RegularizedCoulomb
from .eom import EquationsOfMotion
from .errors import (
    FormNotApplicable,
    IndeterminateSystem,
    InconsistentInitialConditions,
    IntegrationFailed,
    MechanicsError,
    ModelError,
    NonidealError,
    PainleveParadox,
    SingularSystem,
)
from .formalisms import FORMS, derive
from .mechanics import model_from_mechanics
from .model import Constraint, Model, Parameter, SimulationSettings
from .simulation import Simulation, simulate
from .trajectory import Trajectory

__version__ = "0.1.0"

__all__ = [
    "Model", "Parameter", "Constraint", "SimulationSettings", "model_from_mechanics",
    "Particle", "PlanarBody", "RigidBody", "Force", "Torque",
    "Contact", "Coulomb", "RegularizedCoulomb", "LinearizedCoulomb", "Plastic", "Newton",
    "EquationsOfMotion", "FORMS", "derive", "simulate", "Simulation", "Trajectory",
    "NonidealError", "ModelError", "MechanicsError", "PainleveParadox", "IndeterminateSystem",
    "InconsistentInitialConditions", "IntegrationFailed", "SingularSystem", "FormNotApplicable",
]
