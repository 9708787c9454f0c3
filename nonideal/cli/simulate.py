"""``nonideal simulate``."""

from __future__ import annotations

import json

from ..errors import MechanicsError, ModelError
from .common import json_option, model_argument, load_spec, check_options, parse_times, explained, form_type, method_type, METHODS, PLOT_SAMPLES
from .outputs import Outputs, emit_json


def add_parser(sub, ctx) -> None:
    solvers, solver_help = ctx.solvers, ctx.solver_help
    s = sub.add_parser("simulate", help="the hybrid simulation",
                       description="The hybrid simulation with exact switching of modes.")
    model_argument(s)
    s.add_argument("--t-end", type=float, default=None, help="end time (default: [simulation] t_end)")
    s.add_argument("--times", help="output exactly at these times, comma-separated, strictly "
                   "increasing (negative times: --times=-1,0,1)")
    s.add_argument("--grid", type=int, metavar="N", help="output on N uniform times from t0 to the "
                   "end, with each event's state before and after its switch (default: "
                   "[simulation] grid, else 1001)")
    s.add_argument("--every-step", action="store_true", help="output at every accepted step of the "
                   "integrator and at each event (beyond 5000 steps: every 2nd, 4th, ... step)")
    s.add_argument("--form", default="lagrange1", type=form_type(solvers), metavar="FORM",
                   help=solver_help)
    s.add_argument("--rtol", type=float, help="relative tolerance (default: [simulation] rtol)")
    s.add_argument("--atol", type=float, help="absolute tolerance (default: [simulation] atol)")
    s.add_argument("--method", type=method_type, metavar="METHOD",
                   help=f"integrator: {', '.join(METHODS)} (default: [simulation] method)")
    json_option(s)
    s.add_argument("--csv", metavar="OUT", help="write the trajectory as CSV (the samples of the JSON: "
                   "--times, --every-step, or the output grid with each event's states)")
    s.add_argument("--plot", metavar="PNG", help="plot the trajectory, reactions and energy")
    s.add_argument("--animate", metavar="GIF", help="animation of the motion (.gif; .mp4 needs "
                   "ffmpeg; .png: the last frame): the bodies drawn from the model's geometry (in "
                   "3-D with the shapes of contacts from geometry), each contact's mode coloured")
    s.set_defaults(func=run)


def run(args) -> int:
    from ..simulation.hybrid import simulate

    check_options(args)
    problems = []
    if args.grid is not None and args.grid < 2:
        problems.append(f"--grid: must be an integer >= 2, the number of output times (got {args.grid})")
    given = [flag for flag, on in (("--times", args.times is not None), ("--grid", args.grid is not None),
                                   ("--every-step", args.every_step)) if on]
    if len(given) > 1:
        problems.append(f"{' and '.join(given)}: choose one output (exact times, a uniform grid, or every step)")
    if problems:
        raise ModelError(problems)
    model = load_spec(args.model, args.set)
    times = parse_times(args.times) if args.times is not None else None
    if args.t_end is not None and not args.t_end > model.t0:
        raise ModelError(f"--t-end: must be later than t0 = {model.t0:g} (got {args.t_end:g})")
    if times is not None and args.t_end is not None and times[-1] > args.t_end:
        raise ModelError(f"--times: the last time {times[-1]:g} is after --t-end {args.t_end:g}; "
                         "drop --t-end (it defaults to the last time) or extend it")
    if times is not None and times[0] < model.t0:
        raise ModelError(f"--times: {times[0]:g} is before the initial time t0 = {model.t0:g}"
                         " ([simulation] t0)")
    if args.t_end is None and times is None and model.simulation.t_end is None:
        problems = ["no end time: give t_end in [simulation] (e.g. t_end = 10.0), or --t-end T "
                    "or --times on the command line"]
        try:   # report the initial state's problems too, in the same run
            from ..numeric.consistency import complete_state
            from ..numeric.kernel import kernel_of, parameter_vector

            complete_state(kernel_of(model), model.numeric_initial(), parameter_vector(model),
                           model.t0)
        except ModelError as exc:
            problems += exc.problems
        raise ModelError(problems, None if model.source == "<api>" else model.source)
    options = {}
    for key in ("rtol", "atol", "method", "grid"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    if args.every_step:
        options["every_step"] = True
    try:
        traj = simulate(model, t_end=args.t_end, times=times, form=args.form, **options)
    except MechanicsError as exc:
        raise explained(model, exc) from None
    outputs = Outputs()
    drawn = traj
    if args.plot or args.animate:
        # a drawing never splines through a few samples (--times): the same run on a fine grid
        # (dense output) with the events' instants on it, so that a switch and the forces'
        # jumps are drawn where they happen
        grid = plot_grid(traj)
        drawn = simulate(model, t_end=traj.t[-1], times=grid, form=args.form, **options)
    if args.csv:
        outputs.add("--csv", args.csv, traj.to_csv)
    if args.animate:
        from ..plotting import animate_trajectory

        outputs.add("--animate", args.animate, lambda tmp: animate_trajectory(drawn, model, tmp))
    if args.plot:
        from ..plotting import plot_trajectory

        outputs.add("--plot", args.plot, lambda tmp: plot_trajectory(drawn, tmp, model=model))
    heat = _actuator_heat(model, traj, args.form, options)
    payload = traj.to_dict()
    from ..modeling.units import units_report

    units = units_report(model)
    payload["units"] = units
    if heat is not None:
        payload["actuator_heat"] = heat
    stdout = None
    if args.json == "-":
        stdout = json.dumps(payload, indent=1, allow_nan=True)
    elif args.json:
        emit_json(args, payload, outputs)
    outputs.commit()
    if stdout is not None:
        print(stdout)
    elif not args.json:
        import numpy as np

        d = traj.diagnostics
        print(f"{traj.model}: simulated t = {traj.t[0]:g} .. {traj.t[-1]:g} "
              f"({d['samples']} samples, {d['events']} events, form {d['form']}, {d['method']})")
        from ..numeric.display import number

        def unit(u):   # shown where the model declares its units ([units])
            return f" {u}" if units["declared"] and u else ""
        for k, c in enumerate(traj.coordinates):   # noise against the coordinate's range: 0
            sq, sv = float(abs(traj.q[:, k]).max()), float(abs(traj.qd[:, k]).max())
            print(f"  {c:>10}(t_end) = {number(traj.q[-1, k], sq, 12, True)}{unit(units['q'][c])}   "
                  f"{c}'(t_end) = {number(traj.qd[-1, k], sv, 12, True)}{unit(units['qdot'][c])}")
        for label, series in (("speed", traj.speeds), ("output", traj.outputs)):
            for name, values in series.items():
                rng = float(abs(values).max()) if len(values) else None
                print(f"  {name:>10}(t_end) = {number(values[-1], rng, 12, True)}   ({label}; "
                      f"from {number(values.min(), rng, 8, True)} to {number(values.max(), rng, 8, True)})")
        shown = traj.events if len(traj.events) <= 24 else traj.events[:20]
        for e in shown:
            zeno = (f" (accumulation of impacts, geometric ratio {e['ratio']:.6g}, after "
                    f"{e['impacts']} impacts: the rest of the series skipped)") if e["type"] == "zeno" else \
                (f" (singular constraints: multipliers unbounded; continued on the {e['branch']} branch "
                 f"over t = {e['interval'][0]:.6g} .. {e['interval'][1]:.6g})") if e["type"] == "singular" else ""
            print(f"  event at t = {e['t']:.12g}: {e['type']} {e.get('constraint', e.get('contact', ''))}"
                  f" -> mode [{e.get('mode', '')}]{zeno}")
        if len(shown) < len(traj.events):
            last = traj.events[-1]
            print(f"  ... {len(traj.events) - len(shown)} more events, the last at t = {last['t']:.12g} "
                  f"-> mode [{last.get('mode', '')}] (all of them: --json or --csv)")
        split = d.get("indeterminate")
        if split:
            print(f"  statically indeterminate reactions (the motion is unique, their split is "
                  f"not); shown: {split['rule']}")
            for ph in split["phases"]:
                print(f"    t = {ph['t'][0]:.12g} .. {ph['t'][1]:.12g} [{ph['mode']}], at the end:")
                for label, (lo, hi, shown) in ph["end"].items():
                    print(f"      {label}: shown {number(shown, None, 8)}, admissible from "
                          f"{number(lo, None, 8)} to {number(hi, None, 8)}")
        for name, c in traj.controls.items():
            if "force" not in c:    # a program realized by the shared controls
                continue
            u = np.asarray(c["force"], dtype=float)
            extra = "".join(f", {k} = {number(c[k][-1], None, 10)}" for k in sorted(c)
                            if k.startswith("u_"))
            print(f"  control {name}: force at t_end = {number(u[-1], float(abs(u).max()), 10)}"
                  f" (from {number(u.min(), None, 8)} to {number(u.max(), None, 8)}){extra}, "
                  f"work = {number(c['work'][-1], None, 10)}")
        if heat is not None:
            print(f"  work of the reactions A = {traj.energy['reaction_work'][-1]:.12g}, heat lost in "
                  f"the drives W = {heat['total']:.12g} (Briskin et al. 2021, (3.7))")
        print(f"  constraint residual max = {d['constraint_residual_max']:.3e}, "
              f"energy balance (relative) = {d['energy_balance_relative']:.3e}")
    return 0


def plot_grid(traj, samples: int = PLOT_SAMPLES):
    """The times a run is drawn at: *samples* uniform ones over the run, its own sample times,
    and each event's instant with one just after it (a force's jump drawn as a jump).

    Returns
    -------
    ndarray, strictly increasing
    """
    import numpy as np

    t0, t1 = float(traj.t[0]), float(traj.t[-1])
    span = max(t1 - t0, 1e-300)
    points = [np.linspace(t0, t1, samples), np.asarray(traj.t, dtype=float)]
    for e in traj.events:
        te = float(e["t"])
        if t0 <= te <= t1:
            points.append([te, min(t1, te + 1e-9 * span)])
    grid = np.unique(np.concatenate([np.atleast_1d(p) for p in points]))
    keep = np.concatenate(([True], np.diff(grid) > 1e-12 * span))
    return grid[keep]


def _actuator_heat(model, traj, form, options) -> dict | None:
    """The drives' heat ``W`` up to the end of *traj* (constraints with ``losses``), integrated
    on a dense uniform sampling of the same motion; None without losses."""
    if not any(c.losses is not None for c in model.constraints):
        return None
    import numpy as np

    from ..analysis.studies.quasi_ideal import HEAT_SAMPLES, actuator_heat
    from ..simulation.hybrid import simulate

    dense = simulate(model, t_end=traj.t[-1], times=np.linspace(traj.t[0], traj.t[-1], HEAT_SAMPLES),
                     form=form, **options)
    h = actuator_heat(model, dense)
    return {"total": float(h["total"][-1]),
            "by_constraint": {c: float(v[-1]) for c, v in h["heat"].items()}}
