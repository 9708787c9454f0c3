"""Modes of a hybrid mechanical system and the motion in a mode.

A :class:`Mode` says which unilateral constraints are held (and, for contacts, whether each
is separated, sticking or sliding in which direction).  :class:`ModeSolver` evaluates the
motion in a mode at a state -- accelerations and the multiplier of every active row -- in the
chosen formalism: Lagrange I uses the compiled model kernel and selects rows numerically; the
other forms are derived symbolically once per mode and compiled (the physical motion must not
depend on the form, which the tests check).

:func:`select_mode` is the small complementarity problem solved at every switch: among the
closed unilateral constraints, find the set held such that held multipliers are ``>= 0`` and
released constraints separate (``f'' >= 0``).  For ideal constraints the answer is unique
(``G M^-1 G^T`` is positive definite); when it is not, the problem is reported as mechanics
without a unique answer.  :func:`impact` applies the impact law when a gap closes.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from .errors import MechanicsError, SingularSystem
from .formalisms import derive
from .numeric import FormSystem, Kernel, SingularMatrix, solve_saddle

__all__ = ["Mode", "Solution", "ModeSolver", "select_mode", "impact"]

MAX_ENUMERATION = 12  # at most 2**12 candidate sets


@dataclass(frozen=True)
class Mode:
    """Which unilateral constraints are held (names)."""

    held: frozenset[str] = frozenset()

    def label(self) -> str:
        return ", ".join(sorted(self.held)) if self.held else "free"


@dataclass
class Solution:
    """The motion at one state in one mode.

    Attributes
    ----------
    qdd : ndarray, shape (n_q,)
    rows : list of int -- kernel row indices active in this mode
    multipliers : ndarray -- one per active row (same order)
    M, F : ndarray -- mass matrix and forcing at the state
    G, gamma, B : ndarray -- all rows of the kernel at the state
    """

    qdd: np.ndarray
    rows: list[int]
    multipliers: np.ndarray
    M: np.ndarray
    F: np.ndarray
    G: np.ndarray
    gamma: np.ndarray
    B: np.ndarray
    direct: dict[str, float] = field(default_factory=dict)

    def multiplier(self, row: int) -> float:
        return float(self.multipliers[self.rows.index(row)]) if row in self.rows else 0.0


class ModeSolver:
    """Evaluate the motion of a model in a mode, in a given formalism.

    Parameters
    ----------
    kernel : Kernel
    params : ndarray
    form : str
    independent : tuple of str, optional
    """

    def __init__(self, kernel: Kernel, params: np.ndarray, form: str = "lagrange1",
                 independent=None):
        self.kernel = kernel
        self.params = params
        self.form = form
        self.independent = independent
        self.model = kernel.model
        self.bilateral = [i for i, r in enumerate(kernel.rows) if not r.unilateral]
        self.unilateral = [i for i, r in enumerate(kernel.rows) if r.unilateral]
        self._forms: dict[tuple, FormSystem] = {}
        self._active: dict[Mode, FormSystem] = {}
        self.x = kernel.layout.make(params)

    def rows(self, mode: Mode) -> list[int]:
        return [i for i, r in enumerate(self.kernel.rows)
                if not r.unilateral or r.name in mode.held]

    def input(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        x = self.x
        n = self.kernel.n
        x[0] = t
        x[1:1 + n] = q
        x[1 + n:1 + 2 * n] = qd
        return x

    def form_system(self, mode: Mode, independent=None) -> FormSystem:
        """The compiled form for *mode* (derived once per mode and choice of independent
        coordinates)."""
        independent = independent if independent is not None else self.independent
        key = (mode, independent)
        fs = self._forms.get(key)
        if fs is None:
            rows = [self.kernel.rows[i] for i in self.rows(mode)]
            eom = derive(self.model, self.form, rows=rows, independent=independent)
            fs = FormSystem(eom)
            self._forms[key] = fs
            if independent is None:
                self._forms[(mode, eom.independent)] = fs
        return fs

    def _current_form(self, mode: Mode, G: np.ndarray, idx: list[int]) -> FormSystem:
        """The form for *mode*; when the user did not fix the independent coordinates and the
        dependent block of the current choice is ill-conditioned at this state, re-partition
        (pivoted QR at the state) -- coordinate partitioning, as in multibody codes."""
        fs = self._active.get(mode) or self.form_system(mode)
        if self.independent is not None or not fs.eom.eliminated:
            self._active[mode] = fs
            return fs
        ideal = [i for i in idx if self.kernel.rows[i].reaction_kind == "ideal"]
        if not ideal:
            return fs
        coords = list(self.model.coordinates)
        Gi = G[ideal]
        dep = [coords.index(c) for c in coords if c not in fs.eom.independent]
        s_all = np.linalg.svd(Gi, compute_uv=False)
        s_dep = np.linalg.svd(Gi[:, dep], compute_uv=False)
        if s_dep[-1] < 1e-3 * s_all[0]:
            from scipy.linalg import qr
            _, _, piv = qr(Gi, pivoting=True)
            new_dep = sorted(piv[:len(ideal)])
            ind = tuple(c for j, c in enumerate(coords) if j not in new_dep)
            fs = self.form_system(mode, ind)
        self._active[mode] = fs
        return fs

    def accelerations(self, t: float, q: np.ndarray, qd: np.ndarray, mode: Mode):
        """Fast path for the right-hand side: ``(qdd, mu, rows, kernel_outputs)``.

        The kernel outputs are views into a reused buffer (valid until the next call).
        """
        x = self.input(t, q, qd)
        out = self.kernel.dynamics(x)
        idx = self.rows(mode)
        M, F = out["M"], out["F"]
        try:
            if self.form == "lagrange1":
                if idx:
                    qdd, mu = solve_saddle(M, F, out["B"][:, idx], out["G"][idx], out["gamma"][idx])
                else:
                    qdd, mu = solve_saddle(M, F)
                return qdd, mu, idx, out, None
            G = out["G"] if self.kernel.m else np.zeros((0, self.kernel.n))
            fs = self._current_form(mode, G, idx)
            _, mu_form, qdd = fs.solve(x)
            return qdd, None, idx, out, dict(zip(fs.eom.constraint_names, map(float, mu_form)))
        except SingularMatrix:
            m_all = self.kernel.m
            G = out["G"][idx] if m_all else np.zeros((0, self.kernel.n))
            B = out["B"][:, idx] if m_all else np.zeros((self.kernel.n, 0))
            raise diagnose_singular(self.kernel, M, G, B, idx, t, q, qd) from None

    def solve(self, t: float, q: np.ndarray, qd: np.ndarray, mode: Mode) -> Solution:
        """Accelerations and the multiplier of every active row at a state.

        Raises
        ------
        SingularSystem
            Singular mass matrix or dependent constraints (named).
        """
        qdd, mu, idx, out, direct = self.accelerations(t, q, qd, mode)
        n, m_all = self.kernel.n, self.kernel.m
        M, F = out["M"].copy(), out["F"].copy()
        G = out["G"].copy() if m_all else np.zeros((0, n))
        gamma = out["gamma"].copy() if m_all else np.zeros(0)
        B = out["B"].copy() if m_all else np.zeros((n, 0))
        if mu is None:
            mu = recover_multipliers(M, F, B[:, idx], qdd) if idx else np.zeros(0)
            for j, i in enumerate(idx):
                name = self.kernel.rows[i].name
                if name in direct:
                    mu[j] = direct[name]
        else:
            direct = {self.kernel.rows[i].name: float(v) for i, v in zip(idx, mu)}
        return Solution(np.array(qdd, dtype=float), idx, np.array(mu, dtype=float), M, F, G, gamma, B, direct)


def recover_multipliers(M: np.ndarray, F: np.ndarray, B: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Multipliers from ``B mu = M q'' - F`` (exact for a consistent motion; least squares)."""
    mu, *_ = np.linalg.lstsq(B, M @ qdd - F, rcond=None)
    return mu


def diagnose_singular(kernel: Kernel, M, G, B, idx, t, q, qd) -> Exception:
    """Turn a singular linear system into an actionable error naming what is singular."""
    names = list(kernel.model.coordinates)
    n = kernel.n
    src = None if kernel.model.source == "<api>" else kernel.model.source
    where = f" at t = {t:.6g}, q = {dict(zip(names, np.round(q, 6)))}"
    if idx:
        rank = np.linalg.matrix_rank(G)
        if rank < len(idx):
            # find the dependent rows greedily
            dep, keep = [], []
            for j, i in enumerate(idx):
                if np.linalg.matrix_rank(G[keep + [j]]) == len(keep) + 1:
                    keep.append(j)
                else:
                    dep.append(kernel.rows[i].name)
            return SingularSystem(
                f"dependent (redundant) constraints: {', '.join(repr(d) for d in dep)} "
                f"repeat what the others impose{where}; remove them or make them independent", src)
        U, s, Vt = np.linalg.svd(G)
        null = Vt[rank:].T
    else:
        null = np.eye(n)
    Mr = null.T @ M @ null if null.size else np.zeros((0, 0))
    if null.size and (np.linalg.matrix_rank(Mr) < Mr.shape[0]):
        w, v = np.linalg.eigh(Mr)
        vec = null @ v[:, 0]
        vec /= np.max(np.abs(vec))
        combo = " + ".join(f"{c:.3g}*{nm}'" for c, nm in zip(vec, names) if abs(c) > 1e-9)
        return SingularSystem(
            f"singular mass matrix{where}: the kinetic energy does not depend on the velocity "
            f"combination {combo}; give that motion inertia (mass or moment of inertia) or "
            "constrain it", src)
    if idx and not np.allclose(B, G.T):
        return MechanicsError(
            "the non-ideal constraints (servo / quasi-ideal / friction) cannot be realized by "
            "their reactions: G M^-1 B is singular" + where)
    return SingularSystem(f"the equations of motion are singular{where}", src)


# --------------------------------------------------------------------------- mode selection


def _candidates(solver: ModeSolver, t, q, qd, tol_pos: float, tol_vel: float):
    out = solver.kernel.observables(solver.input(t, q, qd))
    closed = []
    for i in solver.unilateral:
        if abs(out["pos"][i]) <= tol_pos and out["vel"][i] <= tol_vel:
            closed.append(i)
    return closed


def select_mode(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray,
                tol_pos: float = 1e-9, tol_vel: float = 1e-9) -> Mode:
    """Choose the held unilateral constraints at a state (complementarity by enumeration).

    A constraint is a candidate when it is closed (``f ~ 0``, ``f' ~ 0``).  A candidate set is
    consistent when every held multiplier is ``>= 0`` and every released candidate separates
    (``f'' >= 0``).

    Raises
    ------
    MechanicsError
        No consistent set, or several that give different accelerations.
    """
    scale_q = 1 + np.max(np.abs(q))
    scale_v = 1 + np.max(np.abs(qd))
    closed = _candidates(solver, t, q, qd, tol_pos * scale_q, tol_vel * scale_v)
    names = [solver.kernel.rows[i].name for i in closed]
    if len(closed) > MAX_ENUMERATION:
        raise MechanicsError(f"too many simultaneous contacts to enumerate ({len(closed)})", t)
    consistent = []
    for k in range(len(closed), -1, -1):
        for subset in itertools.combinations(range(len(closed)), k):
            mode = Mode(frozenset(names[j] for j in subset))
            sol = solver.solve(t, q, qd, mode)
            scale_f = 1e-9 * (1 + np.max(np.abs(sol.F)) + np.max(np.abs(sol.multipliers), initial=0))
            ok = all(sol.multiplier(closed[j]) >= -scale_f for j in subset)
            if ok:
                for j in range(len(closed)):
                    if j in subset:
                        continue
                    i = closed[j]
                    acc = sol.G[i] @ sol.qdd + sol.gamma[i]
                    if acc < -1e-9 * (1 + np.max(np.abs(sol.qdd))):
                        ok = False
                        break
            if ok:
                consistent.append((mode, sol))
    if not consistent:
        raise MechanicsError(
            "no consistent set of held unilateral constraints: every choice among "
            f"{names} either pulls (negative multiplier) or penetrates", t,
            dict(zip(solver.model.coordinates, q)))
    mode0, sol0 = consistent[0]
    for mode, sol in consistent[1:]:
        if not np.allclose(sol.qdd, sol0.qdd, rtol=1e-7, atol=1e-9 * (1 + np.max(np.abs(sol0.qdd)))):
            raise MechanicsError(
                f"the motion is not unique: held sets [{mode0.label()}] and [{mode.label()}] are "
                "both consistent and give different accelerations", t,
                dict(zip(solver.model.coordinates, q)))
    return mode0


def impact(solver: ModeSolver, t: float, q: np.ndarray, qd: np.ndarray, hitting: list[int],
           restitution: dict[int, float] | None = None):
    """Velocity jump when unilateral constraints close (impact law per constraint).

    The impulse set is chosen by enumeration so that impulses are ``>= 0`` and constraints
    without impulse do not approach (``f'+ >= 0``); bilateral constraints always keep their
    velocity-level equation.  Plastic impact (``e = 0``) makes the normal velocity zero;
    Newton's law (``e > 0``) reverses it.

    Returns
    -------
    qd_plus : ndarray
    impulses : dict name -> impulse
    """
    restitution = restitution or {}
    kernel = solver.kernel
    x = solver.input(t, q, qd)
    out = kernel.dynamics(x)
    obs = kernel.observables(x)
    M = out["M"]
    G, B = out["G"], out["B"]
    vel = obs["vel"]
    scale_q = 1 + np.max(np.abs(q))
    closed = [i for i in solver.unilateral if abs(obs["pos"][i]) <= 1e-8 * scale_q]
    for i in hitting:
        if i not in closed:
            closed.append(i)
    eq_rows = [i for i in solver.bilateral if kernel.rows[i].velocity is not None]
    best = None
    for k in range(len(closed), -1, -1):
        for subset in itertools.combinations(closed, k):
            rows = eq_rows + list(subset)
            if not rows:
                qd_plus, lam = qd.copy(), np.zeros(0)
            else:
                Gr = G[rows]
                c = vel[rows] - Gr @ qd
                target = np.array([-restitution.get(i, 0.0) * min(vel[i], 0.0) if i in subset else 0.0
                                   for i in rows])
                try:
                    qd_plus, lam = solve_saddle(M, M @ qd, B[:, rows], Gr, c - target)
                except SingularMatrix:
                    continue
            ok = all(lam[len(eq_rows) + j] >= -1e-12 * (1 + np.max(np.abs(lam))) for j in range(k))
            if ok:
                for i in closed:
                    if i not in subset:
                        vplus = G[i] @ qd_plus + (vel[i] - G[i] @ qd)
                        if vplus < -1e-10 * (1 + np.max(np.abs(qd_plus))):
                            ok = False
                            break
            if ok:
                best = (qd_plus, {kernel.rows[r].name: float(v) for r, v in zip(rows, lam)})
                break
        if best is not None:
            break
    if best is None:
        raise MechanicsError("no consistent impact: every impulse set pulls or lets a contact "
                             "penetrate", t, dict(zip(solver.model.coordinates, q)))
    return best
