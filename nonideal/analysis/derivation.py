"""The equations of motion of a model as a user asks for them: :func:`derive` with the model's
defaults filled in from its initial state (the branch of Lagrange II's chart through the
completed initial coordinates).  The symbolic stage (:func:`nonideal.equations.formalisms.derive`)
takes everything explicitly; this is the entry point of the public API and the command line."""

from __future__ import annotations

from ..equations.eom import EquationsOfMotion
from ..equations.formalisms import FORMS, derive as derive_symbolic
from ..equations.dynamics import ConstraintRow
from ..modeling.arguments import require_form, require_model
from ..modeling.model import Model
from ..modes.routes import route_for
from ..numeric.consistency import initial_branch

__all__ = ["derive"]


def derive(model: Model, form: str = "lagrange1", rows: list[ConstraintRow] | None = None,
           independent: tuple[str, ...] | None = None,
           branch: dict[str, float] | None = None) -> EquationsOfMotion:
    """Equations of motion of *model* in *form* (see :func:`nonideal.equations.formalisms.derive`
    for the parameters); Lagrange II takes the roots of the holonomic constraints through the
    model's initial state, completed from the constraints when coordinates are missing.

    Examples
    --------
    >>> from nonideal import derive, gallery
    >>> derive(gallery.load("chaplygin-sleigh"), "maggi").unknowns
    ("x''", "theta''")
    """
    require_model(model, "derive")
    require_form(form, "derive", FORMS)
    if branch is None and route_for(form).charts:
        branch = initial_branch(model)
    return derive_symbolic(model, form, rows=rows, independent=independent, branch=branch)
