"""Linearizing the knife chain about its steady straight-line motion: nonideal vs
sympy.physics.mechanics ``KanesMethod.linearize`` (dependent speeds), side by side.

    python benchmarks/bench_linearize.py [--n 2,4,6] [--repeat 3]

Both sides start from a fresh model: ours ``build(n)`` + ``linearize(model, about="steady",
...)`` (the Jacobians of the implicit motion compiled, the state reduced on the constraint
manifold, Newton's check of the steady state, eigenvalues and the Hurwitz analysis included);
the peer ``kane_knife_chain(n)`` (``kanes_equations``) + ``linearize(A_and_B=True,
op_point=...)`` + substitution of the constants.  The state is the same on both sides:
``q = (x, y, theta_1..theta_n)`` and the independent speeds ``(x', y')``; the matrices are
compared entry by entry.  Prints a markdown table and writes
``benchmarks/results/linearize.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal, not an installed copy

import _common as C  # noqa: E402
import peers  # noqa: E402

from nonideal.analysis.stability.linearize import linearize  # noqa: E402
from nonideal.gallery.knife_chain import build  # noqa: E402

V = 1.0           # speed of the rear end along x
M_, L_ = 1.0, 1.0


def ours(n: int):
    model = build(n, m=M_, l=L_, vx=V, vy=0.0)
    at = {"x'": V, "y'": 0.0, **{f"theta{k}": 0.0 for k in range(1, n + 1)}}
    return linearize(model, about="steady", at=at, independent=["x", "y"], keep=["x", "y"], exact=True)


def peer(n: int):
    km = peers.kane_knife_chain(n)
    q, u = list(km.q), list(km.u)
    ux, uy = u[0], u[1]
    op = {qi: 0 for qi in q}
    op.update({ux: V, uy: 0})
    op.update({w: 0 for w in u[2:]})
    op.update({ui.diff(): 0 for ui in u})        # steady: the speeds are constant
    A, B, _ = km.linearize(A_and_B=True, op_point=op, simplify=False)
    m, l = peers.knife_constants()
    return np.array(A.subs({m: M_, l: L_}), dtype=float)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", default="2,4,6")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    rows = []
    for n in [int(x) for x in args.n.split(",")]:
        t_ours, lin = C.best_of(lambda: ours(n), args.repeat)
        t_peer, A_peer = C.best_of(lambda: peer(n), max(1, args.repeat if n <= 4 else 1))
        same_order = list(lin.variables) == ["x", "y"] + [f"theta{k}" for k in range(1, n + 1)] + ["x'", "y'"]
        diff = float(np.max(np.abs(lin.A - A_peer))) if same_order and lin.A.shape == A_peer.shape else float("nan")
        rows.append({"n": n, "ours_s": t_ours, "kane_s": t_peer, "ratio": t_peer / t_ours,
                     "max_abs_difference": diff, "shape": list(lin.A.shape)})
        print(f"n = {n}: ours {t_ours:.3f} s, KanesMethod.linearize {t_peer:.3f} s, "
              f"ratio {t_peer / t_ours:.1f}x, max |A_ours - A_kane| = {diff:.2e}", flush=True)
    print()
    print("| n | nonideal linearize (s) | KanesMethod.linearize (s) | ratio | max abs difference of A |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['n']} | {r['ours_s']:.3f} | {r['kane_s']:.3f} | {r['ratio']:.1f} | {r['max_abs_difference']:.1e} |")
    C.RESULTS.mkdir(exist_ok=True)
    (C.RESULTS / "linearize.json").write_text(json.dumps({"rows": rows, "time": time.strftime("%Y-%m-%d %H:%M")}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
