"""The classical forms of the equations of motion, one module each.

:func:`derive` is the entry point: ``derive(model, "maggi")`` returns an
:class:`~nonideal.equations.eom.EquationsOfMotion`.  :data:`FORMS` maps the CLI names to the classes:

=============  ===========================================================================
``lagrange1``  Lagrange I: every constraint keeps its multiplier (:mod:`.lagrange1`)
``lagrange2``  Lagrange II: holonomic constraints eliminated by minimal coordinates, the
               other constraints with multipliers, Routh--Voss (:mod:`.lagrange2`)
``maggi``      Maggi: the dynamics projected on the possible velocities (:mod:`.maggi`)
``appell``     Gibbs--Appell: derivatives of the acceleration energy (:mod:`.appell`)
``shulgin``    Shulgin: redundant coordinates kept, dependent velocities eliminated,
               Voronets' terms for nonholonomic constraints (:mod:`.shulgin`)
``servo``      Béghin: Lagrange's equations with the reactions of servo-constraints
               (controls) kept and their control-free combinations (:mod:`.servo`)
=============  ===========================================================================

The ideal constraints disappear from the reduced forms; non-ideal ones (servo, quasi-ideal,
sliding friction) keep their multipliers in every form.
"""

from __future__ import annotations

from dataclasses import replace

from ..dynamics import ConstraintRow, dynamics_of
from ..eom import EquationsOfMotion
from ...errors import FormNotApplicable, did_you_mean
from ...modeling.model import Model
from .appell import Appell
from .base import Formalism
from .lagrange1 import Lagrange1
from .lagrange2 import Lagrange2
from .maggi import Maggi
from .servo import Servo
from .kane import Kane
from .hamel import BoltzmannHamel
from .poincare import PoincareChetaev
from .voronets import Chaplygin, Voronets
from .shulgin import Shulgin

__all__ = ["FORMS", "derive", "Formalism"]

FORMS: dict[str, type[Formalism]] = {
    "lagrange1": Lagrange1,
    "lagrange2": Lagrange2,
    "maggi": Maggi,
    "appell": Appell,
    "shulgin": Shulgin,
    "servo": Servo,
    "kane": Kane,
    "boltzmann_hamel": BoltzmannHamel,
    "poincare_chetaev": PoincareChetaev,
    "voronets": Voronets,
    "chaplygin": Chaplygin,
}


def split_independent(model, names) -> tuple[tuple[str, ...] | None, tuple[str, ...] | None]:
    """``(speeds, coordinates)`` of an ``independent`` list of a model with ``[speeds]``: the
    speed names (a coordinate whose velocity is itself a declared speed stands for it), in the
    list's order, and the coordinate names; None for an empty part."""
    own = {}
    for name, e in model.speeds.items():   # speeds that are a coordinate's velocity
        for q, qd in zip(model.coordinates, model.qd):
            if e == qd:
                own.setdefault(q, name)
    speeds = tuple(dict.fromkeys(n if n in model.speeds else own[n] for n in names
                                 if n in model.speeds or n in own))
    coords = tuple(n for n in names if n not in model.speeds)
    return speeds or None, coords or None


def derive(model: Model, form: str = "lagrange1", rows: list[ConstraintRow] | None = None,
           independent: tuple[str, ...] | None = None,
           branch: dict[str, float] | None = None) -> EquationsOfMotion:
    """Equations of motion of *model* in *form*.

    Parameters
    ----------
    model : Model
    form : str
        One of :data:`FORMS` (``lagrange1``, ``lagrange2``, ``maggi``, ``appell``, ``shulgin``).
    rows : list of ConstraintRow, optional
        Constraint rows to respect (default: every constraint of the model, unilateral ones
        taken as active).  The hybrid simulation passes the rows of the current mode.
    independent : tuple of str, optional
        Independent coordinates for the reduced forms (default: the model's ``independent``,
        else a sparse, well-conditioned choice); with declared speeds, speed names too: the
        speeds the quasi-velocity forms keep first (:func:`split_independent`).
    branch : dict name -> float, optional
        Lagrange II only: the coordinates through which the roots of the holonomic
        constraints are chosen (default: the model's initial state).  The hybrid simulation
        passes the current state when it changes charts.

    Returns
    -------
    EquationsOfMotion

    Examples
    --------
    >>> from nonideal import gallery
    >>> eom = derive(gallery.load("chaplygin-sleigh"), "maggi")
    >>> eom.unknowns
    ("x''", "theta''")
    """
    if form not in FORMS:
        raise FormNotApplicable(
            f"--form: unknown form '{form}'{did_you_mean(form, FORMS)}; choose one of "
            + ", ".join(FORMS)
        )
    dyn = dynamics_of(model)
    free_flight = rows is None and bool(model.contacts)
    if rows is None:
        rows = dyn.rows()
    if independent is None:
        independent = model.independent
    formalism = FORMS[form]()
    if independent is not None and model.speeds:   # speed names for the speed forms
        formalism.speed_order, independent = split_independent(model, independent)
    if branch is not None:
        formalism.branch = dict(branch)
    eom = formalism.derive(dyn, list(rows), independent)
    if free_flight:   # said, never silent: the contacts need their states (nonideal.derive)
        names = ", ".join(f"'{c.name}'" for c in model.contacts)
        note = (f"the contacts {names} are not in these equations (no normal force, no friction: "
                "free flight); nonideal.derive puts them in their states at t0, as "
                "'nonideal derive' does")
        eom = replace(eom, notes=(note,) + tuple(eom.notes))
    quasi = [r.name for r in rows if r.reaction_kind == "quasi-ideal"]
    if quasi:   # the multiplier of R = adj(A) grad f mu is not the paper's lambda: say so
        note = ("quasi-ideal constraint(s) " + ", ".join(f"'{n}'" for n in quasi) + ": the reaction "
                "is R = adj(A) grad f * lambda_<name> (finite where det A = 0), so lambda_<name> "
                "here is mu, and Briskin et al. 2021's lambda in A R = lambda grad f is "
                "det(A) * lambda_<name>")
        eom = replace(eom, notes=tuple(eom.notes) + (note,))
    return eom
