"""Constraints that become singular along a motion.

The motion in a mode is determined while the active constraint rows ``G q'' + gamma = 0`` are
independent and none has a vanishing gradient.  Both can fail along a motion that starts
regular, and then the multipliers pass through a pole (``lambda ~ 1/(t - t*)``) while the
accelerations may stay finite, so that the integrator steps over the point without noticing:

* two holonomic constraints whose gradients become parallel -- ``x^2 + y^2 = 1`` and the
  program ``y = -cos t`` at ``t = pi`` (``x = 0``): beyond it the constraints allow both
  ``x = sin t`` and ``x = |sin t|``, and which one a step takes is decided by rounding;
* a nonlinear nonholonomic constraint whose gradient ``d phi/dq'`` vanishes, like
  ``z'^2 = a^2 (x'^2 + y'^2)`` wherever all three velocities vanish: the reaction has no
  direction there (Chetaev's condition gives none).

The watched quantity is the *regularity* of the active ideal rows (servo- and quasi-ideal rows
are watched by the realizability test of the simulation, ``G M^-1 B``):

    rho = min( min_i |G_i| / max_run |G_i|,   sqrt(sigma_min(G~ M^-1 G~^T) / |G~| |M^-1 G~^T|) )

with ``G~`` the rows scaled to unit norm: the first term is a gradient that has shrunk to
nothing relative to its size earlier in the run, the second rows that have become dependent in
the metric of the mass matrix (:func:`~nonideal.modes.weakest_reactions`).  At the end of each
step a cheap test (:meth:`Regularity.suspect`: a row that reversed, rows whose orientation
flipped) says whether the step may have passed a singular point; only then is ``rho`` guarded
inside the step like the events (:mod:`nonideal.guards`), and when it falls below :data:`SINGULAR` the
run stops with :class:`~nonideal.errors.SingularMotion` (exit code 3), naming the constraints,
the time and the state -- when the model's ``[simulation] singular = "stop"``.

By default (``singular = "smooth"``) the run goes on through the singular instant on the
*smooth branch*, the continuation whose velocities and accelerations are continuous
(:meth:`Regularity.pass_through`): ``x = sin t`` and not ``|sin t|`` for the dependent pair,
``z' = a x'`` changing sign with ``x'`` for the cone.  The guard then watches for the regularity
falling to :data:`JUMP_FROM` (closer to the singular point the accelerations, computed from
rows that are nearly dependent, lose accuracy as ``1/rho``: at 1e-6 the velocity of the
dependent pair is already 10 % off).  The step is re-integrated up to there (``t* - d``), the
singular instant ``t*`` is located from the linear fall of ``rho``, and the state is carried
over ``[t* - d, t* + 2d]`` by the Hermite polynomial of the motion before it (values and
derivatives at ``t* - 4d, ..., t* - d``, each integrated to from the step's start: degree
seven), then projected onto the constraints
at ``t* + 2d``, where they are regular again (Newton
from the extrapolated state converges to the root of the smooth branch).  The run records an
event ``type = "singular"`` naming the constraints and the branch; the multipliers are
unbounded at ``t*`` (a pole ``~ 1/(t - t*)``) and are not sampled inside the interval.
When the projected velocities differ from the extrapolated ones (the rows only came close to
dependent and the motion turns back, or no smooth branch exists), the step is integrated as it
is and guarded as with ``"stop"``: a singular instant without a smooth branch stops the run.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import diags, issparse
from scipy.sparse.linalg import splu

from scipy.interpolate import KroghInterpolator
from scipy.optimize import brentq, minimize_scalar

from ..errors import IntegrationFailed, MechanicsError, PainleveParadox, SingularMotion, SingularSystem
from ..modes.diagnosis import weakest_reactions
from ..numeric.blocks import row_groups
from ..modes.motion import Motion
from ..modes.switching import effective_compliance
from ..modes.types import SLIDE
from .guards import StepScan
from .slipstall import slip_stall

__all__ = ["SINGULAR", "AMPLIFY", "singular_level", "JUMP_FROM", "BRANCHES", "LOST", "Regularity", "servo_stall", "mass_stall", "MassGuard", "explain_stall"]

BRANCHES = ("smooth", "stop")
"""Values of ``[simulation] singular``: go on on the smooth branch, or stop (exit code 3)."""

SINGULAR = 1e-6
"""Regularity below which the constraint rows are treated as singular."""
AMPLIFY = 1e3
"""The rows count as singular where their regularity is below this many times the relative
tolerance (:func:`singular_level`)."""
SUSPECT = 1e-3
"""Regularity (or determinant of the rows at the two ends of a step) below which a step is
scanned inside for a singular point."""
JUMP_FROM = 1e-2
"""Regularity from which the smooth branch is extrapolated over the singular instant (closer,
the state loses accuracy as ``1/rho``: the constraints fix the coordinates along the weakest
combination only to their residual divided by ``rho``; farther, the extrapolation does)."""
ZERO = 1e-4
"""Least regularity along the carried-over motion below which the rows count as singular there
(a dip that stays above it is integrated through as it is, as it is with ``"stop"``)."""
BASE = 4
"""Points before the singular instant whose values and derivatives the extrapolation uses
(degree ``2 BASE - 1``)."""
MASS_WATCH = 200
"""Largest number of coordinates whose mass matrix :class:`MassGuard` watches."""
BRANCH_TOL = 1e-4
"""Largest change of the velocities (relative) that the projection onto the constraints may make
to the extrapolated state for it to count as the smooth branch."""


def _row_dots(A, B) -> np.ndarray:
    """Row-wise dot products of two arrays (dense or sparse) of one shape."""
    if issparse(A):
        return np.asarray(A.multiply(B).sum(axis=1)).ravel()
    return np.einsum("ij,ij->i", A, B)


def _scale_rows(A, d: np.ndarray):
    """Each row of *A* (dense or sparse) divided by its entry in *d*."""
    return diags(1.0 / d) @ A if issparse(A) else A / d[:, None]


def _weakest_by_groups(M, Gt, groups, m: int):
    """:func:`~nonideal.modes.diagnosis.weakest_reactions` of ``(M, Gt, Gt^T)`` (sparse, unit
    rows) group by group, groups of one size batched: ``M^-1 Gt^T`` by one sparse LU, the
    blocks of ``Gt M^-1 Gt^T`` by group.  The least relative value and its combination (zero
    outside its group)."""
    X = splu(M.tocsc()).solve(np.asarray(Gt.T.toarray()))   # M^-1 Gt^T, shape (n, m)
    S = np.asarray(Gt @ X)
    col2 = np.einsum("ij,ij->j", X, X)
    best, w = np.inf, None
    by_size: dict[int, list] = {}
    for pos, _ in groups:
        by_size.setdefault(len(pos), []).append(pos)
    for r, members in by_size.items():
        P = np.array(members, dtype=np.intp)
        blocks = S[P[:, :, None], P[:, None, :]]
        _, sv, Vt = np.linalg.svd(blocks)
        scale = np.sqrt(r * col2[P].sum(axis=1))
        rel = sv[:, -1] / np.maximum(scale, 1e-300)
        k = int(np.argmin(rel))
        if rel[k] < best:
            best, w = float(rel[k]), np.zeros(m)
            w[P[k]] = Vt[k, -1]
    return best, w


def _dense(A) -> np.ndarray:
    return A.toarray() if issparse(A) else A


def singular_level(rtol: float) -> float:
    """The regularity below which the rows are singular for a run at relative tolerance
    *rtol*: :data:`SINGULAR`, or :data:`AMPLIFY` ``rtol`` when larger (at most
    :data:`SUSPECT`).  The rows fix the motion
    along their weakest combination only to their error divided by the regularity: at a looser
    tolerance the integrated motion misses the singular configuration by more (``x^2 + y^2 = 1``
    with ``y = -cos t``, RK45 at rtol 1e-8: the regularity bottoms out at 3e-6 and the motion
    turns back on the branch ``x = |sin t|``), and the miss must still be caught.

    Examples
    --------
    >>> singular_level(1e-10), singular_level(1e-6)
    (1e-06, 0.001)
    """
    return min(max(SINGULAR, AMPLIFY * float(rtol)), SUSPECT)


class Regularity:
    """The regularity ``rho`` of a model's active ideal rows along one run.

    Parameters
    ----------
    kernel : Kernel
    """

    def __init__(self, kernel):
        self.kernel = kernel
        self.reference = np.zeros(len(kernel.rows))  # the largest |G_i| seen
        self.last = None  # the unit rows at the last accepted state
        self.last_end = None  # (time, rows, regularity) at the end of the last step scanned by slopes
        self._groups: dict[tuple, list] = {}

    def start(self, motion, rows: list[int]) -> None:
        """The state that starts a phase (its rows are the reference of the next step)."""
        self.last = self._unit_rows(motion, rows, update=True)[0] if rows else None

    def suspect(self, motion, rows: list[int], level: float = SINGULAR) -> bool:
        """Accept the state at the end of a step; True when the rows may have gone through a
        singular configuration since the previous accepted state: a row reversed its direction
        (its gradient went through zero), ``det(G~_new G~_old^T)`` is not positive (they went
        through a dependent configuration, or are close to one), or the regularity is below
        :data:`SUSPECT` (ten times *level* when that is larger).  Cheap:
        only then is the step scanned (:meth:`value` on the dense output)."""
        unit, shrink = self._unit_rows(motion, rows, update=True)
        last, self.last = self.last, unit
        if last is None or last.shape != unit.shape or shrink <= max(SUSPECT, 10 * level):
            return True
        if np.any(_row_dots(unit, last) <= 0.0):
            return True
        bound = max(SUSPECT, 2 * (10 * level) ** 2)
        groups = self.groups(rows)
        if len(groups) == 1:
            return len(rows) > 1 and np.linalg.det(_dense(unit @ last.T)) <= bound
        # rows in groups that share no coordinate (nor mass): one determinant per group
        return any(len(pos) > 1 and np.linalg.det(_dense(unit[pos] @ last[pos].T)) <= bound
                   for pos, _ in groups)

    def groups(self, rows: list[int]) -> list:
        """The rows in groups that share no coordinate and no mass entry
        (:func:`~nonideal.numeric.blocks.row_groups`): ``G M^-1 G^T`` is block diagonal by
        group, so the regularity is the least of the groups' (each relative to its own size:
        relative to the whole, a thousand independent knife edges would look 1000 times less
        regular than one)."""
        key = tuple(rows)
        found = self._groups.get(key)
        if found is None:
            k, n = self.kernel, self.kernel.n
            if k.compact:
                g = (k.patterns["G"].rows, k.patterns["G"].cols)
                mm = (k.patterns["M"].rows, k.patterns["M"].cols)
            else:
                e, f = k.dynamics.entries("G"), k.dynamics.entries("M")
                g, mm = (e // n, e % n), (f // n, f % n)
            found = self._groups[key] = row_groups(n, *g, *mm, list(rows))
        return found

    def _unit_rows(self, motion, rows, update=False):
        """The rows scaled to unit norm, and the smallest ratio of a row's norm to its
        reference."""
        G, _ = self._arrays(motion)
        G = G[rows]
        norms = np.sqrt(_row_dots(G, G))
        if update:
            self.reference[rows] = np.maximum(self.reference[rows], norms)
        ref = self.reference[rows]
        shrink = float(np.min(norms / np.where(ref > 0, ref, 1.0)))
        return _scale_rows(G, np.where(norms > 0, norms, 1.0)), shrink

    def _arrays(self, motion):
        """``(G, M)`` at the state of *motion* (sparse for a compact kernel)."""
        out = self.kernel.dynamics(motion.solver.input(motion.t, motion.q, motion.qd))
        if self.kernel.compact:
            return self.kernel.gradients(out), self.kernel.mass(out)
        return np.asarray(out["G"], dtype=float).reshape(-1, motion.n), np.asarray(out["M"], dtype=float)

    def crossing(self, step, rows: list[int], level: float = SINGULAR, force: bool = False) -> float | None:
        """The first time in *step* (:class:`~nonideal.simulation.guards.Step`) where the
        regularity falls to *level* (:data:`SINGULAR`; :data:`JUMP_FROM` when the run goes on
        through), or None; the step is scanned only when :meth:`suspect` says so (or *force*)."""
        def rho(_, s):
            return self.value(step.motion(s), rows) - level
        if not self.suspect(step.motion(step.b), rows, level) and not force:
            # no sign of a crossing at the ends; a dip of the regularity that returns within
            # the step (the rows becoming dependent and the motion turning back on the
            # non-smooth branch, x = |sin t|) shows in its slopes at the ends
            # (explicit Runge-Kutta steps only: their end derivatives give the slopes for free)
            tangents = step.tangents()
            if tangents is None:
                return None
            last, self.last_end = self.last_end, (step.b, tuple(rows), rho(0, step.b) + level)
            ends = (last[2] - level if last and last[:2] == (step.a, tuple(rows)) else rho(0, step.a),
                    self.last_end[2] - level)
            slopes = ((self.value(tangents[1], rows) - level - ends[0]) / tangents[0],
                      (ends[1] - self.value(tangents[2], rows) + level) / tangents[0])
            scan = StepScan(rho, step.a, step.b, [ends], [True], lambda _: slopes)
            return scan.first_root(0, ends[0] > 0, 0.0)[0] if scan.worth_probing(0, *ends) else None
        ends = (rho(0, step.a), rho(0, step.b))
        return StepScan(rho, step.a, step.b, [ends]).first_root(0, ends[0] > 0, 0.0)[0]

    def rows(self, active: list[int]) -> list[int]:
        """The rows it watches among the *active* kernel rows (the ideal ones)."""
        return [i for i in active if self.kernel.rows[i].reaction_kind == "ideal"]

    def value(self, motion, rows: list[int]) -> float:
        """``rho`` at the state of *motion*."""
        return self.analyse(motion, rows)[0]

    def analyse(self, motion, rows: list[int]):
        """``(rho, vanishing row or None, weakest combination of the rows)``."""
        G, M = self._arrays(motion)
        G = G[rows]
        norms = np.sqrt(_row_dots(G, G))
        ref = self.reference[rows]
        shrink = norms / np.where(ref > 0, ref, 1.0)
        j = int(np.argmin(shrink))
        if shrink[j] <= SINGULAR or norms[j] == 0.0:
            return float(shrink[j]), rows[j], None
        if len(rows) == 1:
            return float(shrink[0]), None, None
        Gt = _scale_rows(G, norms)
        groups = self.groups(rows)
        try:
            if len(groups) == 1:
                dep, w = weakest_reactions(_dense(M), _dense(Gt), _dense(Gt).T)
            elif issparse(M):
                dep, w = _weakest_by_groups(M, Gt, groups, len(rows))
            else:   # the weakest group's combination, zero on the others
                dep, w = np.inf, None
                for pos, cols in groups:
                    Gg = _dense(Gt[pos][:, cols])
                    d, wg = weakest_reactions(_dense(M[cols][:, cols]) if issparse(M) else M[np.ix_(cols, cols)],
                                              Gg, Gg.T)
                    if d < dep:
                        dep, w = d, np.zeros(len(rows))
                        w[pos] = wg
        except np.linalg.LinAlgError:  # a singular mass matrix is diagnosed elsewhere
            return float(shrink[j]), None, None
        return min(float(shrink[j]), float(np.sqrt(dep))), None, w

    def stop(self, model, motion, watched: list[int]) -> None:
        """Stop where the active constraints became singular along the motion
        (:class:`~nonideal.errors.SingularMotion`), naming them, with the state."""
        rho, vanishing, w = self.analyse(motion, watched)
        rows = self.kernel.rows
        names = model.coordinates
        state = dict(zip(names, map(float, motion.q)))
        state.update({c + "'": float(v) for c, v in zip(names, motion.qd)})
        if vanishing is not None or w is None:
            row = rows[vanishing if vanishing is not None else watched[0]]
            raise SingularMotion(
                f"constraint '{row.name}' lost its gradient along the motion: its derivative "
                f"with respect to the {('coordinates', 'velocities', 'accelerations')[min(row.order, 2)]} "
                f"fell to {rho:.2g} of its size earlier in the run, "
                "so its reaction has no direction there and its multiplier passes through a pole; "
                "the equations do not determine the motion beyond this state (write the "
                "constraint so that its gradient does not vanish, e.g. solved for one velocity, "
                "or end the run before it)", motion.t, state,
                {"constraint": row.name, "regularity": f"{rho:.3g}"})
        big = [k for k in range(len(watched)) if abs(w[k]) > 1e-3 * np.max(np.abs(w))]
        involved = [rows[watched[k]].name for k in big]
        combo = " + ".join(f"{w[k]:.4g}*grad('{rows[watched[k]].name}')" for k in big)
        raise SingularMotion(
            f"the constraints {', '.join(repr(x) for x in involved)} became dependent along the "
            f"motion ({combo} ~ 0: the smallest singular value of G M^-1 G^T fell to {rho ** 2:.2g} of "
            "its scale), so their multipliers pass through a pole and the constraints no longer "
            "determine the motion beyond this state (several continuations satisfy them); "
            "remove the redundant constraint, or end the run before this time", motion.t, state,
            {"constraints": ", ".join(involved), "regularity": f"{rho:.3g}"})


    def pass_through(self, sim, mode, fun, step, t_s: float, watched: list[int], Solver, atol):
        """Carry the motion over the singular instant found at *t_s* in *step* on the smooth
        branch (see the module docstring).

        Returns
        -------
        None
            When the rows only come close to dependent (least regularity above :data:`ZERO`),
            or the state projected on the constraints beyond is not the extrapolated one (the
            motion turns back before the singular configuration, or no smooth branch exists):
            the driver then integrates on, guarding as ``"stop"`` does.
        t_b : float
            Where the run resumes (the rows are regular again).
        y_b : ndarray
            The state there, on the constraints.
        dense : callable
            The motion on ``[step.a, t_b]`` (for the requested sample times).
        record : dict
            The ``singular`` event.

        Raises
        ------
        SingularMotion
            When the step cannot be re-integrated up to the singular instant, or the regularity
            does not fall towards it.
        """
        a, n, solver = step.a, sim.n, sim.solver
        pieces = []  # (from, to, dense output) of the motion re-integrated from the step's start

        def integrate(t_from, y_from, t_to):
            ode = Solver(fun, t_from, y_from, t_to, rtol=sim.rtol, atol=atol, max_step=sim.max_step)
            while ode.status == "running" and ode.step() is None and ode.status != "failed":
                pieces.append((min(ode.t_old, ode.t), max(ode.t_old, ode.t), ode.dense_output()))
            if ode.status != "finished":
                self.stop(sim.model, step.motion(t_s), watched)
            return ode.y

        def before(s):
            return next((d for lo, hi, d in pieces if lo <= s <= hi), pieces[-1][2])(s)

        def rho(s):
            return self.value(Motion(solver, mode, s, before(s)), watched)
        integrate(a, step.state(a), t_s)
        rho_s, twice = rho(t_s), 2 * JUMP_FROM
        t_p = brentq(lambda s: rho(s) - twice, a, t_s, xtol=1e-14 * max(1.0, abs(t_s))) \
            if rho(a) > twice else a
        rho_p = rho(t_p)
        if not (t_s > t_p and rho_p > rho_s):
            self.stop(sim.model, step.motion(t_s), watched)
        t_star = t_s + rho_s * (t_s - t_p) / (rho_p - rho_s)  # rho falls linearly to zero at t*
        d = t_star - t_s
        base = [t_star - k * d for k in range(BASE, 0, -1)]
        # the states there integrated to, from the step's start (not read on a dense output,
        # whose order is lower than the integrator's: Radau's is 3)
        y_a = step.state(a)
        ys = [y_a if s == a else integrate(a, y_a, s) for s in base]
        fs = [np.asarray(fun(s, y), dtype=float) for s, y in zip(base, ys)]
        smooth = KroghInterpolator(np.repeat(base, 2), np.array([v for p in zip(ys, fs) for v in p]))
        t_b, t_a = t_star + 2 * d, t_s  # rho(t_b) ~ 2 JUMP_FROM: the guard is armed again
        # the singular instant: where the rows are least regular along the extrapolated motion
        # (which needs only the coordinates there: well conditioned)
        found = minimize_scalar(lambda s: self.value(Motion(solver, mode, s, smooth(s)), watched),
                                bounds=(t_a, t_b), method="bounded",
                                options={"xatol": 1e-13 * max(1.0, abs(t_b))})
        if found.fun > ZERO:  # only close to dependent: the step is integrated as it is
            return None
        y_b = np.array(smooth(t_b), dtype=float)
        q, qd = sim._project(mode, t_b, y_b[:n], y_b[n:2 * n])
        change = float(np.max(np.abs(qd - y_b[n:2 * n])))
        if change > BRANCH_TOL * (1.0 + float(np.max(np.abs(y_b[n:2 * n])))):
            return None  # no smooth branch (or the rows only came close to dependent)
        y_b[:n], y_b[n:2 * n] = q, qd
        _, vanishing, w = self.analyse(Motion(solver, mode, found.x, smooth(found.x)), watched)
        rows = self.kernel.rows
        if vanishing is not None or w is None:
            names = [rows[vanishing if vanishing is not None else watched[0]].name]
            why = "lost its gradient"
        else:
            names = [rows[watched[k]].name for k in range(len(watched)) if abs(w[k]) > 1e-3 * np.max(np.abs(w))]
            why = "became dependent"
        record = {"t": float(found.x), "type": "singular", "constraint": ", ".join(names),
                  "mode": mode.label(), "branch": "smooth", "interval": [float(t_a), float(t_b)],
                  "note": f"the constraint{'s' if len(names) > 1 else ''} {why} at this instant: "
                          "the multipliers are unbounded there (a pole ~ 1/(t - t*)); the motion "
                          "goes on on the branch with continuous velocities and accelerations "
                          "(carried over the interval, then projected onto the constraints)",
                  "velocity_change": change}

        def dense(s):
            return before(s) if s <= t_a else np.asarray(smooth(s), dtype=float)
        return t_b, y_b, dense, record


LOST = 1e-4
"""A servo row's gain on its program below this fraction of its value at the start: the program
is lost (the control no longer reaches it)."""


def _gains(solver, t, q, qd, rows):
    """The dynamics at a state and each row's gain on its own condition, ``1 / (S^-1)_ii`` with
    ``S = G M^-1 B`` over *rows* (the Schur complement: how much the row's condition responds to
    its own multiplier once the other rows' multipliers are solved for); None where singular."""
    out = solver.kernel.dynamics(solver.input(t, q, qd))
    M, G, B = (np.asarray(out[k], dtype=float) for k in ("M", "G", "B"))
    try:
        S = G[rows] @ np.linalg.solve(M, B[:, rows])
        return M, G, B, 1.0 / np.diag(np.linalg.inv(S))
    except (np.linalg.LinAlgError, ZeroDivisionError, FloatingPointError):
        return M, G, B, None


def servo_stall(model, solver, t: float, y: np.ndarray, mode, t0: float | None = None,
                y0: np.ndarray | None = None) -> None:
    """A servo- or quasi-ideal constraint whose reaction stops realizing it stalls the
    integration: say so, naming the constraints (exit code 3).  Called when the integration
    stalls.  Two ways to lose a program:

    * ``G M^-1 B`` singular relative to its scale: the control direction turns orthogonal, in
      the metric of M, to the program's gradient (a thrust that turns tangent to its path);
    * given the starting state *(t0, y0)*: a servo row's gain on its program (the Schur
      complement of ``G M^-1 B``) has fallen below :data:`LOST` of its value at the start -- a
      control acting through the dynamics whose lever vanishes (the friction speed regulator's
      wheel reaching the axis, rho -> 0: Manglieva & Beknazarov 2022, (3.5) blows up).  The
      program, the order of the derivative in which its control was found, the time and the
      state are named."""
    kernel, n = solver.kernel, solver.n
    rows = solver.rows(mode)
    if not any(kernel.rows[i].reaction_kind != "ideal" for i in rows):
        return
    q, qd = y[:n], y[n:2 * n]
    M, G, B, gains = _gains(solver, t, q, qd, rows)
    state = dict(zip(model.coordinates, map(float, q)))
    state.update({c + "'": float(v) for c, v in zip(model.coordinates, qd)})
    reach = kernel.dyn.servo_reach
    try:
        relative, w = weakest_reactions(M, G[rows], B[:, rows])
    except np.linalg.LinAlgError:  # pragma: no cover - M singular is diagnosed elsewhere
        relative = np.inf
    if relative > 1e-6:
        _lost(kernel, rows, gains, solver, t, t0, y0, state)
        return
    involved = [kernel.rows[i].name for k, i in enumerate(rows)
                if abs(w[k]) > 1e-3 * np.max(np.abs(w)) and kernel.rows[i].reaction_kind != "ideal"]
    orders = {x: reach[x].order for x in involved if x in reach}
    tried = "".join(f"; the control of '{x}' acts through the dynamics: the program was differentiated to "
                    f"order {k} (its condition of dynamics loses the control)" for x, k in orders.items() if k > 2)
    raise MechanicsError(
        f"the servo/quasi-ideal constraint(s) {', '.join(repr(x) for x in involved)} stop being "
        f"realizable at t = {t:.10g}: G M^-1 B is singular there (smallest singular value "
        f"{relative:.2g} of its scale) -- the control direction has turned orthogonal, in the "
        "metric of M, to the program's gradient, and the control force needed grows without "
        f"bound; the programmed motion cannot be continued with this control{tried}", t, state,
        details={"order_tried": orders} if tried else None)


def _lost(kernel, rows, gains, solver, t, t0, y0, state) -> None:
    """Raise when a servo row's gain has fallen below :data:`LOST` of its value at *(t0, y0)*."""
    n = solver.n
    if y0 is not None and gains is not None:
        start = _gains(solver, t0, y0[:n], y0[n:2 * n], rows)[3]
        lost = [(k, i) for k, i in enumerate(rows) if kernel.rows[i].reaction_kind == "servo"
                and start is not None and abs(gains[k]) <= LOST * abs(start[k])]
        if lost:
            k, i = lost[0]
            name = kernel.rows[i].name
            order = kernel.dyn.servo_reach[name].order if name in kernel.dyn.servo_reach else 2
            ratio = abs(gains[k]) / abs(start[k])
            how = (f"its control acts through the dynamics: the program was differentiated to order {order} "
                   "before the control appeared, and that derivative's dependence on the control "
                   if order > 2 else "the program's dependence on its control ")
            raise MechanicsError(
                f"servo-constraint '{name}': the program is lost at t = {t:.10g}: {how}(its gain, "
                f"the Schur complement of G M^-1 B) fell to {ratio:.2g} of its value at t0 = {t0:.6g}, so "
                "the control force needed grows without bound and the integration stalled; the "
                "programmed motion cannot be continued with this control beyond this state (Béghin "
                "1922; Yushkov 1999, ch. IV) -- end the run before it or change the program",
                t, state, details={"program": name, "order_tried": order, "gain_ratio": ratio})


def mass_stall(model, solver, t: float, y: np.ndarray, t0: float, y0: np.ndarray) -> None:
    """A mass matrix that becomes singular along the motion (``(1 - t) x'^2/2`` at t = 1, or
    ``cos(x)^2 x'^2/2`` at x = pi/2) stalls the integration: say so, with the smallest
    eigenvalue relative to the mass matrix at the start *(t0, y0)* (exit code 2: the model's
    kinetic energy is degenerate there).  Called when the integration stalls."""
    n = solver.n

    def eig(tt, yy):
        M = solver.kernel.dense(solver.kernel.dynamics(solver.input(tt, yy[:n], yy[n:2 * n])), "M")
        return np.linalg.eigh((M + M.T) / 2)
    w0, _ = eig(t0, y0)
    w, v = eig(t, y)
    scale = max(float(np.max(np.abs(w0))), 1e-300)
    if w[0] > 1e-6 * scale:
        return
    vec = v[:, 0] / v[np.argmax(np.abs(v[:, 0])), 0]
    combo = " + ".join(f"{a:.4g}*{c}'" for a, c in zip(vec, model.coordinates) if abs(a) > 1e-9)
    state = ", ".join(f"{c} = {float(x):.10g}" for c, x in zip(model.coordinates, y[:n]))
    raise SingularSystem(
        f"the mass matrix becomes singular along the motion at t = {t:.10g} ({state}): its "
        f"smallest eigenvalue fell to {w[0]:.3g} ({w[0] / scale:.2g} of its size at the start), "
        f"so the velocity combination {combo} has no inertia there and the accelerations grow "
        "without bound; the kinetic energy is degenerate at this state (check the factors in "
        "front of the velocities), or end the run before it",
        None if model.source == "<api>" else model.source)


class MassGuard:
    """The inertia of a model whose mass matrix varies (with the time or the coordinates),
    watched at the end of every step: a mass matrix that becomes singular where the motion
    does not stall (``(1 - t) x'^2/2`` at rest: ``x'' = x'/(1 - t)`` stays 0 and the step
    goes through t = 1) is reported by :func:`mass_stall` at the first instant where its
    smallest eigenvalue falls to 1e-6 of its size at the start.  Dense eigenvalues: watched
    only up to :data:`MASS_WATCH` coordinates (a larger model stalls where its motion does), and
    only when the mass matrix is positive definite at the start."""

    def __init__(self, sim, t0: float, y0: np.ndarray):
        dyn, self.sim = sim.kernel.dyn, sim
        moving = set(dyn.q) | {dyn.t}
        self.active = sim.n <= MASS_WATCH and any(v in moving for v in dyn.M.free_symbols)
        if self.active:
            self.t0, self.y0 = t0, np.array(y0, dtype=float)
            w = self._eig(t0, self.y0)
            # half the level at which mass_stall reports: the root is found below it
            self.floor = 0.5e-6 * max(float(np.max(np.abs(w))), 1e-300)
            # a mass matrix singular from the start is one that the constraints complete
            # (a sleigh's with its mass at the blade): the diagnosis of the start checks it
            self.active = bool(w[0] > 2 * self.floor)

    def _eig(self, t, y):
        solver, n = self.sim.solver, self.sim.n
        M = solver.kernel.dense(solver.kernel.dynamics(solver.input(t, y[:n], y[n:2 * n])), "M")
        return np.linalg.eigvalsh((M + M.T) / 2)

    def check(self, step) -> None:
        """Raise :class:`~nonideal.errors.SingularSystem` when the mass matrix became singular
        within *step* (:class:`~nonideal.simulation.guards.Step`)."""
        if not self.active:
            return
        low = lambda s: float(self._eig(s, step.ode.y if s == step.b else step.state(s))[0]) - self.floor  # noqa: E731
        if low(step.b) > 0:  # (the state at the end without the dense output)
            return
        a = step.a if low(step.a) > 0 else None
        t = step.b if a is None else brentq(low, a, step.b, xtol=1e-14 * max(1.0, abs(step.b)))
        mass_stall(self.sim.model, self.sim.solver, t, step.state(t), self.t0, self.y0)


def explain_stall(sim, ode, mode) -> None:
    """When the integration of *sim* (a :class:`~nonideal.simulation.hybrid.Simulation`) stalls, name a known cause: a
    singular chart of Lagrange II, a singular mass matrix (:func:`mass_stall`), an unrealizable servo-constraint
    (:func:`servo_stall`), a vanishing slip (:func:`.slipstall.slip_stall`), a slide at the edge of Painleve's paradox."""
    n, model = sim.n, sim.model
    source = None if model.source == "<api>" else model.source
    charts = sim.solver.charts
    reason = charts.explain(mode, ode.t, ode.y[:n], ode.y[n:2 * n]) if charts is not None else None
    if reason:
        raise IntegrationFailed(ode.t, mode.label(), reason, source)
    start = np.concatenate(sim.initial_state())
    mass_stall(model, sim.solver, ode.t, ode.y, model.t0, start)
    servo_stall(model, sim.solver, ode.t, ode.y, mode, model.t0, start)
    slip_stall(sim, ode, mode)
    for name, cs in mode.contacts:
        if cs.state != SLIDE:
            continue
        try:
            b = effective_compliance(sim.solver, ode.t, ode.y[:n], ode.y[n:2 * n], mode, name)
        except Exception:  # pragma: no cover
            continue
        if b <= 1e-6:
            state = dict(zip(model.coordinates, ode.y[:n]))
            raise PainleveParadox(
                f"Painleve paradox at contact '{name}': the integration stalled while the "
                f"effective normal compliance b = {b:.3g} of the sliding contact vanished -- the "
                "normal force grows without bound (dynamic jamming)", ode.t, state)
