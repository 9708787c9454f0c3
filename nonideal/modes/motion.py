"""The motion at one state of one mode, as the events, the drift check and the trajectory
samples read it.

A :class:`Motion` is the motion at one state of one mode, computed on first use: an event
that looks only at the slip or the gap (slip stop, touch) costs one contact-kernel call, no
solve.  The solver remembers its last solve, which explicit Runge-Kutta methods make at the
end of every accepted step (the "first same as last" stage), so the events, the drift check
and the trajectory samples at a step end reuse it instead of solving again.  For the other
forms a Motion wraps their :class:`~nonideal.modes.types.Solution`.
"""

from __future__ import annotations

import numpy as np

from ..numeric.kernel import SingularMatrix, max_abs
from .system import compliance_of, system_of
from .types import SEPARATED, SLIDE, SMOOTH, STICK, Mode

__all__ = ["Motion", "cached"]


def cached(solver, t: float, y: np.ndarray, mode: Mode):
    """The solver's last solve if it was at exactly this state (the same array) and mode."""
    last = solver.last
    if last is not None and last[1] is y and last[0] == t and last[2] is mode:
        return last
    return None


class Motion:
    """The motion in one mode at one state, computed on first use.

    Parameters
    ----------
    solver : ModeSolver
    mode : Mode
    t : float
    y : ndarray
        ``[q, q', ...]`` (the integrator's state; not modified).
    kin : ndarray, optional
        The contact kernel's flat outputs at the state, when the caller has them (not modified).

    Notes
    -----
    Read by the events (:mod:`nonideal.simulation.events`), the drift check and the trajectory samples.
    Kinematic quantities (gap, slip, constraint residuals) need no solve.
    """

    __slots__ = ("system", "solver", "mode", "t", "y", "n", "_sol", "_lu", "_piv", "_solution", "_values",
                 "_kin", "_obs", "_dyn")

    def __init__(self, solver, mode: Mode, t: float, y: np.ndarray, kin: np.ndarray | None = None):
        self.solver, self.mode = solver, mode
        self.system = system_of(solver.kernel, mode)
        self.t, self.y, self.n = t, y, self.system.n
        self._sol = self._lu = self._piv = self._solution = None
        self._values = self._obs = self._dyn = None
        self._kin = kin
        hit = cached(solver, t, y, mode)
        if hit is not None:
            self._sol, self._lu, self._piv = hit[3:]

    @classmethod
    def solved(cls, solver, mode: Mode, t: float, y: np.ndarray, sol: np.ndarray) -> "Motion":
        """The motion at a state whose ``[q''; -lambda]`` *sol* is known (a native step's)."""
        motion = cls(solver, mode, t, y)
        motion._sol = sol
        return motion

    @classmethod
    def in_phase(cls, solver, mode: Mode, system, t: float, y: np.ndarray, sol: np.ndarray) -> "Motion":
        """:meth:`solved` for the many samples of one native phase: *system* is the mode's
        (``system_of(solver.kernel, mode)``, looked up once for the phase), and no solve of
        the solver is looked for (the states are the native loop's, never the solver's)."""
        motion = cls.__new__(cls)
        motion.solver, motion.mode, motion.system = solver, mode, system
        motion.t, motion.y, motion.n = t, y, system.n
        motion._lu = motion._piv = motion._solution = None
        motion._values = motion._obs = motion._dyn = motion._kin = None
        motion._sol = sol
        return motion

    @property
    def q(self) -> np.ndarray:
        return self.y[:self.n]

    @property
    def qd(self) -> np.ndarray:
        return self.y[self.n:2 * self.n]

    # ------------------------------------------------------------------ the motion
    def _solved(self):
        """``[q''; -lambda]`` (Lagrange I), or None when :attr:`_solution` holds the motion."""
        if self._sol is None and self._solution is None:
            if self.solver.route.saddle_point:
                hit = cached(self.solver, self.t, self.y, self.mode)
                try:
                    self._sol, self._lu, self._piv = (hit or self._solve())[3:]
                except SingularMatrix:
                    pass
            if self._sol is None:  # other forms, or a singular system: the general path
                self._solution = self.solver.solve(self.t, self.q, self.qd, self.mode, distribute=False)
        return self._sol

    def _solve(self) -> tuple:
        """Solve at this state (the compiled system of a hot mode, else the index path); the
        solver's :attr:`last`."""
        system, solver, mode = self.system, self.solver, self.mode
        function = system.function if solver.specialize and system in solver.hot else None
        if not (function and function.solve_with_powers(solver, function.inputs(solver, mode), self.t, self.y, mode)):
            system.solve(solver, self.t, self.y, mode)
        return solver.last

    @property
    def qdd(self) -> np.ndarray:
        """Accelerations, shape (n_q,)."""
        sol = self._solved()
        return sol[:self.n] if sol is not None else self._solution.qdd

    @property
    def values(self) -> np.ndarray:
        """Multipliers of the mode's rows (``system.layout`` order; for dependent rows the
        admissible distribution with the widest margins, computed only when asked for)."""
        if self._values is None:
            sol = self._solved()
            if sol is None and self._solution.particular:
                self._solution = self.solver.solve(self.t, self.q, self.qd, self.mode)
            self._values = -sol[self.n:] if sol is not None else self._solution.values
        return self._values

    @property
    def indeterminate(self) -> bool:
        """Whether the mode's rows are dependent here: statically indeterminate reactions."""
        return (bool(self.system.layout) and self._solved() is None and self._solution is not None
                and self.system.dependent(self._solution.Gm))

    @property
    def reported(self) -> np.ndarray:
        """Multipliers as reported: :attr:`values`, or for dependent rows under another split
        rule than the widest margin (``[simulation] split``) that rule's distribution."""
        values = self.values
        sol = self._solution
        return sol.shown.values if sol is not None and sol.shown is not None else values

    def multiplier(self, row: int) -> float:
        """Multiplier of kernel row *row* (0 when it is not active)."""
        j = self.system.row_col.get(row)
        return 0.0 if j is None else float(self.values[j])

    def normal(self, c: int, values: np.ndarray | None = None) -> float:
        """Normal force of contact *c* (0 when separated); in *values* (:attr:`reported`)
        rather than :attr:`values` when given."""
        j = self.system.normal_of.get(c)  # a friction torque: its contact's normal force
        return 0.0 if j is None else float((self.values if values is None else values)[j])

    def friction(self, c: int, values: np.ndarray | None = None, continued: bool = True) -> np.ndarray:
        """Friction force of contact *c* (its slip components); *values* as for :meth:`normal`;
        *continued* as for :meth:`~nonideal.modes.solver.ModeSolver.friction_shape` (False for a
        sample reported after the run)."""
        cs = self.mode.contacts[c][1]
        if cs.state == STICK:
            return (self.values if values is None else values)[self.system.tangent_cols[c]]
        if cs.state in (SLIDE, SMOOTH):
            s = self.solver.friction_shape(c, cs, self.slip(c), self.qd, continued)
            return -cs.sigma * self.mu(c) * self.normal(c, values) * s
        return np.zeros(self.solver.ck.dims[c])

    def compliance(self, c: int) -> float:
        """Effective normal compliance ``b = dg''/dN`` of touching contact *c* (Painleve's
        paradox where it reaches zero while sliding)."""
        self._solved()
        if self._lu is not None:
            return self.system.compliance(self._lu, self._piv, c)
        sol = self._solution or self.solver.solve(self.t, self.q, self.qd, self.mode)
        return compliance_of(sol.M, sol.Bm, sol.Gm, self.system.normal_col[c])

    def _dynamics(self, name: str) -> np.ndarray:
        """Output *name* of the kernel (``M, F, G, gamma, B``) at this state, flat."""
        kd = self.solver.kernel.dynamics
        if self._dyn is None:
            self._dyn = kd.raw(self.solver.input(self.t, self.q, self.qd), np.empty(kd.size))
        return self._dyn[kd.slices[name][0]]

    def force_scale(self) -> float:
        """``1 + max |F|`` (generalized forcing): the scale of force-like event tolerances."""
        return 1.0 + max_abs(self._dynamics("F"))

    def constraint_acc(self, row: int) -> float:
        """``f'' = G q'' + gamma`` of kernel row *row* (a released unilateral constraint)."""
        n = self.n
        kernel = self.solver.kernel
        if kernel.compact:
            pattern = kernel.patterns["G"]
            lo, hi = pattern.indptr[row], pattern.indptr[row + 1]
            g = self._dynamics("G")[lo:hi] @ self.qdd[pattern.cols[lo:hi]]
        else:
            g = self._dynamics("G")[row * n:(row + 1) * n] @ self.qdd
        return float(g + self._dynamics("gamma")[row])

    # ------------------------------------------------------------------ kinematics
    @property
    def kin(self) -> np.ndarray:
        """The contact kernel's flat outputs at this state (a copy)."""
        if self._kin is None:
            ck = self.solver.ck
            self._kin = ck.fn.raw(self.solver.input(self.t, self.q, self.qd), np.empty(ck.size))
        return self._kin

    def slip(self, c: int) -> np.ndarray:
        ck = self.solver.ck
        o = ck.at["U"] + ck.offsets[c]
        return self.kin[o:o + ck.dims[c]]

    def gap(self, c: int) -> float:
        return float(self.kin[self.solver.ck.at["gap"] + c])

    def gap_rate(self, c: int) -> float:
        return float(self.kin[self.solver.ck.at["gap_rate"] + c])

    def mu(self, c: int) -> float:
        return float(self.kin[self.solver.ck.at["mu"] + c])

    def mu_s(self, c: int) -> float:
        return float(self.kin[self.solver.ck.at["mu_s"] + c])

    def gap_acc(self, c: int) -> float:
        """``g'' = Gn q'' + gamma_n`` of contact *c*."""
        ck, n = self.solver.ck, self.n
        o = ck.at["Gn"] + c * n
        return float(self.kin[o:o + n] @ self.qdd + self.kin[ck.at["gamma_n"] + c])

    def slip_acc(self, c: int) -> np.ndarray:
        """``U' = W q'' + gamma_U`` of contact *c*."""
        ck, n = self.solver.ck, self.n
        o, d = ck.offsets[c], ck.dims[c]
        W = self.kin[ck.at["W"] + o * n:ck.at["W"] + (o + d) * n].reshape(d, n)
        return W @ self.qdd + self.kin[ck.at["gamma_U"] + o:ck.at["gamma_U"] + o + d]

    @property
    def observables(self) -> dict:
        """The kernel's observables (energies, constraint residuals ``pos``, ``vel``), copied."""
        if self._obs is None:
            out = self.solver.kernel.observables(self.solver.input(self.t, self.q, self.qd))
            self._obs = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in out.items()}
        return self._obs

    def contact_record(self, c: int) -> tuple:
        """``(state label, N, F, U, gap, mu_s)`` of contact *c* for a trajectory sample (the
        forces as reported: :attr:`reported`)."""
        at, kin = self.solver.ck.at, self.kin
        shown = self.reported
        return (self.mode.contacts[c][1].label(), self.normal(c, shown), self.friction(c, shown, False), self.slip(c),
                kin[at["gap"] + c], kin[at["mu_s"] + c])

    def residuals(self, drift) -> tuple[float, float]:
        """Position and velocity residuals of the mode's rows at the state; *drift* = ``(pos,
        vel)``, the active kernel rows with a position / velocity level."""
        pos, vel = drift
        rp = rv = 0.0
        if pos or vel:
            obs = self.observables
            rp = float(np.abs(obs["pos"][pos]).max()) if pos else 0.0
            rv = float(np.abs(obs["vel"][vel]).max()) if vel else 0.0
        for c, (name, cs) in enumerate(self.mode.contacts):
            if cs.state == SEPARATED:
                continue
            rp = max(rp, abs(self.gap(c)))
            rv = max(rv, abs(self.gap_rate(c)))
            if cs.state == STICK:
                rv = max(rv, max_abs(self.slip(c)))
        return rp, rv
