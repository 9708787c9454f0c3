"""Modes of a hybrid mechanical system and the motion in a mode.

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
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .contact_kernel import contact_kernel_of
from .contacts import Coulomb, LinearizedCoulomb, RegularizedCoulomb
from .dynamics import dynamics_of
from .errors import FormNotApplicable, MechanicsError, SingularSystem
from .formalisms import derive
from .numeric import FormSystem, Kernel, SingularMatrix, max_abs, solve_saddle

__all__ = ["Mode", "ContactState", "RowSpec", "Solution", "ContactForce", "ModeSolver",
           "SEPARATED", "STICK", "SLIDE", "SMOOTH"]

SEPARATED, STICK, SLIDE, SMOOTH = "separated", "stick", "slide", "smooth"


# compiled reduced forms, per model and form: {(id(model), form): ({key: FormSystem},
# {(structure, kept): [FormSystem]} (the charts of Lagrange II), model)}
_FORM_CACHE: dict[tuple, tuple[dict, dict, object]] = {}


@dataclass(frozen=True)
class ContactState:
    """State of one contact.

    Attributes
    ----------
    state : {"separated", "stick", "slide", "smooth"}
        "smooth": touching, for a regularized law or a frictionless contact (no direction).
    direction : tuple of float
        Sliding: ``(+1,)`` or ``(-1,)`` for one slip component (the sign of ``U``); for two
        components the unit direction used only while ``|U| ~ 0`` at the onset of sliding
        (afterwards ``s = U/|U|``).
    sigma : int
        Sign of the normal force (bilateral contacts; +1 for unilateral ones).
    """

    state: str = SEPARATED
    direction: tuple[float, ...] = ()
    sigma: int = 1

    def label(self) -> str:
        return self._label

    @cached_property
    def _label(self) -> str:
        if self.state == SLIDE and len(self.direction) == 1:
            out = "slide+" if self.direction[0] > 0 else "slide-"
        else:
            out = self.state
        return out + ("(N<0)" if self.sigma < 0 else "")

    @property
    def structure(self) -> tuple:
        """What the symbolic equations depend on (directions enter as numbers)."""
        return (self.state, self.sigma)


@dataclass(frozen=True)
class Mode:
    """Held unilateral constraints and the state of every contact (model order)."""

    held: frozenset[str] = frozenset()
    contacts: tuple[tuple[str, ContactState], ...] = ()

    def contact(self, name: str) -> ContactState:
        for n, cs in self.contacts:
            if n == name:
                return cs
        return ContactState()

    def label(self) -> str:
        return self._label

    @cached_property
    def _label(self) -> str:
        parts = sorted(self.held)
        parts += [f"{n}:{cs.label()}" for n, cs in self.contacts]
        return ", ".join(parts) if parts else "free"

    @cached_property
    def structure(self) -> tuple:
        """What the equations depend on (directions enter as numbers)."""
        return (self.held, tuple((n, cs.structure) for n, cs in self.contacts))

    def with_contact(self, name: str, cs: ContactState) -> "Mode":
        return Mode(self.held, tuple((n, cs if n == name else c) for n, c in self.contacts))


@dataclass(frozen=True)
class RowSpec:
    """One row of a mode: ``kind`` is "constraint" (kernel row ``index``), "normal" (contact
    ``index``) or "tangent" (component ``k`` of contact ``index``)."""

    kind: str
    index: int
    k: int = 0
    name: str = ""


@dataclass
class ContactForce:
    """Contact quantities at a state: normal force, friction force, slip, gap."""

    state: str
    N: float = 0.0
    F: np.ndarray = field(default_factory=lambda: np.zeros(0))
    U: np.ndarray = field(default_factory=lambda: np.zeros(0))
    Udot: np.ndarray = field(default_factory=lambda: np.zeros(0))
    gap: float = 0.0
    gap_rate: float = 0.0
    gap_acc: float = 0.0
    mu: float = 0.0
    mu_s: float = 0.0

    def to_dict(self) -> dict:
        return {"mode": self.state, "normal": float(self.N), "friction": [float(v) for v in self.F],
                "slip": [float(v) for v in self.U], "gap": float(self.gap)}


@dataclass
class Solution:
    """The motion at one state in one mode.

    Attributes
    ----------
    qdd : ndarray, shape (n_q,)
    rows : list of int -- active kernel constraint rows
    multipliers : ndarray -- multipliers of ``rows`` (same order)
    layout : list of RowSpec -- every row of the mode; ``values`` their multipliers
    M, F : ndarray -- mass matrix and forcing
    G, gamma, B : ndarray -- every constraint row of the kernel (active or not)
    Gm, gammam, Bm : ndarray -- the assembled rows of the mode
    contacts : dict name -> ContactForce
    friction : ndarray, shape (n_q,) -- generalized friction force ``sum_k W_k^T F_k``
    direct : dict name -> float -- the multipliers the form computes itself
    particular : bool -- the rows are dependent and ``values`` is the minimum-norm solution
        (``ModeSolver.solve(..., distribute=False)``), not the reported distribution

    For a mode with dependent rows (statically indeterminate reactions) ``values`` is the
    admissible distribution with the widest margins (:mod:`nonideal.indeterminate`).
    """

    qdd: np.ndarray
    rows: list[int]
    multipliers: np.ndarray
    layout: list[RowSpec]
    values: np.ndarray
    M: np.ndarray
    F: np.ndarray
    G: np.ndarray
    gamma: np.ndarray
    B: np.ndarray
    Gm: np.ndarray
    gammam: np.ndarray
    Bm: np.ndarray
    contacts: dict[str, ContactForce] = field(default_factory=dict)
    friction: np.ndarray | None = None
    direct: dict[str, float] = field(default_factory=dict)
    particular: bool = False

    def multiplier(self, row: int) -> float:
        return float(self.multipliers[self.rows.index(row)]) if row in self.rows else 0.0


#: re-partition when exchanging one dependent for one independent coordinate would multiply
#: |det G_D| by more than this (the partition is then far from the best one at this state)
REPARTITION_GAIN = 4.0


def _better_partition(Gi: np.ndarray, dep: list[int], gain: float = REPARTITION_GAIN) -> list[int] | None:
    """A better-conditioned choice of dependent coordinates for the rows ``Gi`` (m, n), or
    ``None`` when the current choice *dep* is good enough (every ``|X_ij| <= gain``).

    With ``X = G_D^-1 G_I`` the entry ``|X_ij|`` is the factor by which ``|det G_D|`` changes
    when dependent coordinate i and independent coordinate j are exchanged (Cramer's rule), and
    ``q'_D = -X q'_I`` on the constraint manifold: a large entry means the dependent velocities
    are large multiples of the independent ones and the reduced form loses digits to
    cancellation (the choice becomes singular where the motion has no component along an
    independent coordinate).  The current choice is kept while every ``|X_ij| <= gain``;
    otherwise exchanges of the largest entry are made until all are <= 1.05 (a locally
    maximal-volume choice, as in "maxvol" coordinate partitioning), so switching back needs
    the entries to grow again by ~``gain`` (hysteresis).
    """
    m, n = Gi.shape
    if m == 0:
        return None
    dep = list(dep)
    X = _exchange_factors(Gi, dep)
    if X is not None and (X.size == 0 or float(np.max(np.abs(X))) <= gain):
        return None
    if X is None:
        from scipy.linalg import qr

        _, _, piv = qr(Gi, pivoting=True)
        dep = sorted(int(j) for j in piv[:m])
        X = _exchange_factors(Gi, dep)
        if X is None:
            return dep
    for _ in range(4 * n):
        if X.size == 0:
            break
        i, j = np.unravel_index(int(np.argmax(np.abs(X))), X.shape)
        if abs(X[i, j]) <= 1.05:
            break
        ind = [c for c in range(n) if c not in dep]
        dep[i] = ind[j]
        dep.sort()
        X = _exchange_factors(Gi, dep)
        if X is None:
            break
    return dep


def _exchange_factors(Gi: np.ndarray, dep: list[int]) -> np.ndarray | None:
    """``G_D^-1 G_I`` (rows: dependent coordinates in the order of *dep*), ``None`` when
    ``G_D`` is singular or not square."""
    m, n = Gi.shape
    if len(dep) != m:
        return None
    ind = [c for c in range(n) if c not in dep]
    try:
        X = np.linalg.solve(Gi[:, dep], Gi[:, ind])
    except np.linalg.LinAlgError:
        return None
    return X if np.all(np.isfinite(X)) else None



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
        singular: :attr:`charts`, :mod:`nonideal.charts`).
    specialize : bool
        Lagrange I: use the compiled system of a mode once its structure is hot
        (:class:`~nonideal.mode_system.ModeFunction`); ``False``: always the index path.

    Attributes
    ----------
    frictionless : frozenset of int
        The contacts with Coulomb's law whose ``mu`` and ``mu_static`` are zero at *params*:
        they touch in the single state "smooth" (no sticking, no slip events).
    """

    def __init__(self, kernel: Kernel, params: np.ndarray, form: str = "lagrange1",
                 independent=None, specialize: bool = True):
        self.kernel = kernel
        self.specialize = specialize
        self.params = params
        self.form = form
        self.independent = independent
        self.model = kernel.model
        self.ck = contact_kernel_of(kernel.model)
        self.bilateral = [i for i, r in enumerate(kernel.rows) if not r.unilateral]
        self.unilateral = [i for i, r in enumerate(kernel.rows) if r.unilateral]
        entry = _FORM_CACHE.get((id(self.model), form))
        if entry is None or entry[2] is not self.model:
            if len(_FORM_CACHE) > 64:
                _FORM_CACHE.clear()
            entry = _FORM_CACHE[(id(self.model), form)] = ({}, {}, self.model)
        self._forms: dict[tuple, FormSystem] = entry[0]
        #: Lagrange II: the charts the motion moves through (:class:`~nonideal.charts.Charts`)
        self.charts = None
        if form == "lagrange2":
            from .charts import Charts

            self.charts = Charts(self, entry[1])
        self._active: dict[tuple, FormSystem] = {}
        self._elim_rows: dict[tuple, list[int]] = {}
        self._refused: set[tuple] = set()
        self.x = kernel.layout.make(params)
        self.n = kernel.n
        self.laws = [c.law for c in self.ck.data]
        self.frictionless = self.ck.frictionless(params) if self.ck else frozenset()
        self.reference: dict[int, np.ndarray] = {}
        # one output buffer for both kernels: the Lagrange I fast path gathers from it
        self.z = np.zeros(kernel.dynamics.size + self.ck.size)
        self.kz, self.cz = self.z[:kernel.dynamics.size], self.z[kernel.dynamics.size:]
        #: the last Lagrange I solve: (t, y, mode, [q''; -lambda], LU, pivots)
        self.last = None

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
        """The :class:`~nonideal.mode_system.ModeSystem` of the structure of *mode* (cached per
        model)."""
        from .mode_system import system_of

        return system_of(self.kernel, mode)

    def motion(self, t: float, y: np.ndarray, mode: Mode, kin: np.ndarray | None = None):
        """The :class:`~nonideal.mode_system.Motion` at the state ``y = [q, q', ...]`` (lazy:
        evaluated on first use; reuses :attr:`last` when it was solved at that state, and
        *kin*, the contact kernel's flat outputs at the state, when given)."""
        from .mode_system import Motion

        return Motion(self, mode, t, y, kin)

    # ------------------------------------------------------------------ friction shapes
    def friction_shape(self, c: int, cs: ContactState, U: np.ndarray,
                       qd: np.ndarray | None = None) -> np.ndarray:
        """The vector ``s`` with friction ``F = -sigma mu N s`` (unit slip direction for
        Coulomb sliding; the regularized shape for the smooth laws, zero for a frictionless
        contact).  *qd*: the velocities of the state (default: those of the last
        :meth:`input`), which scale the test ``|U| ~ 0``."""
        law = self.laws[c]
        if cs.state == SMOOTH:
            nrm = float(np.sqrt(U @ U))
            if isinstance(law, RegularizedCoulomb):
                return U / np.sqrt(nrm * nrm + law.eps * law.eps)
            if isinstance(law, LinearizedCoulomb):
                return U / law.eps if nrm <= law.eps else U / nrm
            return np.zeros(len(U))  # Coulomb's law: a frictionless contact
        if len(U) == 1:
            return np.array(cs.direction, dtype=float)
        nrm = math.sqrt(U @ U)
        if qd is None:
            qd = self.x[1 + self.n:1 + 2 * self.n]
        ref = self.reference.get(c)
        # |U| > 1e-12 (1 + max |q'|); the cheap bound 2e-12 (1 + |q'|) decides all but tiny slips
        if nrm > 2e-12 * (1.0 + math.sqrt(qd @ qd)) or nrm > 1e-12 * (1.0 + max_abs(qd)):
            s = U / nrm
            # analytic continuation through U = 0 within a step: keep the orientation of the
            # slip at the start of the step, so that the right-hand side stays smooth up to
            # (and a little past) the stop, where the SlipStop event places the switch
            if ref is not None and s @ ref < 0:
                s = -s
            return s
        if ref is not None:
            return ref
        return np.array(cs.direction, dtype=float) if cs.direction else np.zeros_like(U)

    def set_references(self, mode: "Mode", motion) -> None:
        """Record the slip direction of every two-component sliding contact at the state of
        *motion* (a :class:`~nonideal.mode_system.Motion`; the simulation calls this at the
        start of each step)."""
        self.reference = {}
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state == SLIDE and self.ck.dims[c] > 1:
                U = motion.slip(c)
                nrm = math.sqrt(U @ U)
                scale = 1e-12 * (1.0 + max_abs(motion.qd))
                if nrm > scale:
                    self.reference[c] = U / nrm
                elif cs.direction:
                    self.reference[c] = np.array(cs.direction, dtype=float)

    # ------------------------------------------------------------------ assembly
    def assemble(self, mode: Mode, layout: list[RowSpec], out: dict, cout: dict | None):
        """Numeric ``G (m, n)``, ``gamma (m,)``, ``B (n, m)`` of the mode's rows."""
        n, m = self.n, len(layout)
        G = np.empty((m, n))
        gamma = np.empty(m)
        B = np.empty((n, m))
        for j, r in enumerate(layout):
            if r.kind == "constraint":
                G[j] = out["G"][r.index]
                gamma[j] = out["gamma"][r.index]
                B[:, j] = out["B"][:, r.index]
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
        return G, gamma, B

    # ------------------------------------------------------------------ reduced forms
    def _symbolic_rows(self, mode: Mode):
        """The symbolic rows of *mode* (in layout order, without the ideal rows that repeat the
        others: :attr:`ModeSystem.dropped <nonideal.mode_system.ModeSystem.dropped>`) and the
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
        Lagrange II's chart through these coordinates, see :func:`~nonideal.formalisms.derive`)."""
        rows, extra = self._symbolic_rows(mode)
        eom = derive(self.model, self.form, rows=rows, independent=independent, branch=branch)
        if self.charts is not None and "chart" in eom.extras_:
            from .charts import chart_outputs

            return FormSystem(eom, extra=extra, extra_outputs=chart_outputs(eom))
        return FormSystem(eom, extra=extra)

    def _current_form(self, mode: Mode, Gm: np.ndarray, layout: list[RowSpec]) -> FormSystem:
        """The form for *mode*; when the user did not fix the independent coordinates and the
        current choice is far from the best-conditioned one at this state, re-partition
        (:func:`_better_partition`) -- coordinate partitioning, as in multibody codes.
        Lagrange II changes charts after the evaluation (:meth:`_solve_on_chart`)."""
        key = mode.structure
        fs = self._active.get(key) or self.form_system(mode)
        if self.independent is not None or not fs.eom.eliminated or self.form == "lagrange2":
            self._active[key] = fs
            return fs
        ideal = self._eliminated_rows(mode, fs, layout)
        if not ideal:
            return fs
        coords = list(self.model.coordinates)
        Gi = Gm[ideal]
        dep = [coords.index(c) for c in coords if c not in fs.eom.independent]
        new_dep = _better_partition(Gi, dep)
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
        if self.form == "gauss":
            from .gauss import gauss_accelerations

            qdd = gauss_accelerations(self, t, q, qd, mode).qdd
            x = self.input(t, q, qd)
            self._last_direct = {}
            return qdd, None, layout, self.kernel.dynamics(x), (self.ck(x) if self.ck else None)
        x = self.input(t, q, qd)
        out = self.kernel.dynamics(x)
        cout = self.ck(x) if self.ck else None
        M, F = out["M"], out["F"]
        try:
            if not layout:
                if self.form == "lagrange1":
                    qdd, mu = solve_saddle(M, F)
                    return qdd, mu, layout, out, cout
                Gm = np.zeros((0, self.n))
            else:
                Gm, gm, Bm = self.assemble(mode, layout, out, cout)
                dependent = self.system(mode).dependent(Gm)
                if self.form == "lagrange1":
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
            if self.form == "lagrange1" and any(r.kind != "constraint" for r in layout):
                sol = _minimum_norm(M, F, Bm, Gm, gm)
                if sol is not None:
                    return sol[0], sol[1], layout, out, cout
            raise diagnose_singular(self, M, Gm, Bm, layout, t, q, qd) from None

    def _solve_on_chart(self, mode: Mode, fs: FormSystem, Gm, layout, t, q, xb):
        """Lagrange II: ``(fs, fs.solve(xb))`` on the chart *fs*, or on the chart that
        :meth:`Charts.check <nonideal.charts.Charts.check>` puts in its place (then the active
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
        (:func:`~nonideal.indeterminate.best_distribution`); with ``distribute=False`` the
        minimum-norm one, which is cheaper (``Solution.particular``: for the accelerations).

        Raises
        ------
        SingularSystem
            Singular mass matrix or dependent constraints (named).
        """
        n = self.n
        if self.form == "lagrange1":
            system = self.system(mode)
            y = np.concatenate((q, qd))
            K, r, _ = system.assemble(self, t, y, mode)
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
        M, F = out["M"].copy(), out["F"].copy()
        G = out["G"].copy() if m_all else np.zeros((0, n))
        gamma = out["gamma"].copy() if m_all else np.zeros(0)
        B = out["B"].copy() if m_all else np.zeros((n, 0))
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
        if particular and distribute:
            # statically indeterminate: the admissible distribution with the widest margins; a
            # form's own multipliers are kept for the rows they determine
            from .indeterminate import best_distribution

            best = best_distribution(self, mode, layout, Bm, M @ qdd - F, cout)
            values, particular = best.values, False
            direct = {k: v for k, v in direct.items() if k in best.determinate}
        rows = [r.index for r in layout if r.kind == "constraint"]
        mults = np.array([v for r, v in zip(layout, values) if r.kind == "constraint"])
        contacts, friction = self._contact_forces(mode, layout, values, cout, qdd)
        return Solution(qdd, rows, mults, layout, values, M, F, G, gamma, B, Gm, gm, Bm,
                        contacts, friction, direct, particular)

    def friction_power(self, mode: Mode, layout: list[RowSpec], values: np.ndarray, cout) -> float:
        """The power of the friction forces on their slips, ``sum_c F_c . U_c``: the rate of
        dissipation, never positive.  (``Q_f . q'`` differs from it by what a moving support
        puts in through friction, ``-F . U_0`` with ``U = W q' + U_0``: a belt, a turntable.)"""
        P = 0.0
        for j, r in enumerate(layout):
            if r.kind == "tangent":
                P += values[j] * cout["U"][self.ck.offsets[r.index] + r.k]
            elif r.kind == "normal":
                c = r.index
                cs = mode.contacts[c][1]
                if cs.state in (SLIDE, SMOOTH):
                    o, d = self.ck.offsets[c], self.ck.dims[c]
                    U = cout["U"][o:o + d]
                    P -= cs.sigma * cout["mu"][c] * values[j] * float(self.friction_shape(c, cs, U) @ U)
        return float(P)

    def _contact_forces(self, mode, layout, values, cout, qdd):
        friction = np.zeros(self.n)
        contacts = {}
        if not self.ck:
            return contacts, friction
        normal = {r.index: values[j] for j, r in enumerate(layout) if r.kind == "normal"}
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


def _minimum_norm(M, F, B, G, gamma):
    """Redundant contacts (a body resting on more supports than it needs, both ends of a flat
    rod sticking): the accelerations are unique but the contact forces are statically
    indeterminate.  The accelerations and the minimum-norm forces, if the system is consistent
    (:func:`~nonideal.indeterminate.best_distribution` then finds the forces reported)."""
    n, m = M.shape[0], G.shape[0]
    K = np.zeros((n + m, n + m))
    K[:n, :n] = M
    K[:n, n:] = -B
    K[n:, :n] = G
    rhs = np.concatenate((F, -gamma))
    x, *_ = np.linalg.lstsq(K, rhs, rcond=1e-12)
    scale = 1.0 + float(np.max(np.abs(rhs)))
    if np.max(np.abs(K @ x - rhs)) > 1e-9 * scale:
        return None
    # the accelerations must be unique: M must be definite on the null space of G
    rank = np.linalg.matrix_rank(G)
    if rank < n:
        _, _, Vt = np.linalg.svd(G)
        null = Vt[rank:].T
        if np.linalg.matrix_rank(null.T @ M @ null) < null.shape[1]:
            return None
    return x[:n], x[n:]


def recover_multipliers(M: np.ndarray, F: np.ndarray, B: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """Multipliers from ``B mu = M q'' - F`` (exact for a consistent motion; least squares)."""
    mu, *_ = np.linalg.lstsq(B, M @ qdd - F, rcond=None)
    return mu


def diagnose_singular(solver: ModeSolver, M, G, B, layout, t, q, qd) -> Exception:
    """Turn a singular linear system into an actionable error naming what is singular."""
    kernel = solver.kernel
    if all(np.isfinite(G).ravel()) and np.all(np.isfinite(M)):
        # constraints and the mass matrix: the detailed diagnosis of nonideal.checks
        from .checks import diagnose_state

        closed = [r.index for r in layout if r.kind == "constraint" and kernel.rows[r.index].unilateral]
        found = diagnose_state(kernel.model, t, q, qd, closed, params=solver.params)
        if found is not None:
            from .checks import diagnose_initial_state
            from .errors import SingularSystem as _Singular

            if diagnose_initial_state(kernel.model) is None:
                return _Singular(
                    [p + "; the equations are regular at the initial state, so this is a singular "
                     "configuration of the coordinates or constraints (like r = 0 in polar "
                     "coordinates): choose another state or other coordinates" for p in found.problems],
                    found.source)
            return found
    names = list(kernel.model.coordinates)
    n = kernel.n
    src = None if kernel.model.source == "<api>" else kernel.model.source
    state = ", ".join(f"{c} = {v:.6g}" for c, v in zip(names, q))
    rates = ", ".join(f"{c}' = {v:.6g}" for c, v in zip(names, qd))
    where = f" at t = {t:.6g} ({state}; {rates})"
    m = len(layout)
    bad = [r.name for j, r in enumerate(layout) if not (np.all(np.isfinite(G[j])) and np.all(np.isfinite(B[:, j])))]
    if bad or not (np.all(np.isfinite(M))):
        what = (f"constraint(s) {', '.join(repr(b) for b in bad)} are not differentiable" if bad
                else "the mass matrix is not finite")
        return MechanicsError(
            f"{what}{where}: their gradient is NaN or infinite (e.g. sqrt or a norm of velocities "
            "at zero, a singular point of a nonlinear constraint); the motion cannot be continued "
            "through this state")
    if m:
        rank = np.linalg.matrix_rank(G)
        if rank < m:
            dep, keep = [], []
            for j, r in enumerate(layout):
                if np.linalg.matrix_rank(G[keep + [j]]) == len(keep) + 1:
                    keep.append(j)
                else:
                    dep.append(r.name)
            return SingularSystem(
                f"dependent (redundant) constraints: {', '.join(repr(d) for d in dep)} "
                f"repeat what the others impose{where}; remove them or make them independent", src)
        _, _, Vt = np.linalg.svd(G)
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
    servo = [j for j, r in enumerate(layout)
             if r.kind == "constraint" and kernel.rows[r.index].reaction_kind != "ideal"]
    if len(servo) > 1 and np.linalg.matrix_rank(B[:, servo]) < len(servo):
        j = int(np.linalg.matrix_rank(B[:, servo]))
        names_ = ", ".join(repr(layout[k].name) for k in servo)
        return MechanicsError(
            f"{len(servo)} servo/quasi-ideal constraints ({names_}) but their control directions "
            f"span only j = {j}: with r = {len(servo)} programs and j = {j} < r independent controls "
            "the problem is, in general, impossible (Beghin's count; seed 004); give each program "
            "its own control direction" + where)
    if m and not np.allclose(B, G.T):
        # the combination of reactions that moves nothing along the constraints names them
        _, w = weakest_reactions(M, G, B)
        parts = [(w[j], r.name) for j, r in enumerate(layout) if abs(w[j]) > 1e-6 * np.max(np.abs(w))]
        return MechanicsError(
            "the non-ideal reactions (servo / quasi-ideal / friction) cannot realize the "
            f"constraints: G M^-1 B is singular -- the reactions of {', '.join(repr(x) for _, x in parts)} "
            "in the combination " + ", ".join(f"{c:.4g}*{x}" for c, x in parts)
            + " accelerate the system only along motions the constraints allow, so they cannot "
            "enforce them (a servo-constraint whose control direction is orthogonal, in the "
            "metric of M, to the program's gradient; for a sliding contact the boundary of "
            "Painleve's paradox); choose another reaction direction" + where)
    return SingularSystem(f"the equations of motion are singular{where}", src)


def weakest_reactions(M: np.ndarray, G: np.ndarray, B: np.ndarray) -> tuple[float, np.ndarray]:
    """How nearly the reactions ``B`` fail to realize the constraints ``G``: the smallest
    singular value of ``G M^-1 B`` relative to ``|G| |M^-1 B|`` (what it would be with the
    reactions along the gradients), and its combination of the reactions (unit vector)."""
    Minv_B = np.linalg.solve(M, B)
    _, sv, Vt = np.linalg.svd(G @ Minv_B)
    scale = float(np.linalg.norm(G) * np.linalg.norm(Minv_B))
    return float(sv[-1]) / max(scale, 1e-300), Vt[-1]


def coulomb_exact(law) -> bool:
    return isinstance(law, Coulomb)


def select_mode(*args, **kwargs):
    """See :func:`nonideal.switching.select_mode` (re-exported here for convenience)."""
    from .switching import select_mode as _select

    return _select(*args, **kwargs)
