"""The motion of a hybrid mechanical system in a mode: the solver and its routes.

A :class:`Mode` says which unilateral constraints are held and, for every contact, its
:class:`ContactState`: separated, sticking (rolling), sliding in a direction, or "smooth" -- the
one touching state of a contact without a sticking mode: sliding under a regularized friction
law, or touching without friction (Coulomb's law with ``mu = mu_static = 0`` at the parameters
of the solver, :attr:`ModeSolver.frictionless`).  :class:`ModeSolver` evaluates the motion in a
mode at a state: the accelerations and the multiplier of every active row, in the chosen
formalism.  Lagrange I assembles the rows numerically from the compiled kernels (no
recompilation when the mode changes); the other forms are derived symbolically once per mode
structure and compiled -- the physical motion must not depend on the form.

Rows of a mode (:class:`RowSpec`): the model's active constraints; for a closed contact its
normal row (multiplier ``N``, the normal force) whose reaction column carries the friction
when sliding, ``B = dg/dq - sigma mu sum_k W_k s_k``; for a sticking contact also one
nonholonomic row ``U_k = 0`` per slip component (multiplier = friction force component).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..numeric.consistency import initial_branch
from ..numeric.contact_kernel import SLIP_FLOOR, SLIP_LEVEL, contact_kernel_of
from ..modeling.contacts import CoulombContensou, LinearizedCoulomb, RegularizedCoulomb
from ..numeric.contensou import contensou_shape
from ..equations.dynamics import dynamics_of
from ..errors import FormNotApplicable, SetValuedFriction
from ..equations.formalisms import derive
from ..numeric.kernel import FormSystem, Kernel, SingularMatrix, max_abs, solve_saddle
from .diagnosis import DENSE_DIAGNOSIS_MAX, diagnose_singular
from .indeterminate import minimum_norm
from .partition import better_partition
from .routes import route_for
from .types import SEPARATED, SLIDE, SMOOTH, STICK, ContactForce, ContactState, Mode, RowSpec, Solution

__all__ = ["ModeSolver", "recover_multipliers"]


class ModeSolver:
    """Evaluate the motion of a model in a mode, in a given formalism.

    Parameters
    ----------
    kernel : Kernel
    params : ndarray
    form : str
    independent : tuple of str, optional
        Independent coordinates of the reduced forms, kept as given (no re-partitioning);
        for Lagrange II the first chart only (it changes charts where that one becomes
        singular: :attr:`charts`, :mod:`nonideal.modes.charts`).
    specialize : bool
        Lagrange I: use the compiled system of a mode once its structure is hot
        (:class:`~nonideal.modes.system.ModeFunction`); ``False``: always the index path.

    Attributes
    ----------
    frictionless : frozenset of int
        The contacts with Coulomb's law whose ``mu`` and ``mu_static`` are zero at *params*:
        they touch in the single state "smooth" (no sticking, no slip events).
    rolling : frozenset of int
        The contacts that roll ideally (``mu = inf``): they touch in the single state "stick"
        (rolling), whatever the friction force; only the normal force can end it.
    """

    def __init__(self, kernel: Kernel, params: np.ndarray, form: str = "lagrange1",
                 independent=None, specialize: bool = True):
        self.kernel = kernel
        self.specialize = specialize
        self.params = params
        self.form = form
        #: how the motion is solved (chosen once by the form)
        self.route = route_for(form)
        self.independent = independent
        self.model = kernel.model
        self.ck = contact_kernel_of(kernel.model)
        self.bilateral = [i for i, r in enumerate(kernel.rows) if not r.unilateral]
        self.unilateral = [i for i, r in enumerate(kernel.rows) if r.unilateral]
        # compiled reduced forms of this model and form: ({key: FormSystem},
        # {(structure, kept): [FormSystem]} (the charts of Lagrange II))
        entry = self.model.cached(("forms", form), lambda: ({}, {}))
        self._forms: dict[tuple, FormSystem] = entry[0]
        #: Lagrange II: the charts the motion moves through (:class:`~nonideal.modes.charts.Charts`)
        self.charts = None
        if self.route.charts:
            from .charts import Charts

            self.charts = Charts(self, entry[1])
        self._active: dict[tuple, FormSystem] = {}
        self._elim_rows: dict[tuple, list[int]] = {}
        self._refused: set[tuple] = set()
        self.x = kernel.layout.make(params)
        self.n = kernel.n
        self.laws = [c.law for c in self.ck.data]
        self.frictionless = self.ck.frictionless(params) if self.ck else frozenset()
        self.rolling = self.ck.rolling if self.ck else frozenset()
        self.reference: dict[int, np.ndarray] = {}
        #: while a mode is selected (:func:`~nonideal.modes.switching.select_mode`): the slip below
        #: which a candidate's own sliding direction is its friction's (the slip is zero there)
        self.selecting = 0.0
        if self.ck and self.ck.torques and not self.route.saddle_point:
            from ..errors import ModelError

            raise ModelError(f"--form {form}: the friction torques (spin_friction, rolling_friction) are "
                             "solved with Lagrange's equations of the first kind only; use --form lagrange1",
                             None if self.model.source == "<api>" else self.model.source)
        #: how statically indeterminate reactions are reported: (rule, weights by name)
        settings = self.model.simulation
        self.split = (settings.split, dict(settings.split_weights))
        # one output buffer for both kernels: the Lagrange I fast path gathers from it
        self.z = np.zeros(kernel.dynamics.size + self.ck.size)
        self.kz, self.cz = self.z[:kernel.dynamics.size], self.z[kernel.dynamics.size:]
        #: the last Lagrange I solve: (t, y, mode, [q''; -lambda], LU, pivots)
        self.last = None
        self.start()

    def start(self) -> None:
        """A run starts: its ``calls`` of each mode system, and ``hot``, those compiled for it."""
        self.calls, self.hot = {}, set()

    # ------------------------------------------------------------------ modes and rows
    def initial_contacts(self) -> tuple[tuple[str, ContactState], ...]:
        return tuple((name, ContactState()) for name in self.ck.names)

    def rows(self, mode: Mode) -> list[int]:
        """Active kernel constraint rows."""
        return [i for i, r in enumerate(self.kernel.rows) if not r.unilateral or r.name in mode.held]

    def layout(self, mode: Mode) -> list[RowSpec]:
        """The rows of *mode*: active constraints, then per touching contact its normal row and,
        when sticking, its slip rows."""
        return self.system(mode).layout

    def input(self, t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        x = self.x
        n = self.n
        x[0] = t
        x[1:1 + n] = q
        x[1 + n:1 + 2 * n] = qd
        return x

    def system(self, mode: Mode):
        """The :class:`~nonideal.modes.system.ModeSystem` of the structure of *mode* (cached per
        model)."""
        from .system import system_of

        return system_of(self.kernel, mode)

    def motion(self, t: float, y: np.ndarray, mode: Mode, kin: np.ndarray | None = None):
        """The :class:`~nonideal.modes.motion.Motion` at the state ``y = [q, q', ...]`` (lazy:
        evaluated on first use; reuses :attr:`last` when it was solved at that state, and
        *kin*, the contact kernel's flat outputs at the state, when given)."""
        from .motion import Motion

        return Motion(self, mode, t, y, kin)

    # ------------------------------------------------------------------ friction shapes
    def friction_shape(self, c: int, cs: ContactState, U: np.ndarray,
                       qd: np.ndarray | None = None, continued: bool = True) -> np.ndarray:
        """The vector ``s`` with friction ``F = -sigma mu N s`` (unit slip direction for
        Coulomb sliding; the regularized shape for the smooth laws, zero for a frictionless
        contact).  *qd*: the velocities of the state (default: those of the last
        :meth:`input`), which scale the test ``|U| ~ 0``.  *continued* False: the slip's own
        direction, not its continuation through a stop within the step (for reported samples)."""
        law = self.laws[c]
        if cs.state == SMOOTH:
            nrm = float(np.sqrt(U @ U))
            if isinstance(law, RegularizedCoulomb):
                return U / np.sqrt(nrm * nrm + law.eps * law.eps)
            if isinstance(law, LinearizedCoulomb):
                return U / law.eps if nrm <= law.eps else U / nrm
            if isinstance(law, CoulombContensou):
                s = contensou_shape(U)
                if s is None:
                    raise SetValuedFriction(
                        f"contact '{self.ck.names[c]}': the slip and the pivoting of its patch vanished "
                        "together; Coulomb-Contensou friction is set-valued there (the contact sticks), "
                        "which this law has no mode for -- use friction = \"coulomb\" with "
                        "spin_friction for a body that comes to rest")
                return s
            return np.zeros(len(U))  # Coulomb's law: a frictionless contact
        if len(U) == 1:
            return np.array(cs.direction, dtype=float)
        nrm = math.sqrt(U @ U)
        if nrm <= self.selecting and len(cs.direction) == len(U) and cs.direction[0] != "onset":
            return np.array(cs.direction, dtype=float)  # a candidate onset: its direction, not the noise of U
        if qd is None:
            qd = self.x[1 + self.n:1 + 2 * self.n]
        ref = self.reference.get(c)
        # |U| > SLIP_FLOOR (1 + max |q'|); the cheap bound 2 SLIP_FLOOR (1 + |q'|) decides all but tiny slips
        if nrm > 2.0 * SLIP_FLOOR * (1.0 + math.sqrt(qd @ qd)) or nrm > SLIP_FLOOR * (1.0 + max_abs(qd)):
            s = U / nrm
            # analytic continuation through U = 0 within a step: keep the orientation of the
            # slip at the start of the step, so that the right-hand side stays smooth up to
            # (and a little past) the stop, where the SlipStop event places the switch
            if continued and ref is not None and s @ ref < 0:
                s = -s
            return s
        if ref is not None:
            return ref
        return np.array(cs.direction, dtype=float) if cs.direction else np.zeros_like(U)

    def set_references(self, mode: "Mode", motion, start: bool = False) -> None:
        """Record the slip direction of every two-component sliding contact at the state of
        *motion* (a :class:`~nonideal.modes.motion.Motion`; the simulation calls this at the
        start of each step).  At the *start* of a phase, a slip below the switching tolerance
        (``SLIP_LEVEL (1 + max |q'|)``) is the residue of a stop, not a direction: the mode's own
        sliding direction is the reference (the residue may point the other way, and friction
        oriented by it would push the new slide on)."""
        previous, self.reference = ({} if start else self.reference), {}
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state == SLIDE and self.ck.dims[c] > 1:
                U = motion.slip(c)
                nrm = math.sqrt(U @ U)
                speeds = 1.0 + max_abs(motion.qd)
                if start and len(cs.direction) == len(U) and nrm <= SLIP_LEVEL * speeds:
                    self.reference[c] = np.array(cs.direction, dtype=float)
                elif nrm > SLIP_FLOOR * speeds:
                    self.reference[c] = U / nrm
                elif c in previous:  # below the floor the slip has no direction: the reference stays
                    self.reference[c] = previous[c]
                elif cs.direction:
                    self.reference[c] = np.array(cs.direction, dtype=float)

    # ------------------------------------------------------------------ assembly
    def assemble(self, mode: Mode, layout: list[RowSpec], out: dict, cout: dict | None):
        """Numeric ``G (m, n)``, ``gamma (m,)``, ``B (n, m)`` of the mode's rows."""
        n, m = self.n, len(layout)
        G = np.empty((m, n))
        gamma = np.empty(m)
        B = np.empty((n, m))
        G_all = self.kernel.dense(out, "G") if self.kernel.compact else out.get("G")
        B_all = self.kernel.dense(out, "B") if self.kernel.compact else out.get("B")
        for j, r in enumerate(layout):
            if r.kind == "constraint":
                G[j] = G_all[r.index]
                gamma[j] = out["gamma"][r.index]
                B[:, j] = B_all[:, r.index]
            elif r.kind == "normal":
                c = r.index
                G[j] = cout["Gn"][c]
                gamma[j] = cout["gamma_n"][c]
                cs = mode.contacts[c][1]
                if cs.state in (SLIDE, SMOOTH):
                    o, d = self.ck.offsets[c], self.ck.dims[c]
                    s = self.friction_shape(c, cs, cout["U"][o:o + d])
                    B[:, j] = G[j] - cs.sigma * cout["mu"][c] * (s @ cout["W"][o:o + d])
                else:
                    B[:, j] = G[j]
            else:
                row = self.ck.offsets[r.index] + r.k
                G[j] = cout["W"][row]
                gamma[j] = cout["gamma_U"][row]
                B[:, j] = G[j]
        normal_of = self.system(mode).normal_of
        for c in self.ck.torques:  # a sliding friction torque acts through its contact's N
            cs = mode.contacts[c][1]
            if cs.state in (SLIDE, SMOOTH):
                o, d = self.ck.offsets[c], self.ck.dims[c]
                s = self.friction_shape(c, cs, cout["U"][o:o + d])
                B[:, normal_of[c]] -= cs.sigma * cout["mu"][c] * (s @ cout["W"][o:o + d])
        return G, gamma, B

    # ------------------------------------------------------------------ reduced forms
    def _symbolic_rows(self, mode: Mode):
        """The symbolic rows of *mode* (in layout order, without the ideal rows that repeat the
        others: :attr:`ModeSystem.dropped <nonideal.modes.system.ModeSystem.dropped>`) and the
        names of the sliding directions' inputs."""
        dyn = dynamics_of(self.model)
        rows = [self.kernel.rows[i] for i in self.rows(mode)]
        extra = []
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state == SEPARATED:
                continue
            state = "stick" if cs.state == STICK else "slide"
            new = dyn.contact_rows(c, state, cs.sigma)
            rows += new
            if state == "slide":
                extra += [f"s[{name},{k + 1}]" for k in range(self.ck.dims[c])]
        dropped = self.system(mode).dropped
        return [r for j, r in enumerate(rows) if j not in dropped], extra

    def form_system(self, mode: Mode, independent=None) -> FormSystem:
        """The compiled form for the structure of *mode* (and a choice of independent
        coordinates), derived once."""
        independent = independent if independent is not None else self.independent
        key = (mode.structure, independent)
        fs = self._forms.get(key)
        if fs is None:
            fs = self.derive_form(mode, independent)
            self._forms[key] = fs
            if independent is None:
                self._forms[(mode.structure, fs.eom.independent)] = fs
        return fs

    def derive_form(self, mode: Mode, independent=None, branch=None) -> FormSystem:
        """Derive and compile the form for the structure of *mode* (not cached; *branch*:
        Lagrange II's chart through these coordinates, see :func:`~nonideal.equations.formalisms.derive`)."""
        rows, extra = self._symbolic_rows(mode)
        if branch is None and self.route.charts:
            branch = initial_branch(self.model)
        eom = derive(self.model, self.form, rows=rows, independent=independent, branch=branch)
        if self.charts is not None and "chart" in eom.extras_:
            from .charts import chart_outputs

            return FormSystem(eom, extra=extra, extra_outputs=chart_outputs(eom))
        return FormSystem(eom, extra=extra)

    def _current_form(self, mode: Mode, Gm: np.ndarray, layout: list[RowSpec]) -> FormSystem:
        """The form for *mode*; when the user did not fix the independent coordinates and the
        current choice is far from the best-conditioned one at this state, re-partition
        (:func:`better_partition`) -- coordinate partitioning, as in multibody codes.
        Lagrange II changes charts after the evaluation (:meth:`_solve_on_chart`)."""
        key = mode.structure
        fs = self._active.get(key) or self.form_system(mode)
        if self.independent is not None or not fs.eom.eliminated or not self.route.repartition or fs.eom.speeds:
            self._active[key] = fs
            return fs
        ideal = self._eliminated_rows(mode, fs, layout)
        if not ideal:
            return fs
        coords = list(self.model.coordinates)
        Gi = Gm[ideal]
        dep = [coords.index(c) for c in coords if c not in fs.eom.independent]
        new_dep = better_partition(Gi, dep)
        if new_dep is not None:
            ind = tuple(c for j, c in enumerate(coords) if j not in new_dep)
            if (key, ind) not in self._refused:
                try:
                    fs = self.form_system(mode, ind)
                except FormNotApplicable:
                    # e.g. Shulgin when the explicit coefficients would be too large: keep the
                    # current partition, and do not try this one again
                    self._refused.add((key, ind))
        self._active[key] = fs
        return fs

    def _eliminated_rows(self, mode: Mode, fs: FormSystem, layout: list[RowSpec]) -> list[int]:
        """Positions in *layout* of the ideal rows that the form *fs* eliminates."""
        key = (mode.structure, id(fs))
        ideal = self._elim_rows.get(key)
        if ideal is None:
            ideal = [j for j, r in enumerate(layout) if self._ideal(mode, r) and r.name in fs.eom.eliminated]
            self._elim_rows[key] = ideal
        return ideal

    def _ideal(self, mode: Mode, r: RowSpec) -> bool:
        if r.kind == "constraint":
            return self.kernel.rows[r.index].reaction_kind == "ideal"
        if r.kind == "tangent":
            return True
        return mode.contacts[r.index][1].state == STICK

    # ------------------------------------------------------------------ evaluation
    def accelerations(self, t: float, q: np.ndarray, qd: np.ndarray, mode: Mode):
        """Fast path for the right-hand side: ``(qdd, values, layout, out, cout)``.

        ``values`` are the multipliers of the mode's rows (``None`` for a reduced form, which
        eliminates the ideal ones; :meth:`solve` recovers them).  ``out``/``cout`` are views
        into reused buffers, valid until the next call.
        """
        layout = self.layout(mode)
        if self.route.gauss:
            from .gauss import gauss_accelerations

            qdd = gauss_accelerations(self, t, q, qd, mode).qdd
            x = self.input(t, q, qd)
            self._last_direct = {}
            return qdd, None, layout, self.kernel.dynamics(x), (self.ck(x) if self.ck else None)
        if self.kernel.compact and self.route.saddle_point:
            return self._compact_accelerations(t, q, qd, mode, layout)
        x = self.input(t, q, qd)
        out = self.kernel.dynamics(x)
        cout = self.ck(x) if self.ck else None
        M, F = (self.kernel.dense(out, "M") if self.kernel.compact else out["M"]), out["F"]
        try:
            if not layout:
                if self.route.saddle_point:
                    qdd, mu = solve_saddle(M, F)
                    return qdd, mu, layout, out, cout
                Gm = np.zeros((0, self.n))
            else:
                Gm, gm, Bm = self.assemble(mode, layout, out, cout)
                dependent = self.system(mode).dependent(Gm)
                if self.route.saddle_point:
                    if dependent:
                        raise SingularMatrix("dependent rows")
                    qdd, mu = solve_saddle(M, F, Bm, Gm, gm)
                    return qdd, mu, layout, out, cout
            fs = self._current_form(mode, Gm, layout)
            extra = self._extra_values(mode, cout)
            xb = np.concatenate((x, extra)) if extra.size else x
            if fs.extra_outputs:
                fs, (_, mu_form, qdd) = self._solve_on_chart(mode, fs, Gm, layout, t, q, xb)
            else:
                _, mu_form, qdd = fs.solve(xb)
            self._last_direct = dict(zip(fs.eom.constraint_names, map(float, mu_form)))
            return qdd, None, layout, out, cout
        except SingularMatrix:
            Gm, gm, Bm = self.assemble(mode, layout, out, cout) if layout else (
                np.zeros((0, self.n)), np.zeros(0), np.zeros((self.n, 0)))
            if self.route.saddle_point and any(r.kind != "constraint" for r in layout):
                sol = minimum_norm(M, F, Bm, Gm, gm)
                if sol is not None:
                    return sol[0], sol[1], layout, out, cout
            raise diagnose_singular(self, M, Gm, Bm, layout, t, q, qd) from None

    def _compact_accelerations(self, t, q, qd, mode: Mode, layout):
        """:meth:`accelerations` of a compact kernel (many coordinates): the mode's sparse
        system (:class:`~nonideal.modes.system.ModeSystem`); a singular one is diagnosed on
        dense matrices up to :data:`DENSE_DIAGNOSIS_MAX` coordinates, else refused."""
        n = self.n
        system = self.system(mode)
        try:
            sol = system.solve(self, t, np.concatenate((q, qd)), mode)
        except SingularMatrix:
            x = self.input(t, q, qd)
            out = self.kernel.dynamics(x)
            cout = self.ck(x) if self.ck else None
            if n > DENSE_DIAGNOSIS_MAX:
                from ..errors import MechanicsError
                raise MechanicsError(
                    f"the saddle-point system of mode {mode.label()} is singular at t = {t:.6g} (a mass "
                    "matrix that is not positive definite on the allowed velocities, or dependent "
                    f"constraints); with {n} coordinates it is not diagnosed further (that needs "
                    "dense n x n matrices): run `nonideal check` on the model, or a smaller one") from None
            M, F = self.kernel.dense(out, "M"), out["F"]
            Gm, gm, Bm = self.assemble(mode, layout, out, cout) if layout else (
                np.zeros((0, n)), np.zeros(0), np.zeros((n, 0)))
            if any(r.kind != "constraint" for r in layout):
                found = minimum_norm(M, F, Bm, Gm, gm)
                if found is not None:
                    return found[0], found[1], layout, out, cout
            raise diagnose_singular(self, M, Gm, Bm, layout, t, q, qd) from None
        out = self.kernel.dynamics.views(self.kz)
        cout = self.ck.fn.views(self.ck.fn.raw(self.x, self.cz)) if self.ck else None
        return sol[:n], -sol[n:], layout, out, cout

    def _solve_on_chart(self, mode: Mode, fs: FormSystem, Gm, layout, t, q, xb):
        """Lagrange II: ``(fs, fs.solve(xb))`` on the chart *fs*, or on the chart that
        :meth:`Charts.check <nonideal.modes.charts.Charts.check>` puts in its place (then the active
        one of the structure)."""
        try:
            result = fs.solve(xb)
        except SingularMatrix:
            result = None
        else:
            if fs.last["chart"][0] <= 0.0:  # on the chart, and far from its singularity
                return fs, result
        new = self.charts.check(mode, fs, Gm, layout, t, q, xb)
        if new is None:
            if result is None:
                raise SingularMatrix("Lagrange II on its chart")
            return fs, result
        self._active[mode.structure] = new
        return new, new.solve(xb)

    def _extra_values(self, mode: Mode, cout) -> np.ndarray:
        vals = []
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state in (SLIDE, SMOOTH):
                o, d = self.ck.offsets[c], self.ck.dims[c]
                vals.extend(self.friction_shape(c, cs, cout["U"][o:o + d]))
        return np.array(vals, dtype=float)

    def solve(self, t: float, q: np.ndarray, qd: np.ndarray, mode: Mode, distribute: bool = True) -> Solution:
        """Accelerations, multipliers, contact forces at a state.

        The multipliers of a mode with dependent rows (statically indeterminate) are the
        admissible distribution with the widest margins
        (:func:`~nonideal.modes.indeterminate.best_distribution`); with ``distribute=False`` the
        minimum-norm one, which is cheaper (``Solution.particular``: for the accelerations).

        Raises
        ------
        SingularSystem
            Singular mass matrix or dependent constraints (named).
        """
        n = self.n
        if self.route.saddle_point:
            system = self.system(mode)
            y = np.concatenate((q, qd))
            K, r, _ = system.assemble(self, t, y, mode)
            if K.ndim == 1:   # a compact kernel without rows: K holds M's entries
                Gm, gm, Bm = np.zeros((0, n)), np.zeros(0), np.zeros((n, 0))
            else:
                Gm, gm, Bm = K[n:, :n].copy(), -r[n:], K[:n, n:].copy()  # before the factorization
            try:
                sol, _, _ = system.factor(K, r)
            except SingularMatrix:
                pass  # the general path: minimum-norm contact forces, or a named error
            else:
                cout = None
                if self.ck:
                    cout = self.ck.fn.views(self.ck.fn.raw(self.x, self.cz))  # also without contact rows
                out = self.kernel.dynamics.views(self.kz)
                return self._solution(mode, system.layout, sol[:n].copy(), -sol[n:], out, cout, Gm, gm, Bm)
        qdd, values, layout, out, cout = self.accelerations(t, q, qd, mode)
        if layout:
            Gm, gm, Bm = self.assemble(mode, layout, out, cout)
        else:
            Gm, gm, Bm = np.zeros((0, n)), np.zeros(0), np.zeros((n, 0))
        return self._solution(mode, layout, qdd, values, out, cout, Gm, gm, Bm, distribute)

    def _solution(self, mode, layout, qdd, values, out, cout, Gm, gm, Bm, distribute=True) -> Solution:
        """Package an evaluation (buffers copied) as a :class:`Solution`; *distribute*: see
        :meth:`solve`."""
        n, m_all = self.n, self.kernel.m
        qdd = np.array(qdd, dtype=float)
        kernel = self.kernel   # M, G, B sparse for a compact kernel (many coordinates)
        M, F = kernel.mass(out).copy(), out["F"].copy()
        G = kernel.gradients(out).copy()
        gamma = out["gamma"].copy() if m_all else np.zeros(0)
        B = kernel.reactions(out).copy()
        cout = {k: (np.array(v) if isinstance(v, np.ndarray) else v) for k, v in cout.items()} if cout else None
        direct = {}
        if values is None:
            values = recover_multipliers(M, F, Bm, qdd) if layout else np.zeros(0)
            direct = dict(getattr(self, "_last_direct", {}))
            for j, r in enumerate(layout):
                if r.name in direct:
                    values[j] = direct[r.name]
        else:
            values = np.array(values, dtype=float)
            direct = {r.name: float(v) for r, v in zip(layout, values)}
        particular = bool(layout) and self.system(mode).dependent(Gm)
        arrays = (M, F, G, gamma, B, Gm, gm, Bm)
        if particular and distribute:
            # statically indeterminate: the admissible distribution with the widest margins; a
            # form's own multipliers are kept for the rows they determine
            from .indeterminate import best_distribution, least_norm_distribution, row_weights

            R = M @ qdd - F
            best = best_distribution(self, mode, layout, Bm, R, cout)
            values, particular = best.values, False
            direct = {k: v for k, v in direct.items() if k in best.determinate}
            if self.split[0] == "least-norm":
                shown = least_norm_distribution(self, mode, layout, Bm, R, cout,
                                                row_weights(self, layout, self.split[1]))
                if shown is not None:   # None: no admissible split (a switching instant)
                    return replace(self._packed(mode, layout, qdd, values, cout, arrays, direct, particular),
                                   shown=self._packed(mode, layout, qdd, shown, cout, arrays, direct, particular))
        return self._packed(mode, layout, qdd, values, cout, arrays, direct, particular)

    def _packed(self, mode, layout, qdd, values, cout, arrays, direct, particular) -> Solution:
        rows = [r.index for r in layout if r.kind == "constraint"]
        mults = np.array([v for r, v in zip(layout, values) if r.kind == "constraint"])
        contacts, friction = self._contact_forces(mode, layout, values, cout, qdd)
        return Solution(qdd, rows, mults, layout, values, *arrays, contacts, friction, direct, particular)

    def friction_power(self, mode: Mode, layout: list[RowSpec], values: np.ndarray, cout) -> float:
        """The power of the friction forces on their slips, ``sum_c F_c . U_c``: the rate of
        dissipation, never positive.  (``Q_f . q'`` differs from it by what a moving support
        puts in through friction, ``-F . U_0`` with ``U = W q' + U_0``: a belt, a turntable.)"""
        P = 0.0
        for j, r in enumerate(layout):
            if r.kind == "tangent":
                P += values[j] * cout["U"][self.ck.offsets[r.index] + r.k]
        normal_of = self.system(mode).normal_of
        for c, (_, cs) in enumerate(mode.contacts):   # sliding contacts and friction torques
            if cs.state in (SLIDE, SMOOTH):
                o, d = self.ck.offsets[c], self.ck.dims[c]
                U = cout["U"][o:o + d]
                P -= cs.sigma * cout["mu"][c] * values[normal_of[c]] * float(self.friction_shape(c, cs, U) @ U)
        return float(P)

    def _contact_forces(self, mode, layout, values, cout, qdd):
        friction = np.zeros(self.n)
        contacts = {}
        if not self.ck:
            return contacts, friction
        normal = {c: values[j] for c, j in self.system(mode).normal_of.items()}
        tang = {(r.index, r.k): values[j] for j, r in enumerate(layout) if r.kind == "tangent"}
        for c, (name, cs) in enumerate(mode.contacts):
            o, d = self.ck.offsets[c], self.ck.dims[c]
            U = cout["U"][o:o + d].copy()
            W = cout["W"][o:o + d]
            Udot = W @ qdd + cout["gamma_U"][o:o + d]
            gacc = float(cout["Gn"][c] @ qdd + cout["gamma_n"][c])
            N = float(normal.get(c, 0.0))
            if cs.state == STICK:
                Fv = np.array([tang[(c, k)] for k in range(d)])
            elif cs.state in (SLIDE, SMOOTH):
                Fv = -cs.sigma * cout["mu"][c] * N * self.friction_shape(c, cs, U)
            else:
                Fv = np.zeros(d)
            friction += Fv @ W
            contacts[name] = ContactForce(cs.label(), N, Fv, U, Udot, float(cout["gap"][c]),
                                          float(cout["gap_rate"][c]), gacc, float(cout["mu"][c]),
                                          float(cout["mu_s"][c]))
        return contacts, friction


def recover_multipliers(M: np.ndarray, F: np.ndarray, B: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Multipliers from ``B mu = M q'' - F`` (exact for a consistent motion; least squares)."""
    mu, *_ = np.linalg.lstsq(B, M @ qdd - F, rcond=None)
    return mu
