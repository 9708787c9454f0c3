"""Planar n-link pendulum: nonideal vs sympy.physics.mechanics (and PyDy), side by side.

    python benchmarks/bench_pendulum.py [--quick] [--no-pydy] [--n 2,5,10]

(a) time to derive the equations of motion from a fresh model: ours in every form of
    ``nonideal.formalisms.FORMS`` ("build" = the Model from Particles; "derive"; "+SymPy" =
    the conversion of ``eom.mass_matrix`` and ``eom.forcing``) vs ``KanesMethod`` and
    ``LagrangesMethod`` (frames, points and velocities included).  LagrangesMethod is capped
    (n <= 10, quick: n <= 4); beyond the cap its time is extrapolated (power law fitted on
    the last three measured sizes) and marked "~".
(b) one right-hand-side evaluation from Python: ours is the function the simulation
    integrates (``Simulation(model).rhs(mode)`` at the initial mode); also
    ``ModeSolver.accelerations`` and the compiled kernel alone.  Peer: Kane's M, F through
    ``lambdify(cse=True)`` + ``numpy.linalg.solve``; PyDy's Cython generator when installed.
(c) 10 s of simulation at rtol 1e-8, atol 1e-10 with DOP853: ours ``simulate(...)`` (kernel
    compiled: "warm"; and from a fresh model: "cold", derivation and compilation included) vs
    ``solve_ivp`` on the peer's right-hand side; the final states are compared.

Prints markdown tables and writes ``benchmarks/results/pendulum[-quick].json``.
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
import peers  # noqa: E402

from nonideal.equations.formalisms import FORMS, derive
from nonideal.gallery.nlink_pendulum import build
from nonideal.simulation.hybrid import Simulation, simulate
from nonideal.modes.switching import select_mode

Q0 = 0.5
T_END, RTOL, ATOL, METHOD = 10.0, 1e-8, 1e-10, "DOP853"


def params(n):
    return [1.0] * n + [1.0] * n + [9.81]


# ----------------------------------------------------------------------------- (a) derive


def derive_ours(n: int, form: str, repeat: int) -> dict:
    """Best-of timings of build, derive, SymPy conversion -- each run from a fresh Model."""
    best = {"build": np.inf, "derive": np.inf, "sympy": np.inf}
    eom = None
    for _ in range(repeat):
        C.clear_caches()
        t0 = time.perf_counter()
        model = build(n, q0=Q0)
        t1 = time.perf_counter()
        eom = derive(model, form)
        t2 = time.perf_counter()
        eom.mass_matrix, eom.forcing
        t3 = time.perf_counter()
        best["build"] = min(best["build"], t1 - t0)
        best["derive"] = min(best["derive"], t2 - t1)
        best["sympy"] = min(best["sympy"], t3 - t2)
    out = {k: float(v) for k, v in best.items()}
    out["build+derive"] = out["build"] + out["derive"]
    out["build+derive+sympy"] = out["build+derive"] + out["sympy"]
    out["auxiliaries"] = [list(a.symbols.shape) for a in eom.auxiliaries]
    return out


def part_a(ns, quick, lm_cap, repeat):
    rows = []
    for n in ns:
        row = {"n": n, "forms": {}}
        for form in FORMS:
            try:
                row["forms"][form] = derive_ours(n, form, repeat)
            except Exception as exc:  # a form not applicable here: say so, keep going
                row["forms"][form] = {"error": f"{type(exc).__name__}: {exc}"}
        r_peer = 1 if (quick or n > 10) else 2
        t, km = C.best_of(lambda: _kane_with_matrices(n), r_peer)
        row["kane"] = t
        row["kane_size"] = peers.size_of(list(km.mass_matrix) + list(km.forcing))
        if n <= lm_cap:
            row["lagrange"], _ = C.best_of(lambda: _lagrange_with_matrices(n), 1)
        else:
            row["lagrange"] = None
        rows.append(row)
        print(f"  (a) n = {n}: kane {C.fmt_t(row['kane'])}, lagrange {C.fmt_t(row['lagrange'])}, "
              + ", ".join(f"{f} {C.fmt_t(v.get('build+derive'))}" for f, v in row["forms"].items()),
              flush=True)
    measured = [(r["n"], r["lagrange"]) for r in rows if r["lagrange"]]
    for r in rows:
        if r["lagrange"] is None and len(measured) >= 2:
            est, p = C.extrapolate_power([a for a, _ in measured], [b for _, b in measured], r["n"])
            r["lagrange_extrapolated"] = est
            r["lagrange_extrapolation_exponent"] = p
    return rows


def _kane_with_matrices(n):
    km = peers.kane_pendulum(n)
    km.mass_matrix, km.forcing
    return km


def _lagrange_with_matrices(n):
    lm = peers.lagrange_pendulum(n)
    lm.mass_matrix, lm.forcing
    return lm


# ----------------------------------------------------------------------------- (b) rhs, (c) simulate


def our_rhs(n):
    model = build(n, q0=Q0)
    t0 = time.perf_counter()
    sim = Simulation(model, rtol=RTOL, atol=ATOL, method=METHOD)
    t_compile = time.perf_counter() - t0
    q0, qd0 = sim.initial_state()
    mode = select_mode(sim.solver, model.t0, q0, qd0)
    fun = sim.rhs(mode)
    return model, sim, mode, fun, np.concatenate((q0, qd0)), t_compile


def _rhs_before_tier_up(n, rep):
    """The same right-hand side while the kernel still runs its unoptimized first compile."""
    import nonideal.numeric.kernel as numeric

    saved = getattr(numeric, "TIER_UP_CALLS", None)
    if saved is None:
        return None
    numeric.TIER_UP_CALLS = 10 ** 15
    try:
        _, _, _, fun, y0, _ = our_rhs(n)
        return C.per_call(repeat=rep, fn=lambda: fun(0.0, y0))
    finally:
        numeric.TIER_UP_CALLS = saved


def part_b_c(ns_rhs, ns_sim, use_pydy, pydy_ns, quick=False):
    rep = 3 if quick else 5
    out = []
    for n in sorted(set(ns_rhs) | set(ns_sim)):
        row = {"n": n}
        model, sim, mode, fun, y0, t_compile = our_rhs(n)
        row["ours_compile"] = t_compile
        y_test = y0 + np.r_[np.zeros(n), np.linspace(-0.3, 0.4, n)]  # moving, for the check
        # steady state: per_call makes > TIER_UP_CALLS calls, so the kernel is recompiled
        # with full optimization during the measurement (see nonideal.numeric)
        row["ours_rhs"] = C.per_call(repeat=rep, fn=lambda: fun(0.0, y0))
        row["ours_rhs_before_tier_up"] = _rhs_before_tier_up(n, rep)
        solver = sim.solver
        q, qd = y0[:n], y0[n:]
        row["ours_accelerations"] = C.per_call(repeat=rep, fn=lambda: solver.accelerations(0.0, q, qd, mode))
        x = solver.input(0.0, q, qd)
        row["ours_kernel_eval"] = C.per_call(repeat=rep, fn=lambda: sim.kernel.dynamics.raw(x))
        C.clear_caches()
        km = _kane_with_matrices(n)
        consts, p = peers.pendulum_constants(n), params(n)
        t0 = time.perf_counter()
        sfun = peers.lambdify_rhs(km, consts, p)
        row["sympy_lambdify"] = time.perf_counter() - t0
        row["sympy_rhs"] = C.per_call(repeat=rep, fn=lambda: sfun(0.0, y0))
        row["rhs_agreement"] = float(np.max(np.abs(fun(0.0, y_test) - sfun(0.0, y_test))))
        pfun = None
        if use_pydy and n in pydy_ns:
            t0 = time.perf_counter()
            pfun = peers.pydy_rhs(km, consts, p)
            row["pydy_generate"] = time.perf_counter() - t0
            row["pydy_rhs"] = C.per_call(repeat=rep, fn=lambda: pfun(0.0, y0))
            row["pydy_agreement"] = float(np.max(np.abs(fun(0.0, y_test) - pfun(0.0, y_test))))
        if n in ns_sim:
            from scipy.integrate import solve_ivp

            t0 = time.perf_counter()
            tr = simulate(model, t_end=T_END, rtol=RTOL, atol=ATOL, method=METHOD)
            row["ours_simulate_warm"] = time.perf_counter() - t0
            # best of two for the warm run (the first may include lazy compilation)
            t0 = time.perf_counter()
            tr = simulate(model, t_end=T_END, rtol=RTOL, atol=ATOL, method=METHOD)
            row["ours_simulate_warm"] = min(row["ours_simulate_warm"], time.perf_counter() - t0)
            row["ours_simulate_cold"], _ = C.best_of(
                lambda: simulate(build(n, q0=Q0), t_end=T_END, rtol=RTOL, atol=ATOL, method=METHOD),
                2 if quick else 3)
            row["ours_steps"] = len(tr.t) - 1
            t0 = time.perf_counter()
            sol = solve_ivp(sfun, (0.0, T_END), y0, method=METHOD, rtol=RTOL, atol=ATOL)
            row["sympy_solve_ivp"] = time.perf_counter() - t0
            row["sympy_nfev"] = int(sol.nfev)
            row["sympy_steps"] = len(sol.t) - 1
            y_ours = np.concatenate((tr.q[-1], tr.qd[-1]))
            row["final_state_difference"] = float(np.max(np.abs(y_ours - sol.y[:, -1])))
            row["sympy_cold"] = None  # filled from part (a): Kane + lambdify + solve_ivp
            if pfun is not None:
                t0 = time.perf_counter()
                sp_ = solve_ivp(pfun, (0.0, T_END), y0, method=METHOD, rtol=RTOL, atol=ATOL)
                row["pydy_solve_ivp"] = time.perf_counter() - t0
                row["pydy_final_state_difference"] = float(np.max(np.abs(y_ours - sp_.y[:, -1])))
        out.append(row)
        print(f"  (b,c) n = {n}: rhs ours {C.fmt_t(row['ours_rhs'])} sympy {C.fmt_t(row['sympy_rhs'])}"
              + (f" pydy {C.fmt_t(row.get('pydy_rhs'))}" if "pydy_rhs" in row else "")
              + (f"; simulate ours {C.fmt_t(row.get('ours_simulate_warm'))} sympy "
                 f"{C.fmt_t(row.get('sympy_solve_ivp'))}, |dy_end| = {row['final_state_difference']:.1e}"
                 if "ours_simulate_warm" in row else ""), flush=True)
    return out


# ----------------------------------------------------------------------------- report


def report(a_rows, bc_rows) -> str:
    forms = list(FORMS)
    lines = ["### (a) Time to derive (best of runs, fresh model, SymPy cache cleared)", ""]
    head = ["n", "build"] + [f"{f}: derive / +SymPy" for f in forms] + ["KanesMethod", "LagrangesMethod"]
    rows = []
    for r in a_rows:
        cells = [r["n"], C.fmt_t(next(iter(r["forms"].values())).get("build"))]
        for f in forms:
            v = r["forms"][f]
            cells.append("n/a" if "error" in v else f"{C.fmt_t(v['derive'])} / {C.fmt_t(v['sympy'])}")
        cells.append(C.fmt_t(r["kane"]))
        if r["lagrange"] is not None:
            cells.append(C.fmt_t(r["lagrange"]))
        elif r.get("lagrange_extrapolated"):
            cells.append("~" + C.fmt_t(r["lagrange_extrapolated"]) + " (not run)")
        else:
            cells.append("not run")
        rows.append(cells)
    lines += [C.table(head, rows), ""]
    lines += ["Ratios ours/peer (< 1: ours faster); ours = build + derive, in brackets with the "
              "SymPy conversion:", ""]
    head = ["n"] + [f"{f} / Kane" for f in forms] + [f"{f} / Lagrange" for f in forms]
    rows = []
    for r in a_rows:
        cells = [r["n"]]
        lag = r["lagrange"] if r["lagrange"] is not None else r.get("lagrange_extrapolated")
        for peer in (r["kane"], lag):
            for f in forms:
                v = r["forms"][f]
                if "error" in v or not peer:
                    cells.append("-")
                    continue
                mark = "~" if peer is not r["kane"] and r["lagrange"] is None else ""
                cells.append(f"{mark}{C.fmt_r(v['build+derive'] / peer)} "
                             f"({mark}{C.fmt_r(v['build+derive+sympy'] / peer)})")
        rows.append(cells)
    lines += [C.table(head, rows), ""]
    lines += ["### (b) One right-hand-side evaluation from Python", ""]
    head = ["n", "ours Simulation.rhs", "(first 10^5 calls)", "ours accelerations", "ours kernel only",
            "SymPy lambdify+solve", "PyDy Cython", "ours/SymPy", "ours/PyDy", "max |diff| ours-SymPy"]
    rows = []
    for r in bc_rows:
        rows.append([r["n"], C.fmt_t(r["ours_rhs"]), C.fmt_t(r.get("ours_rhs_before_tier_up")),
                     C.fmt_t(r["ours_accelerations"]),
                     C.fmt_t(r["ours_kernel_eval"]), C.fmt_t(r["sympy_rhs"]), C.fmt_t(r.get("pydy_rhs")),
                     C.fmt_r(C.ratio(r["ours_rhs"], r["sympy_rhs"])),
                     C.fmt_r(C.ratio(r["ours_rhs"], r.get("pydy_rhs"))), f"{r['rhs_agreement']:.1e}"])
    lines += [C.table(head, rows), "",
              "Steady state (kernel recompiled with full LLVM optimization after 10^5 calls); "
              "'first 10^5 calls': the unoptimized first compile.", ""]
    head = ["n", "ours: Kernel compile", "SymPy: lambdify(cse=True)", "PyDy: Cython generation"]
    rows = [[r["n"], C.fmt_t(r["ours_compile"]), C.fmt_t(r["sympy_lambdify"]), C.fmt_t(r.get("pydy_generate"))]
            for r in bc_rows]
    lines += ["Code generation (one-off):", "", C.table(head, rows), ""]
    sims = [r for r in bc_rows if "ours_simulate_warm" in r]
    if sims:
        lines += [f"### (c) {T_END:g} s of simulation, {METHOD}, rtol {RTOL:g}, atol {ATOL:g}", ""]
        head = ["n", "ours simulate (warm)", "SymPy solve_ivp", "PyDy solve_ivp", "ours/SymPy", "ours/PyDy",
                "ours cold", "SymPy cold", "cold ratio", "steps ours/SymPy", "max |y_ours - y_SymPy| at t_end"]
        rows = []
        for r in sims:
            rows.append([r["n"], C.fmt_t(r["ours_simulate_warm"]), C.fmt_t(r["sympy_solve_ivp"]),
                         C.fmt_t(r.get("pydy_solve_ivp")),
                         C.fmt_r(C.ratio(r["ours_simulate_warm"], r["sympy_solve_ivp"])),
                         C.fmt_r(C.ratio(r["ours_simulate_warm"], r.get("pydy_solve_ivp"))),
                         C.fmt_t(r["ours_simulate_cold"]), C.fmt_t(r.get("sympy_cold")),
                         C.fmt_r(C.ratio(r["ours_simulate_cold"], r.get("sympy_cold"))),
                         f"{r['ours_steps']}/{r['sympy_steps']}", f"{r['final_state_difference']:.1e}"])
        lines += [C.table(head, rows), ""]
        lines += ["warm: the model's kernel already compiled; cold: from a fresh Model (build, "
                  "derivation, compilation, simulation); SymPy cold = KanesMethod + lambdify + solve_ivp.", ""]
    return "\n".join(lines)


def targets(a_rows, bc_rows) -> list[str]:
    out = []
    r10 = next((r for r in a_rows if r["n"] == 10), None)
    if r10:
        worst = max((v["build+derive"], f) for f, v in r10["forms"].items() if "error" not in v)
        worst_s = max((v["build+derive+sympy"], f) for f, v in r10["forms"].items() if "error" not in v)
        out.append(f"(a) derive at n = 10 <= 0.13 s in every form: worst {worst[1]} {C.fmt_t(worst[0])} "
                   f"(with SymPy conversion: {worst_s[1]} {C.fmt_t(worst_s[0])}) -> "
                   f"{'MET' if worst[0] <= 0.13 else 'MISSED'}"
                   f"{'' if worst_s[0] <= 0.13 else ' (missed with the SymPy conversion)'}; Kane {C.fmt_t(r10['kane'])}")
    b10 = next((r for r in bc_rows if r["n"] == 10), None)
    if b10:
        out.append(f"(b) RHS at n = 10 <= 15 us: {C.fmt_t(b10['ours_rhs'])} -> "
                   f"{'MET' if b10['ours_rhs'] <= 15e-6 else 'MISSED'} (SymPy {C.fmt_t(b10['sympy_rhs'])}, "
                   f"PyDy {C.fmt_t(b10.get('pydy_rhs'))})")
        if "ours_simulate_warm" in b10:
            out.append(f"(c) simulate at n = 10 <= 0.15 s: {C.fmt_t(b10['ours_simulate_warm'])} warm, "
                       f"{C.fmt_t(b10['ours_simulate_cold'])} cold -> "
                       f"{'MET' if b10['ours_simulate_warm'] <= 0.15 else 'MISSED'} (warm)"
                       f"{'' if b10['ours_simulate_cold'] <= 0.15 else ', missed cold'}; SymPy "
                       f"{C.fmt_t(b10['sympy_solve_ivp'])}; final states agree to "
                       f"{b10['final_state_difference']:.1e}")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, under a minute")
    ap.add_argument("--no-pydy", action="store_true", help="skip PyDy even when installed")
    ap.add_argument("--n", help="comma-separated sizes for (a) (default: 2..20; quick: 2,4,10)")
    args = ap.parse_args(argv)
    quick = args.quick
    ns = [int(s) for s in args.n.split(",")] if args.n else ([2, 4, 10] if quick else [2, 3, 4, 5, 6, 8, 10, 12, 15, 20])
    lm_cap = 4 if quick else 10
    repeat = 3 if quick else 5
    ns_rhs = [n for n in ns if n in ((10,) if quick else (2, 5, 10, 20))] or ns
    ns_sim = [n for n in ns if n in ((10,) if quick else (2, 5, 10, 20))]
    use_pydy = C.pydy_available() and not args.no_pydy
    pydy_ns = {10} if quick else {2, 5, 10, 20}
    info = C.machine()
    print(f"n-link pendulum benchmark ({'quick' if quick else 'full'}) on {info['cpu']} x{info['nproc']}, "
          f"{info['date']}, load average {info['loadavg_at_start'][0]:.2f}; PyDy {'on' if use_pydy else 'off'}", flush=True)
    # warm up imports and JIT machinery once (not measured)
    derive(build(2), "lagrange1")
    peers.kane_pendulum(2)
    t0 = time.perf_counter()
    a_rows = part_a(ns, quick, lm_cap, repeat)
    bc_rows = part_b_c(ns_rhs, ns_sim, use_pydy, pydy_ns, quick)
    for r in bc_rows:
        ra = next((x for x in a_rows if x["n"] == r["n"]), None)
        if ra and "sympy_solve_ivp" in r:
            r["sympy_cold"] = ra["kane"] + r["sympy_lambdify"] + r["sympy_solve_ivp"]
    text = report(a_rows, bc_rows)
    goals = targets(a_rows, bc_rows)
    print()
    print(text)
    print("Targets:")
    for g in goals:
        print("  " + g)
    path = C.write_json("pendulum", {"machine": info, "quick": quick, "forms": list(FORMS),
                                     "settings": {"q0": Q0, "t_end": T_END, "rtol": RTOL, "atol": ATOL,
                                                  "method": METHOD, "repeat": repeat, "lagrange_cap": lm_cap},
                                     "derive": a_rows, "rhs_simulate": bc_rows, "targets": goals,
                                     "markdown": text, "elapsed": time.perf_counter() - t0}, quick)
    print(f"\nwritten {path} ({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
