"""``nonideal derive`` through the command line vs ``KanesMethod``, readable printing included.

    python benchmarks/bench_derive_cli.py [--quick] [--n 10] [--repeat 5] [--form lagrange1]

(a) The cost of deriving *and printing* the equations of an n-link pendulum through the CLI,
    beyond the 1-link run (which pays the interpreter's start, the imports and the model
    reading): ``t_cli(n) - t_cli(1)``, each the best of ``--repeat`` fresh processes
    (``python -m nonideal derive pendulum_n.toml --form F``; text, ``--latex`` and ``--json``),
    in CPU time (user + system, ``getrusage``): the machines these run on are shared.
    The printed equations are the readable ones (grouped, trigonometric identities folded).
    Peer, in this process: ``KanesMethod`` on the same system (frames, points, velocities,
    ``kanes_equations``, ``mass_matrix``, ``forcing``; SymPy's cache cleared before each run),
    and the same plus ``sstr`` of M and F (the peer's printing).  Target: ratio <= 0.2.
(b) Start-up of the commands that need no SymPy (``--help``, ``--version``, ``examples
    list``) against ``python -c pass`` and against ``python -c "import sympy"``.

Prints markdown tables and writes ``benchmarks/results/derive_cli[-quick].json``.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal, not an installed copy

import _common as C  # noqa: E402
import peers  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
TARGET = 0.2


def pendulum_toml(n: int) -> str:
    """The n-link pendulum of ``nonideal.gallery.nlink_pendulum`` as a model file."""
    lines = [f'[model]\nname = "{n}-link pendulum"\nformat = 1\n\n[parameters]']
    lines += [f"m{k} = 1.0" for k in range(1, n + 1)]
    lines += [f"l{k} = 1.0" for k in range(1, n + 1)]
    lines += ["g = 9.81", "", "[coordinates]",
              "q = [" + ", ".join(f'"q{k}"' for k in range(1, n + 1)) + "]", ""]
    for k in range(1, n + 1):
        x = " + ".join(f"l{j}*sin(q{j})" for j in range(1, k + 1))
        y = " - ".join(f"l{j}*cos(q{j})" for j in range(1, k + 1))
        lines += ["[[bodies]]", 'type = "particle"', f'name = "P{k}"', f'mass = "m{k}"',
                  f'position = ["{x}", "-{y}"]', ""]
    lines += ["[gravity]", 'vector = ["0", "-g"]', "", "[initial]"]
    for k in range(1, n + 1):
        lines += [f"q{k} = 0.5", f"\"q{k}'\" = 0.0"]
    return "\n".join(lines) + "\n"


def run_best(argv: list[str], repeat: int) -> tuple[float, float, str]:
    """Best CPU time (user + system of the child, from ``getrusage``) and best wall time of
    *repeat* fresh processes, and the output of the last.  The CPU time is what the ratios
    use: on a shared machine the wall time measures the other jobs as much as this one."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    best_cpu, best_wall, out = float("inf"), float("inf"), ""
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, *argv], capture_output=True, text=True, env=env, cwd=ROOT)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        if proc.returncode != 0:
            raise SystemExit(f"{' '.join(argv)} failed:\n{proc.stderr}")
        best_cpu, best_wall, out = min(best_cpu, cpu), min(best_wall, wall), proc.stdout
    return best_cpu, best_wall, out


def kane(n: int, repeat: int, printing: bool) -> float:
    """Best CPU time (``time.process_time``) of KanesMethod on the n-link pendulum, SymPy's
    cache cleared before each run; with *printing*, plus ``sstr`` of M and F."""
    import sympy as sp

    best = float("inf")
    for _ in range(repeat):
        C.clear_caches()
        t0 = time.process_time()
        km = peers.kane_pendulum(n)
        M, F = km.mass_matrix, km.forcing
        if printing:
            for x in list(M) + list(F):
                sp.sstr(x)
        best = min(best, time.process_time() - t0)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions (3)")
    ap.add_argument("--n", type=int, default=10, help="links of the large pendulum (default 10)")
    ap.add_argument("--repeat", type=int, default=None, help="fresh processes per command (default 5)")
    ap.add_argument("--form", default="lagrange1", help="the form derived (default lagrange1)")
    args = ap.parse_args(argv)
    repeat = args.repeat or (3 if args.quick else 5)
    start = time.perf_counter()
    data: dict = {"machine": C.machine(), "quick": args.quick, "n": args.n, "form": args.form,
                  "repeat": repeat, "target": TARGET}

    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for n in (1, args.n):
            files[n] = Path(tmp) / f"pendulum_{n}.toml"
            files[n].write_text(pendulum_toml(n))
        rows = []
        kane_t = kane(args.n, max(1, repeat // 2), printing=False)
        kane_p = kane(args.n, max(1, repeat // 2), printing=True)
        data["kane"], data["kane_with_printing"] = kane_t, kane_p
        for label, extra in (("text", []), ("--latex", ["--latex"]), ("--json", ["--json"])):
            t1, w1, _ = run_best(["-m", "nonideal", "derive", str(files[1]), "--form", args.form, *extra],
                                 repeat)
            tn, wn, out = run_best(["-m", "nonideal", "derive", str(files[args.n]), "--form", args.form,
                                    *extra], repeat)
            beyond = tn - t1
            rows.append({"output": label, "cli_1": t1, "cli_n": tn, "beyond": beyond,
                         "wall_1": w1, "wall_n": wn,
                         "ratio_kane": beyond / kane_t, "ratio_kane_printing": beyond / kane_p})
            if label == "text":
                data["sample"] = [line for line in out.splitlines() if " = " in line][-1]
        data["derive"] = rows

        startup = []
        base, _, _ = run_best(["-c", "pass"], repeat)
        sympy_t, _, _ = run_best(["-c", "import sympy"], repeat)
        for label, cmd in (("--help", ["--help"]), ("--version", ["--version"]),
                           ("examples list", ["examples", "list"])):
            t, _, _ = run_best(["-m", "nonideal", *cmd], repeat)
            code = ("import sys, runpy; sys.argv = ['nonideal', %s]\n"
                    "try:\n    runpy.run_module('nonideal', run_name='__main__')\n"
                    "except SystemExit:\n    pass\n"
                    "print('sympy' in sys.modules)") % ", ".join(repr(c) for c in cmd)
            _, _, out = run_best(["-c", code], 1)
            startup.append({"command": label, "time": t, "imports_sympy": out.strip().endswith("True")})
        data["startup"] = {"python": base, "import_sympy": sympy_t, "commands": startup}

    n = args.n
    print(f"## derive through the CLI, {n}-link pendulum, --form {args.form} "
          f"(CPU time, best of {repeat} processes)\n")
    print(C.table(["output", "CLI n=1", f"CLI n={n}", "beyond n=1", "/ Kane", "/ Kane+sstr"],
                  [[r["output"], C.fmt_t(r["cli_1"]), C.fmt_t(r["cli_n"]), C.fmt_t(r["beyond"]),
                    C.fmt_r(r["ratio_kane"]), C.fmt_r(r["ratio_kane_printing"])] for r in rows]))
    print(f"\nKanesMethod n={n}: {C.fmt_t(kane_t)} (with sstr of M, F: {C.fmt_t(kane_p)}); "
          f"target: beyond/Kane <= {TARGET}")
    print(f"last printed equation: {data['sample']}\n")
    s = data["startup"]
    print(f"## start-up, CPU time (python -c pass: {C.fmt_t(s['python'])}; import sympy: "
          f"{C.fmt_t(s['import_sympy'])})\n")
    print(C.table(["command", "time", "imports SymPy"],
                  [[c["command"], C.fmt_t(c["time"]), "yes" if c["imports_sympy"] else "no"]
                   for c in s["commands"]]))
    worst = max(r["ratio_kane"] for r in rows)
    ok = worst <= TARGET and not any(c["imports_sympy"] for c in s["commands"])
    data["ok"] = ok
    data["elapsed"] = time.perf_counter() - start
    path = C.write_json("derive_cli", data, args.quick)
    print(f"\nworst ratio {worst:.3g} (target {TARGET}): {'met' if ok else 'MISSED'}; wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
