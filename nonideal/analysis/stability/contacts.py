"""Contacts in the first approximation: each touching contact becomes the constraint it is.

A model with ``[[contacts]]`` is linearized in the mode its contacts have at the state
(:func:`~nonideal.modes.switching.select_mode`, the choice the simulation makes there):

* **sticking / rolling** (``stick``, and ``mu = inf``): the gap ``g(q, t) = 0`` is a holonomic
  constraint (its multiplier is the normal force ``N``) and the slip rows ``U = 0`` are
  nonholonomic constraints (their multipliers are the friction force);
* **sliding** (``slide``): the gap is a holonomic constraint whose reaction carries the
  friction force, ``R = (dg/dq)^T N - mu sigma N W^T U/|U|`` (``W = dU/dq'``, ``sigma`` the
  sign of ``N`` of a bilateral contact, else 1) -- the friction law ``F = -mu |N| U/|U|`` with
  the current slip direction, linearized with the state (a slip of one component keeps its
  sign: ``U/|U|`` is that constant);
* **touching without a sticking mode** (``smooth``: frictionless, or a regularized law): the
  gap constraint, with the regularized friction in its reaction when there is one;
* **separated**: ignored (a perturbation that closes the gap is not linear).

A friction torque (``spin_friction``, ``rolling_friction``) is treated as its contact's slip:
sticking, its angular-velocity rows are nonholonomic constraints; sliding, its torque
``-l N w/|w|`` joins the friction in the reaction of its contact's gap.

The perturbations stay on these constraints, exactly as for hand-written ones
(:mod:`nonideal.analysis.stability.linearize`), so a contact model and the same system
written with ``[[constraints]]`` give the same matrix ``A``.

API::

    contact_modes(model, state, t) -> Mode
    as_constraints(model, mode) -> (Model, {contact: mode label})
"""

from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import sympy as sp

from ...errors import ModelError
from ...modeling.contacts import (Coulomb, CoulombContensou, IdealRolling, LinearizedCoulomb, RegularizedCoulomb,
                                  torques)
from ...modeling.declarations import Constraint
from ...modeling.model import Model
from ...modes.types import SEPARATED, SLIDE, SMOOTH, STICK, Mode
from .linear_system import parse_state

__all__ = ["contact_modes", "as_constraints", "guess_state", "described"]


def described(model: Model, labels: dict[str, str]) -> dict[str, tuple[str, str]]:
    """``{name: (mode label, how it enters the linearization)}`` of every contact and friction
    torque of *model* (for the reports)."""
    torque_names = {name for c in model.contacts for name, _, _ in torques(c)}
    out = {}
    for name, label in labels.items():
        what = "angular velocity" if name in torque_names else "slip"
        force = "torque -l N w/|w|" if name in torque_names else "friction -mu |N| U/|U|"
        if label.startswith("stick"):
            how = f"{what} = 0 nonholonomic" + ("" if name in torque_names else ", gap = 0 holonomic") \
                + " (sticking" + ("" if name in torque_names else "/rolling") + ")"
        elif label.startswith("slide"):
            how = f"{force} in the reaction of the gap = 0 (sliding)"
        elif label.startswith("smooth"):
            how = "gap = 0 holonomic (touching without a sticking mode)"
        else:
            how = "ignored (separated)"
        out[name] = (label, how)
    return out


def guess_state(model: Model, about: str, at, symbolic) -> dict[str, float]:
    """The state the contacts' mode is chosen at: *at* (numbers at the parameters' values)
    over the model's initial values; every velocity 0 for an equilibrium."""
    given = parse_state(model, at, symbolic)
    subs = {sp.Symbol(name): val for name, val in model.parameter_values.items()}
    state = {key: float(expr.xreplace(subs)) for key, expr in given.items()}
    try:
        init = dict(model.numeric_initial())
    except Exception:  # noqa: BLE001 -- an initial state is only a default guess
        init = {}
    if about == "equilibrium":
        init = {key: v for key, v in init.items() if not key.endswith("'")}
        init.update({c + "'": 0.0 for c in model.coordinates})
    init.update(state)
    return init


def contact_modes(model: Model, state: Mapping[str, float], t: float) -> Mode:
    """The mode of the contacts at a state (*state*: coordinates and velocities by name,
    completed from the model's initial values and the closed contacts), as the simulation
    would choose it there.

    Raises
    ------
    MechanicsError
        The contact forces at the state have no consistent answer (Painlevé).
    """
    from ...modes.solver import ModeSolver
    from ...modes.switching import select_mode
    from ...numeric.consistency import complete_state
    from ...numeric.kernel import kernel_of, parameter_vector

    kernel = kernel_of(model)
    params = parameter_vector(model)
    q, qd, _ = complete_state(kernel, dict(state), params, t)
    return select_mode(ModeSolver(kernel, params), t, q, qd)


def _unique(name: str, taken: set[str]) -> str:
    out, k = name, 2
    while out in taken:
        out, k = f"{name}_{k}", k + 1
    taken.add(out)
    return out


def as_constraints(model: Model, mode: Mode) -> tuple[Model, dict[str, str]]:
    """The model without contacts, each touching contact written as the constraint it is in
    *mode* (see the module docstring); with the mode label of every contact and friction torque.

    The gap of contact ``c`` becomes the holonomic constraint ``c`` (its multiplier
    ``lambda_c`` is the normal force), a sticking contact's slip rows the nonholonomic
    constraints ``c_slip`` (one component) or ``c_slip1``, ``c_slip2``; a sticking friction
    torque's angular-velocity rows the nonholonomic constraints ``c_spin`` / ``c_rolling``
    (``c_rolling1``, ``c_rolling2``); a sliding one's torque ``-l N w/|w|`` joins the friction
    in the reaction of the gap.
    """
    taken = {c.name for c in model.constraints}
    added: list[Constraint] = []
    labels: dict[str, str] = {}
    q, qd = model.q, model.qd
    for contact in model.contacts:
        cs = mode.contact(contact.name)
        labels[contact.name] = cs.label()
        channels = [(contact.name, "_slip", [sp.sympify(u) for u in contact.slip], cs, contact.friction)]
        for name, rows, length in torques(contact):
            labels[name] = mode.contact(name).label()
            channels.append((name, "", [sp.sympify(u) for u in rows], mode.contact(name), Coulomb(length)))
        if cs.state == SEPARATED:
            continue
        gap = sp.sympify(contact.gap)
        name = _unique(contact.name, taken)
        friction = [sp.Integer(0)] * model.n_q     # the sliding friction forces and torques
        rows_added = []
        for label, suffix, rows, state, law in channels:
            if state.state == STICK:
                for k, U in enumerate(rows):
                    row = label + suffix + ("" if len(rows) == 1 else str(k + 1))
                    rows_added.append(Constraint(_unique(row, taken), U, kind="nonholonomic"))
                continue
            direction = _friction_direction(replace(contact, friction=law), state, rows)
            if direction is not None:
                mu = sp.sympify(law.mu)
                friction = [f + mu * state.sigma * sum((sp.diff(U, qd[i]) * d for U, d in zip(rows, direction)),
                                                       sp.Integer(0)) for i, f in enumerate(friction)]
        if all(f == 0 for f in friction):
            added.append(Constraint(name, gap, kind="holonomic"))
        else:
            reaction = tuple(sp.diff(gap, q[i]) - friction[i] for i in range(model.n_q))
            added.append(Constraint(name, gap, kind="servo", reaction=reaction))
        added += rows_added
    return model.replace(contacts=(), constraints=tuple(model.constraints) + tuple(added)), labels


def _friction_direction(contact, cs, slips):
    """``U/|U|`` (sliding), the regularized law's ``U/sqrt(|U|^2 + eps^2)`` or ``U/eps``
    (smooth), or ``None`` without friction."""
    law = contact.friction
    if cs.state == SLIDE:
        if len(slips) == 1:
            return [sp.Integer(1) if cs.direction[0] > 0 else sp.Integer(-1)]
        size = sp.sqrt(sum(U ** 2 for U in slips))
        return [U / size for U in slips]
    if cs.state != SMOOTH or isinstance(law, IdealRolling):
        raise ModelError(f"stability: contact '{contact.name}' in the state '{cs.label()}' has no "
                         "linearization")
    if isinstance(law, RegularizedCoulomb):
        eps = sp.sympify(law.eps)
        size = sp.sqrt(sum(U ** 2 for U in slips) + eps ** 2)
        return [U / size for U in slips]
    if isinstance(law, CoulombContensou):
        raise ModelError(f"stability: contact '{contact.name}' uses the Coulomb-Contensou law, whose force "
                         "is the integral f(d) of the patch (no closed form to differentiate); linearize "
                         "the model with friction = \"coulomb\" or \"regularized\"")
    if isinstance(law, LinearizedCoulomb):
        raise ModelError(f"stability: contact '{contact.name}' uses the epsilon-linear law, which is "
                         "not differentiable where |U| = eps; linearize the model with the exact law "
                         "(remove friction and eps) or the smooth one (friction = \"regularized\")")
    return None                        # a Coulomb contact touching smoothly has mu = 0
