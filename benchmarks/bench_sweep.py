"""Sweep benchmark: a 10 000-point parameter study of the sphere launched sliding on a rough
plane (``benchmarks/friction_sphere.toml``), as points per second per core.

Run::

    python benchmarks/bench_sweep.py            # 10 000 points (100 mu x 100 R), ~1-3 min on 2 cores
    python benchmarks/bench_sweep.py --quick    # 1 000 points

Measured side by side in one process (the CLI loop in subprocesses, as a user would run it):

1. **CLI loop** -- ``nonideal simulate friction_sphere.toml --set mu=.. --set R=.. --json
   /dev/null`` per point, a few points timed and extrapolated (every call starts Python,
   imports the library, reads, derives and compiles the model);
2. **API loop** -- the loop a user writes in Python: per point ``load_model(path,
   parameters=...)`` and ``simulate(model)`` (a new model object per point: derived and
   compiled again each time), a few hundred points timed;
3. **sweep** -- ``nonideal.analysis.studies.sweep.sweep(path, axes, "simulate", workers=N)``: the model
   derived and compiled once per worker, each point one simulation with its numbers; all
   points, on ``N = os.cpu_count()`` local processes and on one;
4. **Dask** -- the same sweep through a ``distributed.LocalCluster`` (the ``--scheduler`` path)
   on a subset: the rows must equal the local ones.

Every sweep row is checked against the closed form: sliding from ``v0 = (2, 0, 0)``, rolling
starts at ``t* = 2 |U0| / (7 mu g)`` (``U0 = 2``), the only event.  The ratios are per core
(``points / s / core``); the goal is >= 50x the CLI loop.  Results: ``results/sweep.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

from nonideal.analysis.studies.sweep import Axis, sweep  # noqa: E402
from nonideal.modeling.modelfile import load_model  # noqa: E402
from nonideal.simulation.hybrid import simulate  # noqa: E402

MODEL = HERE / "friction_sphere.toml"
G = 9.81


def axes_for(n_mu: int, n_r: int) -> list[Axis]:
    return [Axis.linspace("mu", 0.1, 0.5, n_mu), Axis.linspace("R", 0.05, 0.2, n_r)]


def check_rows(rows) -> float:
    """Worst relative error of the rolling-start time against t* = 2 |U0| / (7 mu g)."""
    worst = 0.0
    for r in rows:
        assert r["exit_code"] == 0, r
        (event,) = r["summary"]["events"]
        t_star = 2 * 2.0 / (7 * r["parameters"]["mu"] * G)
        worst = max(worst, abs(event["t"] / t_star - 1))
    return worst


def cli_loop(points, count: int) -> float:
    """Seconds per point of a loop of CLI calls (the first *count* points)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    times = []
    for p in points[:count]:
        cmd = [sys.executable, "-m", "nonideal", "simulate", str(MODEL), "--set",
               f"mu={p['mu']!r}", "--set", f"R={p['R']!r}", "--json", os.devnull]
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, env=env, capture_output=True)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def api_loop(points) -> tuple[float, float]:
    """Seconds per point of the plain Python loop, and its worst t* error."""
    t0 = time.perf_counter()
    worst = 0.0
    for p in points:
        model = load_model(MODEL, parameters={"mu": p["mu"], "R": p["R"]})
        traj = simulate(model)
        (event,) = traj.events
        worst = max(worst, abs(event["t"] / (4 / (7 * p["mu"] * G)) - 1))
    return (time.perf_counter() - t0) / len(points), worst


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="1 000 points, 3 CLI calls")
    ap.add_argument("--cli-calls", type=int, default=None)
    ap.add_argument("--api-points", type=int, default=None)
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args(argv)
    n_mu, n_r = (50, 20) if args.quick else (100, 100)
    axes = axes_for(n_mu, n_r)
    from nonideal.analysis.studies.sweep import grid

    points = grid(axes)
    rng = np.random.default_rng(1)
    sample = [points[k] for k in rng.choice(len(points), size=len(points), replace=False)]
    cores = os.cpu_count() or 1
    out = {"points": len(points), "cores": cores, "model": str(MODEL.relative_to(ROOT))}

    cli_s = cli_loop(sample, args.cli_calls or (3 if args.quick else 5))
    out["cli_seconds_per_point"] = cli_s
    api_s, api_err = api_loop(sample[:args.api_points or (50 if args.quick else 200)])
    out["api_seconds_per_point"] = api_s

    t0 = time.perf_counter()
    one = sweep(MODEL, [Axis("mu", axes[0].values[:10]), axes[1]], "simulate", workers=1)
    one_s = (time.perf_counter() - t0) / len(one.rows)
    out["sweep_one_worker_seconds_per_point"] = one_s

    t0 = time.perf_counter()
    full = sweep(MODEL, axes, "simulate", workers=cores)
    wall = time.perf_counter() - t0
    out["sweep_wall_seconds"] = wall
    out["sweep_points_per_second"] = len(points) / wall
    out["sweep_points_per_second_per_core"] = len(points) / wall / cores
    out["worst_t_star_error"] = max(check_rows(full.rows), check_rows(one.rows), api_err)
    per_core = {"cli loop": 1 / cli_s, "api loop": 1 / api_s, "sweep (1 worker)": 1 / one_s,
                f"sweep ({cores} workers, per core)": out["sweep_points_per_second_per_core"]}
    out["points_per_second_per_core"] = per_core
    out["ratio_sweep_vs_cli_per_core"] = out["sweep_points_per_second_per_core"] * cli_s
    out["ratio_sweep_vs_api_per_core"] = out["sweep_points_per_second_per_core"] * api_s
    out["cli_loop_extrapolated_seconds"] = cli_s * len(points)

    if not args.no_dask:
        from distributed import Client, LocalCluster

        subset = [Axis("mu", axes[0].values[:10]), Axis("R", axes[1].values[:20])]
        local = sweep(MODEL, subset, "simulate", workers=1)
        with LocalCluster(n_workers=cores, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            sweep(MODEL, subset[:1] + [Axis("R", subset[1].values[:2])], "simulate",
                  client=client)   # the workers derive and compile the model
            t0 = time.perf_counter()
            remote = sweep(MODEL, subset, "simulate", client=client)
            dask_wall = time.perf_counter() - t0
        out["dask_points"] = len(remote.rows)
        out["dask_points_per_second_per_core"] = len(remote.rows) / dask_wall / cores
        out["dask_rows_equal_local"] = remote.rows == local.rows

    print(f"sweep benchmark: {len(points)} points of {MODEL.name} (mu x R), {cores} cores")
    for label, rate in per_core.items():
        print(f"  {label:28} {rate:10.1f} points/s/core")
    print(f"  sweep wall time {wall:.1f} s; the CLI loop would take ~{cli_s * len(points) / 3600:.1f} h "
          f"({cli_s:.2f} s per call)")
    print(f"  ratio per core: sweep / CLI loop = {out['ratio_sweep_vs_cli_per_core']:.0f}x "
          f"(goal >= 50x), sweep / API loop = {out['ratio_sweep_vs_api_per_core']:.1f}x")
    if "dask_points" in out:
        print(f"  Dask LocalCluster: {out['dask_points']} points, "
              f"{out['dask_points_per_second_per_core']:.1f} points/s/core, rows equal to the "
              f"local sweep: {out['dask_rows_equal_local']}")
    print(f"  worst relative error of the rolling time t* = 2|U0|/(7 mu g): "
          f"{out['worst_t_star_error']:.1e}")
    (HERE / "results").mkdir(exist_ok=True)
    name = "sweep-quick.json" if args.quick else "sweep.json"
    (HERE / "results" / name).write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
