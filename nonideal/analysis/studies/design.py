"""Design on top of the sweep: the minimum of Briskin's criterion ``I = |A| + chi W``
(Briskin et al. 2021, (3.10)) over some parameters of a model -- a sweep over a grid finds the
best point, ``scipy.optimize.minimize`` (Nelder-Mead) polishes it, every evaluation on the
same compiled model (:mod:`nonideal.analysis.studies.sweep`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ...errors import ModelError
from .quasi_ideal import criterion

__all__ = ["CriterionMinimum", "minimize_criterion"]


@dataclass
class CriterionMinimum:
    """The minimum of ``I = |A| + chi W`` over some parameters."""

    names: tuple[str, ...]
    x: dict[str, float]
    value: float
    work: float
    heat: float
    grid_best: dict[str, float]
    grid_value: float
    evaluations: int
    message: str
    sweep: Any = field(default=None, repr=False)

    def to_dict(self) -> dict:
        return {"parameters": self.x, "criterion": self.value, "work": self.work,
                "heat": self.heat, "grid_best": {"parameters": self.grid_best,
                                                 "criterion": self.grid_value},
                "evaluations": self.evaluations, "message": self.message}


def minimize_criterion(model: str, axes, chi: float = 1.0, settings: Mapping[str, str] | None = None,
                       t_end: float | None = None, workers: int | None = 1,
                       bounds: bool = True) -> CriterionMinimum:
    """Minimize Briskin's criterion ``I = |A| + chi W`` (Briskin et al. 2021, (3.10)) over the
    parameters of *axes*.

    A sweep over the grid of *axes* (``--what simulate``: every point's work of the reactions
    and actuator heat, :func:`~nonideal.analysis.studies.sweep.sweep`) gives the best grid point;
    ``scipy.optimize.minimize`` (Nelder-Mead, bounded by the grid's range) starts there.
    Points where the motion is impossible (a singular transform) count as ``+inf``.

    Parameters
    ----------
    model : str or Path
        A model file whose constraints have ``losses``.
    axes : sequence of Axis
        The parameters and the grid of the first search.
    chi : float
        The weight of the heat.
    """
    from scipy.optimize import minimize

    from .sweep import sweep
    from .sweep_points import SweepTask, runner_for

    options = {"t_end": t_end} if t_end is not None else {}
    result = sweep(model, axes, "simulate", settings=settings, options=options, workers=workers)

    def value(row) -> float:
        if row["exit_code"] != 0 or "actuator_heat" not in row["summary"]:
            return np.inf
        s = row["summary"]
        return criterion(s["reaction_work"], s["actuator_heat"], chi)

    values = [value(r) for r in result.rows]
    best = int(np.argmin(values))
    if not np.isfinite(values[best]):
        raise ModelError("minimize_criterion: the motion failed at every grid point, or the "
                         "model has no loss coefficients (losses = [...] in [[constraints]])")
    names = tuple(a.name for a in axes)
    start = np.array([result.rows[best]["parameters"][n] for n in names])
    runner = runner_for(SweepTask(result.spec, "simulate",
                                  tuple(sorted((settings or {}).items())),
                                  tuple(sorted(options.items()))))
    count = [0]
    last = {}

    def objective(x):
        count[0] += 1
        row = runner.run(dict(zip(names, map(float, x))))
        v = value(row)
        if np.isfinite(v):
            last[tuple(x)] = row["summary"]
        return v if np.isfinite(v) else 1e300

    box = [(min(a.values), max(a.values)) for a in axes] if bounds else None
    res = minimize(objective, start, method="Nelder-Mead", bounds=box,
                   options={"xatol": 1e-6, "fatol": 1e-10, "maxiter": 600})
    s = runner.run(dict(zip(names, map(float, res.x))))["summary"]
    return CriterionMinimum(names, dict(zip(names, map(float, res.x))), float(res.fun),
                            float(s["reaction_work"]), float(s["actuator_heat"]),
                            dict(zip(names, map(float, start))), float(values[best]),
                            count[0] + len(values), str(res.message), result)
