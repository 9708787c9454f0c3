"""Impacts that accumulate at a finite time (Zeno behaviour), run through.

A ball dropped on a floor with restitution ``0 < e < 1`` bounces infinitely often before a
finite time: from the first impact at ``t_1`` with speed ``v_1`` the flights last
``2 v_1 e^k / g``, a geometric series that accumulates at

    t_inf = t_1 + 2 v_1 e / (g (1 - e)),

after which the ball rests on the floor.  An event-driven simulation cannot step through the
infinitely many impacts; like the hybrid simulators of Siconos (``EventDriven`` with the
accumulation handled by a switch to the contact mode) and Drake, the loop detects the geometric
accumulation and jumps to its limit.

:class:`ImpactSeries` watches the impacts of the run, one series per constraint or contact
(the impacts of independent balls on their own floors are separate series, each with its own
accumulation, while the others go on).  A series is the impacts of one constraint or contact
that leave it in the same state (other events may come between them: a block bouncing off a
wall on a rough incline stops sliding up and reverses between its impacts).  Once its
intervals ``dt_k = t_k - t_{k-1}`` have a ratio ``r = dt_k / dt_{k-1}`` in ``(0, 1)`` that is
constant (to :data:`RATIO_TOL` over the last :data:`STABLE` ratios), the series is run on as
long as the run can resolve it, and jumped over when it no longer can: when the last flight's
excursion, ``|v_k| dt_k / 4`` (``v_k`` the normal velocity of the impact: the apex of a
parabolic flight), is below :data:`RESOLVE` times the tolerance of the impact's event -- the
remaining flights are shorter and lower still.  A ball with e = 0.99 thus bounces about 800
times, as it does, before it rests: a series that the run still resolves is never cut short.
The limit is extrapolated by the same geometric sum (Aitken's Delta^2 process, exact for a
geometric series):

    t_inf = t_k + dt_k r/(1-r),

and the state at the limit (the velocities ``q'(-)`` before the impacts) by the parabola in
time through the last three impacts: the coordinates of a geometric series are linear in the
impact times (``q_k - q_inf`` and ``t_inf - t_k`` are both proportional to ``r^k``; the
straight line is Aitken's ``q_inf = q_k + (q_k - q_{k-1}) r/(1-r)``), and the coordinates
that take no part in the series (the other balls, in free flight meanwhile) are carried
over the remaining ``dt_k r/(1-r)`` exactly under constant accelerations.  Their own impacts
must not fall between the series' last three, else the series waits.  The driver applies
the impact law at the limit and selects the mode (in contact).  The energy lost in the skipped impacts is counted in the impact work.  The
switch is recorded as an event of type ``zeno`` with the number of impacts simulated, the
ratio and the time of the last one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ImpactSeries", "Accumulation", "RATIO_TOL", "STABLE", "RESOLVE"]

RATIO_TOL = 1e-3
"""Relative spread of the last interval ratios for a series to count as geometric."""
STABLE = 3
"""Number of consecutive interval ratios that must agree."""
RESOLVE = 1e3
"""Jump once the last flight's excursion is below this many times its event's tolerance (a
flight must rise clearly above the tolerance for its landing to be found where it is; the
next two are lower by ``r^2`` and ``r^4``)."""


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


@dataclass
class _Series:
    after: str
    first: float
    count: int = 0
    hits: list = None  # the last STABLE + 2: (t, q, q', whether the previous impact was its own)


class ImpactSeries:
    """The impacts of the run, one series per constraint or contact (see the module docstring)."""

    def __init__(self):
        self.series: dict[str, _Series] = {}
        self.last_name: str | None = None

    def reset(self, name: str | None = None) -> None:
        """Forget the series of *name* (all of them when None)."""
        if name is None:
            self.series.clear()
            self.last_name = None
        else:
            self.series.pop(name, None)

    @property
    def count(self) -> int:
        """Impacts in the series of the last impact."""
        found = self.series.get(self.last_name)
        return found.count if found else 0

    def add(self, name: str, after: str, t: float, q: np.ndarray, qd: np.ndarray,
            speed: float = np.inf, tol: float = 0.0) -> Accumulation | None:
        """Record an impact of *name* at *t* (the state before the impact, its normal *speed*,
        the tolerance *tol* of its event) that leaves *name* in the state *after*; the limit of
        the series when it is geometric and no longer resolved by the run, else None."""
        series = self.series.get(name)
        if series is None or series.after != after:
            series = self.series[name] = _Series(after, float(t), 0, [])
        own = self.last_name == name
        self.last_name = name
        series.count += 1
        series.hits.append((float(t), np.array(q, dtype=float), np.array(qd, dtype=float), own))
        del series.hits[:-(STABLE + 2)]
        if len(series.hits) < STABLE + 2 or not (own and series.hits[-2][3]):
            return None
        times = np.array([h[0] for h in series.hits])
        dt = np.diff(times)
        if np.any(dt <= 0):
            return None
        ratios = dt[1:] / dt[:-1]
        r = float(ratios[-1])
        if not 0.0 < r < 1.0 or np.ptp(ratios) > RATIO_TOL * r:
            return None
        if abs(speed) * float(dt[-1]) / 4 > RESOLVE * tol:
            return None
        rest = float(dt[-1]) * r / (1.0 - r)
        (t0, q0, v0, _), (t1, q1, v1, _), (tk, qk, vk, _) = series.hits[-3:]
        w = _lagrange((t0, t1, tk), tk + rest)
        return Accumulation(name, tk + rest, w[0] * q0 + w[1] * q1 + w[2] * qk,
                            w[0] * v0 + w[1] * v1 + w[2] * vk, r, series.count, tk)


def _lagrange(nodes, x) -> tuple[float, float, float]:
    """The weights of the parabola through three nodes, at *x*: exact for the coordinates of a
    geometric series (linear in the impact times, which are themselves geometric) and for
    the other coordinates under constant accelerations."""
    a, b, c = nodes
    return ((x - b) * (x - c) / ((a - b) * (a - c)), (x - a) * (x - c) / ((b - a) * (b - c)),
            (x - a) * (x - b) / ((c - a) * (c - b)))
