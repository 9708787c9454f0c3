"""The equations of motion of a model as a user asks for them: :func:`derive` with the model's
defaults filled in from its initial state (the branch of Lagrange II's chart through the
completed initial coordinates).  The symbolic stage (:func:`nonideal.equations.formalisms.derive`)
takes everything explicitly; this is the entry point of the public API and the command line."""

from __future__ import annotations

from collections.abc import Mapping

from ..equations.eom import EquationsOfMotion
from ..equations.formalisms import FORMS, derive as derive_symbolic
from ..equations.dynamics import ConstraintRow
from ..errors import ModelError
from ..modeling.arguments import require_form, require_model
from ..equations.high_order import extended
from ..modeling.model import Model
from ..modes.routes import route_for
from ..numeric.consistency import initial_branch

__all__ = ["derive"]


def derive(model: Model, form: str = "lagrange1", rows: list[ConstraintRow] | None = None,
           independent: tuple[str, ...] | None = None,
           branch: dict[str, float] | None = None, *, contacts: Mapping[str, str] | None = None,
           friction: str = "physical") -> EquationsOfMotion:
    """Equations of motion of *model* in *form* -- the same as ``nonideal derive --form FORM``.

    Parameters
    ----------
    model : Model
    form : str
        ``lagrange1``, ``lagrange2``, ``maggi``, ``appell`` or ``shulgin``.
    rows : list of ConstraintRow, optional
        The constraint rows to respect, given explicitly (the symbolic stage,
        :func:`nonideal.equations.formalisms.derive`; the contacts are then left to the
        caller).  Default: the model's constraints, and its contacts in their states.
    independent : tuple of str, optional
        Independent coordinates of the reduced forms.
    branch : mapping, optional
        Lagrange II: the coordinates through which the roots of the holonomic constraints are
        taken (default: the model's initial state, completed from the constraints).
    contacts : mapping contact -> state, optional
        ``"separated"``, ``"stick"``, ``"slide+"``/``"slide-"`` (one slip component) or
        ``"slide"`` (two).  Contacts not given are in their state at the initial state (the
        mode the simulation starts in): a contact touches, sticks or slides in the equations as
        it does at t0 -- a sliding contact's normal force carries Coulomb's friction ``-mu N s``.
    friction : {"physical", "painleve"}
        ``"painleve"``: the touching contacts as ideal constraints plus the friction force
        ``M V mu`` of the extended method of combining constraints (Manglieva & Beknazarov
        2022, (1.52), (2.7)-(2.8)).

    Examples
    --------
    >>> from nonideal import derive, gallery
    >>> derive(gallery.load("chaplygin-sleigh"), "maggi").unknowns
    ("x''", "theta''")
    """
    require_model(model, "derive")
    model = extended(model)  # third-order constraints: the forces are part of the state
    require_form(form, "derive", FORMS)
    if friction not in ("physical", "painleve"):
        raise ModelError(f"friction: {friction!r} unknown; use \"physical\" or \"painleve\"")
    if rows is not None:
        if contacts or friction != "physical":
            raise ModelError("derive: rows= gives the constraint rows explicitly; the contacts= and "
                             "friction= options do not apply to it")
        return _symbolic(model, form, rows, independent, branch)
    if friction == "painleve":
        from .contact.friction_law import painleve_model, touching_contacts

        closed = touching_contacts(model, dict(contacts or {})) if model.contacts else None
        return _symbolic(painleve_model(model, closed)[0], form, None, independent, branch)
    if model.contacts:
        from .contact.friction_law import derive_in_mode

        return derive_in_mode(model, form, dict(contacts or {}), independent)
    if contacts:
        raise ModelError("contacts: the model has no [[contacts]]")
    return _symbolic(model, form, None, independent, branch)


def _symbolic(model, form, rows, independent, branch) -> EquationsOfMotion:
    if branch is None and route_for(form).charts:
        branch = initial_branch(model)
    return derive_symbolic(model, form, rows=rows, independent=independent, branch=branch)
