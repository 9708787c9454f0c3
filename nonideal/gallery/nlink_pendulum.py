"""Planar n-link pendulum of point masses (the benchmark system of multibody codes).

Source: the classical n-link pendulum, the usual scaling benchmark of symbolic multibody
codes (sympy.physics.mechanics and PyDy use it in their examples); ``benchmarks/bench_pendulum.py``
builds the same system with ``KanesMethod`` and ``LagrangesMethod`` and compares.

Model.  n massless rods of lengths l_k carry point masses m_k; the rods hang from a fixed
pivot at the origin and are jointed at the masses.  Coordinates are the absolute angles q_k of
the rods from the downward vertical, so that mass k is at

    x_k = sum_{j<=k} l_j sin(q_j),        y_k = -sum_{j<=k} l_j cos(q_j),

and gravity g acts along -y.  The model is built from :class:`~nonideal.bodies.Particle`
objects and ``gravity``; no constraints (it is an open chain in minimal coordinates), so every
form reduces to the same ``M q'' = F`` and the cross-form check is a check of the forms'
plumbing on a system with a full mass matrix.

Equations.  With mu_jk = sum_{i >= max(j, k)} m_i (the mass hanging below both joints),

    sum_k mu_jk l_j l_k [cos(q_j - q_k) q_k'' + sin(q_j - q_k) q_k'^2] = -mu_jj g l_j sin(q_j).

Closed form (n = 2, linearized about q = 0).  With M0 = [[(m1 + m2) l1^2, m2 l1 l2],
[m2 l1 l2, m2 l2^2]] and K0 = diag((m1 + m2) g l1, m2 g l2) the small oscillations have the
frequencies omega^2 = eigenvalues of M0^{-1} K0, i.e. the roots of

    m1 l1 l2 w^4 - (m1 + m2) g (l1 + l2) w^2 + (m1 + m2) g^2 = 0,

    w^2 = (m1 + m2) g [(l1 + l2) -/+ sqrt((l1 + l2)^2 - 4 m1 l1 l2 / (m1 + m2))] / (2 m1 l1 l2).

For m1 = m2, l1 = l2 = l: w^2 = (2 -/+ sqrt 2) g / l.  ``run`` checks the simulated energy
(conserved to 1e-8 relative), the cross-form agreement, and the linearized frequencies of the
2-link pendulum (from the compiled mass matrix and a finite-difference stiffness at q = 0).
No misprints: the equations above are derived here.
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.model import Model

NAME = "nlink-pendulum"
ORDER = 50
TITLE = "Planar n-link pendulum of point masses (benchmark system; n = 3 in the model file)"
FILE = "nlink_pendulum.toml"


def build(n: int = 3, m: float = 1.0, l: float = 1.0, g: float = 9.81,
          q0: float = 0.5, t_end: float = 10.0) -> Model:
    """The n-link pendulum with the Python API.

    Parameters
    ----------
    n : int
        Number of links (``n >= 1``); coordinates ``q1..qn``, parameters ``m1..mn``,
        ``l1..ln``, ``g``.
    m, l, g : float
        Value of every mass, every length, and gravity.
    q0 : float
        Initial angle of every link (at rest): a large-amplitude, chaotic motion for n >= 2.
    t_end : float
        Default end time of the simulation.

    Returns
    -------
    Model
        Equal to the model file ``nlink_pendulum.toml`` for ``n = 3`` and the defaults.
    """
    if n < 1:
        raise ValueError(f"build(n={n}): the pendulum needs at least one link")
    coords = [f"q{k}" for k in range(1, n + 1)]
    params: dict[str, float] = {}
    for k in range(1, n + 1):
        params[f"m{k}"] = m
    for k in range(1, n + 1):
        params[f"l{k}"] = l
    params["g"] = g
    bodies = []
    x, y = "", ""
    for k in range(1, n + 1):
        x += f" + l{k}*sin(q{k})"
        y += f" - l{k}*cos(q{k})"
        bodies.append(Particle(f"P{k}", f"m{k}", [x.lstrip(" +"), y.strip()]))
    initial = {c: q0 for c in coords}
    initial.update({c + "'": 0.0 for c in coords})
    return Model(
        name=f"{n}-link pendulum",
        coordinates=coords,
        parameters=params,
        bodies=bodies,
        gravity=["0", "-g"],
        initial=initial,
        simulation={"t_end": t_end, "rtol": 1e-10, "atol": 1e-12},
    )


def frequencies_closed_form(m1: float, m2: float, l1: float, l2: float, g: float) -> np.ndarray:
    """Linearized frequencies ``(w_slow, w_fast)`` of the 2-link pendulum (module docstring)."""
    M = m1 + m2
    s = l1 + l2
    disc = np.sqrt(s * s - 4 * m1 * l1 * l2 / M)
    w2 = M * g * np.array([s - disc, s + disc]) / (2 * m1 * l1 * l2)
    return np.sqrt(w2)


def linearized_frequencies(model: Model, eps: float = 1e-6) -> np.ndarray:
    """Small-oscillation frequencies about ``q = 0`` from the compiled kernel.

    ``M0`` is the mass matrix at rest; the stiffness ``K0 = -dF/dq`` by central differences
    (``F`` is the forcing of ``M q'' = F``, velocity terms vanish at rest).
    """
    from ..numeric.kernel import kernel_of, parameter_vector

    kernel = kernel_of(model)
    params = parameter_vector(model)
    n = kernel.n
    z = np.zeros(n)
    M0 = kernel.dynamics(kernel.state_input(0.0, z, z, params))["M"].copy()
    K0 = np.empty((n, n))
    for j in range(n):
        dq = np.zeros(n)
        dq[j] = eps
        Fp = kernel.dynamics(kernel.state_input(0.0, dq, z, params))["F"].copy()
        Fm = kernel.dynamics(kernel.state_input(0.0, -dq, z, params))["F"].copy()
        K0[:, j] = -(Fp - Fm) / (2 * eps)
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(M0, K0)).real)
    return np.sqrt(w2)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..equations.formalisms import FORMS, derive
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    traj = simulate(model)
    E = traj.energy["energy"]
    drift = float(np.max(np.abs(E - E[0])) / abs(E[0]))
    cross = compare_forms(model, count=10)
    forms = {f: derive(model, f) for f in FORMS}

    two = build(2, m=1.0, l=1.0, g=9.81)
    w_num = linearized_frequencies(two)
    w_cf = frequencies_closed_form(1.0, 1.0, 1.0, 1.0, 9.81)
    err_w = float(np.max(np.abs(w_num - w_cf) / w_cf))

    result = {
        "ok": drift < 1e-8 and cross.worst() < 1e-10 and err_w < 1e-6,
        "energy_drift_relative": drift,
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
        "cross_form_max_disagreement": cross.worst(),
        "forms": list(forms),
        "frequencies_2link": w_num.tolist(),
        "frequencies_2link_closed_form": w_cf.tolist(),
        "q_end": {c: float(v) for c, v in zip(model.coordinates, traj.q[-1])},
    }
    if verbose:
        print(TITLE)
        print(forms["lagrange1"].as_text())
        print(f"simulation over t in [0, {model.simulation.t_end:g}] ({len(traj.t)} samples):")
        print(f"  max |E - E0| / |E0|              = {drift:.2e}")
        print(f"  cross-form max disagreement      = {cross.worst():.2e}  ({', '.join(cross.accelerations)})")
        print(f"2-link linearized frequencies      = {w_num}  (closed form {w_cf}, rel. error {err_w:.1e})")
        print("ok" if result["ok"] else "FAILED")
    return result
