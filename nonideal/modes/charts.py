"""Charts of Lagrange II along a motion: which coordinates are kept, on which branch.

Lagrange II (:mod:`nonideal.equations.formalisms.lagrange2`) solves every ideal holonomic constraint for
one dependent coordinate, ``q_d = phi_d(q_k, t)``.  That is a *chart* of the constraint
manifold: the coordinates kept and, where a constraint has several roots, the branch
(``x = +sqrt(l^2 - y^2)`` or ``-sqrt``).  A chart covers part of the manifold only.  It is
singular where the gradient of the constraints loses its component along the dependent
coordinates (``x = 0`` above: the rod vertical), and a motion that passes there (a pendulum
going over the top) must change charts.  This is the coordinate re-partitioning that the
other reduced forms do (:func:`nonideal.modes.better_partition`), plus the choice of branch.

:class:`Charts` does it for a :class:`~nonideal.modes.solver.ModeSolver` after each evaluation of a
Lagrange II form, from the compiled outputs of the form (:attr:`FormSystem.last
<nonideal.numeric.kernel.FormSystem.last>`, :func:`chart_outputs`):

* the state must lie on the chart's branch (:func:`assess`): the equations read ``q_k``
  only, and on another branch they would give the motion of the mirror state;
* ``R_dk = dphi_d/dq_k`` are the exchange factors ``-X = -G_D^-1 G_I`` of the eliminated
  rows; when one exceeds :data:`CHART_GAIN` the chart is heading for its singularity.  The
  simulation re-partitions at the states the integrator accepts
  (:meth:`Charts.settle`), where the state is on the manifold and both charts give the same
  motion: two charts differ off the manifold (each reads the state through its own kept
  coordinates), so a change at a trial state of a step would put a jump of the size of the
  trial state's distance from the manifold into the step.  Within a step a chart is changed
  only when the state left its branch or its exchange factors exceed
  :data:`SINGULAR_GAIN`.

The new chart keeps the coordinates of :func:`~nonideal.modes.better_partition` (or the
same ones, on the branch of the state).  Charts are cached per (mode structure, kept
coordinates) and shared by the solvers of a model.  A cached chart is reused only if the
state lies on its branch; otherwise a chart is derived through the state (``derive(...,
branch=q)``: of several roots, the one nearest to the state's values).  Where no chart can
be derived (a constraint without closed-form solution for the other coordinates, a root
that ``sympy.solve`` does not return) the motion goes on as far as the current chart allows,
and the error names the chart, the constraint, the coordinate and the state
(:meth:`Charts.explain`), pointing to ``lagrange1`` and ``maggi``.

The first chart is the one ``derive(model, "lagrange2")`` gives, with the coordinates the
user chose to keep (``[forms] independent`` or the ``independent`` option).  That choice is
the first one only: where its chart becomes singular the motion continues on another chart
(no single chart covers a pendulum going over the top), and
``Trajectory.diagnostics["chart_changes"]`` counts the changes.
"""

from __future__ import annotations

import numpy as np
import symengine as se

from ..equations.dynamics import dynamics_of
from ..errors import FormNotApplicable
from .partition import better_partition
from ..numeric.kernel import FormSystem, SingularMatrix

__all__ = ["Charts", "assess", "chart_outputs", "CHART_TOL", "MANIFOLD_TOL", "CHART_GAIN",
           "SINGULAR_GAIN"]

#: residuals of a chart below CHART_TOL (1 + max |q|) put a state on it without further test
#: (the drift the simulation allows is 1e-10)
CHART_TOL = 1e-10

#: constraints below MANIFOLD_TOL max |G| (1 + max |q|) put a state on the manifold (a state
#: completed from the constraints, or projected; not a trial state of the integrator)
MANIFOLD_TOL = 1e-8

#: exchange factors above which the simulation changes charts at an accepted state.  Lower
#: than the other forms' :data:`~nonideal.modes.REPARTITION_GAIN` (4): a change costs nothing
#: there, and it keeps the steps off the singularities.  On the double pendulum in Cartesian
#: coordinates (tests/data/double_pendulum_cartesian.toml, 5 s at rtol 1e-12) the error of
#: the final state is 7e-11 at 2 (16 changes) and 1e-9 at 4 (13 changes): a motion whose rods
#: align within one step crossed a singularity of a chart that had been best at gain 4 a
#: few steps before
CHART_GAIN = 2.0

#: exchange factors above which a chart is changed at any state, not only at accepted ones
SINGULAR_GAIN = 100.0

ON, OTHER, UNKNOWN = 1, -1, 0


def chart_outputs(eom) -> dict[str, list]:
    """The output ``chart`` that :func:`assess` reads, compiled with a Lagrange II form
    (:class:`~nonideal.numeric.kernel.FormSystem`):

    ``[verdict, max |r|, max |f - G_D r|, max |G_D r|, max |f|, max |R_D|, max |q|, sum r,
    max |G|]``

    with the chart's residuals ``r_d = q_d - phi_d(q_k, t)`` (``eom.extras_["chart"]``,
    dependent coordinates ascending; zero on the chart), the eliminated constraints ``f``, their
    gradient ``G`` and ``G_D = df/dq_d`` at the state, and the rows ``R_D = dphi_d/dq_k`` of the
    acceleration map (the exchange factors of the chart).  ``verdict <= 0`` when the state is
    on the chart (first two tests of :func:`assess`) and ``max |R_D| <= SINGULAR_GAIN``: all
    that the right-hand side reads in the common case.  The maxima are compiled; they ignore
    NaN, the sum does not, and ``1e-300 |sum r|`` added to the verdict carries a NaN into it.

    Parameters
    ----------
    eom : EquationsOfMotion
        A Lagrange II form with ``extras_["chart"]``.
    """
    r = list(eom.extras_["chart"])
    dep = [j for j, c in enumerate(eom.model.coordinates) if c not in eom.independent]
    rows = [row for row in eom.rows if row.name in eom.eliminated]
    lin = [sum((row.G[d] * rd for d, rd in zip(dep, r)), se.Integer(0)) for row in rows]
    f = [row.position for row in rows]
    R_D = [eom.R_[d, k] for d in dep for k in range(eom.R_.cols)]

    def largest(values):
        return se.Max(*[se.Abs(v) for v in values]) if values else se.Integer(0)

    r_max, lin_max, gain = largest(r), largest(lin), largest(R_D)
    err = largest([a - b for a, b in zip(f, lin)])
    q_max = largest(dynamics_of(eom.model).q)
    total = sum(r, se.Integer(0))
    verdict = (se.Max(se.Min(r_max - CHART_TOL * (1 + q_max), err - lin_max / 2), gain - SINGULAR_GAIN)
               + se.Float(1e-300) * se.Abs(total))
    return {"chart": [verdict, r_max, err, lin_max, largest(f), gain, q_max, total,
                      largest([g for row in rows for g in row.G])]}


def assess(out: dict) -> tuple[int, float]:
    """On which branch lies the state at which a chart was evaluated, and how well the chart
    is conditioned there: ``(side, gain)`` from its outputs *out* (:func:`chart_outputs`).

    ``side`` is ``ON`` (1) when the residuals ``r = q_d - phi_d`` are below ``CHART_TOL (1 +
    max |q|)``, or when the constraints ``f`` at the state are what the chart's root predicts
    to first order, ``|f - G_D r| <= |G_D r| / 2``; ``OTHER`` (-1) when ``|f| <= |G_D r| /
    2``: the state is near another root; ``UNKNOWN`` (0) between the two.  With two roots a
    distance ``s`` apart (``f`` quadratic in ``q_d``), a state ``delta`` from the chart's root
    is ON for ``delta <= s/4`` and OTHER for ``delta >= 3s/4``.  So the trial states of the
    integrator, up to 1e-2 (relative) off the manifold at rtol 1e-6, are told from states on
    another branch, which no tolerance on ``r`` alone does.  Where the chart is not defined
    (NaN: the state is outside its domain, e.g. ``y2 = y1 - sqrt(l2^2 - (x2 - x1)^2)`` on
    the wrong branch of ``x1``), a state on the manifold (``|f| <= MANIFOLD_TOL max |G| (1 +
    max |q|)``) is OTHER, a trial state off it UNKNOWN.  ``gain`` is ``max |R_D|``, the largest
    exchange factor.
    """
    _, r, err, lin, f, gain, q_max, total, g = out["chart"].tolist()
    if total != total:
        return (OTHER if f <= MANIFOLD_TOL * g * (1.0 + q_max) else UNKNOWN), gain
    if r <= CHART_TOL * (1.0 + q_max) or err <= 0.5 * lin:
        return ON, gain
    return (OTHER if f <= 0.5 * lin else UNKNOWN), gain


class Charts:
    """The charts of Lagrange II that a :class:`~nonideal.modes.solver.ModeSolver` moves through.

    Parameters
    ----------
    solver : ModeSolver
        Its form is ``"lagrange2"``.
    cache : dict
        ``{(mode structure, kept coordinates): [FormSystem, ...]}``, shared per model.

    Attributes
    ----------
    changes : int
        Changes of chart so far.
    refused : dict
        ``{(mode structure, kept coordinates): reason}``: no (further) chart of these is
        derived; the cached ones are still used where the state lies on them.
    """

    def __init__(self, solver, cache: dict):
        self.solver = solver
        self.cache = cache
        self.changes = 0
        self.refused: dict[tuple, str] = {}

    def check(self, mode, fs: FormSystem, Gm: np.ndarray, layout, t: float, q: np.ndarray,
              xb: np.ndarray, settled: bool = False) -> FormSystem | None:
        """``None`` when *fs*, just evaluated at the input *xb*, holds at the state; else the
        chart to use instead.

        Parameters
        ----------
        mode : Mode
        fs : FormSystem
            The current chart of the structure of *mode*, with :func:`chart_outputs`.
        Gm : ndarray, shape (m, n_q)
            The mode's constraint rows at the state.
        layout : list of RowSpec
        t : float
        q : ndarray, shape (n_q,)
        xb : ndarray
            The form's input at the state.
        settled : bool
            The state is one the integrator accepted: re-partition above
            :data:`CHART_GAIN` (else above :data:`SINGULAR_GAIN`).

        Raises
        ------
        FormNotApplicable
            When the state lies on another branch and no chart through it can be derived.
        """
        side, gain = assess(fs.last)
        limit = CHART_GAIN if settled else SINGULAR_GAIN
        if side != OTHER and gain <= limit:
            return None
        coords = list(self.solver.model.coordinates)
        kept = fs.eom.independent
        listed = self.cache.setdefault((mode.structure, kept), [])
        if fs not in listed:
            listed.append(fs)
        options = []
        dep = [j for j, c in enumerate(coords) if c not in kept]
        better = better_partition(Gm[self.solver._eliminated_rows(mode, fs, layout)], dep, limit)
        if better is not None:
            options.append(tuple(c for j, c in enumerate(coords) if j not in better))
        if side == OTHER:
            options.append(kept)
        for ind in options:
            new = self._chart(mode, ind, q, xb)
            if new is fs:
                return None
            if new is not None:
                self.changes += 1
                return new
        if side != OTHER:  # near its singularity, but the only chart there is
            return None
        if gain > SINGULAR_GAIN:  # at the singularity, where the roots meet
            why = self._singular(mode, fs, Gm, layout, t, q)
        else:
            why = (f"at t = {t:.10g} ({_state(coords, q)}) the motion has left the chart on "
                   f"which Lagrange II eliminates {_chart_text(fs)} for another branch of the "
                   f"constraints, and no chart through this state could be derived "
                   f"({self._refusals(mode, options)})")
        raise FormNotApplicable(f"lagrange2: {why}; use --form lagrange1 or --form maggi, which "
                                "keep the redundant coordinates")

    def _chart(self, mode, ind: tuple[str, ...], q: np.ndarray, xb: np.ndarray) -> FormSystem | None:
        """A chart of *mode* keeping *ind* with the state on its branch: a cached one, else
        one derived through the state; ``None`` when there is none.  Why a chart cannot be
        derived (no closed-form solution, too large) does not depend on the state: it is
        kept in :attr:`refused`.  A derived chart whose root misses the state (e.g. a
        principal root only) is cached for the states it holds on."""
        key = (mode.structure, ind)
        listed = self.cache.setdefault(key, [])
        for fs in listed:
            try:
                fs.solve(xb)
            except SingularMatrix:
                pass  # the chart's outputs are computed before the linear solve
            if assess(fs.last)[0] == ON:
                return fs
        if key in self.refused:
            return None
        point = dict(zip(self.solver.model.coordinates, q.tolist()))
        try:
            fs = self.solver.derive_form(mode, ind, branch=point)
        except FormNotApplicable as exc:
            self.refused[key] = str(exc).split("; use --form")[0].removeprefix("lagrange2: ")
            return None
        listed.append(fs)
        try:
            fs.solve(xb)
        except SingularMatrix:
            pass
        if assess(fs.last)[0] == OTHER:  # e.g. a principal root only, the others not in closed form
            return None
        return fs

    def settle(self, mode, t: float, q: np.ndarray, qd: np.ndarray) -> None:
        """At a state the integrator accepted: change to a better chart when the active one's
        last evaluation (the integrator's, at or near this state) shows exchange factors
        above :data:`CHART_GAIN`."""
        fs = self.solver._active.get(mode.structure)
        if fs is None or "chart" not in fs.last or fs.last["chart"][5] <= CHART_GAIN:
            return
        Gm, layout, xb = self._evaluate(mode, fs, t, q, qd)
        new = self.check(mode, fs, Gm, layout, t, q, xb, settled=True)
        if new is not None:
            self.solver._active[mode.structure] = new

    def _evaluate(self, mode, fs: FormSystem, t: float, q: np.ndarray, qd: np.ndarray):
        """Evaluate *fs* at a state: ``(Gm, layout, xb)`` as :meth:`check` takes them."""
        solver = self.solver
        x = solver.input(t, q, qd)
        out = solver.kernel.dynamics(x)
        cout = solver.ck(x) if solver.ck else None
        extra = solver._extra_values(mode, cout)
        xb = np.concatenate((x, extra)) if extra.size else x
        layout = solver.layout(mode)
        Gm = solver.assemble(mode, layout, out, cout)[0] if layout else np.zeros((0, solver.n))
        try:
            fs.solve(xb)
        except SingularMatrix:
            pass
        return Gm, layout, xb

    def explain(self, mode, t: float, q: np.ndarray, qd: np.ndarray) -> str | None:
        """Why the motion in *mode* cannot continue at the state on its chart (singular
        there, exchange factors above :data:`SINGULAR_GAIN`, and no other chart could be
        derived), or ``None`` when the chart is not the cause."""
        fs = self.solver._active.get(mode.structure)
        if fs is None or "chart" not in fs.extra_outputs:
            return None
        Gm, layout, _ = self._evaluate(mode, fs, t, q, qd)
        if assess(fs.last)[1] <= SINGULAR_GAIN:
            return None
        return self._singular(mode, fs, Gm, layout, t, q)

    def _singular(self, mode, fs: FormSystem, Gm: np.ndarray, layout, t: float, q: np.ndarray) -> str:
        """What is singular about the chart *fs*, just evaluated at the state."""
        coords = list(self.solver.model.coordinates)
        kept = fs.eom.independent
        dep = [j for j, c in enumerate(coords) if c not in kept]
        ideal = self.solver._eliminated_rows(mode, fs, layout)
        # the singular direction of G_D: which constraints lose their component along which
        # dependent coordinates
        u, _, vt = np.linalg.svd(Gm[np.ix_(ideal, dep)])
        names = [layout[ideal[i]].name for i in np.flatnonzero(np.abs(u[:, -1]) >= 0.3)]
        lost = [coords[dep[i]] for i in np.flatnonzero(np.abs(vt[-1]) >= 0.3)]
        R = np.abs(np.nan_to_num(fs.last["R"], nan=np.inf))
        d, k = np.unravel_index(int(np.argmax(R)), R.shape)
        others = [key[1] for key in self.refused if key[0] == mode.structure]
        return (f"the chart of Lagrange II is singular here: it eliminates {_chart_text(fs, lost)}, "
                f"and the gradient of {', '.join(repr(n) for n in names)} has (almost) no "
                f"component along {', '.join(lost)} at t = {t:.10g} ({_state(coords, q)}; "
                f"|d{coords[d]}/d{kept[k]}| = {R.max():.3g}); no other chart could be derived"
                + (f" ({self._refusals(mode, others)})" if others else ""))

    def _refusals(self, mode, options) -> str:
        """Why no chart keeping each of *options* was found."""
        return "; ".join(f"keeping {', '.join(ind) or 'no coordinate'}: "
                         + self.refused.get((mode.structure, ind),
                                            "the roots in closed form miss the state")
                         for ind in options)


def _chart_text(fs: FormSystem, coordinates=None) -> str:
    """``"x1 by x1 = sqrt(l1**2 - y1**2) (constraint 'rod1')"``: what the chart of *fs*
    eliminates (the given dependent *coordinates*, default all)."""
    eom = fs.eom
    dep = [c for c in eom.model.coordinates if c not in eom.independent]
    shown = coordinates or dep
    solutions = [note.split("  (")[0] for note in eom.notes
                 if any(note.startswith(f"{c} = ") for c in shown)]
    names = ", ".join(repr(n) for n in eom.eliminated)
    return (f"{', '.join(shown)} by {'; '.join(solutions)} "
            f"(constraint{'s' if len(eom.eliminated) > 1 else ''} {names})")


def _state(coords, q) -> str:
    return ", ".join(f"{c} = {v:.6g}" for c, v in zip(coords, q))
