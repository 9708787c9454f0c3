"""Linearization of a constrained motion: equilibria, steady motions, programmed motions.

The motion in the library's frame is the saddle-point system (any constraint kind: holonomic,
nonholonomic linear or Chetaev, servo (Béghin 1922), quasi-ideal (Briskin et al. 2021))::

    E = M(q, t) q'' - F(q, q', t) - B(q, q', t) lambda = 0,     C = G q'' + gamma = 0.

About a state ``(q0, q0', t)`` with accelerations ``a0`` and multipliers ``lambda0`` the
first approximation is ``M da - B dlambda = -(E_q dq + E_v dq')``,
``G da = -(C_q dq + C_v dq')``.  The perturbations are kept on the constraint manifold: the
holonomic rows ``f(q, t) = 0`` give ``f_q dq = 0`` (dependent coordinates eliminated), the
velocity-level rows (``df/dt = 0`` and the nonholonomic ``phi(q, q', t) = 0``) give
``c_q dq + c_v dq' = 0`` (dependent velocities eliminated).  The state of the linear system is
therefore ``x = (dq_I, dp)``: the independent coordinates and the independent velocities
(``n - h`` and ``n - h - k`` of them), so no spurious zero eigenvalue comes from a constraint
and no constraint drift enters ``A``.  Coordinates on which nothing but their own
kinematics depends (cyclic, ignorable: their columns of ``A`` vanish outside the rows of
such coordinates) are dropped and named (``keep`` retains them); in a steady motion the held
velocities of cyclic coordinates whose row of ``A`` vanishes (a neighbouring steady motion of
the family: a zero eigenvalue, Routh) are dropped and named in ``family``, and a velocity
nothing depends on whose acceleration does not vanish (a programmed translation, e.g. a body
pushed along a guide) is dropped and named with the ignorable ones.

API (stable)::

    linearize(model, about="equilibrium" | "steady" | "program", at=None, symbolic=(),
              controls=(), keep=(), independent=None, exact=False, t=None)
        -> Linearization

``Linearization`` (frozen dataclass): ``variables`` (names of the perturbation variables,
``x`` and ``x'``), ``A`` and ``B`` (``numpy`` arrays at the numeric parameter values;
``A_symbolic``/``B_symbolic`` SymPy matrices in the ``symbolic`` parameters), ``state``,
``ignorable``, ``family``, ``eigenvalues``, ``characteristic_polynomial`` (SymPy, in ``s``),
``hurwitz`` (minors), ``verdict``, ``reason``, ``conditions``, ``controllability``,
``residual`` (of the guess), ``to_dict()`` (the JSON of ``nonideal stability``).

Example
-------
>>> from nonideal.modeling.model import Model
>>> m = Model("pendulum", ["th"], {"g": 9.81, "l": 1.0}, kinetic="l^2*th'^2/2",
...           potential="-g*l*cos(th)")
>>> lin = linearize(m, at={"th": 0.1})
>>> lin.variables, lin.verdict
(('th', "th'"), 'critical')
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
import sympy as sp

from ...errors import LinearizationUndefined, ModelError, NotAnEquilibrium, did_you_mean
from ...modeling.model import Model
from ...numeric.display import number
from .linear_system import (NEWTON_STEPS, Partition, Point, check_parameters, clean, ignorable_set,
                            kernel_of, natural_frequencies, parse_state, partition, state_matrices)
from .contacts import as_constraints, contact_modes, described, guess_state
from .routh import analyse, controllability, routh_reduction
from .symbolic import symbolic_matrices

__all__ = ["Linearization", "linearize", "ABOUT"]

ABOUT = ("equilibrium", "steady", "program")


@dataclass(frozen=True)
class Linearization:
    """The first approximation ``x' = A x + B u`` about a motion (see the module docstring).

    Attributes
    ----------
    model, about : str
    t : float
    q, qdot : dict name -> float
        The state linearized about (after Newton, when it was found from a guess).
    variables : tuple of str
        Names of the perturbation variables (independent coordinates, then independent
        velocities), the order of the rows of ``A``.
    A : ndarray, shape (n_x, n_x)
    B : ndarray, shape (n_x, n_u)
    controls : tuple of str
        Parameters taken as inputs (columns of ``B``).
    A_symbolic, B_symbolic : sympy.Matrix or None
        With ``symbolic`` parameters: the same matrices in those parameters.
    symbolic : tuple of str
    ignorable : tuple of str
        Coordinates dropped because nothing depends on them.
    family : tuple of str
        Held velocities dropped with their zero eigenvalue (a neighbouring steady motion of the
        family): decoupled ones as they are, coupled ones at their first integral
        (:func:`routh_reduction`).
    dependent : tuple of str
        Coordinates and velocities eliminated by the constraints.
    eigenvalues : ndarray of complex
    characteristic_polynomial : sympy.Expr (in ``s``)
    hurwitz : tuple
        Hurwitz minors Delta_1 .. Delta_n.
    verdict : str
        "asymptotically stable" | "unstable" | "critical".
    reason : str
    conditions : tuple of sympy relational
        With ``symbolic``: the Routh--Hurwitz (Liénard--Chipart) conditions.
    controllability : dict
        ``{"rank", "n"}`` (Kalman) when there are controls.
    residual : float
        Largest residual rate of the state given (before Newton).
    frequencies : tuple of float
        Natural frequencies of small oscillations (conservative systems), else ().
    """

    model: str
    about: str
    t: float
    q: dict
    qdot: dict
    variables: tuple
    A: np.ndarray
    B: np.ndarray
    controls: tuple = ()
    A_symbolic: Any = None
    B_symbolic: Any = None
    symbolic: tuple = ()
    ignorable: tuple = ()
    family: tuple = ()
    dependent: tuple = ()
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros(0))
    characteristic_polynomial: Any = None
    hurwitz: tuple = ()
    verdict: str = "critical"
    reason: str = ""
    conditions: tuple = ()
    controllability: dict = field(default_factory=dict)
    residual: float = 0.0
    frequencies: tuple = ()
    conditions_meaning: str = ""
    contacts: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The JSON of ``nonideal stability`` (keys of the command's contract)."""
        out = {
            "model": self.model,
            "about": self.about,
            "t": self.t,
            "state": {"q": dict(self.q), "qdot": dict(self.qdot)},
            "variables": list(self.variables),
            "A": _listed(self.A_symbolic if self.A_symbolic is not None else self.A),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in self.eigenvalues],
            "verdict": self.verdict,
            "reason": self.reason,
            "characteristic_polynomial": str(self.characteristic_polynomial),
            "hurwitz": [_scalar(h) for h in self.hurwitz],
            "conditions": [str(c) for c in self.conditions],
            "conditions_meaning": self.conditions_meaning,
            "controllability": dict(self.controllability),
            "ignorable": list(self.ignorable),
            "family": list(self.family),
            "dependent": list(self.dependent),
            "residual": self.residual,
        }
        if self.controls:
            out["controls"] = list(self.controls)
            out["B"] = _listed(self.B_symbolic if self.B_symbolic is not None else self.B)
        if self.frequencies:
            out["frequencies"] = list(self.frequencies)
        if self.contacts:
            out["contacts"] = {name: {"mode": label, "linearized_as": how}
                               for name, (label, how) in self.contacts.items()}
        return out


    def _repr_latex_(self) -> str:
        """Jupyter: the characteristic polynomial and the eigenvalues, typeset."""
        from .display import linearization_latex

        return linearization_latex(self)

    def _repr_html_(self) -> str:
        """Jupyter: the verdict and why, the state, ``A``, the characteristic polynomial and the
        eigenvalues."""
        from .display import linearization_html

        return linearization_html(self)

    def as_text(self) -> str:
        """Readable report: the state, the variables, A, the polynomial, the Hurwitz minors,
        the conditions, the verdict and why."""
        lines = [f"{self.model}: first approximation about the "
                 + ("steady motion" if self.about == "steady" else "equilibrium")]
        state = ", ".join(f"{k} = {number(v)}" for k, v in self.q.items())
        moving = ", ".join(f"{k}' = {number(v)}" for k, v in self.qdot.items() if number(v) != "0")
        lines.append(f"  state: {state}" + (f", {moving}" if moving else ""))
        if self.residual:
            lines.append(f"  (found by Newton from the guess; residual rate at the guess {self.residual:.3g})")
        for name, (label, how) in self.contacts.items():
            lines.append(f"  contact '{name}': {label} -- {how}")
        lines.append(f"  variables: {', '.join(self.variables)}")
        if self.dependent:
            lines.append(f"  eliminated by the constraints: {', '.join(self.dependent)}")
        if self.ignorable:
            lines.append(f"  ignorable (nothing depends on them): {', '.join(self.ignorable)}")
        if self.family:
            lines.append(f"  held (a family of steady motions, zero eigenvalue): {', '.join(self.family)}")
        A = self.A_symbolic if self.A_symbolic is not None else self.A
        lines.append("  A =")
        for row in _listed(A):
            lines.append("    [" + ", ".join(f"{x:.6g}" if isinstance(x, float) else str(x) for x in row) + "]")
        if self.controls:
            lines.append(f"  B (controls {', '.join(self.controls)}) =")
            for row in _listed(self.B_symbolic if self.B_symbolic is not None else self.B):
                lines.append("    [" + ", ".join(f"{x:.6g}" if isinstance(x, float) else str(x) for x in row) + "]")
            c = self.controllability
            lines.append(f"  controllability (Kalman): rank {c.get('rank')} of {c.get('n')}"
                         + (" -- controllable" if c.get("rank") == c.get("n") else " -- not controllable"))
        lines.append(f"  characteristic polynomial: {self.characteristic_polynomial}")
        if self.hurwitz:
            lines.append("  Hurwitz minors: " + ", ".join(f"D{i + 1} = {_short(h)}" for i, h in enumerate(self.hurwitz)))
        if self.conditions:
            lines.append(f"  {self.conditions_meaning} iff: " + "; ".join(str(c) for c in self.conditions))
        lines.append("  eigenvalues: " + ", ".join(_complex(z) for z in self.eigenvalues))
        if self.frequencies:
            lines.append("  natural frequencies (rad/s): " + ", ".join(f"{w:.10g}" for w in self.frequencies))
        lines.append(f"  verdict: {self.verdict} -- {self.reason}")
        return "\n".join(lines)


def _short(x) -> str:
    try:
        return f"{float(x):.6g}"
    except (TypeError, ValueError):
        return str(x)


def _complex(z: complex) -> str:
    if abs(z.imag) <= 1e-12 * max(1.0, abs(z)):
        return f"{z.real:.8g}"
    return f"{z.real:.8g} {'+' if z.imag > 0 else '-'} {abs(z.imag):.8g}i"


def _scalar(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return str(x)


def _listed(m) -> list:
    if isinstance(m, sp.MatrixBase):
        return [[_scalar(m[i, j]) for j in range(m.cols)] for i in range(m.rows)]
    return np.asarray(m, float).tolist()


def _zero(vec, scale) -> bool:
    return float(np.max(np.abs(vec), initial=0.0)) <= 1e-9 * scale


def _rates(pt: Point, q, v, kept_coords, rated):
    """Rates that vanish at an equilibrium / steady motion: the kept coordinates' velocities and
    the accelerations of the independent velocities something depends on (*rated*)."""
    a, lam, b = pt.motion(q, v)
    return np.concatenate([v[kept_coords], a[rated]]), a, lam, b


def linearize(model: Model, about: str = "equilibrium", at: Any = None, symbolic: Sequence[str] = (),
              controls: Sequence[str] = (), keep: Sequence[str] = (), independent: Sequence[str] | None = None,
              exact: bool = False, t: float | None = None) -> Linearization:
    """Linearize the motion of *model* about an equilibrium or a steady motion.

    Parameters
    ----------
    model : Model
    about : {"equilibrium", "steady"}
        ``"equilibrium"``: at rest (every acceleration vanishes), found by Newton from the
        guess *at*; ``"steady"``: a steady motion (cyclic coordinates' velocities held, the
        other coordinates at rest, the accelerations of the velocities something depends on
        zero), found by Newton from *at* (the cyclic velocities given in *at* are held when
        that is possible, else adjusted too).
        Programmed motions: :func:`nonideal.analysis.stability.program.linearize_program`.
    at : mapping or str, optional
        The state (guess): ``{"theta": 0.1, "psi'": 20}`` or ``"theta=0.1, psi'=20"``; values
        may be expressions in the parameters (kept symbolic with *symbolic*).  Missing values
        come from the model's initial state (velocities: 0 at an equilibrium).
    symbolic : sequence of str
        Parameters kept as symbols: ``A`` and the stability conditions in them.
    controls : sequence of str
        Parameters taken as inputs ``u`` (they enter the forces); ``B = dx'/du``.
    keep : sequence of str
        Coordinates kept in the state even when ignorable (a cart's position for a regulator).
    independent : sequence of str, optional
        Coordinates to keep independent (default: the model's ``independent``, else pivoting).
    exact : bool
        The state is given exactly: no Newton; an error when it is not an equilibrium.
    t : float, optional
        Time (default: the model's t0).

    Returns
    -------
    Linearization

    Raises
    ------
    NotAnEquilibrium
        (exit code 2) No equilibrium / steady motion near the guess; the message gives the
        residual accelerations.
    LinearizationUndefined
        (exit code 3) Singular constraint rows or an undetermined motion at the state.
    """
    if about not in ("equilibrium", "steady"):
        if about == "program":
            raise ModelError("linearize: about='program' is computed by "
                             "nonideal.analysis.stability.program.linearize_program (A(t), B(t) along the motion)")
        raise ModelError(f"--about: '{about}' is not one of {', '.join(ABOUT)}{did_you_mean(about, ABOUT)}",
                         _src(model))
    symbolic, controls, keep = tuple(symbolic), tuple(controls), tuple(keep)
    check_parameters(model, symbolic, "--symbolic")
    check_parameters(model, controls, "--controls")
    bad = [k for k in keep if k not in model.coordinates]
    if bad:
        raise ModelError([f"--keep: '{k}' is not a coordinate{did_you_mean(k, model.coordinates)}" for k in bad],
                         _src(model))
    t0 = float(model.t0 if t is None else t)
    if model.contacts:   # each touching contact as the constraint it is in its mode at the state
        return _with_contacts(model, about, at, dict(symbolic=symbolic, controls=controls, keep=keep,
                                                     independent=independent, exact=exact, t=t0))
    values = model.parameter_values
    params = np.array([float(values[n]) for n in model.parameters])
    k = kernel_of(model, controls)
    n = k.n
    given = parse_state(model, at, symbolic)
    subs = {sp.Symbol(name): val for name, val in values.items()}
    num_given = {key: float(expr.xreplace(subs)) for key, expr in given.items()}
    try:
        init = model.numeric_initial()
    except Exception:  # noqa: BLE001 -- an initial state is only a default guess
        init = {}
    names_q = list(model.coordinates)
    names_v = [c + "'" for c in names_q]
    if about == "equilibrium":
        moving = [key for key in names_v if abs(num_given.get(key, 0.0)) > 0]
        if moving:
            raise ModelError(f"--at: an equilibrium is at rest, but {', '.join(moving)} is not 0; "
                             "drop the velocities from --at, or use --about steady for a steady "
                             "motion with cyclic velocities", _src(model))
    q = np.array([num_given.get(c, init.get(c, 0.0)) for c in names_q], float)
    if about == "equilibrium":
        v = np.zeros(n)
    else:
        v = np.array([num_given.get(c, init.get(c, 0.0)) for c in names_v], float)
    pt = Point(k, params, t0)
    indep = [names_q.index(c) for c in (independent or model.independent or ()) if c in names_q]
    part = partition(pt.blocks(q, v), n, indep, model)
    q, v = pt.complete(q, v, part)
    _given_dependent_velocities(model, num_given, v, part, names_v)
    guess_q, guess_v = q.copy(), v.copy()
    cyclic, free_velocities = _ignorable(pt, q, v, part, names_q)
    kept = [j for j in part.coords_I if j not in cyclic]          # at rest in a steady motion
    free_velocities = [j for j in free_velocities if names_q[j] not in keep]
    ignorable = [j for j in cyclic if names_q[j] not in keep]
    if about == "equilibrium":
        free_velocities = []            # at rest: every acceleration must vanish
    rated = [j for j in part.vel_I if j not in free_velocities]
    if about == "steady":
        for j in kept:
            if j in part.vel_I:
                v[j] = 0.0
        q, v = pt.complete(q, v, part)
    residual0, a, lam, b = _rates(pt, q, v, kept, rated)
    scale = _scale(pt, q, v, part)
    res_guess = float(np.max(np.abs(residual0), initial=0.0))
    if not _zero(residual0, scale):
        if exact:
            raise _not_steady(model, about, names_q, names_v, q, v, residual0, kept, rated, None)
        q, v, ok, best = _newton(pt, q, v, part, kept, rated, given, about, names_v, scale)
        runaway = _runaway(guess_q, guess_v, q, v, names_q, names_v) if ok else None
        if runaway:     # the rates vanish only in a limit (a mass growing without bound)
            ok, best = False, (best[0], q, v, runaway)
        if not ok:
            raise _not_steady(model, about, names_q, names_v, guess_q, guess_v, residual0, kept, rated, best)
    a, lam, b = pt.motion(q, v)
    A, Bm = state_matrices(b, part, n, True, model)
    variables = [names_q[j] for j in part.coords_I] + [names_v[j] for j in part.vel_I]
    nI = len(part.coords_I)
    # dropped: the ignorable coordinates and the velocities nothing depends on that drift
    # (a programmed translation: their acceleration does not vanish and enters nothing)
    drifting = [nI + part.vel_I.index(j) for j in free_velocities if not _zero(a[[j]], scale)]
    drop = ignorable_set(A, [part.coords_I.index(j) for j in ignorable] + drifting)
    ignorable = [j for j in ignorable if part.coords_I.index(j) in drop]
    family = []
    if about == "steady":
        sc = max(1.0, float(np.abs(A).max(initial=0.0)))
        for idx, j in enumerate(part.vel_I):
            if (j in ignorable and abs(v[j]) > 0 and _zero(A[nI + idx], sc) and nI + idx not in drop
                    and part.coords_I.index(j) in drop):
                # a velocity held in a family of steady motions: dropped, its zero eigenvalue named
                family.append(nI + idx)
    remove = sorted(set(drop) | set(family))
    stay = [i for i in range(A.shape[0]) if i not in remove]
    A_r, B_r = clean(A[np.ix_(stay, stay)]), clean(Bm[stay])
    A_sym = B_sym = None
    if symbolic:
        A_sym, B_sym = symbolic_matrices(k, model, t0, q, v, given, part, symbolic, values, kept, rated)
        A_sym = A_sym.extract(stay, stay)
        B_sym = B_sym.extract(stay, list(range(B_sym.cols)))
    if about == "steady" and not controls:
        # a held cyclic velocity that the others depend on (a conical pendulum's azimuth rate):
        # its family's zero eigenvalue goes with it, as for the decoupled ones above
        coupled = [nI + part.vel_I.index(j) for j in ignorable if abs(v[j]) > 0
                   and j in part.vel_I and nI + part.vel_I.index(j) in stay]
        for i in coupled:
            reduced = routh_reduction(A_r, A_sym, stay.index(i))
            if reduced is not None:
                A_r, A_sym = reduced
                B_r = np.delete(B_r, stay.index(i), axis=0)
                stay = [x for x in stay if x != i]
                family.append(i)
    info = analyse(A_r, A_sym, symbolic, [variables[i] for i in stay], about == "equilibrium")
    ctrl = controllability(A_r, B_r) if controls else {}
    freqs = natural_frequencies(pt, q, v, part, kept) if about == "equilibrium" else ()
    dependent = [names_q[j] for j in part.coords_D] + [names_v[j] for j in part.vel_D]
    return Linearization(
        model=model.name, about=about, t=t0,
        q={c: float(x) for c, x in zip(names_q, q)}, qdot={c: float(x) for c, x in zip(names_q, v)},
        variables=tuple(variables[i] for i in stay), A=A_r, B=B_r, controls=controls,
        A_symbolic=A_sym, B_symbolic=B_sym if controls else None, symbolic=symbolic,
        ignorable=tuple(names_q[j] for j in ignorable) + tuple(variables[i] for i in drifting if i in drop),
        family=tuple(variables[i] for i in family),
        dependent=tuple(dependent), eigenvalues=info["eigenvalues"],
        characteristic_polynomial=info["polynomial"], hurwitz=tuple(info["hurwitz"]),
        verdict=info["verdict"], reason=info["reason"], conditions=tuple(info["conditions"]),
        controllability=ctrl, residual=res_guess, frequencies=tuple(freqs),
        conditions_meaning=info["conditions_meaning"])


def _with_contacts(model: Model, about, at, options) -> Linearization:
    """Linearize a model with contacts: each touching contact written as the constraint it is
    in the mode the contacts have at the state (:mod:`nonideal.analysis.stability.contacts`).

    The mode is chosen at the guess (completed from the initial values; at rest for an
    equilibrium) and checked at the state Newton finds: when it differs there, the
    linearization is done again in the mode of that state; a mode that still changes is an
    error (the motion is not a steady motion of one mode)."""
    init = guess_state(model, about, at, options["symbolic"])
    t0 = options["t"]
    guess = at
    for _ in range(2):
        reduced, labels = as_constraints(model, contact_modes(model, init, t0))
        lin = linearize(reduced, about, guess, **options)
        init = dict(lin.q)
        init.update({c + "'": v for c, v in lin.qdot.items()})
        found = {name: cs.label() for name, cs in contact_modes(model, init, t0).contacts}
        if found == labels:
            return dataclasses.replace(lin, contacts=described(model, labels))
        guess = {key: v for key, v in init.items() if about == "steady" or not key.endswith("'")}
    raise LinearizationUndefined(
        "the contacts change mode between the guess and the state found ("
        + ", ".join(f"{name}: {labels[name]} -> {found[name]}" for name in labels if labels[name] != found[name])
        + "); the state is not a steady motion in one contact mode", state=init)


def _scale(pt: Point, q, v, part) -> float:
    """Acceleration scale of the problem (for the tolerances): the largest |q''| the forces
    alone would give at the state, at least 1."""
    b = pt.blocks(q, v)
    M = b["E_a"]
    F = -b["E"].ravel()
    try:
        acc = np.linalg.solve(M, F) if M.size else np.zeros(0)
    except np.linalg.LinAlgError:
        acc = F
    return max(1.0, float(np.max(np.abs(acc), initial=0.0)), float(np.max(np.abs(v), initial=0.0)) ** 2)


def _ignorable(pt: Point, q, v, part: Partition, names_q) -> tuple[list, list]:
    """Coordinates and velocities nothing else depends on (columns of A vanishing outside their
    own rows) at the state and at a perturbed one: ``(coordinates, velocities)``, model indices."""
    rng = np.random.default_rng(7)
    nI = len(part.coords_I)
    found = None
    for trial in range(2):
        qq, vv = q.copy(), v.copy()
        if trial:
            qq[part.coords_I] += 0.05 * rng.standard_normal(nI)
            vv[part.vel_I] += 0.05 * rng.standard_normal(len(part.vel_I))
            qq, vv = pt.complete(qq, vv, part)
        _, _, b = pt.motion(qq, vv)
        A, _ = state_matrices(b, part, pt.n, True, pt.k.model)
        cand = list(range(nI + len(part.vel_I)))
        zero = set(ignorable_set(A, cand))
        found = zero if found is None else found & zero
    coords = sorted(part.coords_I[i] for i in found if i < nI)
    vels = sorted(part.vel_I[i - nI] for i in found if i >= nI)
    return coords, vels


def _newton(pt: Point, q, v, part, kept, rated, given, about, names_v, scale):
    """Gauss--Newton (minimum-norm steps) on the kept coordinates and the free velocities."""
    nI = len(part.coords_I)
    held = [j for j in part.vel_I if j not in kept and names_v[j] in given] if about == "steady" else []
    best = (np.inf, q, v)
    for attempt in range(2 if held else 1):
        qq, vv = q.copy(), v.copy()
        free_v = [] if about == "equilibrium" else [j for j in part.vel_I if j not in kept and j not in held]
        cols = [part.coords_I.index(j) for j in kept] + [nI + part.vel_I.index(j) for j in free_v]
        for _ in range(NEWTON_STEPS):
            try:
                R, a, lam, b = _rates(pt, qq, vv, kept, rated)
            except LinearizationUndefined as exc:
                # Newton ran onto a singular state (a coordinate singularity): no steady motion
                # there; the guess's neighbourhood has none it could reach
                return q, v, False, best[:3] + (str(exc),)
            size = float(np.max(np.abs(R), initial=0.0))
            if size < best[0]:
                best = (size, qq.copy(), vv.copy())
            if _zero(R, scale):
                return qq, vv, True, best
            A, _ = state_matrices(b, part, pt.n, True, pt.k.model)
            rows = [part.coords_I.index(j) for j in kept] + [nI + part.vel_I.index(j) for j in rated]
            J = A[np.ix_(rows, cols)]
            step = np.linalg.lstsq(J, -R, rcond=None)[0]
            if not np.all(np.isfinite(step)):
                break
            for c, d in zip(cols, step):
                if c < nI:
                    qq[part.coords_I[c]] += d
                else:
                    vv[part.vel_I[c - nI]] += d
            qq, vv = pt.complete(qq, vv, part)
        held = []
    return q, v, False, best


def _runaway(guess_q, guess_v, q, v, names_q, names_v) -> str | None:
    """Where Newton's state ran off towards a singularity (a velocity or coordinate 1e6 times
    the guess's size: the rates vanish there only as the mass matrix grows without bound, as
    a regulator's wheel speed does when its contact radius x - c goes to zero), what grew."""
    size = 1.0 + max(float(np.max(np.abs(guess_q), initial=0.0)), float(np.max(np.abs(guess_v), initial=0.0)))
    grown = [(abs(x), f"{name} = {x:.6g}") for name, x in zip(names_v, v) if abs(x) > 1e6 * size]
    grown += [(abs(x), f"{name} = {x:.6g}") for name, x in zip(names_q, q) if abs(x) > 1e6 * size]
    if not grown:
        return None
    where = ", ".join(f"{c} = {x:.10g}" for c, x in zip(names_q, q))
    return (f"{max(grown)[1]} grows without bound (at {where}): the rates vanish there only in "
            "the limit, not at a steady motion")


def _not_steady(model, about, names_q, names_v, q, v, R, kept, rated, best) -> NotAnEquilibrium:
    labels = [names_v[j] for j in kept] + [names_v[j] + "'" for j in rated]
    order = np.argsort(-np.abs(R))[:3]
    worst = ", ".join(f"{labels[i]} = {R[i]:.6g}" for i in order if abs(R[i]) > 0)
    state = ", ".join(f"{c} = {x:.6g}" for c, x in zip(names_q, q))
    if about == "steady":
        state += ", " + ", ".join(f"{c} = {x:.6g}" for c, x in zip(names_v, v) if x)
    what = "an equilibrium" if about == "equilibrium" else "a steady motion"
    text = f"--at: the state ({state}) is not {what}: the residual rates are {worst}"
    if best is not None and len(best) > 3:
        text += (f"; Newton from this guess ran onto a state where {best[3]}; no "
                 f"{what.split(' ', 1)[1]} was found near the guess (smallest residual "
                 f"{best[0]:.3g} on the way)")
    elif best is not None:
        text += (f"; Newton from this guess did not converge (smallest residual {best[0]:.3g} "
                 f"after {NEWTON_STEPS} steps)")
    fix = ("give a guess closer to an equilibrium in --at (where the forces balance)"
           if about == "equilibrium" else
           "give a guess closer to a steady motion in --at (the cyclic velocities and the "
           "coordinates where the forces balance)")
    if best is None:
        fix = "drop --exact to let Newton find the state from this guess, or " + fix
    return NotAnEquilibrium(text + ". Fix: " + fix, _src(model))


def _src(model: Model):
    return None if model.source == "<api>" else model.source


def _given_dependent_velocities(model: Model, given: dict[str, float], v: np.ndarray, part,
                                names_v: list[str]) -> None:
    """A velocity given in ``--at`` that the constraints make dependent is recomputed from the
    independent ones: refuse it when the recomputed value differs, rather than linearize
    silently about another state (e.g. a wheel's spin given while the constraints take it from
    the other wheel's)."""
    wrong = []
    for j in part.vel_D:
        name = names_v[j]
        if name in given:
            want = given[name]
            if abs(v[j] - want) > 1e-9 * max(1.0, abs(want)):
                wrong.append(f"{name} = {want:.10g}")
    if wrong:
        independent = ", ".join(names_v[j] for j in part.vel_I)
        raise ModelError(
            f"--at: {', '.join(wrong)} cannot be held: the constraints fix "
            f"{'this velocity' if len(wrong) == 1 else 'these velocities'} from the independent "
            f"ones ({independent}), and with the values given they come out different; give the "
            "state by the independent velocities (or choose them with [forms] independent)",
            _src(model))
