"""Model transformations used by the friction representations (kept apart from the Model)."""

from __future__ import annotations

import sympy as sp

from .dynamics import Dynamics
from .errors import FormNotApplicable
from .formalisms.base import reduce_velocities
from .model import Constraint, Model, Parameter
from .symbols import to_sp

__all__ = ["contact_gap_constraints"]


def contact_gap_constraints(model: Model, contacts=None) -> tuple[Model, list[str]]:
    """See :func:`nonideal.friction_law.painleve_model`."""
    names = [c.name for c in model.contacts] if contacts is None else list(contacts)
    chosen = [c for c in model.contacts if c.name in names]
    if not chosen:
        raise FormNotApplicable("painleve representation: no contact to close (the model has no contacts, "
                                "or none of those asked for touches; e.g. --contact NAME=slide+ closes one)")
    constraints = list(model.constraints) + [Constraint(c.name, c.gap, "holonomic") for c in chosen]
    base = model.replace(constraints=tuple(constraints),
                         contacts=tuple(c for c in model.contacts if c.name not in names))
    dyn = Dynamics(base)
    red = reduce_velocities(dyn, dyn.rows(), base.independent)
    if red.auxiliaries:
        raise FormNotApplicable("painleve representation: the velocity basis is too large to write "
                                "explicitly; use the physical representation")
    k = len(red.independent)
    if k == 0:
        raise FormNotApplicable("painleve representation: with the contacts " + ", ".join(
            f"'{c.name}'" for c in chosen) + " closed the system has no possible velocity (no degree "
            "of freedom is left for the friction force M V mu); close only the contacts that touch "
            "together (e.g. --contact NAME=separated for the others)")
    taken = set(model.parameters) | set(model.coordinates)
    mu_names = []
    for j in range(k):
        name = f"mu_{j + 1}" if f"mu_{j + 1}" not in taken else f"mu_tau_{j + 1}"
        mu_names.append(name)
    M = to_sp(dyn.M)
    V = to_sp(red.V)
    mus = sp.Matrix([sp.Symbol(n) for n in mu_names])
    friction = M * V * mus
    forces = [f + friction[i] for i, f in enumerate(model.forces)]
    params = dict(model.parameters)
    for n_ in mu_names:
        params[n_] = Parameter(n_, 0.0, "", "friction coefficient of the system (seed 000 (1.52))")
    new = base.replace(forces=dict(zip(model.coordinates, forces)), parameters=params,
                       name=f"{model.name} (friction as M V mu)")
    return new, mu_names
