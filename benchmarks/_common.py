"""Shared helpers of the benchmarks: timers, machine description, fits, tables, JSON.

Timings are wall-clock (``time.perf_counter``) in the same process as the peer they are
compared with.  Symbolic derivations are timed from a fresh model with SymPy's cache cleared
before every run (both libraries build SymPy objects; a warm cache would favour whichever
runs second); the best of ``repeat`` runs is kept.  Micro-benchmarks (one right-hand side)
use ``timeit`` with an automatic loop count and keep the best of five.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import platform
import subprocess
import sys
import time
import timeit
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def clear_caches() -> None:
    """Clear SymPy's global cache (what the library derives is cached on the model object
    (``Model.cached``), and every measurement uses a fresh model)."""
    import gc

    from sympy.core.cache import clear_cache

    clear_cache()
    gc.collect()


def best_of(fn, repeat: int = 3, clear: bool = True):
    """``(best wall time in s, last result)`` of ``fn()`` over *repeat* runs (caches cleared
    before each run unless ``clear=False``)."""
    best, result = math.inf, None
    for _ in range(max(1, repeat)):
        if clear:
            clear_caches()
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return best, result


def per_call(fn, target: float = 0.2, repeat: int = 5) -> float:
    """Seconds per call of ``fn()`` (best of *repeat* loops of ~*target* seconds)."""
    fn()
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    number = max(1, int(number * target / 0.2))
    return min(timer.repeat(repeat=repeat, number=number)) / number


def fit_power(ns, ts):
    """Exponent ``p`` of ``t ~ c n^p`` (least squares in log-log); None with < 2 points."""
    pts = [(n, t) for n, t in zip(ns, ts) if t and t > 0]
    if len(pts) < 2:
        return None
    x = np.log([p[0] for p in pts])
    y = np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def fit_growth(ns, ss):
    """Growth factor per unit of n of ``s ~ c g^n`` (least squares in log-linear)."""
    pts = [(n, s) for n, s in zip(ns, ss) if s and s > 0]
    if len(pts) < 2:
        return None
    return float(math.exp(np.polyfit([p[0] for p in pts], np.log([p[1] for p in pts]), 1)[0]))


def extrapolate_power(ns, ts, n_new, last: int = 3):
    """Power-law extrapolation from the last *last* measured points (t ~ c n^p)."""
    pts = [(n, t) for n, t in zip(ns, ts) if t][-last:]
    if len(pts) < 2:
        return None, None
    p = fit_power([a for a, _ in pts], [b for _, b in pts])
    n0, t0 = pts[-1]
    return float(t0 * (n_new / n0) ** p), p


def machine() -> dict:
    """Machine, date and versions (recorded with every result)."""
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    versions = {"python": platform.python_version()}
    for mod in ("nonideal", "sympy", "symengine", "numpy", "scipy", "pydy", "Cython"):
        try:
            versions[mod] = __import__(mod).__version__
        except Exception:  # not installed
            versions[mod] = None
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True,
                                text=True, timeout=10).stdout.strip() or None
    except Exception:
        commit = None
    try:
        import symengine

        llvm = bool(getattr(symengine, "have_llvm", False))
    except Exception:
        llvm = False
    return {
        "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "nproc": os.cpu_count(),
        "cpu": cpu,
        "platform": platform.platform(),
        "versions": versions,
        "symengine_llvm": llvm,
        "git_commit": commit,
        "loadavg_at_start": list(os.getloadavg()),
    }


def write_json(name: str, data: dict, quick: bool) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    if isinstance(data.get("machine"), dict):
        # another job on the machine skews wall-clock timings: record the load
        data["machine"]["loadavg_at_end"] = list(os.getloadavg())
    path = RESULTS / (f"{name}-quick.json" if quick else f"{name}.json")
    path.write_text(json.dumps(data, indent=1, default=_jsonable))
    return path


def _jsonable(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


def fmt_t(t) -> str:
    """A duration for a table: ``"0.123 s"``, ``"12.3 ms"``, ``"4.5 us"``, ``"-"``."""
    if t is None or (isinstance(t, float) and math.isnan(t)):
        return "-"
    if t >= 1:
        return f"{t:.2f} s"
    if t >= 1e-3:
        return f"{t * 1e3:.1f} ms"
    return f"{t * 1e6:.1f} us"


def fmt_r(r) -> str:
    if r is None or (isinstance(r, float) and math.isnan(r)):
        return "-"
    return f"{r:.3g}"


def ratio(a, b):
    if a is None or b is None or not b:
        return None
    return a / b


def table(header: list[str], rows: list[list[str]]) -> str:
    """A GitHub-markdown table (also readable in a terminal)."""
    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) if rows else len(str(h))
              for i, h in enumerate(header)]
    line = "| " + " | ".join(str(h).ljust(w) for h, w in zip(header, widths)) + " |"
    sep = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    body = ["| " + " | ".join(str(c).ljust(w) for c, w in zip(r, widths)) + " |" for r in rows]
    return "\n".join([line, sep, *body])


def pydy_available() -> bool:
    try:
        import Cython  # noqa: F401
        import pydy  # noqa: F401
        return True
    except Exception:
        return False
