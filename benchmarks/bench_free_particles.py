"""Scaling with the number of coordinates: n free particles under gravity (3n coordinates).

For each n, in a fresh process (so that no cache of a smaller n helps): building the model,
its symbolic dynamics, deriving Lagrange I (with the printed equations), ``check`` (which
compiles the numeric kernel and solves the motion at t0) and ``simulate`` to t_end, next to
``sympy.physics.mechanics``' KanesMethod on the same system (ratios ours/peer, < 1 = ours
faster; the peer is capped at ``--kane-max`` particles, beyond which it takes over a minute).
``--springs`` couples neighbours by springs ``k/2 (x_{i+1} - x_i - 1)^2`` (the mass matrix
stays diagonal, the forces couple).  Times are CPU times of the measuring process
(``time.process_time``): on a shared machine under load the wall-clock times of the same run
are several times larger and move with the neighbours' jobs; the wall-clock total per n is
given in a comment after each row.  ``--source DIR`` measures another checkout (e.g. an
exported older commit, for before/after tables on the same machine).

    python benchmarks/bench_free_particles.py                       # n = 10, 30, 100, 300, 1000
    python benchmarks/bench_free_particles.py --n 10,30 --springs
    python benchmarks/bench_free_particles.py --source /tmp/before --timeout 300
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def build(n: int, springs: bool):
    from nonideal import Model, Particle

    coords = [f"{a}{k}" for k in range(n) for a in "xyz"]
    init = {c: 0.0 for c in coords}
    init.update({f"x{k}": float(k) for k in range(n)})
    init.update({c + "'": 0.1 for c in coords})
    potential = "0"
    if springs and n > 1:
        potential = "k/2*(" + " + ".join(f"(x{i + 1} - x{i} - 1)^2" for i in range(n - 1)) + ")"
    return Model(name="free particles", coordinates=coords, parameters={"m": 1.0, "g": 9.81, "k": 10.0},
                 bodies=[Particle(f"p{k}", "m", [f"x{k}", f"y{k}", f"z{k}"]) for k in range(n)],
                 gravity=["0", "0", "-g"], potential=potential, initial=init)


def ours(n: int, springs: bool, t_end: float) -> dict:
    from nonideal import derive, simulate
    from nonideal.analysis.checks import check_model
    from nonideal.equations.dynamics import dynamics_of

    t0 = time.process_time()
    model = build(n, springs)
    t1 = time.process_time()
    dynamics_of(model).F
    t2 = time.process_time()
    eom = derive(model, "lagrange1")
    text = eom.as_text()
    t3 = time.process_time()
    check_model(model)
    t4 = time.process_time()
    traj = simulate(model, t_end=t_end)
    t5 = time.process_time()
    z = traj.q[-1, 2]
    z_exact = 0.1 * t_end - 9.81 * t_end ** 2 / 2   # free fall of particle 0 (no springs)
    from nonideal.numeric.kernel import kernel_of
    kernel = kernel_of(model)
    return {"build": t1 - t0, "dynamics": t2 - t1, "derive": t3 - t2, "check": t4 - t3,
            "simulate": t5 - t4, "lines": text.count("\n") + 1, "samples": len(traj.t),
            "z_error": abs(z - z_exact) if not springs else None,
            "compiled": getattr(kernel.dynamics, "compiled", kernel.dynamics.size),
            "outputs": kernel.dynamics.size}


def kane(n: int) -> float:
    import sympy as sp
    import sympy.physics.mechanics as me

    t0 = time.process_time()
    N, O = me.ReferenceFrame("N"), me.Point("O")
    O.set_vel(N, 0)
    m, g = sp.symbols("m g")
    q = me.dynamicsymbols(f"q0:{3 * n}")
    u = me.dynamicsymbols(f"u0:{3 * n}")
    particles, loads = [], []
    for k in range(n):
        P = O.locatenew(f"P{k}", q[3 * k] * N.x + q[3 * k + 1] * N.y + q[3 * k + 2] * N.z)
        P.set_vel(N, u[3 * k] * N.x + u[3 * k + 1] * N.y + u[3 * k + 2] * N.z)
        particles.append(me.Particle(f"p{k}", P, m))
        loads.append((P, -m * g * N.z))
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
    km.kanes_equations(particles, loads)
    km.mass_matrix, km.forcing
    return time.process_time() - t0


def one(args) -> None:
    sys.path.insert(0, args.source)
    out = ours(args.one, args.springs, args.t_end)
    import nonideal
    out["source"] = os.path.dirname(os.path.dirname(nonideal.__file__))
    if args.one <= args.kane_max:
        out["kane"] = kane(args.one)
    print(json.dumps(out))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", default="10,30,100,300,1000", help="numbers of particles, comma-separated")
    ap.add_argument("--kane-max", type=int, default=30,
                    help="largest n for KanesMethod (about 36 s at n = 30, growing fast)")
    ap.add_argument("--springs", action="store_true", help="springs between neighbours")
    ap.add_argument("--t-end", type=float, default=0.5, help="simulated time (default 0.5)")
    ap.add_argument("--source", default=ROOT, help="the checkout to measure (default: this one)")
    ap.add_argument("--timeout", type=float, default=600, help="seconds allowed per n")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one is not None:
        return one(args)
    print(f"source: {args.source}; springs: {args.springs}; t_end = {args.t_end}; CPU seconds (process_time)")
    print("| particles | coordinates | build | dynamics | derive (+ text) | check (compiles) | simulate "
          "| compiled / outputs | KanesMethod | (dynamics + derive)/Kane |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in [int(v) for v in args.n.split(",")]:
        cmd = [sys.executable, os.path.abspath(__file__), "--one", str(n), "--source", args.source,
               "--kane-max", str(args.kane_max), "--t-end", str(args.t_end)] + (["--springs"] if args.springs else [])
        start = time.perf_counter()
        cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        try:
            res = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
        except subprocess.TimeoutExpired:
            print(f"| {n} | {3 * n} | > {args.timeout:.0f} s in all (stopped) |||||||||", flush=True)
            continue
        if res.returncode:
            print(f"| {n} | {3 * n} | failed: {res.stderr.strip().splitlines()[-1]} |||||||||", flush=True)
            continue
        o = json.loads(res.stdout.strip().splitlines()[-1])
        k = o.get("kane")
        sym = o["dynamics"] + o["derive"]
        print(f"| {n} | {3 * n} | {o['build']:.2f} s | {o['dynamics']:.2f} s | {o['derive']:.2f} s | "
              f"{o['check']:.2f} s | {o['simulate']:.2f} s | {o['compiled']} / {o['outputs']} | "
              + (f"{k:.2f} s | {sym / k:.4f} |" if k else "- | - |")
              + f"  <!-- {time.perf_counter() - start:.0f} s in all (CPU {_cpu(cpu0):.0f} s, imports and the "
              f"peer included), z error {o['z_error']} -->", flush=True)


def _cpu(before) -> float:
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


if __name__ == "__main__":
    main()
