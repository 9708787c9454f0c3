"""Results of a simulation: :class:`Trajectory` (immutable arrays) and its outputs.

Besides ``t, q, q'`` it holds, at every sample, the accelerations, the multiplier of every
constraint (zero while a unilateral constraint is released), the mode, the energy terms and
the events.  Energy: with ``T = T2 + T1 + T0`` the balance checked is

    d/dt (T2 - T0 + V) = Q_nc . q' + R . q' + dV/dt - dT/dt

(Jacobi's integral generalized; for scleronomic systems it is ``d(T + V)/dt`` = power of the
non-potential forces and reactions).  ``balance`` is the residual of its integral, which
should be at the integrator's tolerance.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import cumulative_simpson

from .budget import Block, Sample

__all__ = ["Sample", "Trajectory", "Columns"]


class Columns(np.ndarray):
    """An array of shape ``(N, n)`` whose columns are also read by name: ``traj.q["x"]`` is
    ``traj.q[:, k]`` with ``k`` the index of ``x``.  Every other index is NumPy's.

    Examples
    --------
    >>> c = Columns.named(np.array([[1.0, 2.0], [3.0, 4.0]]), ("x", "phi"))
    >>> c["phi"]
    array([2., 4.])
    >>> float(c[1, 0])
    3.0
    """

    names: tuple[str, ...] = ()

    @classmethod
    def named(cls, array: np.ndarray, names) -> "Columns":
        out = np.asarray(array).view(cls)
        out.names = tuple(names)
        return out

    def __array_finalize__(self, obj) -> None:
        self.names = getattr(obj, "names", ())

    def __getitem__(self, key):
        if isinstance(key, str):
            try:
                k = self.names.index(key)
            except ValueError:
                from ..errors import did_you_mean

                raise KeyError(f"no column {key!r}{did_you_mean(key, self.names)}; the columns are "
                               f"{', '.join(self.names)}") from None
            return np.asarray(self)[:, k]
        out = super().__getitem__(key)
        # a single number stays a number; a slice that drops the columns' axis is a plain array
        if isinstance(out, Columns) and (out.ndim != 2 or out.shape[1] != len(self.names)):
            return np.asarray(out)
        return out

    def __reduce__(self):  # pickled as a plain array with its names
        return (Columns.named, (np.asarray(self), self.names))


@dataclass(frozen=True, eq=False)
class Trajectory:
    """An immutable simulation result.

    Attributes
    ----------
    model : str
    coordinates : tuple of str
    t : ndarray, shape (N,)
    q, qd, qdd : ndarray, shape (N, n_q)
    modes : list of str
    multipliers : dict name -> ndarray (N,)
    energy : dict name -> ndarray (N,) -- ``kinetic``, ``potential``, ``energy`` (T2 - T0 + V),
        ``active_work``, ``reaction_work``, ``friction_work``, ``explicit_time_work``,
        ``impact_work`` (energy change at impacts), ``balance``.  ``friction_work`` is the
        work of the friction forces on the slips, ``int sum_c F_c . U_c dt``: the heat, never
        positive.  On a moving support (a belt, a turntable: ``U = W q' + U_0``) friction also
        transmits the support's work ``-int F . U_0 dt``; it is counted in ``reaction_work``
        with the work of the other reactions, so that the balance holds either way.
    events : list of dict
    diagnostics : dict
    contacts : dict name -> dict of arrays (``normal``, ``friction``, ``slip``, ``mode``)
    controls : dict name -> dict, one per servo-constraint (Béghin 1922): ``force`` (N,) the
        control u (the multiplier of the program: the generalized control force is ``D u``),
        ``power`` (N,) ``u D . q'``, ``work`` (N,) its integral, integrated with the motion
        (the work of controls shared by several programs, ``[[controls]]``, by Simpson's rule
        over the samples: pass a fine ``times`` grid for it), ``order`` the order of the
        time derivative of the coordinates in which the control appears (2 ordinarily, more
        when it acts through the dynamics); for a program with several control directions
        (Béghin's r < j) also ``u_1 .. u_j``, the least-cost controls, and ``force`` is then the
        program's multiplier (the generalized control force is ``sum_k d_k u_k``).  With
        controls shared by several programs (``[[controls]]``) each control has its own entry
        (``force`` u_k, ``power``, ``work``, ``programs``) and each program an entry with its
        ``multiplier`` (not a force), ``power``, ``work`` and ``controls``.
    speeds : dict name -> ndarray (N,)
        The model's generalized speeds (``[speeds]``) at the samples.
    outputs : dict name -> ndarray (N,)
        The model's ``[outputs]`` at the samples.

    Notes
    -----
    Where the reactions are statically indeterminate (the rows of the mode are dependent: a
    ladder sticking at a rough wall and floor, a table's legs sticking), the multipliers and
    contact forces are the admissible distribution chosen by ``[simulation] split``: by
    default the one with the widest margins -- the one that maximizes the smallest of ``N``,
    ``mu_s N - |F|`` and the held multipliers among the contacts whose reactions are
    indeterminate, and among several such the one of least norm; with ``"least-norm"`` the one
    of least compliance-weighted norm (:mod:`nonideal.modes.indeterminate`).  The slip and
    lift-off events fire when no admissible distribution is left, whatever the rule;
    ``diagnostics["indeterminate"]`` gives the rule and the admissible ranges per phase.
    """

    model: str
    coordinates: tuple[str, ...]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    modes: list[str]
    multipliers: dict[str, np.ndarray]
    energy: dict[str, np.ndarray]
    events: list[dict]
    diagnostics: dict[str, Any]
    contacts: dict[str, dict[str, Any]] = field(default_factory=dict)
    controls: dict[str, dict[str, Any]] = field(default_factory=dict)
    speeds: dict[str, np.ndarray] = field(default_factory=dict)
    outputs: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for key in ("q", "qd", "qdd"):
            object.__setattr__(self, key, Columns.named(getattr(self, key), self.coordinates))

    # ---------------------------------------------------------------- construction
    @classmethod
    def from_samples(cls, sim, samples, events, diagnostics, residual_max) -> "Trajectory":
        """Assemble the result: the motion of each sample (the simulation's own at the step
        ends, else evaluated), energies and constraint residuals in one batch evaluation of the
        compiled observables over all samples."""
        kernel, solver = sim.kernel, sim.solver
        n = kernel.n
        t, Y, qdd, labels, motions, batched = _columns_of(samples, solver, n, sim.fast_contacts.sample_motions
                                                          if sim.contacts else None)
        N = len(t)
        q, qd = Y[:, :n], Y[:, n:2 * n]
        rows = kernel.rows
        mult = {r.name: np.zeros(N) for r in rows}
        names = solver.ck.names if solver.ck else []
        dims = solver.ck.dims if names else []
        # per contact: mode label, N, F, U, gap, mu_s at every sample
        records = [([""] * N, np.zeros(N), np.zeros((N, d)), np.zeros((N, d)), np.zeros(N), np.zeros(N))
                   for d in dims]
        assert not names or len(motions) + sum(len(k) for k, _, _ in batched) == N, \
            "blocks of samples are for models without contacts"
        res_p = res_v = 0.0
        X = np.empty((N, len(solver.x)))
        X[:] = solver.x
        X[:, 0] = t
        X[:, 1:1 + 2 * n] = Y[:, :2 * n]
        obs = kernel.observables.views(kernel.observables.batch(X))
        for k, m in motions:  # (the rows of a block have no rows and no contacts)
            if m.system.row_col:
                values = m.reported
                for i, j in m.system.row_col.items():
                    mult[rows[i].name][k] = values[j]
                pos, vel = m.system.drift_rows
                if pos:
                    res_p = max(res_p, float(np.abs(obs["pos"][k, pos]).max()))
                if vel:
                    res_v = max(res_v, float(np.abs(obs["vel"][k, vel]).max()))
            for c, rec in enumerate(records):
                for column, value in zip(rec, m.contact_record(c)):
                    column[k] = value
        for ks, batch, rs in batched:  # the samples solved natively, mode by mode, as arrays
            system = batch.system
            if system.row_col:
                values = batch.values(rs)
                for i, j in system.row_col.items():
                    mult[rows[i].name][ks] = values[:, j]
                pos, vel = system.drift_rows
                if pos:
                    res_p = max(res_p, float(np.abs(obs["pos"][np.ix_(ks, pos)]).max()))
                if vel:
                    res_v = max(res_v, float(np.abs(obs["vel"][np.ix_(ks, vel)]).max()))
            for c, rec in enumerate(records):
                label = batch.mode.contacts[c][1].label()
                for k in ks.tolist():
                    rec[0][k] = label
                for column, value in zip(rec[1:], batch.contact_columns(c, rs)):
                    column[ks] = value
        T, V = obs["T"], obs["V"]
        E = obs["T2"] - obs["T0"] + V
        works = Y[:, 2 * n:2 * n + 5] if Y.shape[1] > 2 * n else np.zeros((N, 5))
        W_nc, W_R, W_t, W_f, W_i = (works[:, k] for k in range(5))
        balance = (E - E[0]) - (W_nc + W_R + W_t + W_f + W_i) if N else np.zeros(0)
        scale = max(1e-300, float(np.max(np.abs(np.concatenate((E, T, V, W_nc, W_R, W_t, W_f, W_i)))))) if N else 1.0
        energy = {
            "kinetic": T, "potential": V, "energy": E, "active_work": W_nc,
            "reaction_work": W_R, "friction_work": W_f, "explicit_time_work": W_t,
            "impact_work": W_i,
            "balance": balance,
        }
        diag = dict(diagnostics)
        diag.update(
            constraint_residual_max=max(res_p, res_v, residual_max["position"], residual_max["velocity"]),
            position_residual_max=max(res_p, residual_max["position"]),
            velocity_residual_max=max(res_v, residual_max["velocity"]),
            energy_balance_max=float(np.max(np.abs(balance))) if N else 0.0,
            energy_balance_relative=float(np.max(np.abs(balance)) / scale) if N else 0.0,
            samples=N,
        )
        from ..modes.indeterminate import split_phases

        gapped, previous = [], -1  # (one None where a block of a native phase lies between two motions)
        for k, m in motions:
            gapped += [None, m] if gapped and k != previous + 1 else [m]
            previous = k
        split = split_phases(solver, gapped)
        if split:   # where the reactions are statically indeterminate: the rule, the ranges
            diag["indeterminate"] = split
        contacts = {}
        for name, rec in zip(names, records):
            label, normal, friction, slip, gap, mu_s = rec
            contacts[name] = {"normal": normal, "friction": friction.tolist(), "slip": slip.tolist(),
                              "gap": gap, "mu_static": mu_s, "mode": label}
        # the controls' works integrated with the motion (the states after the five works)
        integrated = {kernel.rows[i].name: Y[:, 2 * n + 5 + k]
                      for k, i in enumerate(getattr(sim, "control_rows", ()))
                      if Y.shape[1] > 2 * n + 5 + k}
        controls = _controls(kernel, mult, qd, kernel.dynamics.views(kernel.dynamics.batch(X)), t, X,
                             integrated) \
            if any(r.reaction_kind == "servo" for r in kernel.rows) else {}  # (no n x n M per sample)
        speeds, outputs = _speeds_and_outputs(kernel.model, solver.params, t, q, qd, mult)
        return cls(kernel.model.name, tuple(kernel.model.coordinates), t, q, qd, qdd,
                   labels, mult, energy, list(events), diag, contacts,
                   controls, speeds, outputs)

    # ---------------------------------------------------------------- access
    def __len__(self) -> int:
        return len(self.t)

    def coordinate(self, name: str) -> np.ndarray:
        """The coordinate *name* over the samples, shape (N,); the same as ``traj.q[name]``."""
        return self.q[name]

    def velocity(self, name: str) -> np.ndarray:
        """The velocity of coordinate *name* over the samples, shape (N,); ``traj.qd[name]``."""
        return self.qd[name]

    def __getitem__(self, name: str) -> np.ndarray:
        """A named series over the samples, shape (N,): ``traj["t"]``, a coordinate
        ``traj["x"]``, its velocity ``traj["x'"]`` and acceleration ``traj["x''"]``, a
        multiplier ``traj["lambda_c"]``, an energy term (``traj["kinetic"]``, ``"balance"``...)
        or any column of :meth:`to_csv` (a contact's ``N_c``, ``gap_c``...).

        Examples
        --------
        >>> import nonideal
        >>> traj = nonideal.simulate(nonideal.Model("fall", ["x"], parameters={"g": 9.81},
        ...     kinetic="x'**2/2", potential="g*x", initial={"x": 0, "x'": 0}), t_end=1.0)
        >>> round(float(traj["x"][-1]), 6), round(float(traj["x'"][-1]), 6)
        (-4.905, -9.81)
        """
        if not isinstance(name, str):
            raise TypeError(f"a trajectory is indexed by a name such as {self.coordinates[0]!r} "
                            f"or \"{self.coordinates[0]}'\" (got {name!r}); use traj.q[k] for "
                            "a sample")
        stripped = name.rstrip("'")
        order = len(name) - len(stripped)
        if stripped in self.coordinates and order <= 2:
            return (self.q, self.qd, self.qdd)[order][stripped]
        if name.startswith("lambda_") and name[7:] in self.multipliers:
            return self.multipliers[name[7:]]
        if name in self.energy:
            return self.energy[name]
        columns = dict(self._columns())
        if name in columns:
            return columns[name]
        from ..errors import did_you_mean

        raise KeyError(f"{self.model}: no series {name!r}{did_you_mean(name, list(columns))}; "
                       f"the names are {', '.join(columns)}")

    def at(self, name: str, k: int = -1) -> float:
        """Value of a coordinate (``"x"``) or velocity (``"x'"``) at sample *k*."""
        if name.endswith("'"):
            return float(self.velocity(name[:-1])[k])
        return float(self.coordinate(name)[k])

    # ---------------------------------------------------------------- outputs
    # ---------------------------------------------------------------- Jupyter
    def _final_rows(self) -> list[tuple[str, float, float]]:
        """(coordinate, value, velocity) at the end; rounding noise against the coordinate's
        range as 0."""
        from ..numeric.display import clean

        return [(c, clean(self.q[-1, k], float(abs(self.q[:, k]).max())),
                 clean(self.qd[-1, k], float(abs(self.qd[:, k]).max())))
                for k, c in enumerate(self.coordinates)]

    def _repr_latex_(self) -> str:
        """Jupyter: the state at the end of the run."""
        from ..modeling.symbols import latex_names
        import sympy as sp

        names = latex_names([sp.Symbol(c) for c in self.coordinates]
                            + [sp.Symbol(c + "'") for c in self.coordinates])
        rows = [f"{names[sp.Symbol(c)]}(t_1) &= {_tex_number(q)}, & {names[sp.Symbol(c + chr(39))]}(t_1) &= "
                f"{_tex_number(v)}" for c, q, v in self._final_rows()]
        head = rf"t_1 = {_tex_number(float(self.t[-1]))}" if len(self.t) else ""
        return "$$\\begin{aligned}\n" + " \\\\\n".join(rows) + "\n\\end{aligned}\\quad " + head + "$$"

    def _repr_html_(self) -> str:
        """Jupyter: the run (times, samples), its events and the final state."""
        from html import escape

        if not len(self.t):
            return f"<div><b>{escape(self.model)}</b>: no samples</div>"
        events = "".join(
            f"<tr><td>{e['t']:.10g}</td><td>{escape(str(e.get('type', '')))}</td>"
            f"<td>{escape(str(e.get('contact', e.get('constraint', ''))))}</td></tr>"
            for e in self.events[:20])
        more = f"<br>... {len(self.events) - 20} more events" if len(self.events) > 20 else ""
        final = "".join(f"<tr><td>{escape(c)}</td><td>{q:.10g}</td><td>{v:.10g}</td></tr>"
                        for c, q, v in self._final_rows())
        return (f"<div><b>{escape(self.model)}</b>: t = {self.t[0]:g} .. {self.t[-1]:g}, "
                f"{len(self.t)} samples, {len(self.events)} events"
                + (f"<table><tr><th>t</th><th>event</th><th>of</th></tr>{events}</table>{more}"
                   if events else "")
                + f"<table><tr><th>coordinate</th><th>value at the end</th><th>velocity</th></tr>"
                  f"{final}</table></div>")

    def to_dict(self) -> dict[str, Any]:
        """The JSON structure of ``simulate --json`` (non-finite numbers become ``null``)."""
        def arr(a):
            return [float(x) if np.isfinite(x) else None for x in a]
        return {
            "model": self.model,
            "t": arr(self.t),
            "q": {c: arr(self.q[:, i]) for i, c in enumerate(self.coordinates)},
            "qdot": {c: arr(self.qd[:, i]) for i, c in enumerate(self.coordinates)},
            "qddot": {c: arr(self.qdd[:, i]) for i, c in enumerate(self.coordinates)},
            "multipliers": {k: arr(v) for k, v in self.multipliers.items()},
            "contacts": {name: {key: (_jsonable(val) if isinstance(val, list) else arr(val))
                                for key, val in c.items()} for name, c in self.contacts.items()},
            "modes": list(self.modes),
            "events": [_jsonable(e) for e in self.events],
            "energy": {k: arr(v) for k, v in self.energy.items()},
            "controls": {name: {k: (arr(v) if isinstance(v, np.ndarray) else v) for k, v in c.items()}
                         for name, c in self.controls.items()},
            "diagnostics": _jsonable(self.diagnostics),
            **({"speeds": {k: arr(v) for k, v in self.speeds.items()}} if self.speeds else {}),
            **({"outputs": {k: arr(v) for k, v in self.outputs.items()}} if self.outputs else {}),
        }

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1)

    def _columns(self) -> list[tuple[str, Any]]:
        """The columns of :meth:`to_csv` and :meth:`to_pandas`, in order: (name, values)."""
        cols: list[tuple[str, Any]] = [("t", np.asarray(self.t))]
        for arr, suffix in ((self.q, ""), (self.qd, "'"), (self.qdd, "''")):
            cols += [(c + suffix, np.asarray(arr)[:, k]) for k, c in enumerate(self.coordinates)]
        cols += [(k, np.asarray(v, dtype=float)) for k, v in self.speeds.items()]
        cols += [(k, np.asarray(v, dtype=float)) for k, v in self.outputs.items()]
        cols += [(f"lambda_{k}", v) for k, v in self.multipliers.items()]
        for name, c in self.contacts.items():
            cols.append(("N_" + name, np.asarray(c["normal"], dtype=float)))
            for key, label in (("friction", "F_"), ("slip", "U_")):
                values = np.asarray(c[key], dtype=float).reshape(len(self.t), -1)
                d = values.shape[1]
                cols += [(label + name + (f"_{j + 1}" if d > 1 else ""), values[:, j]) for j in range(d)]
            if "gap" in c:
                cols.append(("gap_" + name, np.asarray(c["gap"], dtype=float)))
            cols.append(("mode_" + name, list(c["mode"])))
        cols += list(self.energy.items())
        for name, c in self.controls.items():
            cols += [(f"{label}_{name}", np.asarray(c[key], dtype=float))
                     for label, key in zip(_control_columns(c, labels=True), _control_columns(c))]
        cols.append(("mode", list(self.modes)))
        return cols

    def to_csv(self, path) -> None:
        """One row per sample: t, q, q', q'', multipliers, per contact its normal force
        ``N_<name>``, friction and slip components (``F_<name>``, ``U_<name>``; suffixed
        ``_1, _2`` for two components), gap and mode, then the energy terms and the mode of
        the whole system."""
        cols = self._columns()
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow([name for name, _ in cols])
            for k in range(len(self.t)):
                w.writerow([v[k] if isinstance(v, list) else f"{v[k]:.17g}" for _, v in cols])

    def to_pandas(self):
        """The columns of :meth:`to_csv` as a ``pandas.DataFrame`` indexed by ``t`` (the modes
        as strings, everything else float).  Needs pandas (``pip install pandas``); it is not
        a dependency of nonideal."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Trajectory.to_pandas needs pandas, which nonideal does not require: "
                              "pip install pandas (or use traj.to_csv / traj.to_dict)") from None
        cols = self._columns()
        return pd.DataFrame({name: v for name, v in cols[1:]},
                            index=pd.Index(np.asarray(self.t), name="t"))


def _columns_of(samples, solver, n: int, native=None):
    """``(t, Y, qdd, labels, motions, batched)`` of the samples in order: *motions* the pairs
    (row, motion) of the samples with a motion (the simulation's own, else evaluated one by
    one); the samples without one that *native* ``(mode, T, Y) -> SampleBatch or None`` solves,
    all those of a mode at once, in *batched* ``(rows, batch, rows in the batch)``; the blocks
    of a native phase in a mode without rows or contacts as they are (their accelerations)."""
    sizes = [len(s) if isinstance(s, Block) else 1 for s in samples]
    N = sum(sizes)
    if not N:
        return np.zeros(0), np.zeros((0, 2 * n)), np.zeros((0, n)), [], [], []
    first = samples[0]
    t, qdd = np.empty(N), np.empty((N, n))
    Y = np.empty((N, (first.y.shape[1] if isinstance(first, Block) else len(first.y))))
    labels: list[str] = []
    motions, unsolved = [], {}  # mode -> rows without a motion
    k = 0
    for s, size in zip(samples, sizes):
        if isinstance(s, Block):
            t[k:k + size], Y[k:k + size] = s.t, s.y
            if s.qdd is not None:
                qdd[k:k + size] = s.qdd
            else:
                unsolved.setdefault(s.mode, []).extend(range(k, k + size))
            labels += [s.mode.label()] * size
        else:
            t[k], Y[k] = s.t, s.y
            if s.motion is not None:
                motions.append((k, s.motion))
            else:
                unsolved.setdefault(s.mode, []).append(k)
            labels.append(s.mode.label())
        k += size
    batched = []
    for mode, rows in unsolved.items():
        ks = np.array(rows, dtype=np.intp)
        batch = native(mode, t[ks], Y[ks]) if native is not None else None
        ok = batch.ok if batch is not None else np.zeros(len(ks), dtype=bool)
        if ok.any():
            rs = np.flatnonzero(ok)
            batched.append((ks[rs], batch, rs))
        for k in ks[~ok].tolist():
            motions.append((k, solver.motion(float(t[k]), Y[k], mode)))
    motions.sort(key=lambda pair: pair[0])
    for k, m in motions:
        qdd[k] = m.qdd
    for ks, batch, rs in batched:
        qdd[ks] = batch.qdd(rs)
    return t, Y, qdd, labels, motions, batched


def _speeds_and_outputs(model, params, t, q, qd, mult):
    """The model's speeds and outputs at the samples (empty dicts when it declares none)."""
    speeds: dict[str, np.ndarray] = {}
    outputs: dict[str, np.ndarray] = {}
    if not (model.speeds or model.outputs):
        return speeds, outputs
    from ..numeric.speeds import output_kernel_of, speed_kernel_of

    N = len(t)
    if model.speeds:
        sk = speed_kernel_of(model)
        values = np.array([sk.values(t[k], q[k], qd[k], params) for k in range(N)]).reshape(N, len(sk.names))
        speeds = {name: values[:, j].copy() for j, name in enumerate(sk.names)}
    if model.outputs:
        ok = output_kernel_of(model)
        values = np.array([ok(t[k], q[k], qd[k], params, {n: v[k] for n, v in mult.items()})
                           for k in range(N)]).reshape(N, len(ok.names))
        outputs = {name: values[:, j].copy() for j, name in enumerate(ok.names)}
    return speeds, outputs


def _control_columns(c: dict, labels: bool = False) -> list[str]:
    """The CSV columns of one entry of ``controls``: its force ``u`` (a program realized by
    shared controls has none: its multiplier is ``lambda_<name>``), power ``P``, work ``W`` and
    the several controls ``u_<k>`` of one program."""
    keys = [k for k in ("force", "power", "work") if k in c] + sorted(x for x in c if x.startswith("u_"))
    if not labels:
        return keys
    return [{"force": "u", "power": "P", "work": "W"}.get(k, k) for k in keys]


def _controls(kernel, mult, qd, dynamics, t, X, integrated=None) -> dict[str, dict[str, Any]]:
    """Control force, power and work of every servo-constraint over the samples (and, for a
    program with several control directions, each control ``u_<k>``).  The work is the one
    integrated with the motion where the simulation carried it (*integrated*: name -> work
    at the samples), else the quadrature of the power over the samples."""
    integrated = integrated or {}
    from ..numeric.kernel import Compiled
    out = {}
    reach = kernel.dyn.servo_reach
    several = kernel.dyn.control_rows
    names, _, C = kernel.dyn.shared_rows
    shared = [ctl.name for ctl in kernel.model.controls] if names else []
    for i, r in enumerate(kernel.rows):
        if r.reaction_kind != "servo":
            continue
        u = mult[r.name]
        B = kernel.dense(dynamics, "B").reshape(len(t), kernel.n, -1)[:, :, i]
        power = u * np.einsum("ki,ki->k", B, qd)
        work = integrated[r.name].copy() if r.name in integrated else _work(power, t)
        if r.name in names:
            # a program realized by the shared controls: its multiplier is no force (the
            # controls' forces are u = C mu, reported under the controls' own names)
            out[r.name] = {"multiplier": u, "power": power, "work": work, "order": 2,
                           "controls": shared}
            continue
        out[r.name] = {"force": u, "power": power, "work": work,
                       "order": reach[r.name].order if r.name in reach else 2}
        if r.name in several:
            coef = Compiled(kernel.symbols, {"c": list(several[r.name][1])})
            C = np.asarray(coef.batch(X), dtype=float).reshape(len(t), -1)
            for k in range(C.shape[1]):
                out[r.name][f"u_{k + 1}"] = C[:, k] * u
    if names:   # the shared controls (Beghin: r programs, j controls): u = C mu, one entry each
        N, controls = len(t), kernel.model.controls
        coef = Compiled(kernel.symbols, {"c": [x for row in C for x in row],
                                         "d": [x for u in controls for x in u.direction]})
        vals = coef.views(coef.batch(X))
        Cn = np.asarray(vals["c"], dtype=float).reshape(N, len(controls), len(names))
        Dn = np.asarray(vals["d"], dtype=float).reshape(N, len(controls), kernel.n)
        mu = np.column_stack([mult[x] for x in names])
        for a, ctl in enumerate(controls):
            u = np.einsum("ki,ki->k", Cn[:, a, :], mu)
            power = u * np.einsum("ki,ki->k", Dn[:, a, :], qd)
            out[ctl.name] = {"force": u, "power": power, "work": _work(power, t), "order": 2,
                             "programs": list(names)}
    return out


def _work(power: np.ndarray, t: np.ndarray) -> np.ndarray:
    if len(t) >= 3 and np.all(np.diff(t) > 0):
        return cumulative_simpson(power, x=t, initial=0.0)
    return np.concatenate(([0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))) \
        if len(t) else np.zeros(0)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    return obj


def _tex_number(x: float, scale: float | None = None) -> str:
    from ..numeric.display import number

    text = number(x, scale)
    if "e" in text:
        mant, exp = text.split("e")
        return rf"{mant} \cdot 10^{{{int(exp)}}}"
    return text
