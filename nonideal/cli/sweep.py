"""``nonideal sweep``: a command's summary over a grid of parameter values.

Every finished point is appended at once to a journal next to the output (``OUT.journal``,
one JSON row a line); the output itself is written only when the sweep has finished, and the
journal is then removed.  ``--resume`` reads the journal of an interrupted sweep (and the
rows of an earlier complete output, when it is a JSON) and runs only the missing points.
"""

from __future__ import annotations

import contextlib
import json
import sys
import time
from pathlib import Path

from ..errors import ModelError, did_you_mean
from .common import check_options, form_type, method_type, model_argument, parse_at, parse_overrides, METHODS
from .outputs import Outputs
from .terminal import EXIT_INTERRUPTED, EXIT_TERMINATED, Terminated

JOURNAL_SUFFIX = ".journal"


def add_parser(sub, ctx) -> None:
    from ..analysis.studies.sweep_points import WHATS  # (numpy-free: --help stays light)

    s = sub.add_parser(
        "sweep", help="a command's summary over a grid of parameter values",
        description="Run simulate, evaluate, realizability, stability or check at every point of "
        "a grid of parameter values, in parallel (local processes, or a Dask cluster with "
        "--scheduler); one row per point with its exit code, message and summary.  A failing "
        "point is recorded and the sweep goes on; every finished point is journaled at once, "
        "so --resume completes an interrupted sweep.",
        epilog="Example: nonideal sweep block-on-incline --vary alpha=0.2:0.6:5 --vary "
        "mu_s=0.3:0.7:5 --what simulate --json out.json --plot map.png --quantity events.count")
    model_argument(s)
    s.add_argument("--vary", action="append", default=[], metavar="NAME=START:STOP:N",
                   help="a varied parameter: N values from START to STOP, or a list "
                   "NAME=V1,V2,... (repeatable: the grid is the product)")
    s.add_argument("--what", required=True, choices=WHATS, help="the command run at each point")
    where = s.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help="local worker processes (default: the number of CPUs)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a Dask cluster (dask.distributed), e.g. tcp://host:8786")
    out = s.add_mutually_exclusive_group(required=True)
    out.add_argument("--json", metavar="OUT", help="write the rows as JSON")
    out.add_argument("--csv", metavar="OUT", help="write the rows as CSV (summaries flattened: "
                     "q.x, qdot.x, ...)")
    out.add_argument("--parquet", metavar="OUT", help="write the rows as Apache Parquet, "
                     "columns typed (parameters and summaries float64, exit_code int64, "
                     "message string); needs pyarrow: pip install 'nonideal[parquet]'")
    s.add_argument("--resume", action="store_true",
                   help="complete an interrupted sweep from its journal (OUT.journal)")
    s.add_argument("--plot", metavar="PNG", help="plot --quantity against the varied parameter "
                   "(one --vary) or as a map over two")
    s.add_argument("--quantity", metavar="KEY", help="the plotted column, e.g. q.x, margin, "
                   "qddot.x, events.count, exit_code (default: a natural one for --what)")
    s.add_argument("--t-end", type=float, default=None, help="simulate: end time")
    s.add_argument("--at", help="evaluate, realizability, stability: the state (default: the "
                   "model's initial state at each point)")
    s.add_argument("--about", choices=("equilibrium", "steady"), default=None,
                   help="stability: the motion linearized about at each point (default "
                   "equilibrium; --at gives the state or the guess)")
    s.add_argument("--form", default=None, type=form_type(ctx.solvers), metavar="FORM",
                   help="simulate, evaluate: " + ctx.solver_help)
    s.add_argument("--rtol", type=float, help="simulate: relative tolerance")
    s.add_argument("--atol", type=float, help="simulate: absolute tolerance")
    s.add_argument("--method", type=method_type, metavar="METHOD",
                   help=f"simulate: integrator, one of {', '.join(METHODS)}")
    s.add_argument("--no-progress", action="store_true", help="no progress bar on a terminal")
    s.set_defaults(func=run)


def model_file(spec: str) -> Path:
    """The model file of a path or of a gallery example's name (the same errors as every
    command for anything else)."""
    from ..modeling.modelfile import load_model
    from .common import model_path

    path = model_path(spec)      # not found: the command line's error, with the nearest names
    if not path.is_file():
        load_model(path)         # says what it is instead (a directory, ...)
        raise ModelError(f"{spec}: not a model file")  # pragma: no cover
    return path


def _journal_path(args) -> Path:
    out = args.json or args.csv or args.parquet
    return Path(out).with_name(Path(out).name + JOURNAL_SUFFIX)


def _read_journal(path: Path, header: dict) -> list[dict]:
    rows = []
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    if not lines:
        return rows
    try:
        first = json.loads(lines[0])
    except json.JSONDecodeError:
        raise ModelError(f"--resume: {path} is not a sweep journal (its first line is not JSON); "
                         "remove it, or drop --resume to start again") from None
    if first.get("sweep") != header:
        diff = [k for k in header if first.get("sweep", {}).get(k) != header[k]]
        raise ModelError(f"--resume: {path} journals another sweep (its {', '.join(diff) or 'header'} "
                         "differ); give the same model, --what, --set and options, or remove "
                         "the journal to start again")
    for k, line in enumerate(lines[1:], start=2):
        try:
            row = json.loads(line)
        except json.JSONDecodeError:
            if k != len(lines):   # only the last line can be cut short by an interruption
                raise ModelError(f"--resume: {path}, line {k}: not a JSON row; the journal is "
                                 "damaged (remove it to start again)") from None
            continue
        if not (isinstance(row, dict) and isinstance(row.get("parameters"), dict)):
            raise ModelError(f"--resume: {path}, line {k}: a row without its 'parameters' (the "
                             "point it belongs to); the journal is damaged (remove it to start "
                             "again)")
        rows.append(row)
    return rows


def _previous_rows(args, header: dict) -> list[dict]:
    """Rows of an earlier complete JSON output of the same sweep (its grid may differ)."""
    if not args.json or not Path(args.json).is_file():
        return []
    try:
        data = json.loads(Path(args.json).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    if data.get("model") != header["model_name"] or data.get("what") != header["what"]:
        return []
    return [r for r in data.get("rows", []) if isinstance(r, dict) and "parameters" in r]


class _Progress:
    """A one-line progress bar on standard error (only on a terminal)."""

    def __init__(self, total: int, done: int, enabled: bool):
        self.total, self.done, self.failed = total, done, 0
        self.enabled = enabled
        self.start = time.perf_counter()
        self.new = 0
        self.last = 0.0

    def __call__(self, row: dict) -> None:
        self.done += 1
        self.new += 1
        self.failed += row["exit_code"] != 0
        now = time.perf_counter()
        if self.enabled and (now - self.last > 0.1 or self.done == self.total):
            self.last = now
            rate = self.new / max(now - self.start, 1e-9)
            eta = (self.total - self.done) / rate if rate > 0 else float("inf")
            width = 30
            fill = int(width * self.done / max(self.total, 1))
            sys.stderr.write(f"\r[{'#' * fill}{'.' * (width - fill)}] {self.done}/{self.total} "
                             f"points, {self.failed} failed, {rate:.3g}/s, ETA {eta:.0f} s ")
            sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")


def run(args) -> int:
    from ..analysis.studies.sweep import check_grid, parse_vary, sweep, SweepTask

    check_options(args)
    if not args.vary:
        raise ModelError("sweep: nothing varies; give at least one --vary NAME=START:STOP:N, "
                         "e.g. --vary mu=0.1:0.9:9")
    problems = []
    axes = []
    for item in args.vary:
        try:
            axes.append(parse_vary(item))
        except ModelError as exc:
            problems += exc.problems
    if axes and not problems:
        try:  # before anything is written: no journal of a grid refused at once
            check_grid(axes)
        except ModelError as exc:
            problems += exc.problems
    if args.parquet:
        try:
            import pyarrow.parquet  # noqa: F401
        except ImportError:
            problems.append("--parquet: needs pyarrow, which is not installed: pip install "
                            "'nonideal[parquet]' (or pyarrow), or write --csv or --json")
    if "-" in (args.json, args.csv, args.parquet):
        problems.append("--json/--csv/--parquet: give a file name (the sweep journals every finished point "
                        "next to it, OUT.journal, for --resume)")
    if args.workers is not None and args.workers < 1:
        problems.append(f"--workers: must be at least 1 (got {args.workers})")
    if args.plot and len(axes) > 2:
        problems.append(f"--plot: draws one quantity against one parameter or as a map over two; "
                        f"{len(axes)} are varied")
    simulate_only = [o for o in ("t_end", "rtol", "atol", "method") if getattr(args, o) is not None]
    if args.what != "simulate" and simulate_only:
        problems += [f"--{o.replace('_', '-')}: an option of --what simulate" for o in simulate_only]
    if args.at and args.what not in ("evaluate", "realizability", "stability"):
        problems.append("--at: an option of --what evaluate, realizability or stability")
    if args.about and args.what != "stability":
        problems.append("--about: an option of --what stability")
    if problems:
        raise ModelError(problems)
    settings = parse_overrides(args.set)
    options = {}
    for key in ("t_end", "rtol", "atol", "method", "form", "about"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    if args.at:
        from .common import load_spec

        options["at"] = parse_at(load_spec(args.model, args.set), args.at)
    journal = _journal_path(args)
    model_path = str(model_file(args.model).resolve())
    task = SweepTask(model_path, args.what, tuple(sorted(settings.items())),
                     tuple(sorted(options.items())))
    header = {**task.header(), "vary": {a.name: list(a.values) for a in axes}}
    header.pop("vary")
    done = []
    if args.resume:
        if journal.exists():
            done = _read_journal(journal, header)
        done = _previous_rows(args, {**header, "model_name": _model_name(args)}) + done
    elif journal.exists():
        raise ModelError(f"{journal}: the journal of an interrupted sweep to the same output; "
                         "add --resume to complete it, or remove the file to start again")
    n_points = 1
    for a in axes:
        n_points *= len(a.values)
    progress = _Progress(n_points, 0, sys.stderr.isatty() and not args.no_progress)
    journal_file = []   # opened at the first finished point: a sweep refused up front leaves none

    def on_row(row):
        if not journal_file:
            journal.parent.mkdir(parents=True, exist_ok=True)
            fh = open(journal, "a", encoding="utf-8")
            if fh.tell() == 0:
                fh.write(json.dumps({"sweep": header}) + "\n")
            journal_file.append(fh)
        journal_file[0].write(json.dumps(row, allow_nan=True) + "\n")
        journal_file[0].flush()
        progress(row)

    resumed = len(done)
    try:
        if args.plot and args.quantity:
            # the plotted column is checked on the first point before the others run (a
            # mistyped --quantity would fail only after the whole sweep)
            probe = _check_quantity(args, model_path, axes, settings, options, done)
            for row in probe:       # journaled once the column is known to be there
                on_row(row)
            done = done + probe
        result = sweep(model_path, axes, args.what, settings=settings, options=options,
                       workers=args.workers, scheduler=args.scheduler, done=done, on_row=on_row)
    except (KeyboardInterrupt, Terminated) as exc:
        if journal_file:    # the finished points are kept: say how to complete the sweep
            kind = "interrupted" if isinstance(exc, KeyboardInterrupt) else "terminated"
            with contextlib.suppress(Exception):
                print(f"nonideal: sweep {kind} after {progress.done} of {n_points} points; the "
                      f"finished ones are journaled in {journal}: run the same command with "
                      "--resume to complete it (no output was written)", file=sys.stderr)
            return EXIT_INTERRUPTED if kind == "interrupted" else EXIT_TERMINATED
        raise
    finally:
        for fh in journal_file:
            fh.close()
        progress.close()
    outputs = Outputs()
    if args.json:
        text = json.dumps(result.to_dict(), indent=1, allow_nan=True)
        outputs.add("--json", args.json, lambda tmp: Path(tmp).write_text(text + "\n"))
    if args.csv:
        outputs.add("--csv", args.csv, result.to_csv)
    if args.parquet:
        outputs.add("--parquet", args.parquet, result.to_parquet)
    if args.plot:
        from ..plotting import plot_sweep

        outputs.add("--plot", args.plot, lambda tmp: plot_sweep(result, tmp, args.quantity))
    outputs.commit()
    journal.unlink(missing_ok=True)
    failed = result.failed
    print(f"{result.model}: {args.what} at {len(result.rows)} points "
          f"({len(result.rows) - resumed} run, "
          f"{len(failed)} failed) in {result.elapsed:.3g} s on {result.workers} worker"
          f"{'s' if result.workers > 1 else ''}")
    codes = {}
    for r in failed:
        codes.setdefault(r["exit_code"], r)
    for code, r in sorted(codes.items()):
        n = sum(1 for x in failed if x["exit_code"] == code)
        print(f"  exit {code} at {n} point{'s' if n > 1 else ''}, e.g. {r['parameters']}: "
              f"{r['message'].splitlines()[0]}")
    return 0


def _check_quantity(args, model_path, axes, settings, options, done) -> list[dict]:
    """Run the grid's first point (unless *done* has it) and refuse a ``--quantity`` that is not
    one of its columns (nothing journaled then); the new row is returned to be reused."""
    from ..analysis.studies.sweep import Axis, flatten, point_key, sweep

    first = [Axis(a.name, (a.values[0],)) for a in axes]
    key = point_key({a.name: a.values[0] for a in axes})
    rows = [r for r in done if point_key(r["parameters"]) == key]
    new = []
    if not rows:
        rows = sweep(model_path, first, args.what, settings=settings, options=options, workers=1).rows
        new = rows
    row = rows[0]
    columns = flatten(row)
    if row.get("exit_code") == 0 and args.quantity not in columns:
        names = sorted(columns)
        raise ModelError(f"--quantity {args.quantity}: not a column of this sweep"
                         f"{did_you_mean(args.quantity, names)}; columns: {', '.join(names)}")
    return new


def _model_name(args) -> str:
    from .common import load_spec

    return load_spec(args.model, args.set).name
