"""Many bodies with a constraint each: an elastic chain of n knife-edge links, sparse all through.

Each link (a uniform rod of mass m, length l, planar coordinates ``x_i, y_i, th_i`` of its
centre and its angle) carries a knife edge at its centre, ``-x_i' sin th_i + y_i' cos th_i = 0``
(n nonholonomic rows), and the centres of neighbours are joined by springs
``k/2 ((x_{i+1} - x_i - l)^2 + (y_{i+1} - y_i)^2)``.  ``M`` is diagonal, each row touches one
link: the saddle-point system has O(n) nonzero entries.  The model file is generated (TOML),
read with ``load_model``; ``check`` and a 1 s ``simulate`` are timed (CPU time of this
process, ``time.process_time``) per size in a fresh process (no cache of a smaller size helps),
with the invariants of the run: the energy (springs conservative, knife edges ideal: constant)
and the knife edges' residual.

Side by side at a small size (one process): ``sympy.physics.mechanics.KanesMethod`` with the
same chain (dependent speeds ``u_y``), ``mass_matrix_full``/``forcing_full`` lambdified and
integrated by ``solve_ivp`` (DOP853, the same tolerances); both final states are compared.

    python benchmarks/bench_knife_chain.py --elastic                 # n = 10, 100, 1000; Kane at n = 3
    python benchmarks/bench_knife_chain.py --elastic --n 10,100 --kane 2
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RTOL, ATOL, T_END = 1e-10, 1e-12, 1.0
PARAMS = {"m": 1.0, "l": 1.0, "k": 100.0}


def initial(n: int) -> dict[str, float]:
    """Link i at x = i, zig-zag angles +-0.3, moving along its knife edge at unit speed."""
    out = {}
    for i in range(n):
        th = 0.3 * (-1) ** i
        out.update({f"x{i}": float(i), f"y{i}": 0.0, f"th{i}": th,
                    f"x{i}'": math.cos(th), f"y{i}'": math.sin(th), f"th{i}'": 0.0})
    return out


def model_file(n: int) -> str:
    """The chain as a model file (TOML text)."""
    q = ", ".join(f'"{a}{i}"' for i in range(n) for a in ("x", "y", "th"))
    lines = ["[model]", f'name = "elastic chain of {n} knife-edge links"', "format = 1", "",
             "[parameters]"] + [f"{k} = {v}" for k, v in PARAMS.items()] + ["", "[coordinates]", f"q = [{q}]", ""]
    for i in range(n):
        lines += ["[[bodies]]", 'type = "planar"', f'name = "link{i}"', 'mass = "m"', 'inertia = "m*l^2/12"',
                  f'position = ["x{i}", "y{i}"]', f'angle = "th{i}"', ""]
    for i in range(n):
        lines += ["[[constraints]]", f'name = "knife{i}"', 'type = "nonholonomic"',
                  f"expr = \"-x{i}'*sin(th{i}) + y{i}'*cos(th{i})\"", ""]
    springs = "+".join(f"(x{i + 1}-x{i}-l)^2+(y{i + 1}-y{i})^2" for i in range(n - 1)) or "0"
    lines += ["[energy]", f'potential = "k/2*({springs})"', "", "[initial]"]
    lines += [f'"{k}" = {v!r}' for k, v in initial(n).items()]
    lines += ["", "[simulation]", f"t_end = {T_END}", f"rtol = {RTOL}", f"atol = {ATOL}", 'method = "DOP853"']
    return "\n".join(lines) + "\n"


def ours(n: int) -> dict:
    """Load, check, simulate 1 s; CPU seconds and the invariants (run in a fresh process)."""
    import resource

    from nonideal import simulate
    from nonideal.analysis.checks import check_model
    from nonideal.modeling.modelfile import load_model

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, f"chain{n}.toml")
        with open(path, "w") as f:
            f.write(model_file(n))
        t0 = time.process_time()
        model = load_model(path)
        t1 = time.process_time()
        check_model(model)
        t2 = time.process_time()
        traj = simulate(model)
        t3 = time.process_time()
    E = np.asarray(traj.energy["energy"], dtype=float)
    return {"n": n, "coordinates": 3 * n, "load": t1 - t0, "check": t2 - t1, "simulate": t3 - t2,
            "samples": len(traj.t), "energy_drift": float(np.max(np.abs(E - E[0])) / abs(E[0])),
            "residual": float(traj.diagnostics["constraint_residual_max"]),
            "final": traj.q[-1].tolist(), "maxrss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def kane(n: int) -> dict:
    """The same chain with KanesMethod (dependent speeds), lambdified and integrated."""
    import sympy as sp
    import sympy.physics.mechanics as me
    from scipy.integrate import solve_ivp

    t0 = time.process_time()
    m, l, k = sp.symbols("m l k")
    x, y, th = (me.dynamicsymbols(f"{a}0:{n}") for a in ("x", "y", "th"))
    ux, uy, w = (me.dynamicsymbols(f"u{a}0:{n}") for a in ("x", "y", "w"))
    N, O = me.ReferenceFrame("N"), me.Point("O")
    O.set_vel(N, 0)
    bodies, loads = [], []
    V = sum(((x[i + 1] - x[i] - l) ** 2 + (y[i + 1] - y[i]) ** 2 for i in range(n - 1)), sp.S(0)) * k / 2
    for i in range(n):
        A = N.orientnew(f"A{i}", "Axis", [th[i], N.z])
        A.set_ang_vel(N, w[i] * N.z)
        P = O.locatenew(f"P{i}", x[i] * N.x + y[i] * N.y)
        P.set_vel(N, ux[i] * N.x + uy[i] * N.y)
        bodies.append(me.RigidBody(f"link{i}", P, A, m, (me.inertia(A, 0, 0, m * l ** 2 / 12), P)))
        loads.append((P, -sp.diff(V, x[i]) * N.x - sp.diff(V, y[i]) * N.y))
    q = list(x) + list(y) + list(th)
    kd = [a.diff() - b for a, b in zip(q, list(ux) + list(uy) + list(w))]
    cons = [-ux[i] * sp.sin(th[i]) + uy[i] * sp.cos(th[i]) for i in range(n)]
    km = me.KanesMethod(N, q_ind=q, u_ind=list(ux) + list(w), u_dependent=list(uy), kd_eqs=kd,
                        velocity_constraints=cons)
    km.kanes_equations(bodies, loads)
    MM, FF = km.mass_matrix_full, km.forcing_full
    u = list(ux) + list(w) + list(uy)
    args = q + u + [m, l, k]
    fM, fF = sp.lambdify(args, MM, cse=True), sp.lambdify(args, FF, cse=True)
    t1 = time.process_time()
    p = [PARAMS["m"], PARAMS["l"], PARAMS["k"]]
    s0 = initial(n)
    z0 = ([s0[f"x{i}"] for i in range(n)] + [s0[f"y{i}"] for i in range(n)] + [s0[f"th{i}"] for i in range(n)]
          + [s0[f"x{i}'"] for i in range(n)] + [s0[f"th{i}'"] for i in range(n)] + [s0[f"y{i}'"] for i in range(n)])

    def rhs(_, z):
        return np.linalg.solve(np.asarray(fM(*z, *p), dtype=float), np.asarray(fF(*z, *p), dtype=float).ravel())

    sol = solve_ivp(rhs, (0.0, T_END), z0, method="DOP853", rtol=RTOL, atol=ATOL)
    t2 = time.process_time()
    zf = sol.y[:, -1]
    final = [v for i in range(n) for v in (zf[i], zf[n + i], zf[2 * n + i])]   # ours: x_i, y_i, th_i
    return {"n": n, "derive": t1 - t0, "simulate": t2 - t1, "final": final}


def run(argv) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elastic", action="store_true")
    ap.add_argument("--n", default="10,100,1000", help="numbers of links, comma-separated")
    ap.add_argument("--kane", type=int, default=3, help="number of links for the KanesMethod comparison")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--timeout", type=float, default=900)
    args = ap.parse_args(argv)
    if args.one is not None:
        sys.path.insert(0, ROOT)
        print(json.dumps(ours(args.one)))
        return 0
    print(f"elastic chain of n knife-edge links; CPU seconds (process_time); rtol {RTOL}, atol {ATOL}, "
          f"t_end {T_END}; load average {os.getloadavg()[0]:.2f}")
    print("| links | coordinates | rows | load | check | simulate 1 s | samples | energy drift | knife residual | max RSS |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    results = {}
    for n in [int(v) for v in args.n.split(",")] + ([args.kane] if args.kane else []):
        if n in results:
            continue
        cmd = [sys.executable, os.path.abspath(__file__), "--one", str(n)]
        try:
            res = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
        except subprocess.TimeoutExpired:
            print(f"| {n} | {3 * n} | {n} | > {args.timeout:.0f} s (stopped) |||||||", flush=True)
            continue
        if res.returncode:
            print(f"| {n} | {3 * n} | {n} | failed: {res.stderr.strip().splitlines()[-1]} |||||||", flush=True)
            continue
        o = results[n] = json.loads(res.stdout.strip().splitlines()[-1])
        print(f"| {n} | {3 * n} | {n} | {o['load']:.2f} s | {o['check']:.2f} s | {o['simulate']:.2f} s | "
              f"{o['samples']} | {o['energy_drift']:.1e} | {o['residual']:.1e} | {o['maxrss_MB']:.0f} MB |", flush=True)
    if args.kane and args.kane in results:
        sys.path.insert(0, ROOT)
        n = args.kane
        o = ours(n)   # in this process, next to the peer
        kn = kane(n)
        diff = float(np.max(np.abs(np.array(o["final"]) - np.array(kn["final"]))))
        print(f"\nside by side at n = {n} (one process): nonideal load + check + simulate "
              f"{o['load'] + o['check'] + o['simulate']:.2f} s (simulate {o['simulate']:.2f} s); KanesMethod "
              f"derive + lambdify {kn['derive']:.2f} s, solve_ivp {kn['simulate']:.2f} s; ratio (ours/Kane) "
              f"{(o['load'] + o['check'] + o['simulate']) / (kn['derive'] + kn['simulate']):.3f}; "
              f"final states agree to {diff:.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
