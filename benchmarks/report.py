"""Refresh the measured tables of RESULTS.md from benchmarks/results/*.json.

    python benchmarks/report.py

Replaces the text between ``<!-- BEGIN name -->`` and ``<!-- END name -->`` markers of
RESULTS.md: ``machine`` (from the pendulum run), ``pendulum``, ``knife_chain`` and
``profile``.  The prose around the markers (verdicts, proposals) is written by hand.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import _common as C  # noqa: E402


def machine_block(info: dict, runs: dict) -> str:
    v = info["versions"]
    lines = [
        f"* machine: {info['nproc']} cores (`nproc`), CPU `{info['cpu']}` (`/proc/cpuinfo`), {info['platform']}",
        f"* versions: Python {v['python']}, nonideal {v['nonideal']} (git {info.get('git_commit')}), "
        f"SymPy {v['sympy']}, SymEngine {v['symengine']} (LLVM: {info['symengine_llvm']}), NumPy {v['numpy']}, "
        f"SciPy {v['scipy']}, PyDy {v['pydy']}, Cython {v['Cython']}",
    ]
    for name, d in runs.items():
        m = d["machine"]
        la = m.get("loadavg_at_start")
        le = m.get("loadavg_at_end")
        load = f", load average {la[0]:.2f} at start, {le[0]:.2f} at end" if la and le else ""
        took = f", {d['elapsed']:.0f} s" if "elapsed" in d else ""
        lines.append(f"* `{name}`: run {m['date']}{load}{took}")
    return "\n".join(lines)


def profile_block(d: dict) -> str:
    out = []
    for p in d["derive"]:
        out.append(f"**Derive, {p['system']}, form {p['form']}** -- total {C.fmt_t(p['total'])} "
                   "(build, kernel, form, SymPy conversion, compilation):")
        out.append("")
        rows = [[k, C.fmt_t(v), f"{v / p['total']:.0%}"] for k, v in p["stages"].items()]
        rows += [[f"  inside: {it['what']}", C.fmt_t(it["seconds"]), f"{it['share']:.0%}"] for it in p["inside"]]
        out += [C.table(["stage", "time", "share"], rows), ""]
    for r in d["rhs"]:
        out.append(f"**One right-hand side, {r['system']}, form {r['form']}:**")
        out.append("")
        rows = [[k, C.fmt_t(v)] for k, v in r["pieces"].items()]
        rows += [[f"prototype: {k}", C.fmt_t(v) if "difference" not in k else f"{v:.1e}"]
                 for k, v in r["prototypes"].items()]
        out += [C.table(["piece", "per call"], rows), ""]
    for s in d["simulate"]:
        extra = ""
        if "bare_without_work_integrals" in s:
            extra = (f"; the same without the work integrals in the state: "
                     f"{C.fmt_t(s['bare_without_work_integrals'])} ({s['steps_without_work_integrals']} steps)")
        out.append(f"**Simulate, {s['system']}, form {s['form']}:** {C.fmt_t(s['simulate_warm'])} warm, "
                   f"{s['steps']} steps; bare `solve_ivp` on the same right-hand side "
                   f"{C.fmt_t(s['bare_solve_ivp_same_rhs'])} ({s['bare_steps']} steps){extra}.")
        out.append("")
        rows = [[it["what"], C.fmt_t(it["seconds"]), "" if it["share"] is None else f"{it['share']:.0%}",
                 it["calls"] if it["calls"] is not None else ""] for it in s["breakdown"]]
        out += [C.table(["part", "time", "share", "calls"], rows), ""]
    fs = d.get("form_setup", {})
    if fs:
        out.append("**Each `Simulation` derives and compiles a reduced form again:** "
                   + "; ".join(f"{k}: {C.fmt_t(v)}" for k, v in fs.items()) + ".")
        out.append("")
    lam = d.get("lambdify", {})
    if lam:
        rows = []
        for k, v in lam.items():
            for lab, r in v.items():
                if isinstance(r, dict):
                    rows.append([k, lab, r["outputs"], C.fmt_t(r["build"]), C.fmt_t(r["eval"])])
            rows.append([k, "break-even (evaluations)", "", f"{v['break-even evaluations']:.3g}", ""])
        out += ["**SymEngine Lambdify (with CSE): compile time vs evaluation time:**", "",
                C.table(["system", "backend", "outputs", "build", "eval"], rows), ""]
    return "\n".join(out)


def main() -> int:
    res = HERE / "results"
    data = {}
    for name in ("pendulum", "knife_chain", "profile"):
        p = res / f"{name}.json"
        if p.exists():
            data[name] = json.loads(p.read_text())
    doc = HERE / "RESULTS.md"
    text = doc.read_text()
    blocks = {}
    if "pendulum" in data:
        blocks["machine"] = machine_block(data["pendulum"]["machine"], data)
        blocks["pendulum"] = data["pendulum"]["markdown"] + "\nScript verdicts:\n\n" + "\n".join(
            f"* {g}" for g in data["pendulum"]["targets"])
    if "knife_chain" in data:
        blocks["knife_chain"] = data["knife_chain"]["markdown"] + "\nScript verdicts:\n\n" + "\n".join(
            f"* {g}" for g in data["knife_chain"]["targets"])
    if "profile" in data:
        blocks["profile"] = profile_block(data["profile"])
    for name, body in blocks.items():
        pat = re.compile(rf"(<!-- BEGIN {name} -->\n).*?(<!-- END {name} -->)", re.S)
        if not pat.search(text):
            print(f"RESULTS.md: no markers for {name}; skipped")
            continue
        text = pat.sub(lambda m: m.group(1) + body.rstrip() + "\n" + m.group(2), text)
    doc.write_text(text)
    print(f"updated {doc}: {', '.join(blocks)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
