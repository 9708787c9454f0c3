"""A nonholonomic chain of n knife-edge links (a snake-like "train" of Chaplygin sleighs).

Source: chains of rigid bodies with nonholonomic constraints, Yushkov 1999, ch. I (the
introduction lists chains of rigid bodies among the systems the method covers); the system is
the standard scalable nonholonomic benchmark of the benchmarks (``benchmarks/bench_knife_chain.py``),
the same chain is built there with ``sympy.physics.mechanics.KanesMethod`` with dependent speeds.

Model.  n uniform rods (mass m, length l, central moment of inertia m l^2/12) move in a
horizontal plane, joined end to end by revolute joints.  Coordinates ``(x, y, theta1..thetan)``:
``(x, y)`` is the free rear end P0 of link 1 and ``theta_k`` the absolute angle of link k, so
the joints and the centres are

    P_k = P_{k-1} + l (cos theta_k, sin theta_k),      C_k = P_{k-1} + (l/2)(cos theta_k, sin theta_k).

Each link carries a knife edge at its centre C_k: the velocity of C_k across the link vanishes,

    phi_k = -x' sin(theta_k) + y' cos(theta_k)
            + sum_{j<k} l theta_j' cos(theta_k - theta_j) + (l/2) theta_k' = 0,   k = 1..n,

n nonholonomic constraints on n + 2 coordinates: two degrees of freedom, e.g. the velocity
of P0.  The constraint matrix is lower triangular in the theta' with diagonal l/2, so the
dependent angular velocities follow by forward substitution -- but written out explicitly
the k-th one contains all the earlier ones: the expression doubles with every link.  The
reduced forms (Maggi...) therefore keep the dependent-velocity coefficients as auxiliary
symbols solved numerically once the explicit inverse would exceed their size budget.

No forces act: the kinetic energy is conserved and the ideal knife edges do no work;
``run`` checks energy (1e-8 relative), the constraint residuals along the motion, and the
agreement of every form with Lagrange I at random admissible states.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import PlanarBody
from ..modeling.model import Constraint, Model

NAME = "knife-chain"
ORDER = 60
TITLE = "Chain of n knife-edge links (nonholonomic benchmark; n = 3 in the model file)"
FILE = "knife_chain.toml"


def constraint_expr(k: int) -> str:
    """The knife-edge constraint of link *k* (1-based), see the module docstring."""
    parts = [f"-x'*sin(theta{k})", f"y'*cos(theta{k})"]
    parts += [f"l*theta{j}'*cos(theta{k} - theta{j})" for j in range(1, k)]
    parts.append(f"l/2*theta{k}'")
    return " + ".join(parts)


def build(n: int = 3, m: float = 1.0, l: float = 1.0, vx: float = 1.0, vy: float = 0.3,
          t_end: float = 5.0) -> Model:
    """The chain with the Python API.

    Parameters
    ----------
    n : int
        Number of links (``n >= 1``).
    m, l : float
        Mass and length of every link.
    vx, vy : float
        Initial velocity of the rear end P0; the angular velocities follow from the knife
        edges.  Initial angles ``theta_k = 0.3 (-1)^k k / n`` (a zig-zag).
    t_end : float

    Returns
    -------
    Model
        Equal to the model file ``knife_chain.toml`` for ``n = 3`` and the defaults.
    """
    if n < 1:
        raise ValueError(f"build(n={n}): the chain needs at least one link")
    th = [f"theta{k}" for k in range(1, n + 1)]
    bodies = []
    px, py = "x", "y"
    for k in range(1, n + 1):
        bodies.append(PlanarBody(f"link{k}", "m", "m*l^2/12",
                                 [f"{px} + l/2*cos(theta{k})", f"{py} + l/2*sin(theta{k})"], f"theta{k}"))
        px += f" + l*cos(theta{k})"
        py += f" + l*sin(theta{k})"
    constraints = [Constraint.nonholonomic(f"knife{k}", constraint_expr(k)) for k in range(1, n + 1)]
    initial = {"x": 0.0, "y": 0.0, "x'": vx, "y'": vy}
    initial.update({f"theta{k}": round(0.3 * (-1) ** k * k / n, 12) for k in range(1, n + 1)})
    return Model(
        name=f"chain of {n} knife-edge links",
        coordinates=["x", "y"] + th,
        parameters={"m": m, "l": l},
        bodies=bodies,
        constraints=constraints,
        initial=initial,
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12},
    )


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..errors import FormNotApplicable
    from ..equations.formalisms import FORMS, derive
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    traj = simulate(model)
    E = traj.energy["energy"]
    drift = float(np.max(np.abs(E - E[0])) / abs(E[0]))
    residual = traj.diagnostics["constraint_residual_max"]
    work = float(np.max(np.abs(traj.energy["reaction_work"])))
    cross = compare_forms(model, count=10)
    forms = {}
    for f in FORMS:
        try:
            forms[f] = derive(model, f)
        except FormNotApplicable:  # a form for holonomic systems only
            continue
    aux = {f: [a.symbols.shape for a in e.auxiliaries] for f, e in forms.items()}
    result = {
        "ok": drift < 1e-8 and residual < 1e-8 and work < 1e-8 and cross.worst() < 1e-10,
        "energy_drift_relative": drift,
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
        "constraint_residual_max": residual,
        "reaction_work_max": work,
        "cross_form_max_disagreement": cross.worst(),
        "forms": list(forms),
        "auxiliaries": {f: [list(s) for s in v] for f, v in aux.items()},
    }
    if verbose:
        print(TITLE)
        print(forms["lagrange1"].as_text())
        print(f"simulation over t in [0, {model.simulation.t_end:g}] ({len(traj.t)} samples):")
        print(f"  max |E - E0| / |E0|              = {drift:.2e}")
        print(f"  constraint residual (max)        = {residual:.2e}")
        print(f"  work of the knife edges (max)    = {work:.2e}")
        print(f"  cross-form max disagreement      = {cross.worst():.2e}  ({', '.join(cross.accelerations)})")
        print(f"  auxiliary symbols per form       = {aux}")
        print("ok" if result["ok"] else "FAILED")
    return result
