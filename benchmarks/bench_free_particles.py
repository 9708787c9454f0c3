"""Scaling with the number of coordinates: n free particles under gravity (3n coordinates).

For each n: building the model, its symbolic dynamics (mass matrix and velocity terms),
``check`` (which compiles the numeric kernel) and deriving Lagrange I, next to
``sympy.physics.mechanics``' KanesMethod on the same system in the same process (ratios
ours/peer, < 1 = ours faster).  The dense kernel's compilation grows with the number of mass
matrix entries (n^2): the remaining cost at large n.

    python benchmarks/bench_free_particles.py            # n = 10, 30, 100
    python benchmarks/bench_free_particles.py --n 10,30,100,200
"""

from __future__ import annotations

import argparse
import time


def ours(n: int) -> dict:
    from nonideal import Model, Particle, derive
    from nonideal.analysis.checks import check_model
    from nonideal.equations.dynamics import dynamics_of

    coords = [f"{a}{k}" for k in range(n) for a in "xyz"]
    init = {c: 0.0 for c in coords}
    init.update({c + "'": 0.1 for c in coords})
    t0 = time.perf_counter()
    model = Model(name="free particles", coordinates=coords, parameters={"m": 1.0, "g": 9.81},
                  bodies=[Particle(f"p{k}", "m", [f"x{k}", f"y{k}", f"z{k}"]) for k in range(n)],
                  gravity=["0", "0", "-g"], initial=init)
    t1 = time.perf_counter()
    dynamics_of(model).M
    t2 = time.perf_counter()
    derive(model, "lagrange1")
    t3 = time.perf_counter()
    check_model(model)
    t4 = time.perf_counter()
    return {"build": t1 - t0, "dynamics": t2 - t1, "derive": t3 - t2, "check": t4 - t3}


def kane(n: int) -> float:
    import sympy as sp
    import sympy.physics.mechanics as me

    t0 = time.perf_counter()
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
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", default="10,30,100,200", help="numbers of particles, comma-separated")
    ap.add_argument("--kane-max", type=int, default=30,
                    help="largest n for KanesMethod (about 36 s at n = 30, growing fast)")
    args = ap.parse_args()
    print("| particles | coordinates | build | dynamics + derive lagrange1 | check (compiles) | KanesMethod | derive/Kane |")
    print("|---|---|---|---|---|---|---|")
    for n in [int(v) for v in args.n.split(",")]:
        o = ours(n)
        derive = o["dynamics"] + o["derive"]
        k = kane(n) if n <= args.kane_max else None
        print(f"| {n} | {3 * n} | {o['build']:.2f} s | {derive:.2f} s | {o['check']:.2f} s | "
              + (f"{k:.2f} s | {derive / k:.4f} |" if k else "- | - |"), flush=True)


if __name__ == "__main__":
    main()
