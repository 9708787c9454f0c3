"""One point of a sweep: :class:`PointRunner` runs a command at a point of parameter values
in a worker process, with the model read, derived and compiled once per process
(:func:`run_chunk`, the function every local or Dask worker calls), and summarizes the result
in a row ``{"parameters", "exit_code", "message", "summary"}``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Mapping, Sequence

from ...errors import ModelError, NonidealError

__all__ = ["SweepTask", "PointRunner", "runner_for", "run_chunk", "simulation_summary", "WHATS",
           "stability_available", "STABILITY_MISSING"]

WHATS = ("simulate", "evaluate", "realizability", "stability", "check")

# ------------------------------------------------------------------------------ one point


@dataclass(frozen=True)
class SweepTask:
    """What every worker needs to run points: picklable, hashable.

    Attributes
    ----------
    model : str
        A model file (absolute path).
    what : str
        The command summarized at each point (:data:`WHATS`).
    settings : tuple of (name, value)
        Fixed ``--set`` overrides, applied before the point's values.
    options : tuple of (name, value)
        The command's options: ``t_end``, ``form``, ``rtol``, ``atol``, ``method`` (simulate),
        ``at`` (a state for evaluate/realizability/stability), ``about`` (stability).
    """

    model: str
    what: str
    settings: tuple = ()
    options: tuple = ()

    def header(self) -> dict:
        return {"model": self.model, "what": self.what, "settings": dict(self.settings),
                "options": dict(self.options)}


_RUNNERS: dict[SweepTask, "PointRunner"] = {}


def runner_for(task: SweepTask) -> "PointRunner":
    """The :class:`PointRunner` of *task* in this process, made on the first call and kept
    (a forked worker inherits its parent's)."""
    runner = _RUNNERS.get(task)
    if runner is None:
        if len(_RUNNERS) > 8:
            _RUNNERS.clear()
        runner = _RUNNERS[task] = PointRunner(task)
    return runner


def run_chunk(task: SweepTask, points: Sequence[Mapping[str, float]]) -> list[dict]:
    """Run *points* of *task* in this process (a local worker or a Dask worker): the rows."""
    runner = runner_for(task)
    return [runner.run(p) for p in points]


def _error_row(parameters, exc: BaseException) -> dict:
    if isinstance(exc, NonidealError):
        code, message = exc.exit_code, str(exc)
    else:
        code = 1
        message = (f"internal error: {type(exc).__name__}: {exc} (please report it with the "
                   "model file and the parameters)")
    return {"parameters": dict(parameters), "exit_code": int(code), "message": message,
            "summary": {}}


class PointRunner:
    """Runs the points of one :class:`SweepTask` in one process.

    The model is read and its equations derived and compiled on creation; :meth:`run` then
    evaluates a point with its parameter values passed as numbers (``parameters=`` of
    :func:`~nonideal.simulation.hybrid.simulate` and friends) and the initial values
    recomputed from them -- unless a varied parameter also sets something that is not a
    number of the equations (then each point's model is rebuilt: correct, slower).
    """

    def __init__(self, task: SweepTask):
        from ...modeling.modelfile import load_model

        self.task = task
        self.what = task.what
        self.options = dict(task.options)
        self.settings = dict(task.settings)
        self.path = self._path(task.model)
        self.base = load_model(self.path, parameters=self.settings or None)
        self._raw = None
        self._fast: dict[tuple, bool] = {}
        self._initial = None

    @staticmethod
    def _path(spec: str) -> Path:
        path = Path(spec)
        if not path.is_file():
            raise ModelError(f"model file not found: {spec}; check the path (relative to "
                             f"{Path.cwd()})")
        return path

    # ---------------------------------------------------------------- parameters of a point
    def _raw_parameters(self) -> dict:
        if self._raw is None:
            import tomllib

            from ...modeling.limits import read_text

            data = tomllib.loads(read_text(self.path).removeprefix("\ufeff"))
            self._raw = data
        return self._raw

    def values(self, point: Mapping[str, float]) -> dict[str, float]:
        """Every parameter's value at *point* (derived parameters re-evaluated)."""
        from ...modeling.model import resolve_parameters
        from ...modeling.modelfile import override_parameters

        data = override_parameters(self._raw_parameters(), {**self.settings, **point},
                                   str(self.path))
        raw = {k: (v["value"] if isinstance(v, dict) else v)
               for k, v in data.get("parameters", {}).items()}
        values, problems = resolve_parameters(raw)
        if problems:
            raise ModelError(problems, str(self.path))
        return values

    def initial(self, values: Mapping[str, float]) -> dict[str, float]:
        """The model's initial values evaluated with the parameter *values*."""
        if self._initial is None:
            import sympy as sp

            symbols = [sp.Symbol(n) for n in self.base.parameters]
            keys = list(self.base.initial)
            exprs = [sp.sympify(self.base.initial[k]) for k in keys]
            self._initial = (keys, sp.lambdify(symbols, exprs, "math"))
        keys, fn = self._initial
        numbers = fn(*(values[n] for n in self.base.parameters))
        return {k: float(v) for k, v in zip(keys, numbers)}

    def fast(self, names: tuple[str, ...]) -> bool:
        """Whether varying *names* changes only numbers of the equations and the initial
        values (then the compiled model serves every point): the model rebuilt at a perturbed
        point must equal the base model up to its parameter values."""
        hit = self._fast.get(names)
        if hit is None:
            from ...modeling.modelfile import load_model

            base = self.values({})
            probe = {n: repr(base[n] * 1.2345678901 + 0.3141592653) for n in names}
            try:
                other = load_model(self.path, parameters={**self.settings, **probe})
                hit = other.replace(parameters=self.base.parameters) == self.base
            except NonidealError:
                hit = False
            self._fast[names] = hit
        return hit

    # ---------------------------------------------------------------- a point
    def run(self, point: Mapping[str, float]) -> dict:
        """The row of *point*: ``{"parameters", "exit_code", "message", "summary"}``."""
        import warnings

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                summary = self._summary(point)
        except Exception as exc:   # noqa: BLE001 -- a failing point is recorded, the sweep goes on
            return _error_row(point, exc)
        return {"parameters": dict(point), "exit_code": 0, "message": "ok", "summary": summary}

    def _summary(self, point: Mapping[str, float]) -> dict:
        from ...modeling.modelfile import load_model

        names = tuple(sorted(point))
        if self.fast(names):
            model = self.base
            values = self.values(point)
            initial = self.initial(values)
        else:
            model = load_model(self.path, parameters={**self.settings,
                                                      **{k: repr(float(v)) for k, v in point.items()}})
            values, initial = None, None
        return getattr(self, "_" + self.what)(model, values, initial)

    def _simulate(self, model, values, initial) -> dict:
        from ...simulation.hybrid import simulate

        opts = {k: self.options[k] for k in ("rtol", "atol", "method") if k in self.options}
        t_end = self.options.get("t_end")
        times = None
        lossy = any(c.losses is not None for c in model.constraints)
        if lossy:   # the actuators' heat is integrated on a dense uniform sampling
            import numpy as np

            from .quasi_ideal import HEAT_SAMPLES

            end = t_end if t_end is not None else model.simulation.t_end
            times = np.linspace(model.t0, float(end), HEAT_SAMPLES) if end is not None else None
        if times is None:   # the summary reads the final state, the events and the works
            opts["grid"] = 2  # integrated with the motion: no samples between (their cost)
        traj = simulate(model, t_end=t_end, times=times, form=self.options.get("form", "lagrange1"),
                        parameters=values, initial=initial, **opts)
        summary = simulation_summary(traj)
        if lossy:
            from .quasi_ideal import actuator_heat

            summary["actuator_heat"] = float(actuator_heat(model, traj, values)["total"][-1])
        return summary

    def _state(self, initial):
        at = dict(initial or {})
        at.update(self.options.get("at") or {})
        return at or None

    def _evaluate(self, model, values, initial) -> dict:
        from ..evaluation import evaluate

        ev = evaluate(model, at=self._state(initial), form=self.options.get("form", "lagrange1"),
                      parameters=values)
        d = ev.to_dict()
        out = {"qddot": d["qddot"], "multipliers": d["multipliers"]}
        if d.get("contacts"):
            out["contacts"] = {name: {"mode": c.get("mode"), "normal": c.get("normal")}
                               for name, c in d["contacts"].items()}
        return out

    def _realizability(self, model, values, initial) -> dict:
        from ..contact.realizability import realizability

        report = realizability(model, at=self._state(initial), parameters=values)
        margins = {name: c.margin for name, c in report.contacts.items()}
        return {"margin": min(margins.values()) if margins else None,
                "realizable": report.realizable, "margins": margins}

    def _check(self, model, values, initial) -> dict:
        from ..checks import check_model

        if values is not None:   # check the point's own model: its numbers matter here
            from ...modeling.modelfile import load_model

            model = load_model(self.path, parameters={**self.settings, **{
                k: repr(float(v)) for k, v in values.items() if k in model.parameters}})
        d = check_model(model).to_dict()
        return {"determinacy": d["determinacy"], "dof": d["counts"].get("dof"),
                "initial_mode": d["initial_mode"]}

    def _stability(self, model, values, initial) -> dict:
        from ...modeling.modelfile import load_model
        from ..stability.linearize import linearize

        if values is not None:   # the linearization is symbolic: the point's own model
            model = load_model(self.path, parameters={**self.settings, **{
                k: repr(float(v)) for k, v in values.items() if k in self.base.parameters}})
        lin = linearize(model, about=self.options.get("about", "equilibrium"),
                        at=dict(self.options["at"]) if self.options.get("at") else None)
        d = lin.to_dict()
        return {"verdict": d["verdict"], "eigenvalues": d["eigenvalues"],
                "state": d["state"]}


#: the message of ``--what stability`` while the stability analysis is not part of the library
STABILITY_MISSING = ("sweep --what stability: the stability analysis is not available in this "
                     "version of nonideal; sweep simulate, evaluate, realizability or check")


def stability_available() -> bool:
    """Whether ``--what stability`` can run (:mod:`nonideal.analysis.stability.linearize`)."""
    import importlib.util

    return importlib.util.find_spec("nonideal.analysis.stability.linearize") is not None


def simulation_summary(traj) -> dict:
    """The sweep's summary of a :class:`~nonideal.simulation.trajectory.Trajectory`: the
    final state, the events (time, type, contact or constraint, mode) and the heat of
    friction (``-friction_work``, >= 0), with the work of the reactions."""
    events = []
    for e in traj.events:
        item = {"t": float(e["t"]), "type": e["type"]}
        for key in ("contact", "constraint", "mode"):
            if key in e:
                item[key] = e[key]
        events.append(item)
    energy = traj.energy
    out = {"t_end": float(traj.t[-1]),
           "q": {c: float(traj.q[-1, k]) for k, c in enumerate(traj.coordinates)},
           "qdot": {c: float(traj.qd[-1, k]) for k, c in enumerate(traj.coordinates)},
           "events": events,
           "friction_heat": 0.0 - float(energy["friction_work"][-1]) if "friction_work" in energy else 0.0}
    if "reaction_work" in energy:
        out["reaction_work"] = float(energy["reaction_work"][-1])
    return out
