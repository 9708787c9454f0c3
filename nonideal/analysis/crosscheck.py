"""Cross-checks every form against Lagrange I at random admissible states.

All forms must give the same accelerations (and the same multipliers where they define
them) at any admissible state -- the library's strongest internal test, run on every gallery
model.  Unilateral constraints are taken as held.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..numeric.consistency import complete_state, random_admissible_states
from ..errors import FormNotApplicable
from ..equations.formalisms import FORMS
from ..equations.high_order import extended
from ..modeling.contacts import IdealRolling
from ..modeling.model import Model
from ..modeling.speeds import on_unit_sphere
from ..modes.types import SLIDE, SMOOTH, STICK, ContactState, Mode
from ..modes.solver import ModeSolver
from ..numeric.kernel import kernel_of, parameter_vector

__all__ = ["compare_forms", "CrossCheck"]


@dataclass
class CrossCheck:
    """Largest relative disagreement of each form with Lagrange I."""

    states: int
    accelerations: dict[str, float] = field(default_factory=dict)
    multipliers: dict[str, float] = field(default_factory=dict)
    off_chart: dict[str, int] = field(default_factory=dict)  # states no chart of lagrange2 covers
    skipped: dict[str, str] = field(default_factory=dict)    # forms that do not apply, and why

    def worst(self) -> float:
        return max(list(self.accelerations.values()) + list(self.multipliers.values()) + [0.0])


def _rel(a: np.ndarray, b: np.ndarray, scale: float = 0.0) -> float:
    """Relative disagreement of *a* with the reference *b*, measured against ``|b|_inf`` or
    the size *scale* of the terms that produce it, whichever is larger: a reference that
    vanishes by cancellation (a body held at rest by its reactions) is compared with the
    forces that cancel, not with round-off."""
    if a.size == 0:
        return 0.0
    diff = np.abs(a - b)
    if not np.all(np.isfinite(diff)):
        return float("inf")
    return float(np.max(diff) / max(np.max(np.abs(b)), scale, 1e-300))


def _contact_mode(solver: ModeSolver, t, q, qd, held, contact_state: str) -> Mode:
    if not solver.ck:
        return Mode(held)
    cout = solver.ck(solver.input(t, q, qd))
    states = []
    for c, name in enumerate(solver.ck.names):
        if c in solver.frictionless:
            states.append((name, ContactState(SMOOTH)))
            continue
        if contact_state == "stick" or c in solver.rolling:  # ideal rolling never slides
            states.append((name, ContactState(STICK)))
            continue
        U = solver.ck.slip(cout, c)
        direction = (float(np.sign(U[0])) or 1.0,) if len(U) == 1 else tuple(U / np.linalg.norm(U))
        states.append((name, ContactState(SLIDE, direction)))
    return Mode(held, tuple(states))


def compare_forms(model: Model, forms=None, count: int = 20, seed: int = 0,
                  spread: float = 0.3, contact_state: str = "slide", held=None) -> CrossCheck:
    """Evaluate *forms* (default: all, and the numerical Gauss solver) at *count* random
    admissible states.

    Contacts are taken as touching (their gaps closed) and, by *contact_state*, either
    sliding along the current slip (``"slide"``) or sticking (``"stick"``); frictionless ones
    in their one touching state ("smooth").  Unilateral
    constraints are held: all of them, or the names in *held*.

    Returns
    -------
    CrossCheck
        ``skipped[form]``: when *forms* is not given, the forms that do not apply to the model
        (e.g. ``chaplygin`` on a system that is not a Chaplygin system), each with its reason
        (a form asked for by name raises instead).
        ``accelerations[form]`` and ``multipliers[form]``: max over the states of
        ``|x_form - x_lagrange1|_inf / |x_lagrange1|_inf``.  Multipliers are compared for the
        constraints a form keeps in its equations (the others it recovers from Lagrange I's
        residual, which would make the comparison empty).
    """
    requested = forms is not None
    forms = list(forms or (list(FORMS) + ["gauss"]))
    model = extended(model)  # third-order constraints: the forces are part of the state
    kernel = kernel_of(model)
    params = parameter_vector(model)
    q0, qd0, _ = complete_state(kernel, model.numeric_initial(), params, model.t0)
    if held is None:
        held = frozenset(r.name for r in kernel.rows if r.unilateral)
    else:
        held = frozenset(held)
    rows = [i for i, r in enumerate(kernel.rows) if not r.unilateral or r.name in held]
    nc = len(kernel.rows) + len(model.contacts)
    rows += list(range(len(kernel.rows), nc))
    offset = nc
    for c in model.contacts:  # sticking contacts (and ideally rolling ones): their slips vanish too
        if contact_state == "stick" or isinstance(c.friction, IdealRolling):
            rows += list(range(offset, offset + len(c.slip)))
        offset += len(c.slip)
    states = random_admissible_states(kernel, q0, qd0, params, count, seed=seed, spread=spread,
                                      t0=model.t0, rows=rows)
    # Euler parameters on their unit sphere, the manifold the motion keeps (the speed forms'
    # equations are written modulo |e| = 1)
    states = [(t, *on_unit_sphere(model, q, qd)) for t, q, qd in states]
    ref = ModeSolver(kernel, params, "lagrange1")
    solvers = {f: ModeSolver(kernel, params, f, model.independent) for f in forms if f != "lagrange1"}
    report = CrossCheck(len(states), {f: 0.0 for f in solvers}, {f: 0.0 for f in solvers})
    for t, q, qd in states:
        mode = _contact_mode(ref, t, q, qd, held, contact_state)
        r = ref.solve(t, q, qd, mode)
        # the sizes of the terms: accelerations of the free system, generalized forces
        force_scale = float(np.max(np.abs(r.F), initial=0.0))
        try:
            accel_scale = float(np.max(np.abs(np.linalg.solve(r.M, r.F)), initial=0.0))
        except np.linalg.LinAlgError:   # a singular M (massless coordinates): no such scale
            accel_scale = 0.0
        for f, s in solvers.items():
            if f in report.skipped:
                continue
            try:
                sol = s.solve(t, q, qd, mode)
            except FormNotApplicable as exc:
                if s.charts is None and requested:
                    raise
                if s.charts is None:   # all forms asked for: the ones outside their domain say why
                    report.skipped[f] = str(exc)
                    report.accelerations.pop(f, None)
                    report.multipliers.pop(f, None)
                    continue
                report.off_chart[f] = report.off_chart.get(f, 0) + 1  # no chart derivable here
                continue
            report.accelerations[f] = max(report.accelerations[f], _rel(sol.qdd, r.qdd, accel_scale))
            keys = [k for k in sol.direct if k in r.direct]
            if keys:
                a = np.array([sol.direct[k] for k in keys])
                b = np.array([r.direct[k] for k in keys])
                report.multipliers[f] = max(report.multipliers[f], _rel(a, b, force_scale))
    return report
