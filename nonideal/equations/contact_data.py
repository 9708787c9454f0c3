"""The symbolic data of a contact, as :class:`~nonideal.equations.dynamics.Dynamics` derives it."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ContactData"]


@dataclass(frozen=True)
class ContactData:
    """Symbolic data of a contact: gap ``g``, ``g'``, ``dg/dq``, ``gamma_n`` (so that
    ``g'' = dg/dq . q'' + gamma_n``), slip velocities ``U``, their Jacobian ``W`` and
    ``gamma_U`` (``U' = W q'' + gamma_U``), friction coefficients.

    A friction torque (``spin_friction``, ``rolling_friction``) is a contact of its own whose
    ``parent`` is the index of the contact it acts at: it has that contact's gap and normal
    force (no normal row of its own), its ``U`` is the angular velocity (spin, rolling), its
    "friction force" the torque, ``mu = mu_s`` the length.
    """

    name: str
    gap: object
    gap_rate: object
    Gn: tuple
    gamma_n: object
    U: tuple
    W: tuple
    gamma_U: tuple
    mu: object
    mu_s: object
    law: object
    bilateral: bool
    restitution: float
    parent: int | None = None
