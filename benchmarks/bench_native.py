"""The native phases (numba, ``simulate(native=...)``) side by side with their peers, in one
process.

    python benchmarks/bench_native.py [--quick] [--no-pydy]

(1) A 1-DOF pendulum over 300 s (DOP853, rtol 1e-10, atol 1e-12): ours natively
    (``native=True``, kernel compiled and native code loaded: "warm"; every step kept, and on
    601 requested times), ours on the SciPy path
    (``native=False``), SciPy's DOP853 on a hand-written Python right-hand side, and a
    hand-written numba DOP853 loop on a hand-written numba right-hand side (SciPy's tableau,
    the same error norm and step control; the loop keeps only the final state).
(2) The 10-link pendulum: one right-hand side from Python (``Simulation(model,
    native=...).rhs(mode)``) against the kernel call it contains; 10 s (DOP853, rtol 1e-8,
    atol 1e-10) against PyDy's Cython right-hand side in ``solve_ivp``.
(3) Start-up: ``nonideal simulate`` of the gallery's n-link pendulum file in fresh processes:
    0.01 s (start-up), and 100 s twice, the second with the native code read from the disk
    cache; ``--help``; the import of the simulation stage alone.

Prints a markdown table and writes ``benchmarks/results/native[-quick].json``.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal

import _common as C  # noqa: E402
import peers  # noqa: E402

from nonideal.gallery.nlink_pendulum import build  # noqa: E402
from nonideal.modes.switching import select_mode  # noqa: E402
from nonideal.simulation.hybrid import Simulation, simulate  # noqa: E402

G, L = 9.81, 1.0


def python_pendulum(t, y):
    """What a user writes without any tool: theta'' = -g/l sin(theta)."""
    return np.array([y[1], -G / L * math.sin(y[0])])


def numba_peer():
    """A hand-written numba DOP853 loop (SciPy's tableau) on a hand-written right-hand side."""
    from numba import njit
    from scipy.integrate import DOP853

    A, B, Cc, E3, E5 = DOP853.A.copy(), DOP853.B.copy(), DOP853.C.copy(), DOP853.E3.copy(), DOP853.E5.copy()
    S = B.shape[0]

    @njit(cache=True)
    def f(y, out):
        out[0] = y[1]
        out[1] = -9.81 * math.sin(y[0])

    @njit(cache=True)
    def run(y0, t_end, h, rtol, atol):
        y = y0.copy()
        K = np.empty((S + 1, 2))
        tmp = np.empty(2)
        f(y, K[0])
        t, steps = 0.0, 0
        while t < t_end:
            h = min(h, t_end - t)
            while True:
                for s in range(1, S):
                    for i in range(2):
                        v = 0.0
                        for k in range(s):
                            v += K[k, i] * A[s, k]
                        tmp[i] = y[i] + h * v
                    f(tmp, K[s])
                yn = np.empty(2)
                for i in range(2):
                    v = 0.0
                    for k in range(S):
                        v += K[k, i] * B[k]
                    yn[i] = y[i] + h * v
                f(yn, K[S])
                e5 = e3 = 0.0
                for i in range(2):
                    sc = atol + max(abs(y[i]), abs(yn[i])) * rtol
                    v5 = v3 = 0.0
                    for k in range(S + 1):
                        v5 += K[k, i] * E5[k]
                        v3 += K[k, i] * E3[k]
                    e5 += (v5 / sc) ** 2
                    e3 += (v3 / sc) ** 2
                err = 0.0 if e5 == 0 and e3 == 0 else h * e5 / math.sqrt((e5 + 0.01 * e3) * 2)
                if err < 1:
                    t += h
                    y = yn
                    K[0] = K[S]
                    h *= 10.0 if err == 0 else min(10.0, 0.9 * err ** (-1 / 8))
                    steps += 1
                    break
                h *= max(0.2, 0.9 * err ** (-1 / 8))
        return y, steps
    return run


def part1(repeat):
    from scipy.integrate import solve_ivp

    model = build(1, q0=0.5)
    kw = dict(t_end=300.0, rtol=1e-10, atol=1e-12, method="DOP853")
    simulate(model, native=True, **kw)  # warm: the kernel compiled, the native code loaded
    row = {}
    row["ours_native"], tr = C.best_of(lambda: simulate(model, native=True, every_step=True, **kw), repeat,
                                       clear=False)
    row["ours_native_default"], _ = C.best_of(lambda: simulate(model, native=True, **kw), repeat, clear=False)
    row["ours_scipy_path"], tr0 = C.best_of(lambda: simulate(model, native=False, **kw), max(1, repeat - 1),
                                            clear=False)
    grid = np.linspace(0.0, 300.0, 601)
    row["ours_native_601"], _ = C.best_of(lambda: simulate(model, native=True, times=grid, **kw), repeat, clear=False)
    y0 = np.array([0.5, 0.0])
    row["scipy_python_rhs"], sol = C.best_of(
        lambda: solve_ivp(python_pendulum, (0, 300.0), y0, method="DOP853", rtol=1e-10, atol=1e-12),
        repeat, clear=False)
    run = numba_peer()
    run(y0, 1.0, 1e-3, 1e-10, 1e-12)
    row["numba_loop"], (y_nb, steps_nb) = C.best_of(lambda: run(y0, 300.0, 1e-3, 1e-10, 1e-12), repeat, clear=False)
    row["ours_steps"], row["scipy_steps"], row["numba_steps"] = len(tr.t) - 1, len(sol.t) - 1, int(steps_nb)
    # where the time goes: the run's fixed cost (t_end 1e-6), and the native phase alone
    # (the loop called directly from the initial state: no samples, no Python per step)
    row["ours_fixed"], _ = C.best_of(lambda: simulate(model, native=True, **dict(kw, t_end=1e-6)), repeat,
                                     clear=False)
    sim = Simulation(model, native=True, rtol=1e-10, atol=1e-12)
    nat = sim.fast.native
    mode = select_mode(sim.solver, 0.0, *sim.initial_state())
    w, ix = sim.fast.buffers(mode)
    f0 = np.empty(2)
    nat.rhs(0.0, y0, w, ix, f0)
    atol = np.full(2, 1e-12)

    def phase(times):
        return nat.integrator.phase(nat.kernel, 0.0, y0, f0, 1e-3, 300.0, 1e-10, atol, np.inf, w, ix, times,
                                    0, 10 ** 8, 0.0)
    row["phase_only"], _ = C.best_of(lambda: phase(np.zeros(0)), repeat, clear=False)
    row["phase_only_601"], _ = C.best_of(lambda: phase(grid), repeat, clear=False)
    loop = sim.fast.c_loop(mode, 0.0, y0)  # the same phase compiled in C (None: no C compiler)
    if loop is not None:
        def c_phase(times):
            return loop.phase_arrays(0.0, y0, f0, 1e-3, 300.0, 1e-10, atol, np.inf, times, 0, 10 ** 8, 0.0)
        row["phase_c"], _ = C.best_of(lambda: c_phase(np.zeros(0)), repeat, clear=False)
        row["phase_c_601"], _ = C.best_of(lambda: c_phase(grid), repeat, clear=False)
    ours = np.r_[tr.q[-1], tr.qd[-1]]
    row["final_vs_scipy"] = float(np.max(np.abs(ours - sol.y[:, -1])))
    row["final_native_vs_scipy_path"] = float(np.max(np.abs(ours - np.r_[tr0.q[-1], tr0.qd[-1]])))
    row["final_vs_numba"] = float(np.max(np.abs(ours - y_nb)))
    return row


def part2(repeat, use_pydy):
    n = 10
    model = build(n, q0=0.5)
    row = {}
    sims = {nat: Simulation(model, native=nat, rtol=1e-8, atol=1e-10) for nat in (False, True)}
    q0, qd0 = sims[True].initial_state()
    mode = select_mode(sims[True].solver, 0.0, q0, qd0)
    y0 = np.concatenate((q0, qd0 + np.linspace(-0.3, 0.4, n)))
    for nat, sim in sims.items():
        fun = sim.rhs(mode)
        row[f"rhs_native_{nat}"] = C.per_call(repeat=repeat, fn=lambda: fun(0.0, y0))
    x = sims[True].solver.input(0.0, y0[:n], y0[n:])
    kd = sims[True].kernel.dynamics
    row["kernel_call"] = C.per_call(repeat=repeat, fn=lambda: kd.raw(x))
    diff = sims[True].rhs(mode)(0.0, y0) - sims[False].rhs(mode)(0.0, y0)
    row["rhs_native_vs_numpy"] = float(np.max(np.abs(diff)))
    kw = dict(t_end=10.0, rtol=1e-8, atol=1e-10, method="DOP853")
    simulate(model, native=True, **kw)
    row["sim10_native"], tr = C.best_of(lambda: simulate(model, native=True, **kw), repeat, clear=False)
    row["sim10_scipy_path"], _ = C.best_of(lambda: simulate(model, native=False, **kw), max(1, repeat - 2), clear=False)
    if use_pydy:
        from scipy.integrate import solve_ivp

        km = peers.kane_pendulum(n)
        pfun = peers.pydy_rhs(km, peers.pendulum_constants(n), [1.0] * n + [1.0] * n + [9.81])
        y = np.concatenate((q0, qd0))
        row["sim10_pydy"], sol = C.best_of(
            lambda: solve_ivp(pfun, (0, 10.0), y, method="DOP853", rtol=1e-8, atol=1e-10), repeat, clear=False)
        row["sim10_final_vs_pydy"] = float(np.max(np.abs(np.r_[tr.q[-1], tr.qd[-1]] - sol.y[:, -1])))
    return row


def part3():
    """Fresh processes: start-up (a run of 0.01 s) and a long run (100 s, natively after its
    first steps) twice, the second reading the native code from the disk cache."""
    root = Path(__file__).resolve().parent.parent
    model = root / "nonideal" / "gallery" / "nlink_pendulum.toml"
    env = dict(os.environ, PYTHONPATH=str(root))
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        env["NONIDEAL_CACHE_DIR"] = cache
        target = Path(cache) / "out.json"

        def cli(*argv):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "nonideal", *argv], check=True, env=env, capture_output=True)
            return time.perf_counter() - t0

        out["cli_startup"] = min(cli("simulate", str(model), "--t-end", "0.01", "--json", str(target))
                                 for _ in range(2))
        out["cli_long_first"] = cli("simulate", str(model), "--t-end", "100", "--json", str(target))
        out["cli_long_second"] = cli("simulate", str(model), "--t-end", "100", "--json", str(target))
        out["cli_help"] = cli("--help")
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import nonideal.simulation.hybrid"], check=True, env=env)
        out["import_only"] = time.perf_counter() - t0
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-pydy", action="store_true")
    args = ap.parse_args()
    repeat = 2 if args.quick else 3
    use_pydy = not args.no_pydy and C.pydy_available()
    machine = C.machine()
    r3 = part3()
    r1 = part1(repeat)
    r2 = part2(repeat, use_pydy)
    print("\n| measurement | ours | peer | ratio ours/peer | goal |\n|---|---|---|---|---|")
    print(f"| pendulum 300 s, every step kept, vs SciPy + Python RHS | {C.fmt_t(r1['ours_native'])} | "
          f"{C.fmt_t(r1['scipy_python_rhs'])} | {C.fmt_r(C.ratio(r1['ours_native'], r1['scipy_python_rhs']))} | <= 0.5 |")
    print(f"| pendulum 300 s, every step kept, vs numba DOP853 loop | {C.fmt_t(r1['ours_native'])} | "
          f"{C.fmt_t(r1['numba_loop'])} | {C.fmt_r(C.ratio(r1['ours_native'], r1['numba_loop']))} | <= 3 |")
    print(f"| pendulum 300 s, default output (1001-time grid) vs numba DOP853 loop | {C.fmt_t(r1['ours_native_default'])} | "
          f"{C.fmt_t(r1['numba_loop'])} | {C.fmt_r(C.ratio(r1['ours_native_default'], r1['numba_loop']))} | <= 3 |")
    print(f"| pendulum 300 s on 601 samples vs numba DOP853 loop | {C.fmt_t(r1['ours_native_601'])} | "
          f"{C.fmt_t(r1['numba_loop'])} | {C.fmt_r(C.ratio(r1['ours_native_601'], r1['numba_loop']))} | <= 3 |")
    print(f"| the same, native phase alone (every step recorded / 601 times) | {C.fmt_t(r1['phase_only'])} / "
          f"{C.fmt_t(r1['phase_only_601'])} | {C.fmt_t(r1['numba_loop'])} | "
          f"{C.fmt_r(C.ratio(r1['phase_only'], r1['numba_loop']))} / "
          f"{C.fmt_r(C.ratio(r1['phase_only_601'], r1['numba_loop']))} | |")
    if "phase_c" in r1:
        print(f"| the same phase in C (what `simulate` runs with a C compiler) | {C.fmt_t(r1['phase_c'])} / "
              f"{C.fmt_t(r1['phase_c_601'])} | {C.fmt_t(r1['numba_loop'])} | "
              f"{C.fmt_r(C.ratio(r1['phase_c'], r1['numba_loop']))} / "
              f"{C.fmt_r(C.ratio(r1['phase_c_601'], r1['numba_loop']))} | |")
    print(f"| simulate's fixed cost (t_end 1e-6, native) | {C.fmt_t(r1['ours_fixed'])} | {C.fmt_t(r1['numba_loop'])} | "
          f"{C.fmt_r(C.ratio(r1['ours_fixed'], r1['numba_loop']))} | |")
    print(f"| pendulum 300 s, SciPy path (native=False) | {C.fmt_t(r1['ours_scipy_path'])} | "
          f"{C.fmt_t(r1['scipy_python_rhs'])} | {C.fmt_r(C.ratio(r1['ours_scipy_path'], r1['scipy_python_rhs']))} | |")
    print(f"| n = 10 RHS (native) vs kernel call | {C.fmt_t(r2['rhs_native_True'])} | {C.fmt_t(r2['kernel_call'])} | "
          f"{C.fmt_r(C.ratio(r2['rhs_native_True'], r2['kernel_call']))} | <= 1.5 |")
    print(f"| n = 10 RHS (NumPy) vs kernel call | {C.fmt_t(r2['rhs_native_False'])} | {C.fmt_t(r2['kernel_call'])} | "
          f"{C.fmt_r(C.ratio(r2['rhs_native_False'], r2['kernel_call']))} | |")
    pydy = r2.get("sim10_pydy")
    print(f"| n = 10, 10 s vs PyDy Cython | {C.fmt_t(r2['sim10_native'])} | {C.fmt_t(pydy) if pydy else 'not run'} | "
          f"{C.fmt_r(C.ratio(r2['sim10_native'], pydy)) if pydy else ''} | <= 0.3 |")
    print(f"| n = 10, 10 s, SciPy path | {C.fmt_t(r2['sim10_scipy_path'])} | | | |")
    print(f"| CLI simulate 0.01 s (start-up) | {C.fmt_t(r3['cli_startup'])} | | | <= 0.3 s + integration |")
    print(f"| CLI simulate 100 s, first / second run | {C.fmt_t(r3['cli_long_first'])} | "
          f"{C.fmt_t(r3['cli_long_second'])} | | |")
    print(f"| import of the simulation stage alone | {C.fmt_t(r3['import_only'])} | | | |")
    print(f"| --help | {C.fmt_t(r3['cli_help'])} | | | |")
    print("\nsteps (ours, SciPy, numba):", r1["ours_steps"], r1["scipy_steps"], r1["numba_steps"],
          "; final-state differences: vs SciPy %.1e, native vs SciPy path %.1e, vs numba %.1e" % (
              r1["final_vs_scipy"], r1["final_native_vs_scipy_path"], r1["final_vs_numba"]),
          "; RHS native vs NumPy %.1e" % r2["rhs_native_vs_numpy"],
          ("; n = 10 final vs PyDy %.1e" % r2["sim10_final_vs_pydy"]) if "sim10_final_vs_pydy" in r2 else "")
    path = C.write_json("native", {"machine": machine, "pendulum_1dof": r1, "pendulum_10": r2, "startup": r3},
                        args.quick)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
