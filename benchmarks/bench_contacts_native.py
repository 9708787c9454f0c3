"""Contact modes in native code, side by side in one process.

Run from the repository root::

    python benchmarks/bench_contacts_native.py [--quick]

1. **Friction sphere** (``benchmarks/friction_sphere.toml``, cases (a) and (b) of
   ``bench_friction_sphere.py``: sliding, then rolling from the exact slip-stop event at
   t* = 2|U0|/(7 mu g)): a warm ``simulate`` with the contact modes in native code
   (``native=True``) and on the Python path (``native=False``), against MuJoCo's
   ``rollout`` at its default timestep 2e-3 (default contact settings, pyramidal cone: MuJoCo's
   defaults; the ball settled into its soft contact first).  Reported: median and best wall
   time of each, the error of our event time against the closed form, the native vs Python
   difference of the event time and of the final state.
2. **Stick-slip oscillator** (gallery ``stick-slip-oscillator``, k = 1e6, 0.1 s: 31 switches)
   native and on the Python path: the cost of an event.
3. **Rattleback** (gallery ``rattleback``, 5 s, rtol 1e-10) with Coulomb friction mu = 0.1
   against the same body rolling ideally (mu = inf): wall time of warm runs (default options:
   native after a phase's first 1000 steps; and ``native=True``), events, the size of the
   default JSON output, the native vs Python difference of the final state.

Timings are medians of repeats (best in brackets) after warm-up runs (the model's kernels
and the native code loaded).  Output: a markdown table on stdout.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import nonideal  # noqa: E402
from nonideal.modeling.modelfile import load_model  # noqa: E402

from bench_friction_sphere import CASES, MODEL_FILE, T_END, MujocoSphere, closed_form, initial_of  # noqa: E402

DT_MUJOCO = 2e-3


def timed(fn, repeat: int, warm: int = 2):
    for _ in range(warm):
        out = fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), out


def ms(v: float) -> str:
    return f"{v * 1e3:.2f} ms" if v < 1 else f"{v:.2f} s"


def sphere(repeat: int) -> list[str]:
    model = load_model(MODEL_FILE)
    try:
        import mujoco
    except ImportError:
        mujoco = None
    rows = []
    for key, case in CASES.items():
        exact = closed_form(case["v0"], case["w0"])
        init = initial_of(case)
        # every step kept, as MuJoCo's rollout keeps the state at each of its steps
        med_n, best_n, nat = timed(lambda: nonideal.simulate(model, t_end=T_END, initial=init, native=True,
                                                             every_step=True), repeat)
        med_p, best_p, py = timed(lambda: nonideal.simulate(model, t_end=T_END, initial=init, native=False,
                                                             every_step=True), repeat)
        med_g, best_g, grid = timed(lambda: nonideal.simulate(model, t_end=T_END, initial=init, native=True), repeat)
        t_n, t_p = nat.events[0]["t"], py.events[0]["t"]
        err = abs(t_n - exact["t_star"]) / exact["t_star"]
        diff = max(np.abs(nat.q[-1] - py.q[-1]).max(), np.abs(nat.qd[-1] - py.qd[-1]).max())
        title = f"sphere {case['title']}"
        notes = f"t* error {err:.1e}; native vs Python: t* {abs(t_n - t_p):.1e}, final state {diff:.1e}"
        if mujoco is not None:
            sph = MujocoSphere(mujoco, DT_MUJOCO, "pyramidal", {})
            state0 = sph.initial_state(case)
            nstep = int(round(T_END / DT_MUJOCO))
            med_m, best_m, states = timed(lambda: sph.rollout(state0, nstep), repeat)
            _, _, v, _, _ = MujocoSphere.kinematics(states)
            v_err = float(np.linalg.norm(v[-1, :2] - exact["v_f"]) / np.linalg.norm(exact["v_f"]))
            rows.append(f"| {title}, native, every step | {ms(med_n)} ({ms(best_n)}) | MuJoCo rollout dt 2e-3 "
                        f"{ms(med_m)} ({ms(best_m)}) | {med_n / med_m:.2f} | goal <= 1; {notes}; MuJoCo's "
                        f"final velocity off by {v_err:.1e} |")
            rows.append(f"| {title}, native, default output ({len(grid.t)} samples with reactions) | "
                        f"{ms(med_g)} ({ms(best_g)}) | MuJoCo rollout dt 2e-3 ({nstep} states) "
                        f"{ms(med_m)} ({ms(best_m)}) | {med_g / med_m:.2f} | |")
        else:
            rows.append(f"| {title}, native | {ms(med_n)} ({ms(best_n)}) | MuJoCo not importable | | {notes} |")
        rows.append(f"| {title}, native, every step | {ms(med_n)} ({ms(best_n)}) | Python path (native=False) "
                    f"{ms(med_p)} ({ms(best_p)}) | {med_n / med_p:.2f} | |")
    return rows


def rattleback(repeat: int) -> list[str]:
    from nonideal import gallery

    ideal = gallery.load("rattleback")
    text = Path(gallery.__file__).with_name("rattleback.toml").read_text(encoding="utf-8")
    assert 'mu = "inf"' in text
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "rattleback_mu.toml"
        path.write_text(text.replace('mu = "inf"', 'mu = "0.1"'), encoding="utf-8")
        rough = load_model(path)
        med_i, best_i, ti = timed(lambda: nonideal.simulate(ideal), repeat, warm=1)
        med_d, best_d, td = timed(lambda: nonideal.simulate(rough), repeat, warm=1)
        med_n, best_n, tn = timed(lambda: nonideal.simulate(rough, native=True), repeat, warm=1)
        med_p, best_p, tp = timed(lambda: nonideal.simulate(rough, native=False), repeat, warm=1)
        med_in, best_in, _ = timed(lambda: nonideal.simulate(ideal, native=True), repeat, warm=1)
        size = len(td.to_json().encode())
        # pitched 0.2 rad: it slips and sticks about 35 times in the 5 s (the event-heavy case;
        # the start above stays inside the friction cone)
        slipping = Path(tmp) / "rattleback_slipping.toml"
        slipping.write_text(text.replace('mu = "inf"', 'mu = "0.1"').replace("b = 0.01", "b = 0.2"),
                            encoding="utf-8")
        slips = load_model(slipping)
        start = time.perf_counter()
        ts = nonideal.simulate(slips, native=True)
        wall_s = time.perf_counter() - start
        size_s = len(ts.to_json().encode())
        rolling = slipping.with_name("rattleback_pitched.toml")  # the same start, rolling ideally
        rolling.write_text(text.replace("b = 0.01", "b = 0.2"), encoding="utf-8")
        rolls = load_model(rolling)
        med_r, _, _ = timed(lambda: nonideal.simulate(rolls, native=True), repeat, warm=1)
    diff = max(np.abs(tn.q[-1] - tp.q[-1]).max(), np.abs(tn.qd[-1] - tp.qd[-1]).max())
    return [
        f"| rattleback mu = 0.1 pitched 0.2 rad (slips), 5 s, native=True, one run | {wall_s * 1e3:.0f} ms | "
        f"the same start rolling ideally, native=True {ms(med_r)} | {wall_s / med_r:.0f} | goal <= 3; {len(ts.events)} events, "
        f"{len(ts.t)} samples, JSON {size_s / 1e6:.2f} MB |",
        f"| rattleback mu = 0.1, 5 s, default options | {ms(med_d)} ({ms(best_d)}) | ideal rolling "
        f"{ms(med_i)} ({ms(best_i)}) | {med_d / med_i:.2f} | goal <= 3; {len(td.events)} events, "
        f"{len(td.t)} samples, JSON {size / 1e6:.2f} MB |",
        f"| rattleback mu = 0.1, native=True | {ms(med_n)} ({ms(best_n)}) | native=False {ms(med_p)} "
        f"({ms(best_p)}) | {med_n / med_p:.2f} | final state native vs Python {diff:.1e} |",
        f"| rattleback mu = 0.1, native=True | {ms(med_n)} ({ms(best_n)}) | ideal rolling, native=True "
        f"{ms(med_in)} ({ms(best_in)}) | {med_n / med_in:.2f} | |",
    ]


def stick_slip(repeat: int) -> list[str]:
    """The stiff stick-slip oscillator (gallery), 0.1 s: an event every ~3 ms."""
    from nonideal.gallery import stick_slip_oscillator

    model = stick_slip_oscillator.build(k=1e6, t_end=0.1)
    med_n, best_n, tn = timed(lambda: nonideal.simulate(model, native=True), repeat, warm=1)
    med_p, best_p, tp = timed(lambda: nonideal.simulate(model, native=False), repeat, warm=1)
    gap = max(abs(a["t"] - b["t"]) for a, b in zip(tn.events, tp.events))
    same = [e["type"] for e in tn.events] == [e["type"] for e in tp.events]
    return [f"| stick-slip oscillator k = 1e6, 0.1 s, native=True | {ms(med_n)} ({ms(best_n)}) | native=False "
            f"{ms(med_p)} ({ms(best_p)}) | {med_n / med_p:.2f} | {len(tn.events)} events "
            f"({ms(med_n / len(tn.events))} an event natively, {ms(med_p / len(tp.events))} on the Python path); "
            f"same sequence: {same}, instants within {gap:.1e} |"]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    args = parser.parse_args(argv)
    repeat = 5 if args.quick else 15
    print("| measurement | ours | peer | ratio | notes |")
    print("|---|---|---|---|---|")
    for row in sphere(repeat):
        print(row, flush=True)
    for row in stick_slip(3 if args.quick else 5):
        print(row, flush=True)
    for row in rattleback(3 if args.quick else 5):
        print(row, flush=True)


if __name__ == "__main__":
    main()
