"""Parameter sweeps: one command's summary at every point of a grid of parameter values.

:func:`sweep` runs a command -- ``simulate``, ``evaluate``, ``realizability``, ``stability`` or
``check`` -- at every point of a grid (:class:`Axis`, :func:`grid`) and returns a
:class:`SweepResult`, one row per point: its parameters, its exit code and message (0 and
``"ok"``, or the code and the message the command would have given: 2 bad input, 3 no
consistent or unique motion) and the command's summary.  A point that fails is recorded and the
sweep goes on.

The points run in parallel: in local processes by default, on a Dask cluster with
``scheduler=ADDRESS`` (``dask.distributed``; the same function runs every chunk of points on
either).  Each worker process reads the model and derives and compiles its equations once
(:class:`PointRunner`, cached per process); a point then costs one evaluation or simulation
with the point's parameter values passed numerically.  Where a varied parameter enters the
model other than as a number of the equations (an end time, a restitution, a derived value
that sets a tolerance), the point's model is rebuilt instead -- decided once per worker by
building the model at a perturbed point and comparing.

Every finished row is handed to ``on_row`` at once (the command line appends it to a journal
next to the output), so an interrupted sweep can be completed: pass the finished rows as
``done`` and only the missing points run.
"""

from __future__ import annotations

import itertools
import math
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from ...errors import ModelError, did_you_mean
from .sweep_points import WHATS, PointRunner, SweepTask, run_chunk, runner_for

__all__ = ["Axis", "parse_vary", "grid", "point_key", "SweepTask", "PointRunner", "SweepResult",
           "sweep", "run_chunk", "flatten", "WHATS", "MAX_POINTS", "check_grid"]


# ------------------------------------------------------------------------------ the grid


@dataclass(frozen=True)
class Axis:
    """One varied parameter and its values (in the order they are swept)."""

    name: str
    values: tuple[float, ...]

    @classmethod
    def linspace(cls, name: str, start: float, stop: float, n: int) -> "Axis":
        """``n`` equally spaced values from ``start`` to ``stop`` (both included)."""
        if n == 1:
            return cls(name, (float(start),))
        return cls(name, tuple(float(v) for v in np.linspace(start, stop, n)))


MAX_POINTS = 1_000_000
"""Points of a sweep's grid at most (a million runs of even a millisecond each are a quarter of
an hour of processor time; the journal and the output grow with every point)."""


def check_grid(axes: Sequence[Axis]) -> None:
    """Refuse a grid of more than :data:`MAX_POINTS` points, from the sizes of its axes (the
    grid itself is never built for that)."""
    total = math.prod(len(a.values) for a in axes)
    if total > MAX_POINTS:
        sizes = " x ".join(f"{len(a.values)} ({a.name})" for a in axes)
        raise ModelError(f"--vary: the grid has {sizes} = {total:.3g} points, more than "
                         f"{MAX_POINTS:,} (the limit); sweep fewer values, or split the sweep")


def parse_vary(text: str) -> Axis:
    """``NAME=START:STOP:N`` (N values, both ends included) or ``NAME=V1,V2,...`` (a list).

    Examples
    --------
    >>> parse_vary("mu=0:1:3")
    Axis(name='mu', values=(0.0, 0.5, 1.0))
    >>> parse_vary("theta=0.1,0.2")
    Axis(name='theta', values=(0.1, 0.2))
    """
    example = "e.g. --vary mu=0.1:0.9:9 or --vary mu=0.1,0.3,0.5"
    name, eq, rest = text.partition("=")
    name, rest = name.strip(), rest.strip()
    if not eq or not name or not rest:
        raise ModelError(f"--vary {text}: expected NAME=START:STOP:N or NAME=V1,V2,...; {example}")
    if not name.isidentifier():
        raise ModelError(f"--vary {text}: '{name}' is not a parameter name; {example}")
    if ":" in rest:
        parts = [p.strip() for p in rest.split(":")]
        if len(parts) != 3:
            raise ModelError(f"--vary {text}: a range has three parts START:STOP:N (got "
                             f"{len(parts)}); {example}")
        try:
            start, stop = float(parts[0]), float(parts[1])
        except ValueError:
            raise ModelError(f"--vary {text}: START and STOP must be numbers; {example}") from None
        try:
            n = int(parts[2])
        except ValueError:
            raise ModelError(f"--vary {text}: N must be a whole number of values (got "
                             f"'{parts[2]}'); {example}") from None
        if n < 1:
            raise ModelError(f"--vary {text}: N must be at least 1 (got {n})")
        if n > MAX_POINTS:  # before the values are made: 1e10 of them do not fit in memory
            raise ModelError(f"--vary {text}: N = {n:.3g} values, more than {MAX_POINTS:,} "
                             "points in all (the limit); sweep fewer values")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise ModelError(f"--vary {text}: START and STOP must be finite numbers")
        return Axis.linspace(name, start, stop, n)
    if rest.count(",") >= MAX_POINTS:
        raise ModelError(f"--vary {name}: more than {MAX_POINTS:,} values (the limit); sweep fewer")
    values = []
    for p in rest.split(","):
        try:
            v = float(p)
        except ValueError:
            raise ModelError(f"--vary {text}: '{p.strip()}' is not a number; {example}") from None
        if not math.isfinite(v):
            raise ModelError(f"--vary {text}: '{p.strip()}' is not a finite number")
        values.append(v)
    return Axis(name, tuple(values))


def grid(axes: Sequence[Axis]) -> list[dict[str, float]]:
    """Every combination of the axes' values, the first axis varying slowest."""
    names = [a.name for a in axes]
    seen = [n for n in dict.fromkeys(names) if names.count(n) > 1]
    if seen:
        raise ModelError([f"--vary {n}: given {names.count(n)} times; vary each parameter once"
                          for n in seen])
    check_grid(axes)
    return [dict(zip(names, combo)) for combo in itertools.product(*(a.values for a in axes))]


def point_key(parameters: Mapping[str, float]) -> tuple:
    """A point's identity (its parameter values, rounded to 12 significant digits: a value
    read back from a journal or a CSV is the same point)."""
    return tuple(sorted((k, float(f"{float(v):.12g}")) for k, v in parameters.items()))


# ------------------------------------------------------------------------------ the sweep


@dataclass
class SweepResult:
    """The rows of a sweep, in grid order.  ``to_dict()`` is the JSON of ``nonideal sweep``."""

    model: str
    what: str
    axes: tuple[Axis, ...]
    rows: list[dict]
    elapsed: float = 0.0
    workers: int = 1
    spec: str = ""

    def to_dict(self) -> dict:
        return {"model": self.model, "what": self.what,
                "vary": {a.name: list(a.values) for a in self.axes}, "rows": self.rows}

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.rows if r["exit_code"] != 0]

    def column(self, key: str) -> np.ndarray:
        """A flattened column (``"q.x"``, ``"margin"``, ``"exit_code"``, a parameter name) as an
        array over the rows (NaN where a row has no value)."""
        out = []
        for r in self.rows:
            v = flatten(r).get(key)
            out.append(np.nan if v is None or isinstance(v, str) else float(v))
        return np.array(out, dtype=float)

    def to_csv(self, path) -> None:
        import csv

        flat = [flatten(r) for r in self.rows]
        columns = [a.name for a in self.axes] + ["exit_code", "message"]
        for f in flat:
            columns += [k for k in f if k not in columns]
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(columns)
            for f in flat:
                w.writerow(["" if f.get(c) is None else _csv_value(f[c]) for c in columns])


def _csv_value(v):
    if isinstance(v, float):
        return repr(v)
    return v


def flatten(row: Mapping[str, Any]) -> dict[str, Any]:
    """A row as one level of columns: the parameters by name, ``exit_code``, ``message``, the
    summary's nested keys joined by dots (``q.x``, ``qdot.x``, ``multipliers.rod``); the events
    as ``events`` = ``"type@t;..."``, ``events.count`` and ``events.first`` (the first one's
    type, ``"none"``); a list of numbers as ``key.0``, ``key.1`` ..."""
    out: dict[str, Any] = dict(row.get("parameters", {}))
    out["exit_code"] = row.get("exit_code")
    out["message"] = row.get("message")

    def walk(prefix: str, value):
        if isinstance(value, Mapping):
            for k, v in value.items():
                walk(f"{prefix}.{k}" if prefix else str(k), v)
        elif prefix == "events" and isinstance(value, list):
            out["events"] = ";".join(f"{e.get('type')}@{e.get('t'):.10g}" for e in value)
            out["events.count"] = len(value)
            out["events.first"] = value[0].get("type") if value else "none"
        elif isinstance(value, (list, tuple)):
            for k, v in enumerate(value):
                walk(f"{prefix}.{k}", v)
        else:
            out[prefix] = value

    walk("", row.get("summary", {}))
    return out


def _chunks(points: list, size: int) -> list[list]:
    return [points[k:k + size] for k in range(0, len(points), size)]


def sweep(model: str, axes: Sequence[Axis], what: str = "simulate", *,
          settings: Mapping[str, str] | None = None, options: Mapping[str, Any] | None = None,
          workers: int | None = None, scheduler: str | None = None, client=None,
          done: Iterable[dict] = (), on_row: Callable[[dict], None] | None = None,
          chunk: int | None = None) -> SweepResult:
    """Run *what* at every point of the grid of *axes*.

    Parameters
    ----------
    model : str or Path
        A model file (a gallery example's: ``gallery.model_path(name)``).
    axes : sequence of Axis
        The varied parameters (:func:`parse_vary`); the grid is their product.
    what : {"simulate", "evaluate", "realizability", "stability", "check"}
    settings : mapping, optional
        Fixed parameter overrides (``--set``) applied at every point.
    options : mapping, optional
        The command's options (see :class:`SweepTask`).
    workers : int, optional
        Local worker processes (default: the number of CPUs; 1 runs in this process).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``): the points run on its cluster.
    client : dask.distributed.Client, optional
        An existing Dask client (e.g. of a ``LocalCluster``), instead of *scheduler*.
    done : iterable of dict
        Rows already finished (a resumed sweep): their points are not run again.
    on_row : callable, optional
        Called with every new row as soon as it is finished.

    Returns
    -------
    SweepResult
    """
    if what not in WHATS:
        raise ModelError(f"sweep: unknown --what '{what}'{did_you_mean(what, WHATS)}; choose "
                         f"one of {', '.join(WHATS)}")
    axes = tuple(axes)
    if not axes:
        raise ModelError("sweep: nothing varies; give at least one --vary NAME=START:STOP:N")
    spec = str(Path(model).resolve())
    task = SweepTask(spec, what, tuple(sorted((settings or {}).items())),
                     tuple(sorted((k, _freeze(v)) for k, v in (options or {}).items())))
    runner = _validate(task, axes)
    points = grid(axes)
    finished = {point_key(r["parameters"]): r for r in done}
    todo = [p for p in points if point_key(p) not in finished]
    start = time.perf_counter()
    emit = on_row or (lambda row: None)

    def collect(rows):
        for row in rows:
            finished[point_key(row["parameters"])] = row
            emit(row)

    n_workers = 1
    if todo:
        if client is not None or scheduler is not None:
            n_workers = _run_dask(task, todo, collect, scheduler, client, chunk)
        else:
            n_workers = max(1, min(workers or os.cpu_count() or 1, len(todo)))
            _run_local(task, todo, collect, n_workers, chunk)
    rows = [finished[point_key(p)] for p in points]
    return SweepResult(runner.base.name, what, axes, rows, time.perf_counter() - start,
                       n_workers, spec)


def _freeze(value):
    if isinstance(value, Mapping):
        return tuple(sorted(value.items()))
    if isinstance(value, list):
        return tuple(value)
    return value


def _validate(task: SweepTask, axes: Sequence[Axis]) -> "PointRunner":
    """The model loads and every varied name is a parameter of it (reported together)."""
    from .sweep_points import STABILITY_MISSING, stability_available

    if task.what == "stability" and not stability_available():
        raise ModelError(STABILITY_MISSING)
    runner = runner_for(task)
    known = list(runner.base.parameters)
    problems = [f"--vary {a.name}: not a parameter of the model{did_you_mean(a.name, known)} "
                f"(its [parameters]: {', '.join(known) or 'none'})"
                for a in axes if a.name not in known]
    clash = [a.name for a in axes if a.name in dict(task.settings)]
    problems += [f"--vary {n}: also given with --set; a parameter is either fixed or varied"
                 for n in clash]
    if problems:
        raise ModelError(problems, str(runner.path))
    return runner


def _chunk_size(n_points: int, n_workers: int, chunk: int | None) -> int:
    if chunk:
        return max(1, int(chunk))
    # a few chunks per worker keep them all busy to the end; at most 16 points wait in one
    return max(1, min(16, n_points // (4 * n_workers) or 1))


def _run_local(task, todo, collect, n_workers: int, chunk) -> None:
    collect(run_chunk(task, todo[:1]))   # derives and compiles here, before the workers start
    todo = todo[1:]
    if n_workers == 1 or not todo:
        for p in todo:
            collect(run_chunk(task, [p]))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # fork where the platform has it: the workers start with this process's runner (the model
    # read, derived and compiled here once); spawn elsewhere (each worker builds its own)
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    size = _chunk_size(len(todo), n_workers, chunk)
    with ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx) as pool:
        futures = [pool.submit(run_chunk, task, c) for c in _chunks(todo, size)]
        try:
            for f in as_completed(futures):
                collect(f.result())
        except BaseException:
            for f in futures:
                f.cancel()
            raise


def _run_dask(task, todo, collect, scheduler, client, chunk) -> int:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise ModelError("--scheduler: Dask is not installed; install the extra: pip install "
                         "'nonideal[sweep]' (dask[distributed])") from None
    own = client is None
    if own:
        try:
            client = Client(scheduler, timeout=30)
        except (OSError, TimeoutError) as exc:
            raise ModelError(f"--scheduler {scheduler}: cannot connect ({exc}); start a "
                             "scheduler (dask scheduler) and workers, or drop --scheduler to run "
                             "on this machine") from None
    try:
        n_workers = max(1, sum(w.get("nthreads", 1) for w in
                               client.scheduler_info().get("workers", {}).values()))
        size = _chunk_size(len(todo), n_workers, chunk)
        chunks = _chunks(todo, size)
        futures = client.map(run_chunk, [task] * len(chunks), chunks, pure=False)
        for f in as_completed(futures):
            collect(f.result())
    finally:
        if own:
            client.close()
    return n_workers
