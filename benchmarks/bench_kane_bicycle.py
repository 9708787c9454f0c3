"""Kane's equations of the benchmark bicycle: nonideal (from its model file with frames and
points) vs sympy.physics.mechanics (KanesMethod), side by side in one process.

    python benchmarks/bench_kane_bicycle.py [--quick] [--repeat 3]

* ours: ``load_model(benchmark_bicycle_frames.toml)`` (frames, points, rolling constraints
  written with ``vel``, ``cross``, ``omega``), Kane's equations derived from it
  (``derive(model, "kane")``: partial velocities from the independent speeds phi', thetaR',
  delta', generalized active and inertia forces), compiled, and linearized about upright
  straight running: the roll/steer state matrix A(v) (phi, delta, phi', delta') by
  fourth-order central differences of Kane's accelerations at consistent states (pitch from
  the front contact, dependent velocities from the rolling constraints), at v = 0..10;
* the peer: the same bicycle built with ``ReferenceFrame``s and ``Point``s,
  ``KanesMethod.kanes_equations`` and ``KanesMethod.linearize`` (the peer of
  ``bench_bicycle_linearize.py``, imported from there).

Both A(v) are compared (max |A_ours - A_peer|) and their eigenvalues with Table 2 of Meijaard et
al. (2007).  Timings: wall clock, caches cleared before every run, best of ``--repeat`` for ours
(``--quick``: one), one run of the peer (minutes).  The ratio ours/peer is printed (goal <= 0.1)
and the JSON goes to ``benchmarks/results/kane_bicycle[-quick].json``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal, not an installed copy

import _common as C  # noqa: E402

SPEEDS = list(range(11))


class KaneRollSteer:
    """Roll and steer accelerations of Kane's equations near upright running at speed v."""

    def __init__(self, model):
        from nonideal.modes.solver import ModeSolver
        from nonideal.numeric.kernel import kernel_of, parameter_vector

        self.model = model
        self.kernel = kernel_of(model)
        self.params = parameter_vector(model)
        self.solver = ModeSolver(self.kernel, self.params, "kane")
        self.names = list(model.coordinates)
        self.rR = model.parameter_values["rR"]

    def state(self, z, v):
        k, names = self.kernel, self.names
        q = np.zeros(len(names))
        qd = np.zeros(len(names))
        q[names.index("phi")], q[names.index("delta")] = z[0], z[1]
        qd[names.index("phi")], qd[names.index("delta")] = z[2], z[3]
        qd[names.index("thetaR")] = -v / self.rR
        hol = [j for j, r in enumerate(k.rows) if r.position is not None]
        dep_q = [names.index("thetaB")]
        for _ in range(30):
            x = k.state_input(0.0, q, qd, self.params)
            res = k.observables(x)["pos"][hol]
            step = np.linalg.lstsq(k.dynamics(x)["G"][hol][:, dep_q], -res, rcond=None)[0]
            q[dep_q] += step
            if np.max(np.abs(step)) < 1e-16:
                break
        dep_v = [j for j, n in enumerate(names) if n not in ("phi", "delta", "thetaR")]
        x = k.state_input(0.0, q, qd, self.params)
        qd[dep_v] -= np.linalg.solve(k.dynamics(x)["G"][:, dep_v], k.observables(x)["vel"])
        return q, qd

    def __call__(self, z, v):
        from nonideal.modes.types import Mode

        q, qd = self.state(z, v)
        qdd = self.solver.solve(0.0, q, qd, Mode()).qdd
        return np.array([qdd[self.names.index("phi")], qdd[self.names.index("delta")]])


def _derivative(f, n: int, h: float) -> np.ndarray:
    cols = []
    for k in range(n):
        e = np.zeros(n)
        e[k] = h
        cols.append((8 * (f(e) - f(-e)) - (f(2 * e) - f(-2 * e))) / (12 * h))
    return np.column_stack(cols)


def ours() -> dict:
    from nonideal import derive, gallery

    model = gallery.load("benchmark-bicycle-frames")
    derive(model, "kane")                                 # the equations, as `derive` prints them
    acc = KaneRollSteer(model)
    out = {}
    for v in SPEEDS:
        J = _derivative(lambda z, v=v: acc(z, v), 4, 1e-4)
        out[v] = np.vstack([np.hstack([np.zeros((2, 2)), np.eye(2)]), J])
    return out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="one run of each side")
    ap.add_argument("--repeat", type=int, default=3, help="runs of ours (best kept)")
    args = ap.parse_args(argv)
    from bench_bicycle_linearize import peer
    from nonideal.gallery.benchmark_bicycle import TABLE2

    info = C.machine()
    t_start = time.perf_counter()
    t_ours, A_ours = C.best_of(ours, 1 if args.quick else args.repeat)
    t_peer, A_peer = C.best_of(peer, 1)

    def eig_error(A):
        return max(float(np.max(np.abs(np.sort_complex(np.linalg.eigvals(A[v]))
                                       - np.sort_complex(TABLE2[v])) / np.maximum(1.0, np.abs(TABLE2[v]))))
                   for v in SPEEDS)

    diff = max(float(np.max(np.abs(A_ours[v] - A_peer[v]))) for v in SPEEDS)
    rows = [["nonideal: load frames model + derive kane + linearize (v = 0..10)", C.fmt_t(t_ours),
             f"{t_ours / t_peer:.4f}", f"{diff:.1e}", f"{eig_error(A_ours):.1e}"],
            ["sympy: KanesMethod + kanes_equations + linearize + constants", C.fmt_t(t_peer), "1", "0",
             f"{eig_error(A_peer):.1e}"]]
    print(C.table(["benchmark bicycle, Kane's equations", "time", "ratio to sympy",
                   "max |A - A_sympy|, v = 0..10", "eigenvalues vs Table 2 (rel.)"], rows))
    ratio = t_ours / t_peer
    print(f"ours/peer = {ratio:.4f} ({1 / ratio:.0f}x faster; goal >= 10x: {'met' if ratio <= 0.1 else 'missed'})")
    info["loadavg_at_end"] = list(__import__("os").getloadavg())
    data = {"machine": info, "elapsed": time.perf_counter() - t_start, "t_ours": t_ours, "t_peer": t_peer,
            "ratio": ratio, "max_A_difference": diff, "eigenvalue_error_ours": eig_error(A_ours),
            "eigenvalue_error_peer": eig_error(A_peer)}
    C.write_json("kane_bicycle", data, args.quick)
    return data


if __name__ == "__main__":
    main()
