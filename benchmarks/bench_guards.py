"""What the event guards cost: ``simulate`` with the guards inside each step (the default,
``nonideal.simulation.guards``) vs the detection of sign changes at the ends of the steps only
(what a plain event-driven loop does, and what misses an event hidden inside one step), side by
side in the same process, on small gallery runs.

    python benchmarks/bench_guards.py [--repeat 7] [--json OUT]

For each run: the processor time of ``simulate(model)`` (kernel compiled: the best of
``--repeat`` runs after a first one), the number of integrator steps, of events found, and of
states at which the event functions were evaluated inside steps (``probes``).  The ratio
``guards / ends`` is the cost of the guards.  The stiff stick-slip oscillator (k = 1e6) is the
case the guards exist for: with sign changes at the ends only, most of its stick phases (6 us
long, inside 0.4 ms steps) are missed; its period from the slips is compared with the closed
form.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal

from nonideal import gallery  # noqa: E402
from nonideal.gallery import stick_slip_oscillator  # noqa: E402
from nonideal.simulation import guards, hybrid  # noqa: E402
from nonideal.simulation.hybrid import simulate  # noqa: E402


def ends_only(step, events, armed, tols, g_prev, g_new, rates=(None, None)):
    """Sign changes between the ends of the step only (Brent's method on the dense output;
    the rates of the force guards are not read)."""
    hits = []
    for k, ev in enumerate(events):
        if armed[k] and g_prev[k] > 0 >= g_new[k]:
            te = brentq(lambda s, ev=ev: ev.value(step.motion(s)), step.a, step.b,
                        xtol=1e-15 * max(1.0, abs(step.b)), rtol=8.9e-16, maxiter=200)
            hits.append((te, k))
        elif not armed[k] and g_new[k] > tols[k]:
            armed[k] = True
    return hits


class Counter:
    """Counts the states at which a step is read inside (``Step.motion`` at a new time)."""

    def __init__(self):
        self.n = 0
        self.original = guards.Step.motion

    def __enter__(self):
        counter, original = self, self.original

        def motion(step, s):
            if s not in step._motions:
                counter.n += 1
            return original(step, s)
        guards.Step.motion = motion
        return self

    def __exit__(self, *exc):
        guards.Step.motion = self.original


def cases():
    stiff = stick_slip_oscillator.build(k=1e6, t_end=0.05)
    return [
        ("pendulum (no events)", gallery.load("nlink-pendulum")),
        ("block on incline", gallery.load("block-on-incline")),
        ("stick-slip oscillator", gallery.load("stick-slip-oscillator")),
        ("bouncing ball (e = 0.5, Zeno)", gallery.load("bouncing-ball")),
        ("stick-slip, stiff spring k = 1e6", stiff),
    ]


def run(model, detection):
    """``(processor time, trajectory)`` of ``simulate(model)`` with *detection*."""
    original = hybrid.event_hits
    if detection == "ends":
        hybrid.event_hits = ends_only
    try:
        start = time.process_time()
        traj = simulate(model)
        return time.process_time() - start, traj
    finally:
        hybrid.event_hits = original


def measure(model, repeat):
    """Both detections, alternating (the best of *repeat* each, after one run that compiles)."""
    out = {}
    run(model, "guards")
    best = {"ends": np.inf, "guards": np.inf}
    for _ in range(repeat):
        for detection in best:
            seconds, traj = run(model, detection)
            best[detection] = min(best[detection], seconds)
            out[detection] = traj
    result = {}
    for detection, traj in out.items():
        with Counter() as count:
            run(model, detection)
        result[detection] = {"seconds": best[detection], "samples": len(traj.t),
                             "events": len(traj.events), "probes": count.n,
                             "slips": [e["t"] for e in traj.events if e["type"] == "slip"]}
    return result


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    rows = []
    print("| run | ends only: s | guards: s | ratio | steps+events | events (ends / guards) | probes |")
    print("|---|---|---|---|---|---|---|")
    for label, model in cases():
        both = measure(model, args.repeat)
        ends, full = both["ends"], both["guards"]
        ratio = full["seconds"] / ends["seconds"]
        rows.append({"run": label, "ends": ends, "guards": full, "ratio": ratio})
        print(f"| {label} | {ends['seconds']:.4f} | {full['seconds']:.4f} | {ratio:.2f} | "
              f"{full['samples']} | {ends['events']} / {full['events']} | {full['probes']} |")
    stiff = rows[-1]["guards"]["slips"]
    T = stick_slip_oscillator.closed_form(cases()[-1][1].parameter_values)["T"]
    periods = np.diff(stiff)
    print(f"\nstiff stick-slip: closed-form period {T:.9e} s; guards: {len(stiff)} slips, period "
          f"max relative error {np.max(np.abs(periods / T - 1)) if periods.size else np.inf:.1e}; "
          f"ends only: {len(rows[-1]['ends']['slips'])} slips")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1, default=float))


if __name__ == "__main__":
    main()
