"""Where the time goes: derive, right-hand side and simulate paths, with prototypes of fixes.

    python benchmarks/profile_paths.py [--quick]

Wraps the library's functions with wall-clock timers (no edits to the library), prints
cProfile's top entries for each path, times the pieces of one right-hand-side evaluation,
and measures prototypes of the proposed optimizations *outside* the library (so the numbers
say what a change would gain before anyone makes it).  Writes ``results/profile.json``.
Systems: the 10-link pendulum and the 6-link knife-edge chain.
"""

from __future__ import annotations

import argparse
import cProfile
import functools
import io
import math
import pstats
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal, not an installed copy

import _common as C  # noqa: E402

import nonideal.equations.formalisms.base as fbase  # noqa: E402
import nonideal.modeling.model as nmodel  # noqa: E402
import nonideal.modeling.values as nvalues  # noqa: E402
import nonideal.simulation.hybrid as nsim  # noqa: E402
import nonideal.simulation.trajectory as ntraj  # noqa: E402
from nonideal.equations.dynamics import dynamics_of
from nonideal.equations.formalisms import derive
from nonideal.gallery import knife_chain, nlink_pendulum
from nonideal.numeric.kernel import Kernel, solve_saddle
from nonideal.modes.switching import select_mode


class Timers:
    """Accumulating wall-clock wrappers around library functions (restored on exit)."""

    def __init__(self):
        self.acc: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._undo = []

    def wrap(self, owner, name, label):
        f = owner.__dict__[name] if isinstance(owner, type) else getattr(owner, name)
        raw = f.__func__ if isinstance(f, (classmethod, staticmethod)) else f

        @functools.wraps(raw)
        def w(*a, **k):
            t0 = time.perf_counter()
            try:
                return raw(*a, **k)
            finally:
                self.acc[label] = self.acc.get(label, 0.0) + time.perf_counter() - t0
                self.calls[label] = self.calls.get(label, 0) + 1
        new = classmethod(w) if isinstance(f, classmethod) else staticmethod(w) if isinstance(f, staticmethod) else w
        self._undo.append((owner, name, f))
        setattr(owner, name, new)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        for owner, name, f in reversed(self._undo):
            setattr(owner, name, f)

    def report(self, total: float) -> list[dict]:
        return [{"what": k, "seconds": v, "share": v / total, "calls": self.calls[k]}
                for k, v in sorted(self.acc.items(), key=lambda kv: -kv[1])]


def top(fn, n=15, only_ours: bool = True) -> str:
    """cProfile of ``fn()``: our functions by cumulative time (or everything by own time)."""
    pr = cProfile.Profile()
    pr.enable()
    fn()
    pr.disable()
    s = io.StringIO()
    st = pstats.Stats(pr, stream=s)
    if only_ours:
        st.sort_stats("cumulative").print_stats(r"nonideal/", n)
    else:
        st.sort_stats("tottime").print_stats(n)
    lines = [ln for ln in s.getvalue().splitlines() if ln.strip()]
    start = next(i for i, ln in enumerate(lines) if ln.lstrip().startswith("ncalls"))
    root = str(Path(nmodel.__file__).parent.parent) + "/"
    return "\n".join(ln.replace(root, "") for ln in lines[start:start + n + 1])


# ----------------------------------------------------------------------------- derive path


def derive_path(label, make, form):
    C.clear_caches()
    make()  # warm imports
    C.clear_caches()
    t0 = time.perf_counter()
    with Timers() as tm:
        tm.wrap(nvalues, "parse_expression", "Model: parse expressions (safe parser -> SymPy)")
        tm.wrap(nvalues, "identically_zero", "Model: identically_zero (4 evalf at random points)")
        tm.wrap(fbase, "numeric_instances", "derive: numeric_instances (xreplace + n() per entry)")
        tm.wrap(fbase, "_symbolic_solve", "derive: symbolic solve of the dependent block")
        tb = time.perf_counter()
        model = make()
        t_build = time.perf_counter() - tb
        td = time.perf_counter()
        dyn = dynamics_of(model)
        dyn.M, dyn.F, dyn.rows()
        t_dyn = time.perf_counter() - td
        te = time.perf_counter()
        eom = derive(model, form)
        t_form = time.perf_counter() - te
        ts = time.perf_counter()
        eom.mass_matrix, eom.forcing
        t_sympy = time.perf_counter() - ts
        tk = time.perf_counter()
        Kernel(model)
        t_kernel = time.perf_counter() - tk
    total = time.perf_counter() - t0
    stages = {"Model(...) construction": t_build, "dynamics_of: M, F, rows (SymEngine)": t_dyn,
              f"derive '{form}' after the kernel": t_form, "conversion to SymPy": t_sympy,
              "Kernel compile (Lambdify + LLVM)": t_kernel}
    C.clear_caches()
    prof = top(lambda: (derive(make(), form).mass_matrix), n=25)
    return {"system": label, "form": form, "total": total, "stages": stages, "inside": tm.report(total),
            "cprofile": prof}


# ----------------------------------------------------------------------------- rhs path


def rhs_pieces(label, model, form):
    sim = nsim.Simulation(model, form=form, rtol=1e-8, atol=1e-10)
    q0, qd0 = sim.initial_state()
    mode = select_mode(sim.solver, model.t0, q0, qd0)
    fun = sim.rhs(mode)
    y = np.concatenate((q0, qd0, np.zeros(nsim.N_WORK if sim.track else 0)))
    fun(0.0, y)
    S, K = sim.solver, sim.kernel
    x = S.input(0.0, q0, qd0)
    out = K.dynamics(x)
    lay = S.layout(mode)
    system = S.system(mode)
    pieces = {
        "Simulation.rhs(mode)(t, y)": lambda: fun(0.0, y),
        "general path: ModeSolver.accelerations": lambda: S.accelerations(0.0, q0, qd0, mode),
        "Compiled.raw (kernel M, F, G, gamma, B)": lambda: K.dynamics.raw(x),
        "Compiled.__call__ (raw + dict of views)": lambda: K.dynamics(x),
    }
    if form == "lagrange1":
        Ks, rs, _ = system.assemble(S, 0.0, y, mode)
        pieces["ModeSystem.assemble (kernel call + gather by index)"] = lambda: system.assemble(S, 0.0, y, mode)
        pieces["ModeSystem.factor (LAPACK, with a copy of K)"] = \
            lambda: system.factor(np.array(Ks, order="F"), np.array(rs))
    if lay:
        Gm, gm, Bm = S.assemble(mode, lay, out, None)
        pieces["general path: ModeSolver.assemble (loop over rows)"] = lambda: S.assemble(mode, lay, out, None)
        pieces["general path: solve_saddle(M, F, B, G, gamma)"] = lambda: solve_saddle(out["M"], out["F"], Bm, Gm, gm)
        if form != "lagrange1":
            fs = S._current_form(mode, Gm, lay)
            pieces["ModeSolver._current_form (partition check)"] = lambda: S._current_form(mode, Gm, lay)
            pieces["FormSystem.solve (compiled form + solves)"] = lambda: fs.solve(x)
    res = {k: C.per_call(v, target=0.1, repeat=3) for k, v in pieces.items()}
    # floors: bare closures around the same kernel (what a right-hand side costs without the
    # library's bookkeeping) -------------------------------------------------------------
    proto = {}
    n = K.n
    raw, buf = K.dynamics.fn, K.dynamics.out
    sl_M, shM = K.dynamics.slices["M"]
    sl_F, _ = K.dynamics.slices["F"]
    Mv, Fv = buf[sl_M].reshape(shM), buf[sl_F]
    xx = x.copy()
    from scipy.linalg import lapack
    dposv, dgesv = lapack.dposv, lapack.dgesv
    if not lay and form == "lagrange1":
        def fast(t, yy):
            xx[0] = t
            xx[1:1 + 2 * n] = yy[:2 * n]
            raw.unsafe_real(xx, buf)
            dy = np.empty_like(yy)
            dy[:n] = yy[n:2 * n]
            dy[n:2 * n] = dposv(Mv, Fv)[1]
            return dy
        proto["floor: bare closure, kernel + dposv (lagrange1, no rows)"] = C.per_call(lambda: fast(0.0, y), 0.1, 3)
        proto["  its max |difference| to Simulation.rhs"] = float(np.max(np.abs(fast(0.0, y) - fun(0.0, y))))
    elif lay and all(r.kind == "constraint" for r in lay):
        idx = np.array([r.index for r in lay])
        sG, shG = K.dynamics.slices["G"]
        sg, _ = K.dynamics.slices["gamma"]
        sB, shB = K.dynamics.slices["B"]
        Gall, gall, Ball = buf[sG].reshape(shG), buf[sg], buf[sB].reshape(shB)
        m = len(idx)
        s = n + m

        def fast(t, yy):
            xx[0] = t
            xx[1:1 + 2 * n] = yy[:2 * n]
            raw.unsafe_real(xx, buf)
            Kk = np.zeros((s, s), order="F")
            Kk[:n, :n] = Mv
            Kk[:n, n:] = Ball[:, idx]
            Kk[n:, :n] = Gall[idx]
            rhs = np.empty(s)
            rhs[:n] = Fv
            np.negative(gall[idx], out=rhs[n:])
            sol = dgesv(Kk, rhs, overwrite_a=1, overwrite_b=1)[2]
            qdd = sol[:n]
            dy = np.empty_like(yy)
            dy[:n] = yy[n:2 * n]
            dy[n:2 * n] = qdd
            # reaction power R.q' with R = M q'' - F (ideal rows: zero up to round-off)
            dy[2 * n:] = 0.0
            dy[2 * n + 1] = (Mv @ qdd - Fv) @ yy[n:2 * n]
            return dy
        proto["floor: bare closure, kernel + dgesv (constraint rows, work integral kept)"] = \
            C.per_call(lambda: fast(0.0, y), 0.1, 3)
        proto["  its max |difference| to Simulation.rhs"] = float(np.max(np.abs(fast(0.0, y) - fun(0.0, y))))
    return {"system": label, "form": form, "pieces": res, "prototypes": proto}


# ----------------------------------------------------------------------------- simulate path


def simulate_path(label, model, t_end, form="lagrange1"):
    opts = dict(t_end=t_end, rtol=1e-8, atol=1e-10, form=form)
    nsim.simulate(model, **opts)  # compile
    t0 = time.perf_counter()
    tr = nsim.simulate(model, **opts)
    total = time.perf_counter() - t0
    with Timers() as tm:
        tm.wrap(nsim.Simulation, "initial_state", "Simulation.initial_state (memoized)")
        tm.wrap(nsim.Simulation, "__init__", "Simulation.__init__ (ModeSolver, parameters)")
        tm.wrap(nsim.Simulation, "_residuals", "per step: constraint residuals (observables)")
        tm.wrap(nsim.Simulation, "_project", "projections (start and drift)")
        tm.wrap(nsim, "select_mode", "select_mode (initial mode)")
        tm.wrap(nsim, "validate_state", "validate_state")
        tm.wrap(ntraj.Trajectory, "from_samples", "Trajectory.from_samples (one batch evaluation)")
        rhs_label = "right-hand side calls of the integrator"
        original_rhs = nsim.Simulation.rhs

        def timed_rhs(self, mode):
            f = original_rhs(self, mode)

            def g(t, y):
                t0 = time.perf_counter()
                try:
                    return f(t, y)
                finally:
                    tm.acc[rhs_label] = tm.acc.get(rhs_label, 0.0) + time.perf_counter() - t0
                    tm.calls[rhs_label] = tm.calls.get(rhs_label, 0) + 1
            return g
        nsim.Simulation.rhs = timed_rhs
        try:
            t1 = time.perf_counter()
            tr = nsim.simulate(model, **opts)
            inst = time.perf_counter() - t1
        finally:
            nsim.Simulation.rhs = original_rhs
    steps = len(tr.t) - 1
    items = tm.report(inst)
    acc = sum(v["seconds"] for v in items)
    items.append({"what": "rest: SciPy's stepping, the loop's bookkeeping, samples",
                  "seconds": inst - acc, "share": (inst - acc) / inst, "calls": None})
    # prototype: the bare integration of the same rhs with SciPy's solver (no events, no
    # residual checks, no samples) -- the floor the loop can reach
    from scipy.integrate import solve_ivp
    sim = nsim.Simulation(model, form=form, rtol=1e-8, atol=1e-10)
    q0, qd0 = sim.initial_state()
    mode = select_mode(sim.solver, model.t0, q0, qd0)
    fun = sim.rhs(mode)
    y0 = np.concatenate((q0, qd0, np.zeros(nsim.N_WORK if sim.track else 0)))
    atol = sim._work_tolerances() if sim.track else sim.atol  # as the simulation integrates
    tb = time.perf_counter()
    sol = solve_ivp(fun, (model.t0, t_end), y0, method="DOP853", rtol=1e-8, atol=atol)
    bare = time.perf_counter() - tb
    out = {"system": label, "form": form, "simulate_warm": total, "steps": steps, "breakdown": items,
           "bare_solve_ivp_same_rhs": bare, "bare_steps": len(sol.t) - 1, "bare_nfev": int(sol.nfev)}
    if sim.track:
        # the same without the work integrals in the state (the steps of the motion alone)
        n = sim.n

        def mech(t, yy):
            return fun(t, np.concatenate((yy, np.zeros(nsim.N_WORK))))[:2 * n]
        tb = time.perf_counter()
        s2 = solve_ivp(mech, (model.t0, t_end), y0[:2 * n], method="DOP853", rtol=1e-8, atol=1e-10)
        out["bare_without_work_integrals"] = time.perf_counter() - tb
        out["steps_without_work_integrals"] = len(s2.t) - 1
    # numeric_initial prototype: xreplace + float instead of subs
    import sympy as sp
    values = {sp.Symbol(k): v for k, v in model.parameter_values.items()}
    proto = lambda: {k: float(sp.sympify(e).xreplace(values)) for k, e in model.initial.items()}  # noqa: E731
    out["numeric_initial"] = C.per_call(model.numeric_initial, 0.1, 3)
    out["numeric_initial_xreplace_prototype"] = C.per_call(proto, 0.1, 3)
    # cProfile of one run
    out["cprofile"] = top(lambda: nsim.simulate(model, **opts))
    return out


def reduced_form_setup(model, form):
    """Time each Simulation spends deriving and compiling a reduced form again."""
    nsim.simulate(model, t_end=0.01, form=form)
    ref = nsim.Simulation(model)
    q0, qd0 = ref.initial_state()
    mode = select_mode(ref.solver, model.t0, q0, qd0)
    best = math.inf
    for _ in range(3):
        sim = nsim.Simulation(model, form=form)
        t0 = time.perf_counter()
        sim.solver.form_system(mode)
        best = min(best, time.perf_counter() - t0)
    return best


def lambdify_tiers(model):
    import symengine as se

    dyn = dynamics_of(model)
    syms = [dyn.t] + dyn.q + dyn.qd + dyn.params
    exprs = list(dyn.M) + list(dyn.F) + [x for r in dyn.rows() for x in list(r.G) + [r.gamma]]
    x = np.random.default_rng(0).uniform(-1, 1, len(syms))
    outb = np.zeros(len(exprs))
    res = {}
    for label, kw in (("LLVM opt_level=0", {"backend": "llvm", "opt_level": 0}),
                      ("LLVM opt_level=3 (previous default)", {"backend": "llvm", "opt_level": 3}),
                      ("lambda backend (no LLVM)", {"backend": "lambda"})):
        t0 = time.perf_counter()
        f = se.Lambdify(syms, exprs, cse=True, **kw)
        build = time.perf_counter() - t0
        ev = C.per_call(lambda: f.unsafe_real(x, outb), 0.1, 3)
        res[label] = {"build": build, "eval": ev, "outputs": len(exprs)}
    a, b = res["LLVM opt_level=0"], res["LLVM opt_level=3 (previous default)"]
    res["break-even evaluations"] = (b["build"] - a["build"]) / max(a["eval"] - b["eval"], 1e-12)
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    info = C.machine()
    pend = lambda: nlink_pendulum.build(10)  # noqa: E731
    chain = lambda: knife_chain.build(6)  # noqa: E731
    data = {"machine": info}
    t_start = time.perf_counter()
    print("== derive path ==")
    data["derive"] = [derive_path("pendulum n=10", pend, "maggi"), derive_path("knife chain n=6", chain, "maggi")]
    for d in data["derive"]:
        print(f"-- {d['system']}, {d['form']}: total {C.fmt_t(d['total'])}")
        for k, v in d["stages"].items():
            print(f"   {k:45s} {C.fmt_t(v):>9s}  {v / d['total']:5.1%}")
        print("   inside those stages:")
        for it in d["inside"]:
            print(f"     {it['what']:55s} {C.fmt_t(it['seconds']):>9s}  {it['share']:5.1%}  ({it['calls']} calls)")
        print(d["cprofile"])
    print("\n== one right-hand side ==")
    data["rhs"] = [rhs_pieces("pendulum n=10", pend(), "lagrange1"),
                   rhs_pieces("knife chain n=6", chain(), "lagrange1"),
                   rhs_pieces("knife chain n=6", chain(), "maggi")]
    for d in data["rhs"]:
        print(f"-- {d['system']}, {d['form']}")
        for k, v in d["pieces"].items():
            print(f"   {k:55s} {C.fmt_t(v):>9s}")
        for k, v in d["prototypes"].items():
            print(f"   prototype: {k:55s} {C.fmt_t(v) if 'difference' not in k else f'{v:.1e}':>9s}")
    print("\n== simulate ==")
    data["simulate"] = [simulate_path("pendulum n=10 (10 s)", pend(), 10.0),
                        simulate_path("knife chain n=6 (5 s)", chain(), 5.0),
                        simulate_path("knife chain n=6 (5 s)", chain(), 5.0, "maggi")]
    for d in data["simulate"]:
        print(f"-- {d['system']}, {d['form']}: simulate (warm) {C.fmt_t(d['simulate_warm'])}, {d['steps']} steps; "
              f"bare solve_ivp on the same rhs {C.fmt_t(d['bare_solve_ivp_same_rhs'])} ({d['bare_steps']} steps)"
              + (f"; without the work integrals in y: {C.fmt_t(d['bare_without_work_integrals'])} "
                 f"({d['steps_without_work_integrals']} steps)" if "bare_without_work_integrals" in d else ""))
        for it in d["breakdown"]:
            share = f"{it['share']:5.1%}" if it["share"] is not None else "     "
            print(f"   {it['what']:55s} {C.fmt_t(it['seconds']):>9s}  {share}  ({it['calls']} calls)")
        print(f"   numeric_initial {C.fmt_t(d['numeric_initial'])}; xreplace prototype "
              f"{C.fmt_t(d['numeric_initial_xreplace_prototype'])}")
    print("\n== per-Simulation re-derivation of a reduced form ==")
    data["form_setup"] = {"knife chain n=6, maggi": reduced_form_setup(chain(), "maggi"),
                          "pendulum n=10, maggi": reduced_form_setup(pend(), "maggi")}
    for k, v in data["form_setup"].items():
        print(f"   {k}: {C.fmt_t(v)} per Simulation object")
    print("\n== Lambdify: compile vs evaluation ==")
    data["lambdify"] = {"pendulum n=10": lambdify_tiers(pend()), "knife chain n=12": lambdify_tiers(knife_chain.build(12))}
    if not args.quick:
        data["lambdify"]["pendulum n=20"] = lambdify_tiers(nlink_pendulum.build(20))
    for k, v in data["lambdify"].items():
        print(f"-- {k} ({v['LLVM opt_level=0']['outputs']} outputs): break-even {v['break-even evaluations']:.3g} evaluations")
        for lab, r in v.items():
            if isinstance(r, dict):
                print(f"   {lab:38s} build {C.fmt_t(r['build']):>9s}  eval {C.fmt_t(r['eval']):>9s}")
    data["elapsed"] = time.perf_counter() - t_start
    path = C.write_json("profile", data, args.quick)
    print(f"\nwritten {path}")


if __name__ == "__main__":
    main()
