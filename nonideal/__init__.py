"""nonideal -- analytical dynamics of mechanical systems with ideal and non-ideal constraints.

Describe a system once (:class:`Model`, or a TOML model file) and get its equations of motion
in the classical forms (:func:`derive`), the reactions at a state (:func:`evaluate`) and an
exact hybrid simulation (:func:`simulate`).
"""

from .modeling.bodies import Force, Particle, PlanarBody, RigidBody, Torque
from .modeling.contacts import (
    Contact,
    Coulomb,
    LinearizedCoulomb,
    Newton,
    Plastic,
    RegularizedCoulomb,
)
from .equations.eom import EquationsOfMotion
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
from .analysis.derivation import derive
from .analysis.evaluation import evaluate
from .equations.formalisms import FORMS
from .modeling.mechanics import model_from_mechanics
from .modeling.modelfile import load_model
from .modeling.model import Constraint, Model, Parameter, SimulationSettings
from .simulation.hybrid import Simulation, simulate
from .simulation.trajectory import Trajectory

__version__ = "0.1.0"

__all__ = [
    "Model", "Parameter", "Constraint", "SimulationSettings", "model_from_mechanics",
    "Particle", "PlanarBody", "RigidBody", "Force", "Torque",
    "Contact", "Coulomb", "RegularizedCoulomb", "LinearizedCoulomb", "Plastic", "Newton",
    "EquationsOfMotion", "FORMS", "derive", "evaluate", "simulate", "load_model", "Simulation", "Trajectory",
    "NonidealError", "ModelError", "MechanicsError", "PainleveParadox", "IndeterminateSystem",
    "InconsistentInitialConditions", "IntegrationFailed", "SingularSystem", "FormNotApplicable",
]
