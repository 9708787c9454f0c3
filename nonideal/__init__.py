"""nonideal -- analytical dynamics of mechanical systems with ideal and non-ideal constraints.

Describe a system once (:class:`Model`, or a TOML model file) and get its equations of motion
in the classical forms (:func:`derive`), the reactions at a state (:func:`evaluate`) and an
exact hybrid simulation (:func:`simulate`).

The names below are imported on first use (PEP 562), so that the command line answers
``nonideal --help``, ``--version`` and ``examples list`` without loading SymPy.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

__version__ = "0.1.0"

#: public name -> module that defines it
_EXPORTS = {
    "Force": "modeling.bodies", "Particle": "modeling.bodies", "PlanarBody": "modeling.bodies",
    "RigidBody": "modeling.bodies", "Torque": "modeling.bodies",
    "Frame": "modeling.frames", "Point": "modeling.points",
    "Contact": "modeling.contacts", "Coulomb": "modeling.contacts", "IdealRolling": "modeling.contacts",
    "LinearizedCoulomb": "modeling.contacts", "Newton": "modeling.contacts",
    "CoulombContensou": "modeling.contacts",
    "Plastic": "modeling.contacts", "RegularizedCoulomb": "modeling.contacts",
    "EquationsOfMotion": "equations.eom",
    "FormNotApplicable": "errors", "IndeterminateSystem": "errors",
    "InconsistentInitialConditions": "errors", "IntegrationFailed": "errors",
    "MechanicsError": "errors", "ModelError": "errors", "NonidealError": "errors",
    "PainleveParadox": "errors", "SingularSystem": "errors",
    "derive": "analysis.derivation", "evaluate": "analysis.evaluation",
    "FORMS": "equations.formalisms", "model_from_mechanics": "modeling.mechanics",
    "load_model": "modeling.modelfile",
    "Constraint": "modeling.model", "Model": "modeling.model", "Parameter": "modeling.model",
    "SimulationSettings": "modeling.model",
    "Simulation": "simulation.hybrid", "simulate": "simulation.hybrid",
    "Trajectory": "simulation.trajectory",
}

__all__ = [
    "Model", "Parameter", "Constraint", "SimulationSettings", "model_from_mechanics",
    "Particle", "PlanarBody", "RigidBody", "Force", "Torque", "Frame", "Point",
    "Contact", "Coulomb", "IdealRolling", "RegularizedCoulomb", "LinearizedCoulomb", "CoulombContensou", "Plastic", "Newton",
    "EquationsOfMotion", "FORMS", "derive", "evaluate", "simulate", "load_model", "Simulation", "Trajectory",
    "NonidealError", "ModelError", "MechanicsError", "PainleveParadox", "IndeterminateSystem",
    "InconsistentInitialConditions", "IntegrationFailed", "SingularSystem", "FormNotApplicable",
]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'nonideal' has no attribute '{name}'")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs
    from .analysis.derivation import derive
    from .analysis.evaluation import evaluate
    from .equations.eom import EquationsOfMotion
    from .equations.formalisms import FORMS
    from .errors import (FormNotApplicable, InconsistentInitialConditions, IndeterminateSystem,
                         IntegrationFailed, MechanicsError, ModelError, NonidealError,
                         PainleveParadox, SingularSystem)
    from .modeling.bodies import Force, Particle, PlanarBody, RigidBody, Torque
    from .modeling.contacts import (Contact, Coulomb, CoulombContensou, IdealRolling, LinearizedCoulomb, Newton,
                                    Plastic, RegularizedCoulomb)
    from .modeling.frames import Frame
    from .modeling.mechanics import model_from_mechanics
    from .modeling.points import Point
    from .modeling.model import Constraint, Model, Parameter, SimulationSettings
    from .modeling.modelfile import load_model
    from .simulation.hybrid import Simulation, simulate
    from .simulation.trajectory import Trajectory
