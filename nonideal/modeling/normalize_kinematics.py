"""Normalization of a model's frames and points (called by the
:class:`~nonideal.modeling.normalize.Normalizer`): every declaration checked and parsed, the
:class:`~nonideal.modeling.kinematics.Kinematics` built, rigid bodies given by ``frame`` and
``center`` (particles by ``point``) resolved to positions, rotations and angular velocities,
and the initial values of Euler parameters normalized.  Every problem is collected."""

from __future__ import annotations

import math
from dataclasses import replace

import sympy as sp

from ..errors import did_you_mean
from .bodies import Particle, RigidBody
from .frames import FIXED, ORIGIN, Frame, parse_sequence
from .kinematics import RESERVED_KINEMATIC_NAMES, Kinematics
from .points import Point
from .symbols import is_identifier, t
from .values import identically_zero

__all__ = ["normalize_kinematics", "resolve_body", "normalize_quaternion_initial",
           "NORM_TOLERANCE"]

#: Euler parameters given at t0 whose norm differs from 1 by more than this are refused (closer,
#: they are divided by their norm)
NORM_TOLERANCE = 1e-3


def normalize_kinematics(norm) -> Kinematics:
    """Check and parse ``m.frames`` and ``m.points``; set their normalized forms on the model
    and return the :class:`Kinematics` (frames and points with problems are left out)."""
    m, problems = norm.m, norm.problems
    frames, points = tuple(m.frames or ()), tuple(m.points or ())
    seen: dict[str, str] = {}
    q = set(m.q)

    def named(item, kind: str) -> bool:
        where = f"[[{kind}s]] '{getattr(item, 'name', '?')}'"
        name = getattr(item, "name", None)
        if not isinstance(name, str) or not is_identifier(name):
            problems.append(f"{where}: name must be an identifier (letters, digits, _)")
            return False
        if name in RESERVED_KINEMATIC_NAMES:
            problems.append(f"{where}: '{name}' is reserved (N is the fixed frame, O its origin, t "
                            "time, T and V the energies); choose another name")
            return False
        if name in seen:
            problems.append(f"{where}: the name is already used by {seen[name]} '{name}'")
            return False
        seen[name] = kind
        return True

    out_frames, specs = [], {}
    for f in frames:
        if not isinstance(f, Frame):
            problems.append(f"frames: expected Frame declarations, got {type(f).__name__}")
            continue
        if not named(f, "frame"):
            continue
        spec = _frame(norm, f, q)
        if spec is not None:
            specs[f.name] = spec
            out_frames.append(spec[3])
    _chains("frame", {n: s[0] for n, s in specs.items()}, FIXED, "parent", problems, specs)
    # the frames first: point positions may use their unit vectors (B.x, dot(N.z, B.x) ...)
    kin = Kinematics({n: s[:3] for n, s in specs.items()}, {}, m.q, m.qd, m.qdd, t)
    kin.points_ready = False
    norm.kinematics = kin
    out_points, pts = [], {}
    for p in points:
        if not isinstance(p, Point):
            problems.append(f"points: expected Point declarations, got {type(p).__name__}")
            continue
        if not named(p, "point"):
            continue
        where = f"[[points]] '{p.name}'"
        frame_ok = p.frame == FIXED or p.frame in specs
        if not frame_ok:
            problems.append(f"{where}: frame '{p.frame}' is not declared"
                            f"{did_you_mean(str(p.frame), [FIXED, *specs])}; declare it in [[frames]] "
                            "or use N")
        pos = norm.vector(p.position, f"{where}: position", (3,))
        if pos is not None and frame_ok:
            pts[p.name] = (p.origin, p.frame, pos)
            out_points.append(Point(p.name, pos, p.frame, p.origin))
    _chains("point", {n: s[0] for n, s in pts.items()}, ORIGIN, "from", problems, pts)
    norm.set("frames", tuple(out_frames))
    norm.set("points", tuple(out_points))
    kin.points.update(pts)
    kin.points_ready = True
    return kin


def _chains(kind: str, parents: dict, root: str, key: str, problems: list[str], specs: dict) -> None:
    """Every chain of *parents* ends at *root*; loops and unknown names are problems (and the
    items concerned are dropped from *specs*)."""
    bad = set()
    for name in list(parents):
        chain, cur = [name], parents[name]
        while cur != root:
            if cur not in parents:
                if cur not in bad and len(chain) == 1:
                    problems.append(f"[[{kind}s]] '{name}': {key} '{cur}' is not declared"
                                    f"{did_you_mean(str(cur), [root, *parents])}; declare it in "
                                    f"[[{kind}s]] or use {root}")
                bad.add(name)
                break
            if cur in chain:
                loop = chain[chain.index(cur):] + [cur]
                if name == min(loop):
                    problems.append(f"[[{kind}s]] '{name}': its {key} chain {' -> '.join(loop)} is a "
                                    f"loop; one of them must have {key} = \"{root}\" (or another "
                                    f"{kind} that leads to {root})")
                bad.add(name)
                break
            chain.append(cur)
            cur = parents[cur]
        if cur in bad:
            bad.add(name)
    for name in bad:
        specs.pop(name, None)


def _frame(norm, f: Frame, q: set):
    """``(parent, kind, data, normalized Frame)`` of a frame declaration, or None."""
    where = f"[[frames]] '{f.name}'"
    problems = norm.problems
    if not isinstance(f.parent, str):
        problems.append(f"{where}: parent must be the name of a frame (got {f.parent!r})")
        return None
    given = f.given()
    if len(given) != 1:
        problems.append(f"{where}: give one rotation: rotation = \"body ZXZ\" with angles = [..], "
                        "axis = [..] with angle, quaternion = [..] (Euler parameters) or matrix = "
                        f"[[..], [..], [..]]" + (f" (got {' and '.join(given)})" if given else ""))
        return None
    kind = given[0]
    if kind == "rotation":
        if f.rotation is None or f.angles is None:
            problems.append(f"{where}: rotation and angles go together, e.g. rotation = \"body "
                            "ZXZ\", angles = [\"psi\", \"theta\", \"phi\"]")
            return None
        kind, axes, problem = parse_sequence(f.rotation, where)
        if problem:
            problems.append(problem)
            return None
        if not isinstance(f.angles, tuple) or len(f.angles) != len(axes):
            problems.append(f"{where}: rotation '{f.rotation}' has {len(axes)} axes: give "
                            f"{len(axes)} angles (got {f.angles!r})")
            return None
        angles = norm.vector(f.angles, f"{where}: angles", (len(axes),))
        if angles is None:
            return None
        return f.parent, kind, {"axes": axes, "angles": list(angles)}, replace(f, angles=angles)
    if kind == "axis":
        if f.axis is None or f.angle is None:
            problems.append(f"{where}: axis and angle go together, e.g. axis = [\"0\", \"0\", \"1\"], "
                            "angle = \"theta\"")
            return None
        axis = norm.vector(f.axis, f"{where}: axis", (3,))
        angle = norm.smooth(norm.expr(f.angle, f"{where}: angle", 0), f"{where}: angle")
        if axis is None or angle is None:
            return None
        n2 = sp.Add(*[a * a for a in axis])
        if identically_zero(n2):
            problems.append(f"{where}: axis is the zero vector; give its direction, e.g. "
                            "[\"0\", \"0\", \"1\"]")
            return None
        u = sp.Matrix(axis) if n2 == 1 else sp.Matrix(axis) / sp.sqrt(n2)
        return (f.parent, "axis", {"axis": u, "angle": angle, "moving": q | {t}},
                replace(f, axis=axis, angle=angle))
    if kind == "quaternion":
        e = norm.vector(f.quaternion, f"{where}: quaternion", (4,)) \
            if isinstance(f.quaternion, (tuple, list)) else None
        if e is None or not all(x in q for x in e) or len(set(e)) != 4:
            if e is not None or not isinstance(f.quaternion, (tuple, list)):
                problems.append(f"{where}: quaternion must name four different coordinates, the "
                                "Euler parameters e0 (scalar), e1, e2, e3 (got "
                                f"{f.quaternion!r})")
            return None
        return f.parent, "quaternion", {"e": list(e)}, replace(f, quaternion=e)
    rows = f.matrix if isinstance(f.matrix, tuple) and len(f.matrix) == 3 else None
    rows = [norm.vector(r, f"{where}: matrix", (3,)) for r in rows] if rows else None
    if rows is None or any(r is None for r in rows):
        if rows is None:
            problems.append(f"{where}: matrix must be 3x3 (columns: the frame's unit vectors in "
                            "the parent's axes)")
        return None
    R = sp.Matrix(rows)
    off = R.T * R - sp.eye(3)
    det = (R[0, 0] * (R[1, 1] * R[2, 2] - R[1, 2] * R[2, 1]) - R[0, 1] * (R[1, 0] * R[2, 2] - R[1, 2] * R[2, 0])
           + R[0, 2] * (R[1, 0] * R[2, 1] - R[1, 1] * R[2, 0]))   # no symbolic elimination
    if not all(identically_zero(x) for x in off) or not identically_zero(det - 1):
        problems.append(f"{where}: matrix is not a rotation (R^T R = I and det R = 1 must hold "
                        "identically); check its entries, or use rotation = \"body ...\" with angles")
        return None
    return f.parent, "matrix", {"R": R}, replace(f, matrix=tuple(rows))


def resolve_body(norm, kin: Kinematics | None, b, where: str):
    """A rigid body by ``frame`` and ``center`` (a particle by ``point``) with its position,
    rotation and angular velocity filled from the kinematics; other bodies unchanged.  None
    after a problem."""
    if isinstance(b, RigidBody) and (b.frame is not None or b.center is not None):
        if b.frame is None or b.center is None:
            norm.problems.append(f"{where}: a rigid body by frame needs both frame = \"B\" and "
                                 "center = \"G\" (its centre of mass, a point)")
            return None
        if not _known(norm, kin, "frame", b.frame, where) or not _known(norm, kin, "point", b.center, where):
            return None
        R = kin.rotation(b.frame)
        return replace(b, position=tuple(kin.pos(b.center)), rotation=tuple(tuple(R.row(i)) for i in range(3)),
                       omega=tuple(kin.omega_own(b.frame)))
    if isinstance(b, Particle) and b.point is not None:
        if not _known(norm, kin, "point", b.point, where):
            return None
        return replace(b, position=tuple(kin.pos(b.point)))
    return b


def _known(norm, kin, kind: str, name, where: str) -> bool:
    known = [] if kin is None else kin.names_of(kind)
    if name not in known:
        norm.problems.append(f"{where}: {kind} {name!r} is not declared{did_you_mean(str(name), known)}; "
                             f"declare it in [[{kind}s]]")
        return False
    return True


def normalize_quaternion_initial(kin: Kinematics | None, initial: dict, values: dict) -> tuple[dict, list[str]]:
    """Euler parameters given at t0, divided by their norm when it is within
    :data:`NORM_TOLERANCE` of one (values written with a few decimals, 0.7071); farther from
    one they are refused with the normalized values suggested.  Returns the initial values
    and the problems."""
    out, problems = dict(initial), []
    for frame, e in (kin.quaternions() if kin is not None else {}).items():
        names = [x.name for x in e]
        if not all(n in initial for n in names):
            continue
        try:
            vals = [float(initial[n].xreplace(values)) for n in names]
        except (TypeError, ValueError):
            continue
        size = math.sqrt(sum(v * v for v in vals))
        if abs(size - 1.0) > NORM_TOLERANCE:
            hint = ", ".join(f"{n} = {v / size:.12g}" for n, v in zip(names, vals)) if size > 0 else \
                f"{names[0]} = 1, the others 0"
            problems.append(f"[initial] {', '.join(names)}: the Euler parameters of frame '{frame}' have "
                            f"norm {size:.12g}, not 1; give a unit quaternion, e.g. {hint}")
            continue
        elif size != 1.0:
            vals = [v / size for v in vals]
            out.update({n: sp.Float(v, 17) for n, v in zip(names, vals)})
        out.update(_tangent_rates(names, vals, initial, values))
    return out, problems


def _tangent_rates(names: list[str], e: list[float], initial: dict, values: dict) -> dict:
    """The rates e' of unit Euler parameters on their sphere, e . e' = 0: one missing completed
    from it, all four given projected on it (their radial part changes nothing: the rotation
    depends on e/|e| only).  None given, or several missing: left as they are (the speeds or
    the constraints complete them, else the missing velocities are reported)."""
    rates = {}
    for n in names:
        if n + "'" in initial:
            try:
                rates[n] = float(initial[n + "'"].xreplace(values))
            except (TypeError, ValueError):
                return {}
    missing = [k for k, n in enumerate(names) if n not in rates]
    ed = [rates.get(n, 0.0) for n in names]
    radial = sum(a * b for a, b in zip(e, ed))
    if len(missing) > 1:
        return {}
    if missing:
        k = missing[0]
        if abs(e[k]) < 1e-12:
            return {}
        ed[k] -= radial / e[k]
    else:
        ed = [b - a * radial for a, b in zip(e, ed)]
    return {n + "'": sp.Float(v, 17) for n, v in zip(names, ed)}


def describe(kin: Kinematics | None) -> list[str]:
    """One line per declared frame and point (for ``nonideal check``)."""
    if kin is None:
        return []
    lines = []
    for name, (parent, kind, data) in kin.frames.items():
        how = {"body": "body-fixed", "space": "space-fixed"}.get(kind, kind)
        if kind in ("body", "space"):
            how += " " + "".join("XYZ"[i] for i in data["axes"]) + f" ({', '.join(map(str, data['angles']))})"
        elif kind == "quaternion":
            how = f"Euler parameters ({', '.join(map(str, data['e']))}; unit norm kept by the library)"
        elif kind == "axis":
            how = f"about an axis by {data['angle']}"
        lines.append(f"frame {name}: from {parent}, {how}")
    for name, (origin, frame, pos) in kin.points.items():
        lines.append(f"point {name}: from {origin}, [{', '.join(map(str, pos))}] in {frame}")
    return lines

