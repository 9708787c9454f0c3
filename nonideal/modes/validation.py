"""Checks of a state that starts an evaluation or a simulation: what the model file cannot
express about the contacts (friction coefficients at the state, friction on a direction the
constraints fix, an ideally rolling contact that would slip), finite terms, a positive definite
kinetic energy.  Memoized per input."""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..numeric.kernel import max_abs
from .diagnosis import diagnose_initial_state, diagnose_state, format_state, singular_configuration
from .solver import ModeSolver

__all__ = ["validate_contacts", "validate_state"]


def validate_contacts(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray) -> None:
    """Checks of the contacts at a state that the model file cannot express.

    Raises
    ------
    ModelError
        A negative friction coefficient (when it depends on the state), or friction declared on
        a direction the constraints already fix (the slip velocity has no freedom: its Jacobian
        lies in the span of the constraint and gap Jacobians).
    """
    ck = solver.ck
    if not ck:
        return
    x = solver.input(t, q, qd)
    # a pure function of the model and the input: states already found valid are not checked again
    key = x.tobytes()
    seen = solver.model.cached("valid contact inputs", set)
    if key in seen:
        return
    cout = {k: np.array(v) if isinstance(v, np.ndarray) else v for k, v in ck(x).items()}
    out = solver.kernel.dynamics(x)
    src = None if solver.model.source == "<api>" else solver.model.source
    problems = []
    G_con = solver.kernel.dense(out, "G")[solver.bilateral] if solver.kernel.m and solver.bilateral \
        else np.zeros((0, solver.n))
    for c, data in enumerate(ck.data):
        name = data.name
        if cout["mu"][c] < 0 or cout["mu_s"][c] < 0:
            problems.append(f"contact '{name}': friction coefficient is negative at the initial state "
                            f"(mu = {cout['mu'][c]:.6g}, mu_static = {cout['mu_s'][c]:.6g}); it must be >= 0")
        if cout["mu_s"][c] < cout["mu"][c] - 1e-12:
            problems.append(f"contact '{name}': mu_static = {cout['mu_s'][c]:.6g} is smaller than the "
                            f"kinetic mu = {cout['mu'][c]:.6g}; Coulomb's law needs mu_static >= mu")
        o, d = ck.offsets[c], ck.dims[c]
        base = np.vstack([G_con, cout["Gn"][c][None, :]])
        W = cout["W"][o:o + d]
        r0 = np.linalg.matrix_rank(base)
        r1 = np.linalg.matrix_rank(np.vstack([base, W]))
        if r1 < r0 + d:
            problems.append(
                f"contact '{name}': friction on a direction with no tangential freedom -- the slip "
                "velocity's gradient lies in the span of the constraints and the normal; the "
                "constraints already fix that motion, so no friction force can be identified. "
                "Remove the constraint that fixes it or the friction on this contact")
        U = cout["U"][o:o + d]
        sq, sv = 1.0 + max_abs(q), 1.0 + max_abs(qd)
        closed = data.bilateral or (abs(cout["gap"][c]) <= 1e-8 * sq and cout["gap_rate"][c] <= 1e-8 * sv)
        if c in solver.rolling and closed and np.sqrt(U @ U) > 1e-8 * sv:
            problems.append(
                f"contact '{name}' rolls ideally (mu = inf) but slips at the state it starts from "
                f"(slip velocity U = {', '.join(f'{u:.6g}' for u in U)} with the gap closed): an ideally "
                "rolling contact cannot slide; give velocities that make U = 0, or start with the gap "
                "open (the touch is then an impact that stops the slip)")
        if np.linalg.norm(cout["Gn"][c]) < 1e-14:
            problems.append(f"contact '{name}': the gap has zero gradient at the initial state, so no "
                            "normal force can be identified; write the gap as the normal distance")
    if problems:
        raise ModelError(problems, src)
    if len(seen) > 256:
        seen.clear()
    seen.add(key)


def validate_state(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray) -> None:
    """Checks of a state that starts an evaluation or a simulation: the contacts
    (:func:`validate_contacts`), every term of the equations finite there (naming the kinetic
    energy, the potential or the forces), and the kinetic energy positive definite on the
    velocities the bilateral constraints allow (a negative mass or moment of inertia: no
    Painleve paradox, bad input) -- memoized per input like the contacts' checks.

    Raises
    ------
    ModelError
    """
    validate_contacts(solver, t, q, qd)
    x = solver.input(t, q, qd)
    key = x.tobytes()
    seen = solver.model.cached("well-posed inputs", set)
    if key in seen:
        return

    model = solver.model
    src = None if model.source == "<api>" else model.source
    out = solver.kernel.dynamics(x)
    if not (np.all(np.isfinite(out["M"])) and np.all(np.isfinite(out["F"]))):  # the entries (compact: a vector)
        obs = solver.kernel.observables(x)
        parts = [(k, what) for k, what in (("T", "[energy] kinetic (or [[bodies]])"), ("V", "[energy] potential"))
                 if not np.all(np.isfinite(np.asarray(obs[k], dtype=float)))]
        what = (" and ".join(w for _, w in parts) + (" is" if len(parts) == 1 else " are")
                if parts else "the generalized forces ([forces], [[loads]]) or the derivatives of "
                "the energies are")
        raise ModelError(f"{what} not finite at {format_state(model, t, q)} (an overflow, a log or sqrt of a "
                         "non-positive number, asin/acos outside [-1, 1], a division by zero): "
                         "change the initial state or the expression", src)
    problem = diagnose_state(model, t, q, qd, definite=True, params=solver.params)
    if problem is not None:
        if diagnose_initial_state(model, definite=True) is None:  # another state than the initial one
            raise singular_configuration(problem)
        raise problem
    if len(seen) > 256:
        seen.clear()
    seen.add(key)
