"""Generalized speeds (``[speeds]``) and named outputs (``[outputs]``) of a model.

A generalized speed (Kane & Levinson 1985, ch. 2; a quasi-velocity in Yushkov 1999, ch. IV) is
an expression linear in the velocities, ``u = W(q, t) q' + w0(q, t)``.  Together with the
derivatives of the holonomic constraints the speeds must determine every velocity (the
stacked matrix ``[W; df/dq]`` has rank ``n_q``; with Euler parameters, their radial rate
``e . e'``, which the library holds at zero, counts too), and no speed may be a combination of the
others (``W`` has full row rank).  Speed names may then be used in every later expression of
the model: they stand for their definitions.

An output is a named expression in the coordinates, velocities, speeds, time, the energies
``T`` and ``V`` and the multipliers ``lambda_<constraint>``; it is evaluated along a
simulation and printed, never used by the equations.
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from typing import Any

import numpy as np
import sympy as sp

from .declarations import RESERVED_NAMES
from ..errors import ExpressionError
from .symbols import is_identifier
from .values import parameter_values, to_expr

__all__ = ["normalize_speeds", "normalize_outputs", "check_speed_set", "speed_matrix", "radial_rows", "radial_indices", "on_unit_sphere",
           "finish_speeds_and_outputs", "OUTPUT_SPECIAL"]

OUTPUT_SPECIAL = ("T", "V")   # the kinetic and potential energies in an output expression
#: columns of a trajectory's CSV that an output may not shadow
TRAJECTORY_COLUMNS = frozenset({"t", "mode", "kinetic", "potential", "energy", "active_work", "reaction_work",
                                "friction_work", "explicit_time_work", "impact_work", "balance"})


def speed_matrix(model) -> tuple[sp.Matrix, sp.Matrix]:
    """``(W, w0)`` of the model's speeds: ``u = W q' + w0``, shapes (n_u, n_q) and (n_u, 1)."""
    qd = list(model.qd)
    exprs = list(model.speeds.values())
    W = sp.Matrix([[sp.diff(e, v) for v in qd] for e in exprs]) if exprs else sp.zeros(0, len(qd))
    w0 = sp.Matrix([e.xreplace({v: 0 for v in qd}) for e in exprs]) if exprs else sp.zeros(0, 1)
    return W, w0


def normalize_speeds(norm) -> None:
    """Parse ``[speeds]`` (name -> expression linear in the velocities); problems go to the
    normalizer's list.  Called before any other expression is read, so that the speed names
    can be used in them."""
    m = norm.m
    raw = m.speeds
    if not raw:
        object.__setattr__(m, "speeds", {})
        m.__dict__["_speeds_ready"] = True
        return
    if not isinstance(raw, Mapping):
        norm.problems.append("[speeds]: must be a table name = \"expression linear in the velocities\"")
        object.__setattr__(m, "speeds", {})
        return
    taken = set(m.coordinates) | set(m.parameters)
    names = {k: v for k, v in m.names(1).items() if k not in raw}
    qd = set(m.qd)
    out: dict[str, sp.Expr] = {}
    for name, value in raw.items():
        where = f"[speeds] {name}"
        if not isinstance(name, str) or not is_identifier(name):
            norm.problems.append(f"{where}: not a valid name (letters, digits, _, not starting with a digit)")
            continue
        if name in RESERVED_NAMES or name in ("T", "V", "N", "O") or name.startswith("lambda_"):
            norm.problems.append(f"{where}: '{name}' is reserved; choose another name")
            continue
        if name in taken:
            what = "coordinate" if name in m.coordinates else "parameter"
            norm.problems.append(f"{where}: '{name}' is also a {what}; choose another name")
            continue
        try:
            e = to_expr(value, names, where, m.coordinates, getattr(norm, "kinematics", None))
        except ExpressionError as exc:
            unknown = [u for u, _ in exc.unknown if u in raw]
            if unknown:
                norm.problems.append(f"{where}: uses the speed '{unknown[0]}'; define every speed "
                                     "by the coordinates and their velocities only")
            else:
                norm.problems.extend(exc.problems)
                norm.unknown.extend(exc.unknown)
            continue
        used = e.free_symbols & qd
        if not used:
            norm.problems.append(f"{where}: contains no velocity; a speed is an expression linear in "
                                 "the velocities (e.g. \"x'*cos(th) + y'*sin(th)\")")
            continue
        nonlinear = sorted(str(v) for v in used
                           if any(sp.diff(e, v, w) != 0 for w in used))
        if nonlinear:
            norm.problems.append(f"{where}: not linear in the velocities ({', '.join(nonlinear)} enter "
                                 "nonlinearly); a speed is u = W(q, t) q' + w0(q, t)")
            continue
        out[name] = e
    object.__setattr__(m, "speeds", out)
    m.__dict__["_speeds_ready"] = True
    norm._names.clear()   # later expressions see the speed names


def check_speed_set(model, samples: int = 2, seed: int = 5) -> list[str]:
    """Problems of the speed set as a whole: dependent speeds, velocities not determined by
    the speeds together with the holonomic constraints (judged at generic states)."""
    if not model.speeds:
        return []
    W, _ = speed_matrix(model)
    q, qd = list(model.q), list(model.qd)
    hol = [c for c in model.constraints if c.order == 0 and not c.unilateral and c.kind != "servo"]
    Gh = sp.Matrix([[sp.diff(c.expr, v) for v in q] for c in hol]) if hol else sp.zeros(0, len(q))
    radial = radial_rows(model)
    stacked = W.col_join(Gh).col_join(radial) if radial.rows else W.col_join(Gh)
    params = {sp.Symbol(str(k)): float(v) for k, v in parameter_values(model.parameters).items()}
    rng = random.Random(seed)
    fn = sp.lambdify(q + [sp.Symbol("t")] + list(params), stacked, modules="numpy")
    values = []
    for _ in range(samples):
        point = [rng.uniform(0.2, 1.1) * rng.choice((-1, 1)) for _ in range(len(q) + 1)]
        with np.errstate(all="ignore"):
            values.append(np.asarray(fn(*point, *params.values()), dtype=float).reshape(stacked.shape))
    values = [v for v in values if np.all(np.isfinite(v))] or values
    names = list(model.speeds)
    problems = []
    nu = len(names)
    Wn = values[0][:nu]
    rank_w = np.linalg.matrix_rank(Wn, tol=1e-9 * (1 + np.abs(Wn).max()))
    if rank_w < nu:
        dependent = [names[k] for k in range(nu)
                     if np.linalg.matrix_rank(np.delete(Wn, k, axis=0), tol=1e-9 * (1 + np.abs(Wn).max())) == rank_w]
        problems.append(
            f"[speeds]: the speeds {', '.join(dependent)} are linearly dependent ({nu} speeds, only "
            f"{rank_w} independent combinations of the velocities); remove one of them or change its "
            "definition")
    full = values[0]
    rank = np.linalg.matrix_rank(full, tol=1e-9 * (1 + np.abs(full).max()))
    if rank < len(q):
        null = np.linalg.svd(full)[2][rank:]
        missing = [str(qd[j]) for j in range(len(q)) if np.abs(null[:, j]).max() > 1e-8]
        with_h = (" together with the derivatives of the holonomic constraints "
                  + ", ".join(f"'{c.name}'" for c in hol)) if hol else ""
        if radial.rows:
            with_h += " and the unit norm of the Euler parameters"
        problems.append(
            f"[speeds]: the speeds {', '.join(names)}{with_h} do not determine the velocities "
            f"{', '.join(missing)} ({rank} of {len(q)} determined); add a speed that involves "
            f"{' or '.join(missing)} (e.g. {missing[0]} itself)")
    return problems


def radial_indices(model) -> list[list[int]]:
    """The coordinate indices of the Euler parameters of each frame given by them."""
    kin = model.__dict__.get("_kinematics")
    q = list(model.q)
    return [[q.index(x) for x in e] for e in (kin.quaternions().values() if kin is not None else ())
            if all(x in q for x in e)]


def on_unit_sphere(model, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """The state ``(q, q')`` with every frame's Euler parameters divided by their norm and
    their rates made tangent (``e . e' = 0``): the same rotation and angular velocity (they
    depend on ``e/|e|`` only), on the manifold the motion keeps."""
    q, qd = np.array(q, dtype=float), np.array(qd, dtype=float)
    for idx in radial_indices(model):
        size = float(np.linalg.norm(q[idx]))
        if size > 0:
            q[idx] /= size
            qd[idx] = (qd[idx] - q[idx] * float(q[idx] @ qd[idx])) / size
    return q, qd


def radial_rows(model) -> sp.Matrix:
    """One row per frame given by Euler parameters: the coefficients of the radial rate
    ``e . e'`` in the velocities (``e`` in the columns of its coordinates).  The rotation is
    that of ``e/|e|``, so no speed written through the frames involves this rate; the library
    holds it at zero (:mod:`nonideal.modeling.kinematics`), and it counts with the speeds."""
    kin = model.__dict__.get("_kinematics")
    q = list(model.q)
    rows = []
    for e in (kin.quaternions().values() if kin is not None else ()):
        if all(x in q for x in e):
            rows.append([x if x in e else 0 for x in q])
    return sp.Matrix(rows) if rows else sp.zeros(0, len(q))


def normalize_outputs(norm) -> None:
    """Parse ``[outputs]`` (name -> expression).  Names usable: the model's names up to the
    velocities, the speeds, ``T``, ``V`` and ``lambda_<constraint>`` for every constraint."""
    m = norm.m
    raw = m.outputs
    if not raw:
        object.__setattr__(m, "outputs", {})
        return
    if not isinstance(raw, Mapping):
        norm.problems.append("[outputs]: must be a table name = \"expression\"")
        object.__setattr__(m, "outputs", {})
        return
    names: dict[str, Any] = dict(m.names(1))
    names.update({k: sp.Symbol(k) for k in OUTPUT_SPECIAL})
    names.update({f"lambda_{c.name}": sp.Symbol(f"lambda_{c.name}") for c in m.constraints})
    taken = set(m.coordinates) | set(m.speeds)
    out: dict[str, sp.Expr] = {}
    for name, value in raw.items():
        where = f"[outputs] {name}"
        if not isinstance(name, str) or not is_identifier(name):
            norm.problems.append(f"{where}: not a valid name (letters, digits, _, not starting with a digit)")
            continue
        if name in taken or name in TRAJECTORY_COLUMNS or name.startswith("lambda_"):
            what = ("a coordinate or speed (reported anyway)" if name in taken else
                    "a multiplier's name" if name.startswith("lambda_") else
                    "a column of every simulation's output (t, mode, the energy terms)")
            norm.problems.append(f"{where}: '{name}' is already {what}; choose another name")
            continue
        try:
            e = to_expr(value, names, where, m.coordinates, getattr(norm, "kinematics", None))
        except ExpressionError as exc:
            vector = _vector_output(norm, value, names, where) if "is a vector" in str(exc) else None
            if vector is not None:   # a vector output: its components in N, name.x, name.y, name.z
                out.update({f"{name}.{axis}": c for axis, c in zip("xyz", vector)})
                continue
            for p in exc.problems:
                bad = p.split("'")[1] if "'" in p else ""
                if bad.startswith("lambda_"):
                    p += ("; multipliers are named lambda_<constraint> for the constraints "
                          + ", ".join(c.name for c in m.constraints) if m.constraints else
                          "; this model has no constraints, hence no multipliers")
                norm.problems.append(p)
            continue
        out[name] = e
    object.__setattr__(m, "outputs", out)


def _vector_output(norm, value, names, where):
    """The components in N of a vector-valued output, or None (the error is reported)."""
    from .expressions import parse_vector

    try:
        return parse_vector(value, names, where, norm.kinematics).components
    except ExpressionError as exc:
        norm.problems.extend(exc.problems)
        return None


def read_speeds_and_outputs(data: dict, check, problems: list[str]) -> tuple[dict, dict]:
    """The ``[speeds]`` and ``[outputs]`` tables of a model file (name -> expression text)."""
    out: tuple[dict, dict] = ({}, {})
    for key, store in zip(("speeds", "outputs"), out):
        section = data.get(key, {})
        if not isinstance(section, dict):
            problems.append(f"[{key}]: must be a table name = \"expression\"")
            continue
        store.update({k: v for k, v in section.items() if check.expr(section, k, f"[{key}] {k}")})
    return out


def finish_speeds_and_outputs(norm) -> None:
    """After the other sections: the outputs parsed, the speed set checked as a whole."""
    normalize_outputs(norm)
    if not norm.problems:
        norm.problems += check_speed_set(norm.m)
