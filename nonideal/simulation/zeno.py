"""Impacts that accumulate at a finite time (Zeno behaviour), run through.

A ball dropped on a floor with restitution ``0 < e < 1`` bounces infinitely often before a
finite time: from the first impact at ``t_1`` with speed ``v_1`` the flights last
``2 v_1 e^k / g``, a geometric series that accumulates at

    t_inf = t_1 + 2 v_1 e / (g (1 - e)),

after which the ball rests on the floor.  An event-driven simulation cannot step through the
infinitely many impacts; like the hybrid simulators of Siconos (``EventDriven`` with the
accumulation handled by a switch to the contact mode) and Drake, the loop detects the geometric
accumulation and jumps to its limit.

:class:`ImpactSeries` watches the impacts of the run.  A series is the impacts of one
constraint or contact, each leaving the same mode (other events may come between them: a
block bouncing off a wall on a rough incline stops sliding up and reverses between its
impacts).  Once its intervals
``dt_k = t_k - t_{k-1}`` have a ratio ``r = dt_k / dt_{k-1}`` in ``(0, 1)`` that is constant
(to :data:`RATIO_TOL` over the last :data:`STABLE` ratios) and the rest of the series,
``dt_k r / (1 - r)``, is below :data:`REST` times its elapsed span (or the series has
:data:`MAX_IMPACTS` impacts), the limit is extrapolated by the same geometric sum (Aitken's
Delta^2 process, exact for a geometric series):

    t_inf = t_k + dt_k r/(1-r),   q_inf = q_k + (q_k - q_{k-1}) r/(1-r),
    q'_inf(-) = q'_k(-) + (q'_k(-) - q'_{k-1}(-)) r/(1-r)

(``q'(-)``: the velocities before the impacts), and the driver applies the impact law there
and selects the mode (in contact).  The energy lost in the skipped impacts is counted in the
impact work.  The switch is recorded as an event of type ``zeno`` with the number of impacts
simulated, the ratio and the time of the last one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ImpactSeries", "Accumulation", "RATIO_TOL", "STABLE", "REST", "MAX_IMPACTS"]

RATIO_TOL = 1e-3
"""Relative spread of the last interval ratios for a series to count as geometric."""
STABLE = 3
"""Number of consecutive interval ratios that must agree."""
REST = 1e-3
"""Jump when the rest of the series is below this fraction of its elapsed span..."""
MAX_IMPACTS = 200
"""...or once the geometric series has this many impacts."""


@dataclass(frozen=True)
class Accumulation:
    """The limit of a geometric series of impacts."""

    name: str
    t: float
    q: np.ndarray
    qd: np.ndarray  # velocities before the (limit) impact
    ratio: float
    impacts: int
    last: float  # time of the last simulated impact


class ImpactSeries:
    """The impacts of the current series (see the module docstring)."""

    def __init__(self):
        self.reset()

    def reset(self) -> None:
        """Forget the series (any other event ends it)."""
        self.name: str | None = None
        self.after: str | None = None
        self.hits: list[tuple[float, np.ndarray, np.ndarray]] = []  # the last STABLE + 2
        self.count = 0
        self.first = 0.0

    def add(self, name: str, after: str, t: float, q: np.ndarray,
            qd: np.ndarray) -> Accumulation | None:
        """Record an impact of *name* at *t* (the state before the impact) that leaves the
        mode labelled *after*; the limit of the series when it has become geometric and short
        enough to jump to, else None."""
        if (name, after) != (self.name, self.after):
            self.reset()
            self.name, self.after, self.first = name, after, float(t)
        self.count += 1
        self.hits.append((float(t), np.array(q, dtype=float), np.array(qd, dtype=float)))
        del self.hits[:-(STABLE + 2)]
        if len(self.hits) < STABLE + 2:
            return None
        times = np.array([h[0] for h in self.hits])
        dt = np.diff(times)
        if np.any(dt <= 0):
            return None
        ratios = dt[1:] / dt[:-1]
        r = float(ratios[-1])
        if not 0.0 < r < 1.0 or np.ptp(ratios) > RATIO_TOL * r:
            return None
        rest = float(dt[-1]) * r / (1.0 - r)
        if rest > REST * (times[-1] - self.first) and self.count < MAX_IMPACTS:
            return None
        f = r / (1.0 - r)
        (_, q1, v1), (tk, qk, vk) = self.hits[-2], self.hits[-1]
        return Accumulation(name, tk + rest, qk + (qk - q1) * f, vk + (vk - v1) * f, r,
                            self.count, tk)
