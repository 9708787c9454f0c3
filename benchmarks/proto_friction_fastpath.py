"""Prototype of the proposed fast path for simulations with contacts (benchmark only).

Not part of the library: subclasses of :class:`nonideal.simulation.Simulation` that change
only what the proposals change, so ``bench_friction_sphere.py`` can measure each proposal's
gain against the library on the same model, in the same process, and check that the results
agree (event times, final state).  The proposals, for ``nonideal/simulation.py`` and
``nonideal/modes.py`` (named F1-F3 to keep them apart from the P-numbered proposals of the
pendulum and knife-chain sections of RESULTS.md):

F1  ``Simulation.initial_state`` evaluates the model's initial values with SymPy ``subs`` on
    every run (``Model.numeric_initial``): 2 ms here, 10 % of a run.  Cache the numbers per
    model (models are immutable) or compile them with the parameter vector.
F2  ``Simulation.context`` builds a full :class:`~nonideal.modes.Solution` (copies of M, F,
    G, B, every contact force) after every accepted step and at every Brent iteration, and
    the :class:`~nonideal.events.Jam` event rebuilds and re-solves the whole saddle-point
    system (``effective_compliance``, ~60-120 us, the most expensive event value).  A light
    context keeps only what the events and the drift check read (U, N, F, gap, gap rate,
    multipliers) and takes the compliance ``b = 1/(K^-1)_jj`` from the LU factors of the same
    solve (LAPACK ``dgetrf``/``dgetrs``, one more triangular solve).
F3  The right-hand side for ``lagrange1`` with contacts spends ~75 us per call in Python
    (``assemble``'s loop over rows, ``friction_shape`` twice with ``np.max``, the saddle
    matrix copied into a fresh work array) around ~3 us of compiled kernels and a ~5 us LU.
    Compile, once per mode structure, the saddle-point matrix itself -- transposed, so the
    Lambdify buffer *is* the Fortran-ordered matrix LAPACK factors in place -- with the
    sliding contacts' friction columns left to one numeric update ``-sigma mu s W`` (s depends
    on U), plus ``B^T q'`` for the powers.  One compiled call + one ``dgesv`` per evaluation.

``variants(model)`` returns the cumulative variants measured by the benchmark.
"""

from __future__ import annotations

import math

import numpy as np
import symengine as se
from scipy.linalg import lapack

from nonideal.contacts import LinearizedCoulomb, RegularizedCoulomb
from nonideal.events import EventContext, Jam
from nonideal.modes import SEPARATED, SLIDE, SMOOTH, STICK
from nonideal.numeric import Compiled
from nonideal.simulation import Simulation

DESCRIPTIONS = {
    "F1": "cache the numeric initial values per model (no SymPy subs per run)",
    "F2": "light event context (no Solution copies); Jam compliance from the same LU factors",
    "F3": "compiled saddle-point system per mode structure (one Lambdify call + one dgesv per RHS)",
}

_dgesv, _dgetrf, _dgetrs = lapack.dgesv, lapack.dgetrf, lapack.dgetrs
_INITIAL: dict[int, tuple[object, dict]] = {}
_SYSTEMS: dict[tuple, "ModeSystem"] = {}


def _numeric_initial(model) -> dict:
    hit = _INITIAL.get(id(model))
    if hit is not None and hit[0] is model:
        return hit[1]
    values = dict(model.numeric_initial())
    _INITIAL[id(model)] = (model, values)
    return values


def _shape(solver, c: int, cs, U: np.ndarray, vscale: float, ref) -> np.ndarray:
    """``ModeSolver.friction_shape`` with the velocity scale of the degenerate-slip guard
    passed in (computed once per step; it only matters when |U| ~ 1e-12 |q'|)."""
    law = solver.laws[c]
    if cs.state == SMOOTH:
        nrm = math.sqrt(float(U @ U))
        if isinstance(law, RegularizedCoulomb):
            return U / math.sqrt(nrm * nrm + law.eps * law.eps)
        if isinstance(law, LinearizedCoulomb):
            return U / law.eps if nrm <= law.eps else U / nrm
    if len(U) == 1:
        return np.array(cs.direction, dtype=float)
    nrm = math.sqrt(float(U @ U))
    if nrm > vscale:
        s = U / nrm
        if ref is not None and s @ ref < 0:
            s = -s
        return s
    if ref is not None:
        return ref
    return np.array(cs.direction, dtype=float) if cs.direction else np.zeros_like(U)


class ModeSystem:
    """The compiled saddle-point system of one mode structure (lagrange1):
    ``K = [[M, B0], [G, 0]]`` (stored transposed: the flat output is K in Fortran order),
    ``r = [F; -gamma]``, ``B0^T q'``, and for the sliding contacts ``U``, ``W`` and ``mu``;
    the friction part of their reaction columns, ``-sigma mu s W``, is added numerically."""

    def __init__(self, kernel, layout, mode):
        dyn = kernel.dyn
        n, m = kernel.n, len(layout)
        self.n, self.m, self.size = n, m, n + m
        Gr, gam, Bc = [], [], []
        self.sliding, self.tangent = [], []
        U, W, mu = [], [], []
        for j, r in enumerate(layout):
            if r.kind == "constraint":
                row = kernel.rows[r.index]
                Gr.append(list(row.G)), gam.append(row.gamma), Bc.append(list(row.B))
            elif r.kind == "normal":
                cd = dyn.contacts[r.index]
                Gr.append(list(cd.Gn)), gam.append(cd.gamma_n), Bc.append(list(cd.Gn))
                cs = mode.contacts[r.index][1]
                if cs.state in (SLIDE, SMOOTH):
                    d = len(cd.U)
                    self.sliding.append((j, r.index, len(U), d, cs, len(mu)))
                    U += list(cd.U)
                    W += [list(w) for w in cd.W]
                    mu.append(cd.mu)
            else:
                cd = dyn.contacts[r.index]
                w = list(cd.W[r.k])
                Gr.append(w), gam.append(cd.gamma_U[r.k]), Bc.append(w)
                self.tangent.append(j)
        s = n + m
        zero = se.Integer(0)
        K = [[zero] * s for _ in range(s)]
        for i in range(n):
            for k in range(n):
                K[i][k] = dyn.M[i, k]
        for j in range(m):
            for i in range(n):
                K[i][n + j] = Bc[j][i]
                K[n + j][i] = Gr[j][i]
        Kt = [[K[b][a] for b in range(s)] for a in range(s)]
        outputs = {"Kt": Kt, "r": list(dyn.F) + [-g for g in gam],
                   "Bqd": [sum((Bc[j][i] * dyn.qd[i] for i in range(n)), zero) for j in range(m)] or [zero]}
        if U:
            outputs.update(U=U, W=W, mu=mu)
        self.powers = kernel.has_nc_forces or kernel.explicit_time
        if self.powers:
            P_nc = sum((a * b for a, b in zip(dyn.Q_nc, dyn.qd)), zero)
            outputs["P"] = [P_nc, se.diff(dyn.V, dyn.t) - se.diff(dyn.T, dyn.t)]
        self.fn = Compiled(kernel.symbols, outputs)
        sl = self.fn.slices
        self.k_sl, self.r_sl, self.b_sl = sl["Kt"][0], sl["r"][0], sl["Bqd"][0]
        self.u0 = sl["U"][0].start if U else 0
        self.w0 = sl["W"][0].start if U else 0
        self.mu0 = sl["mu"][0].start if U else 0
        self.p_sl = sl["P"][0] if self.powers else None
        self.not_tangent = [j for j in range(m) if j not in self.tangent]

    @classmethod
    def of(cls, kernel, layout, mode) -> "ModeSystem":
        key = (id(kernel), mode.structure, tuple(layout))
        hit = _SYSTEMS.get(key)
        if hit is None or hit[0] is not kernel:
            hit = (kernel, cls(kernel, layout, mode))
            _SYSTEMS[key] = hit
        return hit[1]

    def evaluate(self, solver, x, qd, vscale):
        """``(K in Fortran order, r, friction power per unit multiplier (m,), flat)`` with the
        friction columns filled in; K and r are views into the reused output buffer."""
        n, s = self.n, self.size
        flat = self.fn.raw(x)
        K = flat[self.k_sl].reshape(s, s).T
        r = flat[self.r_sl]
        fpow = np.zeros(self.m)
        for j, c, o, d, cs, k in self.sliding:
            U = flat[self.u0 + o:self.u0 + o + d]
            W = flat[self.w0 + o * n:self.w0 + (o + d) * n].reshape(d, n)
            sv = _shape(solver, c, cs, U, vscale, solver.reference.get(c))
            fdir = (cs.sigma * flat[self.mu0 + k]) * (sv @ W)
            K[:n, n + j] -= fdir
            fpow[j] = -(fdir @ qd)
        for j in self.tangent:
            fpow[j] = flat[self.b_sl][j]
        return K, r, fpow, flat


class _Contact:
    __slots__ = ("state", "N", "F", "U", "gap", "gap_rate", "mu", "mu_s")


class _LightSolution:
    """What the events and the drift check read from a solution."""

    __slots__ = ("F", "contacts", "values", "rows", "compliance")

    def multiplier(self, row: int) -> float:
        j = self.rows.get(row)
        return float(self.values[j]) if j is not None else 0.0


class _FastJam(Jam):
    def value(self, ctx: EventContext) -> float:
        b = getattr(ctx.solution, "compliance", None)
        if b is None:
            return super().value(ctx)
        return b[self.name]


class FastSimulation(Simulation):
    """:class:`Simulation` with the proposals F1-F3 switched on individually."""

    def __init__(self, model, *, f1=True, f2=True, f3=True, **options):
        super().__init__(model, **options)
        self.f1, self.f2, self.f3 = f1, f2, f3
        self._vscale = 1e-12

    # F1 ------------------------------------------------------------------------------
    def initial_state(self, initial=None):
        if not self.f1:
            return super().initial_state(initial)
        from nonideal.consistency import complete_state

        given = dict(_numeric_initial(self.model))
        given.update(initial or {})
        q, qd, _ = complete_state(self.kernel, given, self.params, self.model.t0)
        return q, qd

    @staticmethod
    def _scale(qd) -> float:
        return 1e-12 * (1.0 + float(np.abs(qd).max()))

    # F2 ------------------------------------------------------------------------------
    def events(self, mode, t, y):
        evs = super().events(mode, t, y)
        if not self.f2:
            return evs
        return [_FastJam(e.kind, e.name, e.row) if type(e) is Jam else e for e in evs]

    def _saddle(self, mode, layout, x, out, cout, qd):
        """K (Fortran order, friction columns included) and r of the mode at x."""
        n, m = self.n, len(layout)
        if self.f3:
            K, r, _, _ = ModeSystem.of(self.kernel, layout, mode).evaluate(self.solver, x, qd, self._scale(qd))
            return np.array(K, order="F"), np.array(r)
        G, gamma, B = self.solver.assemble(mode, layout, out, cout)
        K = np.zeros((n + m, n + m), order="F")
        K[:n, :n] = out["M"]
        K[:n, n:] = B
        K[n:, :n] = G
        return K, np.concatenate((out["F"], -gamma))

    def context(self, t, y, mode):
        solver = self.solver
        if not self.f2 or solver.form != "lagrange1":
            return super().context(t, y, mode)
        n, kernel, ck = self.n, self.kernel, solver.ck
        q, qd = y[:n], y[n:2 * n]
        x = solver.input(t, q, qd)
        out = kernel.dynamics(x)
        cout = ck(x) if ck else None
        layout = solver.layout(mode)
        m = len(layout)
        light = _LightSolution()
        light.F = np.array(out["F"])
        light.rows = {r.index: j for j, r in enumerate(layout) if r.kind == "constraint"}
        light.compliance = {}
        if m:
            K, rhs = self._saddle(mode, layout, x, out, cout, qd)
            lu, piv, info = _dgetrf(K, overwrite_a=1)
            if info != 0:
                return super().context(t, y, mode)
            sol, _ = _dgetrs(lu, piv, rhs)
            values = -sol[n:]
            for j, r in enumerate(layout):
                if r.kind == "normal" and mode.contacts[r.index][1].state == SLIDE:
                    e = np.zeros(n + m)
                    e[n + j] = 1.0
                    # K = [[M, B], [G, 0]] acts on [a; -mu]: (K^-1)_jj = -1/b
                    inv_jj = -_dgetrs(lu, piv, e)[0][n + j]
                    light.compliance[ck.names[r.index]] = 1.0 / inv_jj if inv_jj != 0 else math.inf
        else:
            values = np.zeros(0)
        light.values = values
        light.contacts = {}
        if ck:
            normal = {r.index: j for j, r in enumerate(layout) if r.kind == "normal"}
            tang = {(r.index, r.k): j for j, r in enumerate(layout) if r.kind == "tangent"}
            for c, (name, cs) in enumerate(mode.contacts):
                o, d = ck.offsets[c], ck.dims[c]
                cf = _Contact()
                cf.state = cs.state
                cf.N = float(values[normal[c]]) if c in normal else 0.0
                cf.U = np.array(cout["U"][o:o + d])
                cf.gap = float(cout["gap"][c])
                cf.gap_rate = float(cout["gap_rate"][c])
                cf.mu = float(cout["mu"][c])
                cf.mu_s = float(cout["mu_s"][c])
                if cs.state == STICK:
                    cf.F = np.array([values[tang[(c, k)]] for k in range(d)])
                elif cs.state in (SLIDE, SMOOTH):
                    sv = _shape(solver, c, cs, cf.U, self._scale(qd), solver.reference.get(c))
                    cf.F = -cs.sigma * cf.mu * cf.N * sv
                else:
                    cf.F = np.zeros(d)
                light.contacts[name] = cf
        obs = kernel.observables(x) if kernel.rows else {}
        return EventContext(t, q, qd, light, obs, solver, mode)

    # F3 ------------------------------------------------------------------------------
    def rhs(self, mode):
        solver = self.solver
        if not (self.f3 and solver.form == "lagrange1" and self.contacts and self.track):
            return super().rhs(mode)
        layout = solver.layout(mode)
        if not layout:
            return super().rhs(mode)
        n = self.n
        system = ModeSystem.of(self.kernel, layout, mode)
        reaction_rows = system.not_tangent
        b_sl, p_sl = system.b_sl, system.p_sl
        sim = self

        def fun(t, y):
            qd = y[n:2 * n]
            x = solver.input(t, y[:n], qd)
            K, r, fpow, flat = system.evaluate(solver, x, qd, sim._vscale)
            Bqd = flat[b_sl]
            dy = np.zeros_like(y)
            if p_sl is not None:
                dy[2 * n], dy[2 * n + 2] = flat[p_sl]
            _, _, sol, info = _dgesv(K, r, overwrite_a=1, overwrite_b=1)
            if info != 0:
                return Simulation.rhs(sim, mode)(t, y)  # the library explains singular systems
            lam = -sol[n:]
            dy[:n] = qd
            dy[n:2 * n] = sol[:n]
            P_f = float(lam @ fpow)
            dy[2 * n + 1] = float(lam[reaction_rows] @ Bqd[reaction_rows]) if reaction_rows else 0.0
            dy[2 * n + 3] = P_f
            return dy
        return fun

    def run(self, *args, **kwargs):
        # the velocity scale of the degenerate-slip guard is refreshed where the library
        # refreshes the slip reference: at the start of every step
        solver = self.solver
        original = solver.set_references
        sim = self

        def set_references(mode, t, q, qd):
            sim._vscale = sim._scale(qd)
            original(mode, t, q, qd)
        solver.set_references = set_references
        try:
            return super().run(*args, **kwargs)
        finally:
            del solver.set_references


def variants(model):
    """Cumulative variants ``(name, fn(t_end, initial) -> Trajectory)``."""
    def make(**flags):
        return lambda t_end, initial: FastSimulation(model, **flags).run(t_end=t_end, initial=initial)
    return [("F1", make(f1=True, f2=False, f3=False)),
            ("F1+F2", make(f1=True, f2=True, f3=False)),
            ("F1+F2+F3", make(f1=True, f2=True, f3=True))]
