"""Start-up of the command line in fresh processes, against the imports it cannot avoid.

    python benchmarks/bench_startup.py [--quick]

Every measurement is a fresh ``python`` process, best of several runs, with Python's byte
code cached (in a temporary ``PYTHONPYCACHEPREFIX``, as an installed package has it; a
checkout run with ``PYTHONDONTWRITEBYTECODE`` recompiles its ~100 modules, ~0.2 s, every
time) and the model cache in a temporary ``NONIDEAL_CACHE_DIR``:

* the floors: ``python -c pass``; ``import numpy``; the dependencies a simulation imports
  (NumPy, SciPy's integrators, SymPy, SymEngine); numba;
* ``nonideal --help``; ``nonideal simulate`` of the gallery's 3-link pendulum to t = 0.01 s
  (start-up plus a few steps), its first and second run; the same to t = 100 s (the native
  phase: the first run compiles the model's kernel, the second reads it from the disk cache);
* whether the second run's JSON is byte for byte the first's;
* ``-X importtime`` of the start-up run, summed by package (self time of every module).

Prints a markdown table and writes ``benchmarks/results/startup[-quick].json``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _common as C  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "nonideal" / "gallery" / "nlink_pendulum.toml"
DEPENDENCIES = "import numpy, scipy.integrate, sympy, symengine"


def environment(tmp: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(ROOT), NONIDEAL_CACHE_DIR=str(tmp / "models"),
               PYTHONPYCACHEPREFIX=str(tmp / "pyc"))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def timed(env, *argv) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, *argv], check=True, env=env, capture_output=True)
    return time.perf_counter() - t0


def best(env, repeat, *argv) -> float:
    return min(timed(env, *argv) for _ in range(repeat))


def by_package(env, *argv) -> dict[str, float]:
    """Self import time (s) summed by top-level package, from ``-X importtime``."""
    proc = subprocess.run([sys.executable, "-X", "importtime", *argv], env=env, capture_output=True,
                          text=True, check=True)
    total: dict[str, float] = defaultdict(float)
    for line in proc.stderr.splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        self_us, _, name = line[len("import time:"):].split("|")
        total[name.strip().split(".")[0]] += int(self_us) / 1e6
    return dict(sorted(total.items(), key=lambda kv: -kv[1]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    repeat = 3 if args.quick else 5
    out: dict = {"machine": C.machine()}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        env = environment(tmp)
        short = ["-m", "nonideal", "simulate", str(MODEL), "--t-end", "0.01", "--json"]
        long = ["-m", "nonideal", "simulate", str(MODEL), "--t-end", "100", "--json"]
        timed(env, "-c", DEPENDENCIES + ", numba")  # the byte code of everything cached
        r = out["times"] = {}
        r["python"] = best(env, repeat, "-c", "pass")
        r["numpy"] = best(env, repeat, "-c", "import numpy")
        r["dependencies"] = best(env, repeat, "-c", DEPENDENCIES)
        r["numba"] = best(env, repeat, "-c", "import numba")
        r["help"] = best(env, repeat, "-m", "nonideal", "--help")
        first, second = tmp / "first.json", tmp / "second.json"
        r["short_first"] = timed(env, *short, str(first))
        r["short_second"] = best(env, repeat, *short, str(second))
        out["short_identical"] = first.read_bytes() == second.read_bytes()
        r["long_first"] = timed(env, *long, str(first))
        r["long_second"] = best(env, max(1, repeat - 2), *long, str(second))
        out["long_identical"] = first.read_bytes() == second.read_bytes()
        out["importtime"] = by_package(env, *short, str(second))
    r = out["times"]
    rows = [
        ["python -c pass", C.fmt_t(r["python"])],
        ["import numpy", C.fmt_t(r["numpy"])],
        [f"`{DEPENDENCIES}`", C.fmt_t(r["dependencies"])],
        ["import numba", C.fmt_t(r["numba"])],
        ["nonideal --help", C.fmt_t(r["help"])],
        ["simulate 3-link pendulum, t_end 0.01: first / second run",
         f"{C.fmt_t(r['short_first'])} / {C.fmt_t(r['short_second'])}"],
        ["  the second run less the dependencies' imports", C.fmt_t(r["short_second"] - r["dependencies"])],
        ["simulate, t_end 100 (native phase): first / second run",
         f"{C.fmt_t(r['long_first'])} / {C.fmt_t(r['long_second'])}"],
    ]
    print(C.table(["fresh process", "best of runs"], rows))
    print(f"\nsecond run's JSON identical to the first's: t_end 0.01 {out['short_identical']}, "
          f"t_end 100 {out['long_identical']}")
    print("\nself import time by package (s, -X importtime, t_end 0.01):",
          ", ".join(f"{k} {v:.3f}" for k, v in list(out["importtime"].items())[:10]))
    print(f"wrote {C.write_json('startup', out, args.quick)}")


if __name__ == "__main__":
    main()
