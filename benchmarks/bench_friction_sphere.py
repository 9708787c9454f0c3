"""Friction benchmark: a homogeneous sphere launched sliding on a rough plane.

Run (MuJoCo lives only in the benchmark's own virtual environment, see README.md)::

    benchmarks/.venv-mujoco/bin/python benchmarks/bench_friction_sphere.py [--quick]

Without MuJoCo importable (``python benchmarks/bench_friction_sphere.py``) the MuJoCo part
is skipped and the report says so.

The problem (model: ``benchmarks/friction_sphere.toml``; m = 1, R = 0.1, g = 9.81, mu = 0.2,
T = 1 s).  The slip of the contact point, ``U = (x' - R w_y, y' + R w_x)``, obeys
``m v' = F``, ``(2/5) m R^2 w' = (-R e_z) x F`` with ``F = -mu m g U/|U|``, hence
``U' = (7/2) F/m``: it keeps its direction and decreases at ``(7/2) mu g``; rolling starts at
``t* = 2|U0|/(7 mu g)`` and the velocity is then ``v_f = v0 - (2/7) U0`` (conservation of the
angular momentum about the contact point, whatever the friction law).  Two starts:

* (a) pure sliding along x: ``v0 = (2, 0, 0)``, ``w0 = 0``;
* (b) oblique: ``v0 = (2, 1, 0)``, ``w0 = (-20, 5, 0)``, so ``U0 = (1.5, -1)`` is not parallel
  to ``v0`` and both slip components matter.

Measured, side by side in one process:

1. **ours** -- ``nonideal.simulate(model, t_end=T, initial=..., every_step=True)`` (every step
   kept, as MuJoCo's rollout keeps each of its steps; the default output is a 1001-time grid) (exact Coulomb friction,
   slip-stop event located on the dense output): error of the event time and of the final
   velocity, angular velocity and position; wall time of a *warm* run (the model's kernels
   compiled: the script runs ``WARMUP`` runs first), and of the *index path*
   (``specialize=False``).  A run compiles the saddle-point system of a mode once it has
   evaluated it ``SPECIALIZE_CALLS`` times itself (the count is the run's, so that a run does
   not depend on what ran before it); this run's 31 and 62 evaluations stay below, so the two
   take the same path (until 2026-11-28 the count was the process's, and "warm" meant both
   mode systems compiled);
   the first call -- model parsing and compilation -- separately, the compilation of the
   two mode systems separately, a cold process with the import separately too.  Also a
   sweep of the tolerances, a cProfile of the warm run and its wall time by stage.
2. **MuJoCo** (if importable) -- the same sphere in MJCF (sphere geom, free joint, plane,
   sliding friction mu only, condim 3) for both friction cones, several timesteps and
   contact settings (default; impratio = 10; stiff: solref = (2 dt, 1), solimp =
   (0.99, 0.999, 0.001)).  The ball first settles at rest into its soft contact (0.5 s), then
   gets the initial velocities at t = 0.  The whole trajectory comes from one
   ``mujoco.rollout.rollout`` call (C loop; the wall time is that call, median of repeats);
   the Python ``mj_step`` loop most users write is timed for a few settings too.
3. **regularized friction** -- what users write by hand: ``regularized(model, eps,
   law="smooth")`` (``F = -mu N U/sqrt(|U|^2 + eps^2)``) integrated by our simulation with
   Radau/LSODA, and a plain ``scipy.integrate.solve_ivp`` of the planar equations with
   ``F = -mu m g tanh(|U|/eps) U/|U|`` (N = m g assumed).

The rolling time of the peers (no event) is estimated from the sampled slip speed two ways:
``extrapolated`` -- the zero of the least-squares line through the samples with
``0.05 |U0| <= |U| <= 0.5 |U0|`` (headline, the estimator most favourable to them); and
``threshold`` -- the first time ``|U| < 1e-3 |U0|`` (linear interpolation between samples).
For MuJoCo the slip is taken at its contact point (the middle of the penetration).

Output: markdown tables on stdout and ``benchmarks/results/friction_sphere.json``
(``friction_sphere-quick.json`` with ``--quick``, not committed).
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as _dt
import gc
import io
import json
import math
import os
import platform
import pstats
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MODEL_FILE = HERE / "friction_sphere.toml"
RESULTS = HERE / "results"

M, R, G, MU = 1.0, 0.1, 9.81, 0.2
T_END = 1.0
CASES = {
    "a": {"title": "(a) pure sliding along x", "v0": (2.0, 0.0, 0.0), "w0": (0.0, 0.0, 0.0)},
    "b": {"title": "(b) oblique: slip not parallel to v", "v0": (2.0, 1.0, 0.0), "w0": (-20.0, 5.0, 0.0)},
}
THRESHOLD = 1e-3          # "threshold" estimator: |U| < THRESHOLD |U0|
FIT_WINDOW = (0.05, 0.5)  # "extrapolated" estimator: fit |U| in this window of |U0|
GOAL = 1e-9               # the accuracy goal (relative)
WARMUP = 20               # warm runs before timing: the kernels compiled, the native code loaded


# ============================================================================ closed form


def closed_form(v0, w0, T=T_END) -> dict:
    """t*, U0, and the velocity, angular velocity and position at T of the exact motion."""
    v0 = np.asarray(v0, float)
    w0 = np.asarray(w0, float)
    U0 = np.array([v0[0] - R * w0[1], v0[1] + R * w0[0]])
    s = U0 / np.linalg.norm(U0)
    t_star = 2 * np.linalg.norm(U0) / (7 * MU * G)
    a = -MU * G * s                          # acceleration of the centre while sliding
    v_f = v0[:2] + a * t_star                # = v0 - (2/7) U0
    assert np.allclose(v_f, v0[:2] - 2 / 7 * U0)
    w_f = w0 + np.array([2.5 * a[1] / R, -2.5 * a[0] / R, 0.0]) * t_star
    r_star = v0[:2] * t_star + 0.5 * a * t_star ** 2
    r_T = r_star + v_f * (T - t_star)
    return {"U0": U0, "t_star": float(t_star), "v_f": v_f, "w_f": w_f, "r_T": r_T}


def rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def errors(exact: dict, t_star, v_T, w_T, r_T) -> dict:
    return {"t_star": None if t_star is None or not np.isfinite(t_star) else abs(t_star - exact["t_star"]) / exact["t_star"],
            "velocity": rel(v_T, exact["v_f"]), "angular_velocity": rel(w_T, exact["w_f"]),
            "position": rel(r_T, exact["r_T"])}


def slip_time_estimates(t, speed, s0) -> dict:
    """Rolling-start time from a sampled slip speed (see the module docstring)."""
    t, speed = np.asarray(t, float), np.asarray(speed, float)
    out = {"extrapolated": math.nan, "threshold": math.nan}
    lo, hi = FIT_WINDOW[0] * s0, FIT_WINDOW[1] * s0
    below = np.nonzero(speed < lo)[0]
    end = below[0] if below.size else len(speed)
    sel = np.nonzero((speed[:end] >= lo) & (speed[:end] <= hi))[0]
    if sel.size >= 2:
        p = np.polyfit(t[sel], speed[sel], 1)
        if p[0] < 0:
            out["extrapolated"] = float(-p[1] / p[0])
    thr = THRESHOLD * s0
    k = np.nonzero(speed < thr)[0]
    if k.size and k[0] > 0:
        i = k[0]
        ta, tb, sa, sb = t[i - 1], t[i], speed[i - 1], speed[i]
        out["threshold"] = float(ta + (sa - thr) * (tb - ta) / (sa - sb))
    return out


# ============================================================================ helpers


def median_time(fn, repeat: int):
    """(median, min, list) of the wall time of ``fn()`` over *repeat* runs; last result."""
    times, result = [], None
    gc.collect()
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), times, result


def fmt_t(t) -> str:
    if t is None or (isinstance(t, float) and math.isnan(t)):
        return "-"
    if t >= 1:
        return f"{t:.2f} s"
    if t >= 1e-3:
        return f"{t * 1e3:.2f} ms"
    return f"{t * 1e6:.0f} us"


def fmt_e(e) -> str:
    if e is None or (isinstance(e, float) and math.isnan(e)):
        return "-"
    return f"{e:.1e}"


def fmt_r(r) -> str:
    return "-" if r is None or (isinstance(r, float) and math.isnan(r)) else f"{r:.3g}"


def table(header, rows) -> str:
    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) if rows else len(str(h))
              for i, h in enumerate(header)]
    line = "| " + " | ".join(str(h).ljust(w) for h, w in zip(header, widths)) + " |"
    sep = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    return "\n".join([line, sep] + ["| " + " | ".join(str(c).ljust(w) for c, w in zip(r, widths)) + " |"
                                    for r in rows])


def machine(mujoco_version) -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    versions = {"python": platform.python_version(), "mujoco": mujoco_version}
    for mod in ("nonideal", "numpy", "scipy", "sympy", "symengine"):
        try:
            versions[mod] = __import__(mod).__version__
        except Exception:
            versions[mod] = None
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True,
                                text=True, timeout=10).stdout.strip() or None
    except Exception:
        commit = None
    import symengine

    return {"date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "nproc": os.cpu_count(), "cpu": cpu, "platform": platform.platform(),
            "versions": versions, "symengine_llvm": bool(getattr(symengine, "have_llvm", False)),
            "git_commit": commit, "library_modified": _library_dirty(), "executable": sys.executable,
            "loadavg_start": list(os.getloadavg())}


def _library_dirty() -> list[str] | None:
    """Library files with uncommitted changes (the numbers describe the working tree)."""
    try:
        out = subprocess.run(["git", "status", "--porcelain", "--", "nonideal"], cwd=ROOT, capture_output=True,
                             text=True, timeout=10).stdout
        return [line[3:] for line in out.splitlines()]
    except Exception:
        return None


def initial_of(case: dict) -> dict:
    v0, w0 = case["v0"], case["w0"]
    return {"x'": v0[0], "y'": v0[1], "z'": v0[2], "a'": w0[0], "b'": w0[1], "c'": w0[2]}


def clear_library_caches() -> None:
    from sympy.core.cache import clear_cache

    clear_cache()
    # the library's caches live on the model object (Model.cached): a fresh model starts empty
    gc.collect()


# ============================================================================ 1. ours


def ours_measure(traj, exact: dict) -> dict:
    ev = [e for e in traj.events if e["type"] == "stick"]
    t_ev = float(ev[0]["t"]) if ev else math.nan
    qd, q = traj.qd[-1], traj.q[-1]
    err = errors(exact, t_ev, qd[:2], qd[3:6], q[:2])
    return {"t_event": t_ev, "events": [dict(e) for e in traj.events], "errors": err,
            "t_final": float(traj.t[-1]), "samples": len(traj.t),
            "energy_balance_relative": traj.diagnostics.get("energy_balance_relative")}


def bench_ours(repeat: int, quick: bool) -> dict:
    import nonideal
    from nonideal.modeling.modelfile import load_model

    out = {"first_call": {}, "cases": {}, "tolerances": []}
    # first call: parse + compile + first run, from a fresh model with every cache cleared
    firsts = []
    for _ in range(3):
        clear_library_caches()
        t0 = time.perf_counter()
        model = load_model(MODEL_FILE)
        t1 = time.perf_counter()
        from nonideal.simulation.hybrid import Simulation

        sim = Simulation(model)              # compiles the kernels
        t2 = time.perf_counter()
        sim.run(t_end=T_END)
        t3 = time.perf_counter()
        firsts.append((t1 - t0, t2 - t1, t3 - t2, t3 - t0))
    k = int(np.argsort([f[3] for f in firsts])[len(firsts) // 2])
    out["first_call"] = {"load_model": firsts[k][0], "compile": firsts[k][1], "first_run": firsts[k][2],
                         "total": firsts[k][3], "all_totals": [f[3] for f in firsts]}
    out["specialize"] = specialize_time(model)
    for key, case in CASES.items():
        exact = closed_form(case["v0"], case["w0"])
        init = initial_of(case)
        for _ in range(WARMUP):  # the kernels compiled, then the two mode systems
            nonideal.simulate(model, t_end=T_END, initial=init, every_step=True)
        med, best, times, traj = median_time(lambda: nonideal.simulate(model, t_end=T_END, initial=init,
                                                                       every_step=True), repeat)
        res = ours_measure(traj, exact)
        res.update(wall_median=med, wall_min=best, walls=times)
        med, best, _, ref = median_time(lambda: nonideal.simulate(model, t_end=T_END, initial=init,
                                                                 specialize=False, every_step=True), repeat)
        res.update(index_wall_median=med, index_wall_min=best,
                   index_agreement=float(np.max(np.abs(ref.qd[-1] - traj.qd[-1]))),
                   index_event_diff=abs(ours_measure(ref, exact)["t_event"] - res["t_event"]))
        out["cases"][key] = res
    # tolerance sweep (case b)
    case = CASES["b"]
    exact = closed_form(case["v0"], case["w0"])
    init = initial_of(case)
    for rtol in ((1e-10,) if quick else (1e-6, 1e-8, 1e-10, 1e-12)):
        atol = rtol * 1e-2
        fn = lambda: nonideal.simulate(model, t_end=T_END, initial=init, rtol=rtol, atol=atol, every_step=True)  # noqa: E731
        fn()
        med, best, _, traj = median_time(fn, max(3, repeat // 2))
        res = ours_measure(traj, exact)
        out["tolerances"].append({"rtol": rtol, "atol": atol, "wall_median": med, "wall_min": best,
                                  "errors": res["errors"], "samples": res["samples"]})
    out["model"] = model
    return out


def specialize_time(model) -> dict:
    """Compilation of the saddle-point systems of the two modes a run integrates (sliding with
    two slip components, rolling): what the library pays once per model when a mode is hot."""
    from nonideal.modes.system import ModeFunction, system_of
    from nonideal.modes.types import ContactState, Mode
    from nonideal.numeric.kernel import kernel_of

    kernel = kernel_of(model)
    out = {}
    for label, cs in (("sliding", ContactState("slide", (0.8, -0.6))), ("rolling", ContactState("stick"))):
        mode = Mode(frozenset(), (("plane", cs),))
        t0 = time.perf_counter()
        ModeFunction.of(kernel, system_of(kernel, mode), mode)
        out[label] = time.perf_counter() - t0
    return out


def cold_process(code: str) -> float | None:
    """Wall time of *code* in a fresh interpreter (import + build + first run)."""
    try:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                           cwd=ROOT)
        return float(r.stdout.strip().splitlines()[-1])
    except Exception:
        return None


COLD_OURS = f"""
import time; t0 = time.perf_counter()
import nonideal
from nonideal.modelfile import load_model
nonideal.simulate(load_model({str(MODEL_FILE)!r}), t_end={T_END})
print(time.perf_counter() - t0)
"""


def profile_ours(model, case: dict, runs: int = 30) -> dict:
    import nonideal

    init = initial_of(case)
    for _ in range(WARMUP):
        nonideal.simulate(model, t_end=T_END, initial=init)
    pr = cProfile.Profile()
    pr.enable()
    for _ in range(runs):
        nonideal.simulate(model, t_end=T_END, initial=init)
    pr.disable()
    st = pstats.Stats(pr, stream=io.StringIO())
    total = st.total_tt / runs
    rows = []
    for (file, line, fn), (cc, nc, tt, ct, _) in st.stats.items():
        short = f"{Path(file).name}:{line}({fn})" if "nonideal" in file or "scipy" in file else f"{fn}"
        rows.append({"function": short, "calls_per_run": nc / runs, "tottime_per_run": tt / runs,
                     "cumtime_per_run": ct / runs})
    cum = sorted(rows, key=lambda r: -r["cumtime_per_run"])[:25]
    own = sorted(rows, key=lambda r: -r["tottime_per_run"])[:15]
    return {"runs": runs, "total_per_run_profiled": total, "top_cumulative": cum, "top_own": own}


STAGES = ("right-hand side", "SciPy DOP853 steps (without the RHS)", "SciPy: solver set-up",
          "SciPy: dense output", "mode selection", "projection", "initial state and checks",
          "trajectory assembly")


def breakdown(makers: dict, case: dict, runs: int = 30) -> dict:
    """Where the wall time of a warm run goes, by stage (wall clock, no profiler): the
    library's and SciPy's functions are wrapped with timers for the duration of the
    measurement only; each stage's time is its own (nested timed stages subtracted: the
    SciPy stages exclude the right-hand side they call).  The simulations of *makers* (name
    -> factory) run alternately, one run each per round, after WARMUP runs; the stage times
    are medians over the fastest half of the rounds (the shares of a quiet run)."""
    import nonideal.simulation.hybrid as simmod
    from nonideal.simulation.trajectory import Trajectory
    from scipy.integrate import DOP853

    init = initial_of(case)
    acc = dict.fromkeys(STAGES, 0.0)
    calls = dict.fromkeys(STAGES, 0)
    stack: list[float] = []

    def timed(stage, fn):
        def wrapper(*a, **k):
            t0 = time.perf_counter()
            stack.append(0.0)
            try:
                return fn(*a, **k)
            finally:
                dt = time.perf_counter() - t0
                acc[stage] += dt - stack.pop()
                calls[stage] += 1
                if stack:
                    stack[-1] += dt
        return wrapper

    saved = [(simmod, "select_mode"), (simmod, "validate_state"), (Trajectory, "from_samples"),
             (DOP853, "step"), (DOP853, "__init__"), (DOP853, "dense_output")]
    saved = [(owner, name, owner.__dict__.get(name)) for owner, name in saved]  # None: inherited
    simmod.select_mode = timed("mode selection", simmod.select_mode)
    simmod.validate_state = timed("initial state and checks", simmod.validate_state)
    Trajectory.from_samples = classmethod(timed("trajectory assembly", Trajectory.__dict__["from_samples"].__func__))
    DOP853.step = timed("SciPy DOP853 steps (without the RHS)", DOP853.step)
    DOP853.__init__ = timed("SciPy: solver set-up", DOP853.__init__)
    DOP853.dense_output = timed("SciPy: dense output", DOP853.dense_output)
    samples = {name: [] for name in makers}
    try:
        for k in range(runs + WARMUP):
            for name, make in makers.items():
                for stage in STAGES:
                    acc[stage], calls[stage] = 0.0, 0
                sim = make()
                rhs = sim.rhs
                sim.rhs = lambda mode, rhs=rhs: timed("right-hand side", rhs(mode))
                sim._project = timed("projection", sim._project)
                sim.initial_state = timed("initial state and checks", sim.initial_state)
                t0 = time.perf_counter()
                sim.run(t_end=T_END, initial=init)
                total = time.perf_counter() - t0
                if k >= WARMUP:
                    samples[name].append((total, dict(acc), dict(calls)))
    finally:
        for owner, name, f in saved:
            if f is None:
                delattr(owner, name)
            else:
                setattr(owner, name, f)
    out = {}
    for name, runs_ in samples.items():
        fast = sorted(runs_, key=lambda r: r[0])[:max(3, len(runs_) // 2)]
        total = statistics.median(r[0] for r in fast)
        parts = {st: {"time_per_run": statistics.median(r[1][st] for r in fast),
                      "calls_per_run": fast[0][2][st]} for st in STAGES}
        rest = total - sum(p["time_per_run"] for p in parts.values())
        parts["events, motions, the hybrid loop (rest)"] = {"time_per_run": rest, "calls_per_run": None}
        out[name] = {"total_per_run": total, "parts": parts}
    return out


# ============================================================================ 3. regularized


def speed_of(slip) -> np.ndarray:
    return np.linalg.norm(np.asarray(slip, float).reshape(len(slip), -1), axis=1)


def bench_regularized(model, eps_list, methods, repeat: int) -> list[dict]:
    import nonideal
    from nonideal.analysis.contact.realizability import regularized

    out = []
    grid = np.linspace(0.0, T_END, 2001)
    for eps in eps_list:
        reg = regularized(model, eps, law="smooth")
        for method in methods:
            t0 = time.perf_counter()
            try:
                nonideal.simulate(reg, t_end=T_END, initial=initial_of(CASES["a"]), method=method,
                                  rtol=1e-8, atol=1e-10)
            except Exception as exc:  # report, do not hide
                out.append({"eps": eps, "method": method, "error": repr(exc)})
                continue
            first = time.perf_counter() - t0
            for key, case in CASES.items():
                exact = closed_form(case["v0"], case["w0"])
                init = initial_of(case)
                fn = lambda: nonideal.simulate(reg, t_end=T_END, initial=init, method=method,  # noqa: E731
                                               rtol=1e-8, atol=1e-10)
                med, best, _, traj = median_time(fn, repeat)
                dense = nonideal.simulate(reg, times=grid, initial=init, method=method, rtol=1e-8, atol=1e-10)
                est = slip_time_estimates(dense.t, speed_of(dense.contacts["plane"]["slip"]),
                                          np.linalg.norm(exact["U0"]))
                qd, q = traj.qd[-1], traj.q[-1]
                err = errors(exact, est["extrapolated"], qd[:2], qd[3:6], q[:2])
                err["t_star_threshold"] = abs(est["threshold"] - exact["t_star"]) / exact["t_star"]
                out.append({"eps": eps, "method": method, "case": key, "first_call": first,
                            "wall_median": med, "wall_min": best, "samples": len(traj.t),
                            "t_star_estimates": est, "errors": err})
    return out


def sphere_rhs(eps):
    k = 2.5 / R

    def rhs(t, y):  # y = [x, y, vx, vy, wx, wy]; planar motion, N = m g
        vx, vy, wx, wy = y[2], y[3], y[4], y[5]
        ux, uy = vx - R * wy, vy + R * wx
        s = math.hypot(ux, uy)
        f = MU * G * (math.tanh(s / eps) / s if s > 1e-300 else 1.0 / eps)
        ax, ay = -f * ux, -f * uy
        return [vx, vy, ax, ay, k * ay, -k * ax]
    return rhs


def bench_handwritten(eps_list, methods, repeat: int) -> list[dict]:
    out = []
    grid = np.linspace(0.0, T_END, 2001)
    for eps in eps_list:
        rhs = sphere_rhs(eps)
        for method in methods:
            for key, case in CASES.items():
                exact = closed_form(case["v0"], case["w0"])
                v0, w0 = case["v0"], case["w0"]
                y0 = [0.0, 0.0, v0[0], v0[1], w0[0], w0[1]]
                fn = lambda: solve_ivp(rhs, (0.0, T_END), y0, method=method, rtol=1e-8, atol=1e-10)  # noqa: E731
                med, best, _, sol = median_time(fn, repeat)
                if not sol.success:
                    out.append({"eps": eps, "method": method, "case": key, "error": sol.message})
                    continue
                dense = solve_ivp(rhs, (0.0, T_END), y0, method=method, rtol=1e-8, atol=1e-10, t_eval=grid)
                Y = dense.y
                U = np.stack([Y[2] - R * Y[5], Y[3] + R * Y[4]])
                est = slip_time_estimates(dense.t, np.linalg.norm(U, axis=0), np.linalg.norm(exact["U0"]))
                yT = sol.y[:, -1]
                err = errors(exact, est["extrapolated"], yT[2:4], [yT[4], yT[5], w0[2]], yT[0:2])
                err["t_star_threshold"] = abs(est["threshold"] - exact["t_star"]) / exact["t_star"]
                out.append({"eps": eps, "method": method, "case": key, "wall_median": med, "wall_min": best,
                            "rhs_calls": int(sol.nfev), "samples": len(sol.t), "t_star_estimates": est,
                            "errors": err})
    return out


# ============================================================================ 2. MuJoCo


def mujoco_or_none():
    try:
        import mujoco
        from mujoco import rollout  # noqa: F401

        return mujoco
    except Exception as exc:  # not installed in this interpreter
        return exc


MJ_SETTINGS = {
    "default": lambda dt: {},
    "impratio10": lambda dt: {"impratio": 10},
    # harder contact: smaller time constant, impedance close to 1 (less penetration and creep)
    "hard": lambda dt: {"solref": (0.005, 1.0), "solimp": (0.99, 0.999, 0.001)},
    # the stiffest time constant MuJoCo accepts at this timestep (solref >= 2 dt)
    "stiffest": lambda dt: {"solref": (2 * dt, 1.0), "solimp": (0.99, 0.999, 0.001)},
}


def mjcf(dt, cone, impratio=1.0, solref=None, solimp=None) -> str:
    """The sphere on the plane: free joint, exact inertia, sliding friction only, condim 3
    (MuJoCo clamps the unused torsional/rolling coefficients to 1e-5; condim 3 ignores them)."""
    I = 0.4 * M * R * R
    sr = f' solref="{solref[0]:.17g} {solref[1]:.17g}"' if solref else ""
    si = f' solimp="{" ".join(f"{v:.17g}" for v in solimp)}"' if solimp else ""
    return f"""<mujoco model="sphere on plane">
  <option timestep="{dt:.17g}" gravity="0 0 {-G}" cone="{cone}" impratio="{impratio:.17g}"/>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" friction="{MU} 0 0" condim="3"{sr}{si}/>
    <body name="ball" pos="0 0 {R}">
      <freejoint/>
      <inertial pos="0 0 0" mass="{M}" diaginertia="{I:.17g} {I:.17g} {I:.17g}"/>
      <geom name="sphere" type="sphere" size="{R}" friction="{MU} 0 0" condim="3"{sr}{si}/>
    </body>
  </worldbody>
</mujoco>"""


def _quat_rotate(q, v):
    w, u = q[..., :1], q[..., 1:4]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


class MujocoSphere:
    """One MuJoCo configuration: compiled model, the settled initial state of a case."""

    def __init__(self, mujoco, dt, cone, settings: dict):
        self.mj = mujoco
        t0 = time.perf_counter()
        self.model = mujoco.MjModel.from_xml_string(mjcf(dt, cone, **settings))
        self.compile_time = time.perf_counter() - t0
        self.data = mujoco.MjData(self.model)
        self.dt = dt
        self.spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        self.nstate = mujoco.mj_stateSize(self.model, self.spec)
        # settle at rest into the soft contact (no landing transient in the measurement)
        mujoco.mj_resetData(self.model, self.data)
        for _ in range(int(round(0.5 / dt))):
            mujoco.mj_step(self.model, self.data)
        self.settled_qpos = self.data.qpos.copy()
        self.penetration_at_rest = float(R - self.data.qpos[2])

    def initial_state(self, case: dict) -> np.ndarray:
        mj, d = self.mj, self.data
        d.qpos[:] = self.settled_qpos
        d.qpos[0:2] = 0.0
        d.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
        d.qvel[:] = 0.0
        d.qvel[0:3] = case["v0"]
        d.qvel[3:6] = case["w0"]        # body frame = world frame at t = 0
        d.time = 0.0
        d.qacc_warmstart[:] = 0.0
        mj.mj_forward(self.model, d)
        s = np.empty(self.nstate)
        mj.mj_getState(self.model, d, s, self.spec)
        return s

    def rollout(self, state0: np.ndarray, nstep: int) -> np.ndarray:
        from mujoco import rollout

        st, _ = rollout.rollout(self.model, self.data, state0[None, :], nstep=nstep)
        return st[0]

    def python_loop(self, state0: np.ndarray, nstep: int) -> np.ndarray:
        mj, m, d = self.mj, self.model, self.data
        mj.mj_setState(m, d, state0, self.spec)
        out = np.empty((nstep, 14))
        for k in range(nstep):
            mj.mj_step(m, d)
            out[k, 0] = d.time
            out[k, 1:8] = d.qpos
            out[k, 8:14] = d.qvel
        return out

    @staticmethod
    def kinematics(states: np.ndarray):
        """t, slip at the contact point, centre velocity, world angular velocity, position."""
        t = states[:, 0]
        qpos, qvel = states[:, 1:8], states[:, 8:14]
        w = _quat_rotate(qpos[:, 3:7], qvel[:, 3:6])
        lever = 0.5 * (R + qpos[:, 2])     # centre to the contact point (mid-penetration)
        U = np.stack([qvel[:, 0] - lever * w[:, 1], qvel[:, 1] + lever * w[:, 0]], axis=1)
        return t, U, qvel[:, 0:3], w, qpos[:, 0:3]


def bench_mujoco(mujoco, dts, cones, settings, repeat: int, loop_dts) -> list[dict]:
    out = []
    for cone in cones:
        for dt in dts:
            for sname in settings:
                cfg = MJ_SETTINGS[sname](dt)
                sph = MujocoSphere(mujoco, dt, cone, cfg)
                nstep = int(round(T_END / dt))
                for key, case in CASES.items():
                    exact = closed_form(case["v0"], case["w0"])
                    s0 = sph.initial_state(case)
                    reps = repeat if dt >= 1e-4 else max(3, repeat // 3)
                    med, best, _, states = median_time(lambda: sph.rollout(s0, nstep), reps)
                    t, U, v, w, pos = sph.kinematics(states)
                    est = slip_time_estimates(t, np.linalg.norm(U, axis=1), np.linalg.norm(exact["U0"]))
                    err = errors(exact, est["extrapolated"], v[-1, :2], w[-1], pos[-1, :2])
                    err["t_star_threshold"] = (abs(est["threshold"] - exact["t_star"]) / exact["t_star"]
                                               if np.isfinite(est["threshold"]) else None)
                    row = {"cone": cone, "dt": dt, "settings": sname, "params": cfg, "case": key,
                           "compile": sph.compile_time, "steps": nstep, "wall_median": med, "wall_min": best,
                           "t_star_estimates": est, "errors": err,
                           "penetration_at_rest": sph.penetration_at_rest,
                           "final_slip": float(np.linalg.norm(U[-1])), "t_final": float(t[-1]),
                           "max_lift": float(np.max(pos[:, 2]) - R)}
                    if dt in loop_dts and sname == "default":
                        lmed, lbest, _, lst = median_time(lambda: sph.python_loop(s0, nstep), max(3, repeat // 3))
                        row["python_loop_wall_median"] = lmed
                        row["python_loop_agrees"] = bool(np.allclose(lst[:, 1:], states[:, 1:14], rtol=0, atol=1e-12))
                    out.append(row)
    return out


# ============================================================================ report


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer settings and repeats (< 1 min)")
    ap.add_argument("--no-mujoco", action="store_true", help="skip MuJoCo even if importable")
    ap.add_argument("--repeat", type=int, default=None, help="runs per wall-time median")
    ap.add_argument("--report", action="store_true",
                    help="only regenerate the tables of RESULTS.md's friction section from results/friction_sphere.json")
    args = ap.parse_args(argv)
    if args.report:
        write_report(HERE / "RESULTS.md")
        return 0
    t_start = time.perf_counter()
    quick = args.quick
    repeat = args.repeat or (7 if quick else 21)

    mj = None if args.no_mujoco else mujoco_or_none()
    mj_ok = mj is not None and not isinstance(mj, Exception)
    mj_reason = ("--no-mujoco" if args.no_mujoco else f"not importable here ({mj!r}); see "
                 "benchmarks/README.md for the venv") if not mj_ok else None
    info = machine(mj.__version__ if mj_ok else None)
    print(f"# Friction benchmark: sphere launched sliding on a plane ({'quick' if quick else 'full'})")
    print(f"{info['date']}; {info['nproc']} x {info['cpu']}; Python {info['versions']['python']}; "
          f"nonideal {info['versions']['nonideal']} ({info['git_commit']}); numpy {info['versions']['numpy']}; "
          f"scipy {info['versions']['scipy']}; symengine {info['versions']['symengine']}; "
          f"MuJoCo {info['versions']['mujoco'] or 'skipped: ' + mj_reason}; load average "
          f"{info['loadavg_start'][0]:.2f}; library files modified in the working tree: "
          f"{', '.join(info['library_modified'] or []) or 'none'}")
    for key, case in CASES.items():
        ex = closed_form(case["v0"], case["w0"])
        print(f"  {case['title']}: v0 = {case['v0']}, w0 = {case['w0']}, U0 = {tuple(map(float, ex['U0']))}, "
              f"t* = {ex['t_star']:.15g}, v_f = {tuple(round(float(v), 12) for v in ex['v_f'])}")

    result = {"machine": info, "quick": quick, "repeat": repeat, "T": T_END,
              "parameters": {"m": M, "R": R, "g": G, "mu": MU}, "goal_relative": GOAL,
              "cases": {k: {**c, **{kk: (vv.tolist() if isinstance(vv, np.ndarray) else vv)
                                    for kk, vv in closed_form(c["v0"], c["w0"]).items()}}
                        for k, c in CASES.items()},
              "estimators": {"extrapolated": f"zero of the least-squares line through |U| in {FIT_WINDOW} |U0|",
                             "threshold": f"first |U| < {THRESHOLD:g} |U0|"}}

    # ---- ours
    t0 = time.perf_counter()
    ours = bench_ours(repeat, quick)
    model = ours.pop("model")
    ours["cold_process"] = cold_process(COLD_OURS)
    result["ours"] = ours
    print(f"\n## ours ({time.perf_counter() - t0:.1f} s)")
    fc = ours["first_call"]
    print(f"first call (fresh model, caches cleared): load {fmt_t(fc['load_model'])}, compile "
          f"{fmt_t(fc['compile'])}, first run {fmt_t(fc['first_run'])}, total {fmt_t(fc['total'])}; "
          f"cold process (import + all) {fmt_t(ours['cold_process'])}")
    rows = []
    for key, r in ours["cases"].items():
        e = r["errors"]
        rows.append([key, f"{r['t_event']:.15g}", fmt_e(e["t_star"]), fmt_e(e["velocity"]),
                     fmt_e(e["angular_velocity"]), fmt_e(e["position"]), fmt_t(r["wall_median"]),
                     fmt_t(r["wall_min"]), r["samples"]])
    print(table(["case", "slip-stop t", "err t*", "err v(T)", "err w(T)", "err r(T)", "wall (median)",
                 "wall (min)", "samples"], rows))
    if len(ours["tolerances"]) > 1:
        print("\ntolerance sweep, case (b):")
        print(table(["rtol", "atol", "err t*", "err v(T)", "err r(T)", "wall (median)"],
                    [[f"{r['rtol']:g}", f"{r['atol']:g}", fmt_e(r["errors"]["t_star"]), fmt_e(r["errors"]["velocity"]),
                      fmt_e(r["errors"]["position"]), fmt_t(r["wall_median"])] for r in ours["tolerances"]]))

    # ---- MuJoCo
    if mj_ok:
        t0 = time.perf_counter()
        dts = (1e-3, 1e-4) if quick else (2e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)
        settings = ("default", "hard") if quick else ("default", "impratio10", "hard", "stiffest")
        mres = bench_mujoco(mj, dts, ("elliptic", "pyramidal"), settings, max(3, repeat // 2 if quick else repeat // 3),
                            loop_dts=(1e-3, 1e-4) if quick else (2e-3, 1e-3, 1e-4))
        cold = cold_process(
            "import time; t0 = time.perf_counter()\n"
            "import mujoco\n"
            f"m = mujoco.MjModel.from_xml_string({mjcf(1e-3, 'elliptic')!r})\n"
            "d = mujoco.MjData(m); d.qvel[0] = 2.0\n"
            f"for _ in range({int(round(T_END / 1e-3))}): mujoco.mj_step(m, d)\n"
            "print(time.perf_counter() - t0)")
        compiles = [r["compile"] for r in mres]
        result["mujoco"] = {"runs": mres, "version": mj.__version__, "cold_process_dt_1e-3": cold,
                            "compile_median": statistics.median(compiles)}
        print(f"\n## MuJoCo {mj.__version__} ({time.perf_counter() - t0:.1f} s)")
        print(f"model compile (from_xml_string) {fmt_t(result['mujoco']['compile_median'])} (median); cold "
              f"process (import + compile + 1000 mj_step, dt 1e-3) {fmt_t(cold)}")
        rows = []
        for r in mres:
            e = r["errors"]
            rows.append([r["case"], r["cone"], f"{r['dt']:g}", r["settings"], fmt_e(e["t_star"]),
                         fmt_e(e["t_star_threshold"]), fmt_e(e["velocity"]), fmt_e(e["position"]),
                         fmt_t(r["wall_median"]), fmt_t(r.get("python_loop_wall_median")),
                         f"{r['penetration_at_rest']:.1e}", f"{r['max_lift']:.1e}"])
        print(table(["case", "cone", "dt", "contact", "err t* (extrap.)", "err t* (thresh.)", "err v(T)",
                     "err r(T)", "wall rollout", "wall py loop", "penetration", "max lift"], rows))
    else:
        result["mujoco"] = {"skipped": mj_reason}
        print(f"\n## MuJoCo skipped: {mj_reason}")

    # ---- regularized
    t0 = time.perf_counter()
    eps_list = (1e-2, 1e-4) if quick else (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
    methods = ("Radau", "LSODA")
    reg = bench_regularized(model, eps_list, methods, max(3, repeat // 3))
    hand = bench_handwritten(eps_list, methods, max(3, repeat // 3))
    result["regularized"] = reg
    result["handwritten"] = hand
    print(f"\n## regularized friction ({time.perf_counter() - t0:.1f} s; rtol 1e-8, atol 1e-10)")
    rows = []
    for label, runs in (("ours regularized(smooth)", reg), ("solve_ivp tanh by hand", hand)):
        for r in runs:
            if "error" in r:
                rows.append([r.get("case", "-"), label, f"{r['eps']:g}", r["method"], "failed: " + r["error"][:40],
                             "", "", "", "", ""])
                continue
            e = r["errors"]
            rows.append([r["case"], label, f"{r['eps']:g}", r["method"], fmt_e(e["t_star"]),
                         fmt_e(e["t_star_threshold"]), fmt_e(e["velocity"]), fmt_e(e["position"]),
                         fmt_t(r["wall_median"]), r["samples"]])
    rows.sort(key=lambda x: (x[0], x[1], x[3]))
    print(table(["case", "model", "eps", "method", "err t* (extrap.)", "err t* (thresh.)", "err v(T)",
                 "err r(T)", "wall (median)", "steps"], rows))

    # ---- head to head (round robin) and summary
    t0 = time.perf_counter()
    grid = {(r["cone"], r["dt"], r["settings"]) for r in result["mujoco"].get("runs", [])}
    configs = [c for c in H2H_MUJOCO if c in grid]
    result["h2h_rounds"] = 5 if quick else 25
    result["head_to_head"] = {key: head_to_head(model, mj if mj_ok else None, key, result["h2h_rounds"],
                                                configs) for key in CASES}
    print(f"\n(head to head, round robin: {time.perf_counter() - t0:.1f} s)")
    summary = summarize(result)
    result["summary"] = summary
    print("\n## summary (wall: round-robin medians; (*) from the sweep, not interleaved)")
    print(table(["case", "run", "wall (median)", "wall (min)", "err t* (extrap.)", "err t* (thresh.)",
                 "err v(T)", "err r(T)", "ours/peer (median)", "ours/peer (min)"], summary["rows"]))
    for line in summary["goal"]:
        print("* " + line)

    # ---- profile and stages
    t0 = time.perf_counter()
    result["profile"] = profile_ours(model, CASES["b"], runs=10 if quick else 30)
    from nonideal.simulation.hybrid import Simulation

    makers = {"warm": lambda: Simulation(model), "index path": lambda: Simulation(model, specialize=False)}
    result["breakdown"] = breakdown(makers, CASES["b"], 10 if quick else 40)
    print(f"\n## profile of ours, case (b) ({time.perf_counter() - t0:.1f} s)")
    print(table(["function", "calls/run", "own/run", "cum/run"],
                [[r["function"], f"{r['calls_per_run']:.0f}", fmt_t(r["tottime_per_run"]), fmt_t(r["cumtime_per_run"])]
                 for r in result["profile"]["top_cumulative"][:18]]))
    bd = result["breakdown"]
    names = list(bd["warm"]["parts"])
    print("\nwall time of a run by stage, case (b) (timers, no profiler):")
    print(table(["stage"] + [f"{k} ({fmt_t(v['total_per_run'])})" for k, v in bd.items()] + ["calls/run"],
                [[p] + [fmt_t(v["parts"][p]["time_per_run"]) for v in bd.values()]
                 + [fmt_r(bd["warm"]["parts"][p]["calls_per_run"])] for p in names]))

    info["loadavg_end"] = list(os.getloadavg())
    info["wall_total"] = time.perf_counter() - t_start
    path = RESULTS / ("friction_sphere-quick.json" if quick else "friction_sphere.json")
    RESULTS.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(result, indent=1, default=_jsonable))
    print(f"\nwrote {path.relative_to(ROOT)}")
    return 0


H2H_MUJOCO = (("elliptic", 2e-3, "default"), ("elliptic", 1e-3, "default"), ("elliptic", 1e-4, "default"),
              ("elliptic", 1e-4, "hard"))
H2H_EPS = 1e-4


H2H_BLOCK = 3  # timed runs of a contestant per round, after one untimed run


def head_to_head(model, mj, key: str, rounds: int, mj_configs) -> dict:
    """Wall times measured round-robin, so that the load of a shared machine hits every
    contestant alike; the ratios of the summary come from here.  Every contestant runs
    WARMUP times first; then each round runs each contestant once untimed and H2H_BLOCK times
    timed (medians and minima over all timed runs): the first run after another contestant
    pays for the caches the other one took (measured: ~0.4 ms of a 2.5 ms run of ours after
    a MuJoCo rollout) -- a user runs one simulator at a time."""
    import nonideal
    from nonideal.analysis.contact.realizability import regularized

    case = CASES[key]
    init = initial_of(case)
    contestants = [("ours", {"kind": "ours"}, lambda: nonideal.simulate(model, t_end=T_END, initial=init)),
                   ("ours, index path (specialize=False)", {"kind": "ours"},
                    lambda: nonideal.simulate(model, t_end=T_END, initial=init, specialize=False))]
    if mj is not None:
        for cone, dt, sname in mj_configs:
            sph = MujocoSphere(mj, dt, cone, MJ_SETTINGS[sname](dt))
            s0, nstep = sph.initial_state(case), int(round(T_END / dt))
            contestants.append((f"MuJoCo {cone}, {sname} contact, dt {dt:g}",
                                {"kind": "mujoco", "cone": cone, "dt": dt, "settings": sname},
                                lambda sph=sph, s0=s0, nstep=nstep: sph.rollout(s0, nstep)))
    reg = regularized(model, H2H_EPS, law="smooth")
    contestants.append((f"ours regularized(smooth), eps {H2H_EPS:g}, LSODA",
                        {"kind": "regularized", "eps": H2H_EPS, "method": "LSODA"},
                        lambda: nonideal.simulate(reg, t_end=T_END, initial=init, method="LSODA", rtol=1e-8,
                                                  atol=1e-10)))
    rhs = sphere_rhs(H2H_EPS)
    y0 = [0.0, 0.0, case["v0"][0], case["v0"][1], case["w0"][0], case["w0"][1]]
    contestants.append((f"solve_ivp tanh by hand, eps {H2H_EPS:g}, LSODA",
                        {"kind": "handwritten", "eps": H2H_EPS, "method": "LSODA"},
                        lambda: solve_ivp(rhs, (0.0, T_END), y0, method="LSODA", rtol=1e-8, atol=1e-10)))
    times = {name: [] for name, _, _ in contestants}
    for _, _, fn in contestants:
        for _ in range(WARMUP):
            fn()
    gc.collect()
    for _ in range(rounds):
        for name, _, fn in contestants:
            fn()
            for _ in range(H2H_BLOCK):
                t0 = time.perf_counter()
                fn()
                times[name].append(time.perf_counter() - t0)
    return {name: {"config": cfg, "wall_median": statistics.median(times[name]), "wall_min": min(times[name]),
                   "walls": times[name]} for name, cfg, _ in contestants}


def _errors_of(result: dict, key: str, cfg: dict):
    kind = cfg["kind"]
    if kind == "ours":
        return result["ours"]["cases"][key]["errors"]
    runs = {"mujoco": result.get("mujoco", {}).get("runs", []), "regularized": result["regularized"],
            "handwritten": result["handwritten"]}[kind]
    for r in runs:
        if r.get("case") == key and all(r.get(k) == v for k, v in cfg.items() if k != "kind") and "errors" in r:
            return r["errors"]
    return None


def _worst(err: dict) -> float:
    """The error that decides 'most accurate': the worse of the event time and the velocity."""
    return max(err["t_star"] if err["t_star"] is not None else 1.0, err["velocity"])


def summarize(result: dict) -> dict:
    """Headline: the round-robin wall times (``head_to_head``) with each run's errors; then the
    most accurate MuJoCo runs of the sweep (their own medians, not interleaved)."""
    rows, goal, peers = [], [], {}
    mj = result.get("mujoco", {}).get("runs", [])
    for key in CASES:
        h2h = result["head_to_head"][key]
        ow = h2h["ours"]["wall_median"]
        for name, r in h2h.items():
            e = _errors_of(result, key, r["config"]) or {}
            rows.append([key, name, fmt_t(r["wall_median"]), fmt_t(r["wall_min"]), fmt_e(e.get("t_star")),
                         fmt_e(e.get("t_star_threshold")), fmt_e(e.get("velocity")), fmt_e(e.get("position")),
                         fmt_r(ow / r["wall_median"]), fmt_r(h2h["ours"]["wall_min"] / r["wall_min"])])
            peers.setdefault(key, []).append({"label": name, "interleaved": True, "wall_median": r["wall_median"],
                                              "errors": e, "ratio_ours_over_peer": ow / r["wall_median"]})
        for cone in ("elliptic", "pyramidal"):
            runs = [r for r in mj if r["case"] == key and r["cone"] == cone]
            if runs:
                best = min(runs, key=lambda r: _worst(r["errors"]))
                e = best["errors"]
                name = f"MuJoCo {cone}, most accurate of the sweep: {best['settings']}, dt {best['dt']:g} (*)"
                rows.append([key, name, fmt_t(best["wall_median"]), fmt_t(best["wall_min"]), fmt_e(e["t_star"]),
                             fmt_e(e.get("t_star_threshold")), fmt_e(e["velocity"]), fmt_e(e["position"]),
                             fmt_r(ow / best["wall_median"]), fmt_r(h2h["ours"]["wall_min"] / best["wall_min"])])
                peers[key].append({"label": name, "interleaved": False, "wall_median": best["wall_median"],
                                   "errors": e, "ratio_ours_over_peer": ow / best["wall_median"]})
    ours = result["ours"]["cases"]
    worst = max(_worst(ours[k]["errors"]) for k in CASES)
    goal.append(f"accuracy (event time and velocity within {GOAL:g} relative, both cases): "
                f"{'MET' if worst <= GOAL else 'NOT met'} (worst {worst:.1e})")
    for key in CASES:
        h2h = result["head_to_head"][key]
        ow = h2h["ours"]["wall_median"]
        mjr = {n: r for n, r in h2h.items() if r["config"]["kind"] == "mujoco"}
        if not mjr:
            goal.append(f"case {key}: wall time vs MuJoCo not measured (MuJoCo skipped)")
            continue
        faster = [f"{n} ({fmt_t(r['wall_median'])}, ours/MuJoCo {ow / r['wall_median']:.2g})"
                  for n, r in mjr.items() if r["wall_median"] < ow]
        slower = [f"{n} ({fmt_t(r['wall_median'])}, ours/MuJoCo {ow / r['wall_median']:.2g})"
                  for n, r in mjr.items() if r["wall_median"] >= ow]
        goal.append(f"case {key}: ours {fmt_t(ow)} (interleaved median); no worse than "
                    f"{'; '.join(slower) or 'none'}; WORSE than {'; '.join(faster) or 'none'}")
        ell = [r for r in mj if r["case"] == key and r["cone"] == "elliptic"]
        if ell:
            reach = [r for r in ell if _worst(r["errors"]) <= GOAL]
            best = min(ell, key=lambda r: _worst(r["errors"]))
            goal.append(f"case {key}: MuJoCo (elliptic) reaches {GOAL:g} at {len(reach)} of {len(ell)} settings; "
                        f"its best: t* {fmt_e(best['errors']['t_star'])}, v {fmt_e(best['errors']['velocity'])} "
                        f"(dt {best['dt']:g}, {best['settings']}, {fmt_t(best['wall_median'])})")
    return {"rows": rows, "goal": goal, "peers": peers}


BEGIN, END = "<!-- BEGIN friction_sphere -->", "<!-- END friction_sphere -->"


def render(result: dict) -> str:
    """The measured tables of the RESULTS.md section (between its markers), from the JSON."""
    m = result["machine"]
    v = m["versions"]
    out = [f"* run {m['date']}, {m.get('wall_total', 0):.0f} s; machine: {m['nproc']} cores (`nproc`), CPU "
           f"`{m['cpu']}`, {m['platform']}; load average {m['loadavg_start'][0]:.2f} at the start, "
           f"{m.get('loadavg_end', [math.nan])[0]:.2f} at the end (shared machine)",
           f"* versions: Python {v['python']}, nonideal {v['nonideal']} (git {m['git_commit']}"
           f"{', library files modified in the working tree' if m.get('library_modified') else ''}), "
           f"NumPy {v['numpy']}, SciPy {v['scipy']}, SymEngine {v['symengine']} (LLVM: {m['symengine_llvm']}), "
           f"MuJoCo {v['mujoco'] or 'skipped'}", ""]
    out.append(f"**Head to head** (wall: round robin, {result.get('h2h_rounds', '?')} rounds, each contestant "
               f"once untimed then {H2H_BLOCK} times timed per round, after {WARMUP} warm-up runs; median and "
               "minimum over the timed runs; (*) = the most accurate run of the MuJoCo sweep, its own median):\n")
    rows = [r for r in result["summary"]["rows"]]
    out.append(table(["case", "run", "wall (median)", "wall (min)", "err t* (extrap.)", "err t* (thresh.)",
                      "err v(T)", "err r(T)", "ours/peer (median)", "ours/peer (min)"], rows))
    out.append("")
    o = result["ours"]
    fc = o["first_call"]
    sp = o.get("specialize", {})
    out.append(f"**Ours**: first call from a fresh model (caches cleared): parse {fmt_t(fc['load_model'])}, "
               f"compile {fmt_t(fc['compile'])}, first run {fmt_t(fc['first_run'])}, total {fmt_t(fc['total'])}; "
               f"cold process (`import nonideal` + all) {fmt_t(o.get('cold_process'))}; compiling the two "
               f"mode systems once they are hot: sliding {fmt_t(sp.get('sliding'))}, rolling "
               f"{fmt_t(sp.get('rolling'))}. Warm runs (own medians, not interleaved): "
               + "; ".join(f"({k}) {fmt_t(c['wall_median'])}, index path {fmt_t(c['index_wall_median'])}, "
                           f"the two agree to {c['index_agreement']:.0e} (final velocity), "
                           f"{c['index_event_diff']:.0e} (event time)" for k, c in o["cases"].items())
               + ". Tolerance sweep, case (b):\n")
    out.append(table(["rtol", "atol", "err t*", "err v(T)", "err r(T)", "wall (median)"],
                     [[f"{r['rtol']:g}", f"{r['atol']:g}", fmt_e(r["errors"]["t_star"]), fmt_e(r["errors"]["velocity"]),
                       fmt_e(r["errors"]["position"]), fmt_t(r["wall_median"])] for r in o["tolerances"]]))
    out.append("")
    mj = result.get("mujoco", {})
    if "runs" in mj:
        out.append(f"**MuJoCo {mj['version']}** sweep (rollout wall time: minimum of the repeats -- the medians, "
                   "in the JSON, carry the machine's load; model compile "
                   f"{fmt_t(mj['compile_median'])}, cold process with import "
                   f"{fmt_t(mj.get('cold_process_dt_1e-3'))}). `lift` = highest the centre rose above R "
                   "(the ball hops), `pen.` = penetration at rest:\n")
        runs = mj["runs"]
        for cone in ("elliptic", "pyramidal"):
            rows = []
            keys = sorted({(r["settings"], r["dt"]) for r in runs if r["cone"] == cone},
                          key=lambda k: (list(MJ_SETTINGS).index(k[0]), -k[1]))
            for sname, dt in keys:
                ra = next(r for r in runs if (r["cone"], r["settings"], r["dt"], r["case"]) == (cone, sname, dt, "a"))
                rb = next(r for r in runs if (r["cone"], r["settings"], r["dt"], r["case"]) == (cone, sname, dt, "b"))
                rows.append([cone, sname, f"{dt:g}", fmt_t(rb["wall_min"]), fmt_t(rb.get("python_loop_wall_median")),
                             fmt_e(ra["errors"]["t_star"]), fmt_e(ra["errors"]["velocity"]),
                             fmt_e(rb["errors"]["t_star"]), fmt_e(rb["errors"]["t_star_threshold"]),
                             fmt_e(rb["errors"]["velocity"]), fmt_e(rb["errors"]["position"]),
                             f"{rb['penetration_at_rest']:.0e}", f"{rb['max_lift']:.0e}"])
            out.append(table(["cone", "contact", "dt", "wall (b, min)", "py loop (b, median)", "(a) err t*", "(a) err v",
                              "(b) err t*", "(b) err t* thresh.", "(b) err v", "(b) err r", "pen.", "lift (b)"], rows))
            out.append("")
    else:
        out.append(f"MuJoCo skipped: {mj.get('skipped')}\n")
    out.append("**Regularized friction**, case (b) (case (a) alike; rtol 1e-8, atol 1e-10):\n")
    rows = []
    for label, runs in (("ours `regularized(smooth)`", result["regularized"]), ("`solve_ivp`, tanh by hand", result["handwritten"])):
        for r in runs:
            if r.get("case") != "b" or "errors" not in r:
                continue
            e = r["errors"]
            rows.append([label, f"{r['eps']:g}", r["method"], fmt_t(r["wall_min"]), fmt_e(e["t_star"]),
                         fmt_e(e["t_star_threshold"]), fmt_e(e["velocity"]), fmt_e(e["position"]), r["samples"]])
    out.append(table(["model", "eps", "method", "wall (min)", "err t* (extrap.)", "err t* (thresh.)", "err v(T)",
                      "err r(T)", "steps"], rows))
    out.append("")
    bd = result.get("breakdown")
    if bd:
        first = next(iter(bd.values()))
        names = list(first["parts"])
        out.append("**Where a run of ours goes**, case (b) (timers around the stages, no profiler; own "
                   "times, medians over the fastest half of the interleaved rounds):\n")
        out.append(table(["stage"] + [f"{k} ({fmt_t(x['total_per_run'])})" for k, x in bd.items()] + ["calls/run"],
                         [[p] + [fmt_t(x["parts"][p]["time_per_run"]) for x in bd.values()]
                          + [fmt_r(first["parts"][p]["calls_per_run"])] for p in names]))
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def write_report(path: Path) -> None:
    """Regenerate the tables between the markers of the friction section of RESULTS.md."""
    result = json.loads((RESULTS / "friction_sphere.json").read_text())
    text = path.read_text()
    if BEGIN not in text or END not in text:
        print(render(result))
        return
    a, b = text.index(BEGIN) + len(BEGIN), text.index(END)
    path.write_text(text[:a] + "\n" + render(result) + text[b:])
    print(f"updated {path}")


def _jsonable(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (set, frozenset, tuple)):
        return list(x)
    return str(x)


if __name__ == "__main__":
    sys.exit(main())
