"""Chain of n knife-edge links: nonideal vs KanesMethod with dependent speeds, side by side.

    python benchmarks/bench_knife_chain.py [--quick] [--n 2,4,6]
    python benchmarks/bench_knife_chain.py --elastic [--n 10,100,1000] [--kane 3]

``--elastic``: many bodies with a constraint each, sparse all through (each link its own
coordinates, springs between neighbours): check and a 1 s simulation against the number of
links, and KanesMethod side by side at a small size (``benchmarks/elastic_knife_chain.py``).

(a) time to derive from a fresh model, ours in every form of ``nonideal.formalisms.FORMS``
    ("build" = the Model from PlanarBodies and constraints; "derive"; "+SymPy" = conversion of
    ``eom.mass_matrix`` and ``eom.forcing``) vs ``KanesMethod(u_dependent=...,
    velocity_constraints=...)`` (frames, points, bodies included);
    expression size: SymEngine operation counts of what each side compiles for the numerics,
    raw and after common-subexpression elimination -- ours: ``A, Q_f - c, B, G, gamma, R, r``
    and the auxiliary systems ``K, Y`` of the form; Kane: ``mass_matrix`` and ``forcing``
    (constraint rows included).  Growth: exponent p of ``t ~ n^p`` fitted on all sizes and on
    the last ones, growth factor per link of the sizes; which forms switched to auxiliary
    symbols (dependent velocities solved numerically) and their shapes.
(b) one right-hand-side evaluation (ours: ``Simulation(model, form=f).rhs(mode)``; Kane:
    ``lambdify(cse=True)`` + ``numpy.linalg.solve``) and their agreement at the initial state.
(c) 5 s of simulation (DOP853, rtol 1e-8, atol 1e-10), every form, vs ``solve_ivp`` on Kane's
    right-hand side; final states compared.

Prints markdown tables and writes ``benchmarks/results/knife_chain[-quick].json``.
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
from nonideal.gallery.knife_chain import build
from nonideal.simulation.hybrid import N_WORK, Simulation, simulate
from nonideal.modes.switching import select_mode

T_END, RTOL, ATOL, METHOD = 5.0, 1e-8, 1e-10, "DOP853"
PARAMS = [1.0, 1.0]  # m, l


def compiled_exprs(eom) -> list:
    """What FormSystem compiles for this form."""
    out = list(eom.A_) + list(eom.Qf_ - eom.c_) + list(eom.R_) + list(eom.r_)
    if eom.multipliers:
        out += list(eom.B_) + list(eom.G_) + list(eom.gamma_)
    for aux in eom.auxiliaries:
        out += list(aux.K) + list(aux.Y)
    return out


def derive_ours(n: int, form: str, repeat: int) -> dict:
    best = {"build": np.inf, "derive": np.inf, "sympy": np.inf}
    eom = None
    for _ in range(repeat):
        C.clear_caches()
        t0 = time.perf_counter()
        model = build(n)
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
    out["size"] = peers.size_of(compiled_exprs(eom))
    out["auxiliaries"] = [list(a.symbols.shape) for a in eom.auxiliaries]
    out["unknowns"] = len(eom.unknowns)
    out["multipliers"] = len(eom.multipliers)
    return out


def _kane(n):
    km = peers.kane_knife_chain(n)
    km.mass_matrix, km.forcing
    return km


def part_a(ns, quick, repeat, kane_cap, size_cap):
    rows = []
    for n in ns:
        row = {"n": n, "forms": {}}
        for form in FORMS:
            try:
                row["forms"][form] = derive_ours(n, form, repeat)
            except Exception as exc:
                row["forms"][form] = {"error": f"{type(exc).__name__}: {exc}"}
        if n <= kane_cap:
            row["kane"], km = C.best_of(lambda: _kane(n), 1 if (quick or n > 8) else 2)
            row["kane_size"] = (peers.size_of(list(km.mass_matrix) + list(km.forcing))
                                if n <= size_cap else None)
        else:
            row["kane"], row["kane_size"] = None, None
        rows.append(row)
        print(f"  (a) n = {n}: kane {C.fmt_t(row['kane'])} "
              f"({row['kane_size']['ops'] if row['kane_size'] else '-'} ops), "
              + ", ".join(f"{f} {C.fmt_t(v.get('build+derive'))} ({v.get('size', {}).get('ops', '-')} ops"
                          f"{', aux ' + str(v['auxiliaries']) if v.get('auxiliaries') else ''})"
                          for f, v in row["forms"].items()), flush=True)
    return rows


EXPONENTIAL = 4.0
"""A local size exponent d ln(size) / d ln(n) above this at n >= 4 is read as doubling per
link (a polynomial of degree <= 3, the budget of the issue, stays below it)."""


def local_exponents(ns, ss) -> dict:
    """``{n: ln(s_n / s_prev) / ln(n / n_prev)}`` over consecutive sizes."""
    out = {}
    for (a, sa), (b, sb) in zip(zip(ns, ss), list(zip(ns, ss))[1:]):
        if sa and sb and sa > 0 and sb > 0:
            out[b] = float(np.log(sb / sa) / np.log(b / a))
    return out


def growth(rows) -> dict:
    """Fitted exponents and growth factors."""
    ns = [r["n"] for r in rows]
    out = {"forms": {}}
    for f in FORMS:
        ok = [(r["n"], r["forms"][f]) for r in rows if "error" not in r["forms"][f]]
        if len(ok) < 2:
            continue
        n_, v_ = [a for a, _ in ok], [b for _, b in ok]
        tail = [(a, b) for a, b in ok if a >= max(2, n_[-1] // 2)]
        out["forms"][f] = {
            "exponent_build+derive": C.fit_power(n_, [v["build+derive"] for v in v_]),
            "exponent_derive": C.fit_power(n_, [v["derive"] for v in v_]),
            "exponent_build+derive_tail": C.fit_power([a for a, _ in tail], [b["build+derive"] for _, b in tail]),
            "exponent_build+derive+sympy": C.fit_power(n_, [v["build+derive+sympy"] for v in v_]),
            "size_exponent": C.fit_power(n_, [v["size"]["ops"] for v in v_]),
            "size_cse_exponent": C.fit_power(n_, [v["size"]["ops_cse"] for v in v_]),
            "size_growth_per_link": C.fit_growth(n_, [v["size"]["ops"] for v in v_]),
            "auxiliaries_from_n": next((a for a, b in ok if b["auxiliaries"]), None),
            "size_local_exponents": local_exponents(n_, [v["size"]["ops"] for v in v_]),
            "size_cse_local_exponents": local_exponents(n_, [v["size"]["ops_cse"] for v in v_]),
        }
        le = out["forms"][f]["size_local_exponents"]
        out["forms"][f]["exponential_phase"] = [n for n, p in le.items() if n >= 4 and p > EXPONENTIAL]
    kn = [(r["n"], r["kane"]) for r in rows if r["kane"]]
    ks = [(r["n"], r["kane_size"]["ops"], r["kane_size"]["ops_cse"]) for r in rows if r["kane_size"]]
    kl = local_exponents([a for a, _, _ in ks], [b for _, b, _ in ks]) if ks else {}
    out["kane_size_local_exponents"] = kl
    out["kane_exponential_phase"] = [n for n, p in kl.items() if n >= 4 and p > EXPONENTIAL]
    out["kane"] = {
        "exponent": C.fit_power([a for a, _ in kn], [b for _, b in kn]) if kn else None,
        "exponent_tail": C.fit_power([a for a, _ in kn if a >= max(2, kn[-1][0] // 2)],
                                     [b for a, b in kn if a >= max(2, kn[-1][0] // 2)]) if kn else None,
        "size_exponent": C.fit_power([a for a, _, _ in ks], [b for _, b, _ in ks]) if ks else None,
        "size_growth_per_link": C.fit_growth([a for a, _, _ in ks], [b for _, b, _ in ks]) if ks else None,
        "size_cse_growth_per_link": C.fit_growth([a for a, _, _ in ks], [c for _, _, c in ks]) if ks else None,
    }
    out["n"] = ns
    return out


def part_b_c(ns_rhs, ns_sim, kane_rhs_cap, quick):
    from scipy.integrate import solve_ivp

    rep = 3 if quick else 5
    out = []
    for n in sorted(set(ns_rhs) | set(ns_sim)):
        row = {"n": n, "forms": {}}
        model = build(n)
        y0 = None
        sfun = None
        if n <= kane_rhs_cap:
            C.clear_caches()
            km = _kane(n)
            t0 = time.perf_counter()
            sfun = peers.lambdify_rhs(km, peers.knife_constants(), PARAMS)
            row["sympy_lambdify"] = time.perf_counter() - t0
        for f in FORMS:
            try:
                t0 = time.perf_counter()
                sim = Simulation(model, form=f, rtol=RTOL, atol=ATOL, method=METHOD)
                q0, qd0 = sim.initial_state()
                mode = select_mode(sim.solver, model.t0, q0, qd0)
                fun = sim.rhs(mode)
                y = np.concatenate((q0, qd0, np.zeros(N_WORK if sim.track else 0)))
                fun(0.0, y)  # derives and compiles the form for this mode
                setup = time.perf_counter() - t0
                y0 = np.concatenate((q0, qd0))
                v = {"setup": setup, "rhs": C.per_call(repeat=rep, fn=lambda: fun(0.0, y))}
                if sfun is not None:
                    v["agreement"] = float(np.max(np.abs(fun(0.0, y)[:2 * len(q0)] - sfun(0.0, y0))))
                if n in ns_sim:
                    # warm: the model's kernel is compiled (the form is derived again by
                    # each Simulation's ModeSolver -- that is part of the measured time)
                    v["simulate"], tr = C.best_of(
                        lambda: simulate(model, t_end=T_END, form=f, rtol=RTOL, atol=ATOL, method=METHOD),
                        2 if quick else 3, clear=False)
                    v["y_end"] = np.concatenate((tr.q[-1], tr.qd[-1])).tolist()
                    v["steps"] = len(tr.t) - 1
                    v["residual"] = tr.diagnostics["constraint_residual_max"]
                row["forms"][f] = v
            except Exception as exc:
                row["forms"][f] = {"error": f"{type(exc).__name__}: {exc}"}
        if sfun is not None and y0 is not None:
            row["sympy_rhs"] = C.per_call(repeat=rep, fn=lambda: sfun(0.0, y0))
            if n in ns_sim:
                t0 = time.perf_counter()
                sol = solve_ivp(sfun, (0.0, T_END), y0, method=METHOD, rtol=RTOL, atol=ATOL)
                row["sympy_solve_ivp"] = time.perf_counter() - t0
                row["sympy_steps"] = len(sol.t) - 1
                for f, v in row["forms"].items():
                    if "y_end" in v:
                        v["final_state_difference"] = float(np.max(np.abs(np.array(v["y_end"]) - sol.y[:, -1])))
        out.append(row)
        print(f"  (b,c) n = {n}: rhs " + ", ".join(f"{f} {C.fmt_t(v.get('rhs'))}" for f, v in row["forms"].items())
              + f", Kane {C.fmt_t(row.get('sympy_rhs'))}", flush=True)
    return out


def report(a_rows, fits, bc_rows) -> str:
    forms = list(FORMS)
    lines = ["### (a) Time to derive (best of runs, fresh model, SymPy cache cleared)", ""]
    head = ["n", "build"] + [f"{f}: derive / +SymPy" for f in forms] + ["KanesMethod"] + \
        [f"{f}/Kane" for f in forms]
    rows = []
    for r in a_rows:
        first = next((v for v in r["forms"].values() if "build" in v), {})
        cells = [r["n"], C.fmt_t(first.get("build"))]
        for f in forms:
            v = r["forms"][f]
            cells.append("n/a" if "error" in v else f"{C.fmt_t(v['derive'])} / {C.fmt_t(v['sympy'])}")
        cells.append(C.fmt_t(r["kane"]) if r["kane"] else "not run")
        for f in forms:
            v = r["forms"][f]
            cells.append("-" if "error" in v or not r["kane"] else
                         f"{C.fmt_r(v['build+derive'] / r['kane'])} ({C.fmt_r(v['build+derive+sympy'] / r['kane'])})")
        rows.append(cells)
    lines += [C.table(head, rows), "",
              "Ratios ours/Kane: ours = build + derive (in brackets: + SymPy conversion).", ""]
    lines += ["### Expression size (SymEngine count_ops of what is compiled: raw / after CSE)", ""]
    head = ["n"] + forms + ["KanesMethod M, F"] + [f"{f}/Kane (CSE)" for f in forms] + ["auxiliary symbols"]
    rows = []
    for r in a_rows:
        cells = [r["n"]]
        for f in forms:
            v = r["forms"][f]
            cells.append("n/a" if "error" in v else f"{v['size']['ops']} / {v['size']['ops_cse']}")
        ks = r["kane_size"]
        cells.append(f"{ks['ops']} / {ks['ops_cse']}" if ks else "not run")
        for f in forms:
            v = r["forms"][f]
            cells.append("-" if "error" in v or not ks else C.fmt_r(v["size"]["ops_cse"] / ks["ops_cse"]))
        aux = [f"{f} {'x'.join(map(str, s))}" for f in forms if "error" not in r["forms"][f]
               for s in r["forms"][f]["auxiliaries"]]
        cells.append(", ".join(aux) if aux else "none")
        rows.append(cells)
    lines += [C.table(head, rows), ""]
    lines += ["### Growth with n", ""]
    head = ["", "time exponent p (t ~ n^p), all n", "p on the larger half", "p with SymPy conversion",
            "size exponent (fit)", "CSE size exponent", "raw size doubles per link at n =",
            "auxiliaries from n"]
    rows = []
    for f, g in fits["forms"].items():
        rows.append([f, C.fmt_r(g["exponent_build+derive"]), C.fmt_r(g["exponent_build+derive_tail"]),
                     C.fmt_r(g["exponent_build+derive+sympy"]), C.fmt_r(g["size_exponent"]),
                     C.fmt_r(g["size_cse_exponent"]), _ranges(g["exponential_phase"]),
                     g["auxiliaries_from_n"] or "never"])
    k = fits["kane"]
    rows.append(["KanesMethod", C.fmt_r(k["exponent"]), C.fmt_r(k["exponent_tail"]), "-",
                 C.fmt_r(k["size_exponent"]), "-", _ranges(fits.get("kane_exponential_phase", [])), "-"])
    lines += [C.table(head, rows), "",
              f"'doubles per link': local exponent d ln(size)/d ln(n) > {EXPONENTIAL:g} between consecutive "
              "sizes (n >= 4), i.e. faster than any cubic.", ""]
    if bc_rows:
        lines += ["### (b) One right-hand-side evaluation; (c) simulation of "
                  f"{T_END:g} s ({METHOD}, rtol {RTOL:g}, atol {ATOL:g})", ""]
        head = ["n"] + [f"{f} rhs" for f in forms] + ["Kane lambdify+solve", "best ours/Kane"] + \
            [f"{f} simulate" for f in forms] + ["Kane solve_ivp", "max |y_ours - y_Kane| at t_end"]
        rows = []
        for r in bc_rows:
            cells = [r["n"]]
            for f in forms:
                cells.append(C.fmt_t(r["forms"][f].get("rhs")) if "error" not in r["forms"][f] else "n/a")
            cells.append(C.fmt_t(r.get("sympy_rhs")))
            best = min((v["rhs"] for v in r["forms"].values() if "rhs" in v), default=None)
            cells.append(C.fmt_r(C.ratio(best, r.get("sympy_rhs"))))
            for f in forms:
                cells.append(C.fmt_t(r["forms"][f].get("simulate")))
            cells.append(C.fmt_t(r.get("sympy_solve_ivp")))
            diffs = [v["final_state_difference"] for v in r["forms"].values() if "final_state_difference" in v]
            cells.append(f"{max(diffs):.1e}" if diffs else "-")
            rows.append(cells)
        lines += [C.table(head, rows), ""]
    return "\n".join(lines)


def _ranges(ns) -> str:
    if not ns:
        return "never"
    return f"{ns[0]}..{ns[-1]}" if len(ns) > 1 else str(ns[0])


def targets(a_rows, fits) -> list[str]:
    out = []
    r6 = next((r for r in a_rows if r["n"] == 6), None)
    if r6:
        ok = {f: v for f, v in r6["forms"].items() if "error" not in v}
        worst = max((v["build+derive"], f) for f, v in ok.items())
        worst_s = max((v["build+derive+sympy"], f) for f, v in ok.items())
        out.append(f"derive at n = 6 <= 0.1 s in every form: worst {worst[1]} {C.fmt_t(worst[0])} "
                   f"(with SymPy conversion: {worst_s[1]} {C.fmt_t(worst_s[0])}) -> "
                   f"{'MET' if worst[0] <= 0.1 else 'MISSED'}"
                   f"{'' if worst_s[0] <= 0.1 else ' (missed with the SymPy conversion)'}; "
                   f"KanesMethod {C.fmt_t(r6['kane'])}")
    for f, g in fits["forms"].items():
        p = g["exponent_build+derive"]
        out.append(f"{f}: derivation cost exponent {C.fmt_r(p)} (larger half {C.fmt_r(g['exponent_build+derive_tail'])})"
                   f" -> {'MET' if p is not None and p <= 3 and (g['exponent_build+derive_tail'] or 0) <= 3 else 'MISSED'}"
                   f" (<= 3); raw size: "
                   + ("polynomial at every n" if not g["exponential_phase"] else
                      f"DOUBLES per link at n = {_ranges(g['exponential_phase'])}"
                      + (f", polynomial from n = {g['auxiliaries_from_n']} (auxiliary symbols)"
                         if g["auxiliaries_from_n"] else ""))
                   + f"; CSE'd size exponent {C.fmt_r(g['size_cse_exponent'])}")
    return out


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if "--elastic" in argv:   # many links, each its own coordinates: elastic_knife_chain.py
        import elastic_knife_chain
        return elastic_knife_chain.run(argv)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, under a minute")
    ap.add_argument("--n", help="comma-separated sizes (default 2..12; quick 2,3,4,6)")
    args = ap.parse_args(argv)
    quick = args.quick
    ns = [int(s) for s in args.n.split(",")] if args.n else ([2, 3, 4, 6] if quick else list(range(2, 13)))
    repeat = 3 if quick else 5
    kane_cap = 6 if quick else 12
    size_cap = 6 if quick else 10
    ns_rhs = [n for n in ns if n in ((6,) if quick else (3, 6, 9))]
    ns_sim = [n for n in ns if n in ((6,) if quick else (3, 6))]
    kane_rhs_cap = 6
    info = C.machine()
    print(f"knife-edge chain benchmark ({'quick' if quick else 'full'}) on {info['cpu']} x{info['nproc']}, "
          f"{info['date']}, load average {info['loadavg_at_start'][0]:.2f}", flush=True)
    derive(build(2), "lagrange1")
    peers.kane_knife_chain(2)
    t0 = time.perf_counter()
    a_rows = part_a(ns, quick, repeat, kane_cap, size_cap)
    fits = growth(a_rows)
    bc_rows = part_b_c(ns_rhs, ns_sim, kane_rhs_cap, quick)
    text = report(a_rows, fits, bc_rows)
    goals = targets(a_rows, fits)
    print()
    print(text)
    print("Targets:")
    for g in goals:
        print("  " + g)
    path = C.write_json("knife_chain", {"machine": info, "quick": quick, "forms": list(FORMS),
                                        "settings": {"t_end": T_END, "rtol": RTOL, "atol": ATOL, "method": METHOD,
                                                     "repeat": repeat, "kane_cap": kane_cap, "size_cap": size_cap},
                                        "derive": a_rows, "growth": fits, "rhs_simulate": bc_rows,
                                        "targets": goals, "markdown": text,
                                        "elapsed": time.perf_counter() - t0}, quick)
    print(f"\nwritten {path} ({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
