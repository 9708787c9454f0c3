"""Model files (TOML) -> :class:`~nonideal.model.Model`.

The format (``format = 1``, reference: docs/MODEL_FORMAT.md) is extended -- never broken -- with:

* ``[[bodies]]`` (``type = "particle" | "planar" | "rigid"``) and ``[gravity] vector`` to
  assemble the kinetic and potential energy from geometry;
* ``[[loads]]`` (``type = "force" | "torque"``) turned into generalized forces;
* ``restitution`` for unilateral constraints (impact law; 0 = plastic, the default);
* contacts: ``friction = "coulomb" | "regularized" | "linearized" | "contensou"``, ``eps``,
  ``patch_radius``,
  ``restitution``, ``bilateral``; ``mu = "inf"`` (ideal rolling); friction torques;
* ``[forms] independent`` -- independent coordinates for the reduced forms (for
  ``lagrange2`` those of the first chart, see :mod:`nonideal.charts`);
* ``[parameters]`` values may be tables ``{value, unit, description}``, and expressions in the
  other parameters (derived parameters, e.g. ``w = "sqrt(g/l)"``), evaluated in dependency
  order when the file is read;
* numeric settings (``restitution``, ``eps``, ``[simulation]`` times and tolerances) may be
  expressions in the parameters too (e.g. ``t_end = "4*pi/w"``).

Every key is checked; unknown keys are rejected with a suggestion, and every problem in the
file is reported at once with the file name.  Expressions go through the safe parser only.
"""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path
from collections.abc import Mapping
from typing import Any


from .bodies import Force, Particle, PlanarBody, RigidBody, Torque
from .contact_normalize import torque_keys
from .contacts import Contact, Coulomb, CoulombContensou, LinearizedCoulomb, Newton, Plastic, RegularizedCoulomb, is_infinite
from ..errors import ModelError, UnitWarning, did_you_mean, short_repr
from .limits import check_nesting, check_size, read_text
from .declarations import Control, Parameter
from .quantities import base_units, degree_warnings, with_units
from .values import override_parameters  # noqa: F401  (--set; sweeps import it from here)
from .frames import FIXED, ORIGIN, Frame
from .points import Point
from .members import read_members
from .model import Constraint, Model, resolve_parameters
from .speeds import read_speeds_and_outputs

from .filechecks import Checker, control_characters, describe, is_expr, read_simulation, toml_problem, unknown_keys

__all__ = ["load_model", "model_from_dict", "FORMAT_VERSION"]

FORMAT_VERSION = 1

TOP_KEYS = {"model", "parameters", "coordinates", "energy", "forces", "bodies", "gravity", "loads", "constraints",
            "contacts", "initial", "simulation", "forms", "units", "controls", "frames", "points", "speeds", "outputs", "members"}
SECTION_KEYS = {
    "model": {"name", "format", "description", "source"},
    "coordinates": {"q"},
    "energy": {"kinetic", "potential"},
    "gravity": {"vector"},
    "simulation": {"t_end", "rtol", "atol", "method", "max_step", "t0", "split", "split_weights",
                   "singular", "grid", "every_step"},
    "forms": {"independent"},
}
CONSTRAINT_KEYS = {"name", "type", "expr", "reaction", "transform", "unilateral", "restitution",
                   "losses", "root", "cost", "description"}
CONTROL_KEYS = {"name", "direction", "weight", "description"}
CONTACT_KEYS = {"name", "gap", "slip", "mu", "mu_static", "friction", "eps", "patch_radius", "restitution", "bilateral",
                "description", "body", "shape", "surface", "spin", "rolling", "spin_friction", "rolling_friction"}
BODY_KEYS = {
    "particle": {"type", "name", "mass", "position", "point"},
    "planar": {"type", "name", "mass", "inertia", "position", "angle"},
    "rigid": {"type", "name", "mass", "inertia", "position", "rotation", "frame", "center"},
}
#: the keys that place a body: one set of them
BODY_PLACES = {"particle": ({"position"}, {"point"}), "planar": ({"position", "angle"},),
               "rigid": ({"position", "rotation"}, {"frame", "center"})}
FRAME_KEYS = {"name", "parent", "rotation", "angles", "axis", "angle", "quaternion", "matrix",
              "description"}
POINT_KEYS = {"name", "position", "frame", "from", "description"}
LOAD_KEYS = {
    "force": {"type", "name", "point", "force"},
    "torque": {"type", "name", "torque", "angle", "body"},
}
FRICTION_LAWS = ("coulomb", "regularized", "linearized", "contensou")


def load_model(path: str | Path, parameters: Mapping[str, Any] | None = None) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or Path
    parameters : mapping name -> number or str, optional
        Values that override the file's ``[parameters]`` (the command line's ``--set``): a
        number, or an expression in the other parameters.  Every name must be a parameter of
        the file.

    Examples
    --------
    >>> from nonideal import gallery
    >>> model = load_model(gallery.model_path("painleve-rod"), parameters={"mu": 2.0})
    >>> model.parameter_values["mu"]
    2.0

    Raises
    ------
    ModelError
        With the file name, the key and the fix, for every problem found.

    Warns
    -----
    UnitWarning
        A number above 2 pi used as an angle that keeps a contact open at t0 while the same
        number in degrees would close it (probably degrees written without ``deg``).
    """
    path = Path(path)
    source = str(path)
    text = read_text(path)
    text = text.removeprefix("\ufeff")  # a byte-order mark some editors write
    check_nesting(text, source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(toml_problem(str(exc), text), source) from None
    check_size(data, source)
    if parameters:
        data = override_parameters(data, parameters, source)
    model = model_from_dict(data, source, default_name=path.stem)
    for message in degree_warnings(model):
        warnings.warn(UnitWarning(f"{source}: {message}"), stacklevel=2)
    return model


def model_from_dict(data: dict[str, Any], source: str = "<dict>", default_name: str = "model") -> Model:
    """Build a :class:`Model` from the parsed TOML structure (see :func:`load_model`).

    Every problem is collected: those of the file's structure (unknown keys, wrong types) and,
    whenever the coordinates are usable, those the :class:`Model` finds in the expressions
    (unknown symbols, malformed expressions, missing parameters), in one :class:`ModelError`.
    """
    if not isinstance(data, dict):
        raise ModelError(f"model_from_dict: data must be a dict (the parsed TOML of a model file), "
                         f"got {type(data).__name__} {short_repr(data, 40)}", source)
    problems: list[str] = []
    check = Checker(problems)
    problems += unknown_keys(data, TOP_KEYS, "top level")
    problems += control_characters(data)
    for key in ("constraints", "contacts", "bodies", "loads", "controls", "frames", "points", "members"):
        items = data.get(key)
        for i, item in enumerate(items if isinstance(items, list) else []):
            if isinstance(item, dict) and "description" in item and not isinstance(item["description"], str):
                label = item.get("name") if isinstance(item.get("name"), str) else f"#{i + 1}"
                problems.append(f"[[{key}]] '{label}': description must be a string "
                                f"(got {describe(item['description'])})")
    for section, allowed in SECTION_KEYS.items():
        if section in data:
            if not isinstance(data[section], dict):
                problems.append(f"[{section}]: must be a table ([{section}] followed by "
                                "key = value lines)")
            else:
                problems += unknown_keys(data[section], allowed, f"[{section}]")

    def table(key: str) -> dict:
        value = data.get(key, {})
        return value if isinstance(value, dict) else {}

    header = table("model")
    fmt = header.get("format", FORMAT_VERSION)
    if not isinstance(fmt, int) or isinstance(fmt, bool):
        problems.append(f"[model] format: must be an integer, the model file format version "
                        f"(got {fmt!r}); this version of nonideal reads format = {FORMAT_VERSION}")
    elif fmt != FORMAT_VERSION:
        problems.append(
            f"[model] format: this version of nonideal reads model files of format "
            f"{FORMAT_VERSION}, the file declares format = {fmt!r}; "
            + ("it was written for a newer nonideal: upgrade nonideal"
               if fmt > FORMAT_VERSION else f"convert the file to format {FORMAT_VERSION}")
        )
    name = header.get("name", default_name)
    if not isinstance(name, str):
        problems.append(f"[model] name: must be a string (got {describe(name)})")
        name = default_name
    description = header.get("description", "")
    if not isinstance(description, str):
        problems.append(f"[model] description: must be a string (got {describe(description)})")
        description = ""

    coords = table("coordinates").get("q")
    coords_ok = False
    if "coordinates" not in data or coords is None:
        problems.append('[coordinates] q: missing; list the generalized coordinates, e.g. '
                        '[coordinates] q = ["x", "theta"]')
    elif not isinstance(coords, list) or not all(isinstance(c, str) for c in coords):
        problems.append(f"[coordinates] q: must be a list of names in quotes, e.g. "
                        f"q = [\"x\", \"theta\"] (got {describe(coords)})")
    else:
        coords_ok = True
    n_q = len(coords) if coords_ok else None

    params = data.get("parameters", {})
    if not isinstance(params, dict):
        problems.append("[parameters]: must be a table of name = value")
        params = {}
    params = dict(params)
    for pname, value in list(params.items()):
        if isinstance(value, dict):
            problems += unknown_keys(value, {"value", "unit", "description"}, f"[parameters] {pname}")
            if "value" not in value:
                problems.append(f"[parameters] {pname}: missing 'value', e.g. "
                                f"{pname} = {{value = 1.0, unit = \"kg\"}}")
                params[pname] = 0.0   # placeholder: the error above is raised in any case
    check.parameter_names = set(params)
    base = base_units(data.get("units") if isinstance(data.get("units"), dict) else None)
    check.parameters = resolve_parameters(
        {n: (with_units(Parameter(n, v.get("value"), str(v.get("unit", ""))), base, "", []).value
             if isinstance(v, dict) else v) for n, v in params.items()}, base)[0]
    energy = table("energy")
    for key in ("kinetic", "potential"):
        if key in energy:
            check.expr(energy, key, f"[energy] {key}")
    energy = {k: v for k, v in energy.items() if k in ("kinetic", "potential") and is_expr(v)}
    forces = data.get("forces", {})
    if not isinstance(forces, dict):
        problems.append("[forces]: must be a table coordinate = expression")
        forces = {}
    forces = {k: v for k, v in forces.items() if check.expr(forces, k, f"[forces] {k}")}

    constraints = []
    for k, c in enumerate(_array_of_tables(data, "constraints", problems)):
        where = f"[[constraints]] #{k + 1}" + (f" '{c.get('name')}'" if "name" in c else "")
        problems += unknown_keys(c, CONSTRAINT_KEYS, where)
        missing = [key for key in ("name", "expr") if key not in c]
        if missing:
            problems.append(f"{where}: missing {' and '.join(missing)} (a constraint needs "
                            "name = \"...\" and expr = \"...\", meaning expr = 0)")
            continue
        ok = check.name(c, where) & check.expr(c, "expr", where)
        kind = c.get("type", "auto")
        if not isinstance(kind, str):
            problems.append(f"{where}: type must be \"holonomic\", \"nonholonomic\" or "
                            f"\"servo\" (got {describe(kind)})")
            ok = False
        unilateral = check.boolean(c, "unilateral", where)
        restitution = check.number(c, "restitution", where, 0.0, 0.0, 1.0)
        if "reaction" in c:  # a direction, or a list of directions (several controls, r < j)
            cols = c["reaction"] if isinstance(c["reaction"], list) else []
            for col in [r for r in cols if isinstance(r, list)] or [c["reaction"]]:
                ok &= check.expr_list({"reaction": col}, "reaction", where, (n_q,) if n_q else None)
        if "transform" in c:
            ok &= check.matrix(c, "transform", where, n_q)
        ok &= check.expr_list(c, "losses", where, (n_q,) if n_q else None) if "losses" in c else True
        if not ok:
            continue
        constraints.append(_ConstraintSpec(
            name=c["name"], expr=c["expr"], kind=kind, unilateral=unilateral,
            reaction=tuple(c["reaction"]) if "reaction" in c else None,
            transform=tuple(tuple(r) for r in c["transform"]) if "transform" in c else None,
            restitution=float(restitution), losses=tuple(c["losses"]) if "losses" in c else None,
            root=c.get("root"), cost=c.get("cost")))

    controls = []   # shared by the servo-constraints without reaction (Beghin: r programs, j controls)
    for k, u in enumerate(_array_of_tables(data, "controls", problems)):
        where = f"[[controls]] #{k + 1}" + (f" '{u.get('name')}'" if "name" in u else "")
        problems += unknown_keys(u, CONTROL_KEYS, where)
        if "name" not in u or "direction" not in u:
            problems.append(f"{where}: a control needs name = \"...\" and direction = [...] (one "
                            "expression per coordinate)")
            continue
        if check.name(u, where) & check.expr_list(u, "direction", where, (n_q,) if n_q else None) \
                & (check.expr(u, "weight", where) if "weight" in u else True):
            controls.append(Control(u["name"], tuple(u["direction"]), u.get("weight", 1),
                                    str(u.get("description", ""))))

    contacts = []
    for k, c in enumerate(_array_of_tables(data, "contacts", problems)):
        where = f"[[contacts]] #{k + 1}" + (f" '{c.get('name')}'" if "name" in c else "")
        problems += unknown_keys(c, CONTACT_KEYS, where)
        geometric = any(key in c for key in ("body", "shape", "surface"))
        needed = ("name", "body", "shape") if geometric else ("name", "gap", "slip")
        missing = [key for key in needed if key not in c]
        if geometric and ("gap" in c or "slip" in c):
            problems.append(f"{where}: give either gap and slip or body and shape (a contact from "
                            "geometry: the library derives the gap and slip), not both")
            continue
        if missing:
            problems.append(f"{where}: missing {', '.join(missing)} (a contact needs name and "
                            + ("body = \"...\" (a rigid body) and shape = {type = \"sphere\", "
                               "radius = \"r\"} (or another shape)" if geometric else
                               "gap = \"...\" (>= 0) and slip = [\"...\"], or body and shape)"))
            continue
        ok = check.name(c, where)
        if geometric:
            for key in ("shape", "surface"):
                if key in c and not isinstance(c[key], dict):
                    problems.append(f"{where}: {key} must be an inline table such as "
                                    + ("{type = \"sphere\", radius = \"r\"}" if key == "shape"
                                       else "{type = \"plane\", normal = [0, 0, 1]}"))
                    ok = False
            if not isinstance(c["body"], str):
                problems.append(f"{where}: body must be the name of a rigid body in quotes")
                ok = False
        else:
            ok &= check.expr(c, "gap", where)
            ok &= check.expr_list(c, "slip", where, (1, 2), allow_scalar=True)
        for key in ("mu", "mu_static"):
            if key in c and not is_infinite(c[key]):  # mu = "inf" (or inf): ideal rolling
                ok &= check.expr(c, key, where)
        bilateral = check.boolean(c, "bilateral", where)
        e = check.number(c, "restitution", where, 0.0, 0.0, 1.0)
        law = c.get("friction", "coulomb")
        if not isinstance(law, str) or law not in FRICTION_LAWS:
            problems.append(f"{where}: friction {law!r} unknown"
                            f"{did_you_mean(str(law), FRICTION_LAWS)}; use \"coulomb\", "
                            "\"regularized\", \"linearized\" or \"contensou\"")
            continue
        mu = c.get("mu", 0)
        if "patch_radius" in c and law != "contensou":
            problems.append(f"{where}: patch_radius applies to friction = \"contensou\" only; remove it "
                            "or set friction = \"contensou\"")
            continue
        if law == "coulomb":
            if "eps" in c and is_infinite(mu):
                problems.append(f"{where}: eps has no meaning for ideal rolling (mu = \"inf\"); "
                                "remove it")
            elif "eps" in c:
                problems.append(f"{where}: eps applies to the regularized and linearized laws "
                                "only; remove it or set friction = \"regularized\"")
            friction = Coulomb(mu, c.get("mu_static"))
        elif law == "contensou":
            extra = [k for k in ("eps", "mu_static") if k in c]
            friction = None if extra or "patch_radius" not in c or not check.expr(c, "patch_radius", where) \
                else CoulombContensou(mu, c["patch_radius"])
            if extra or "patch_radius" not in c:
                problems.append(f"{where}: the contensou law takes mu and patch_radius only; remove {extra[0]}"
                                if extra else f"{where}: friction = \"contensou\" needs patch_radius (the "
                                "radius of the circular contact patch in m, e.g. patch_radius = 5e-4)")
            if friction is None:
                continue
        else:
            if "eps" not in c:
                problems.append(f"{where}: the {law} friction law needs eps (a slip velocity "
                                "scale in m/s, e.g. eps = 1e-3)")
                continue
            eps = check.number(c, "eps", where, None, positive=True)
            if eps is None:
                continue
            friction = (RegularizedCoulomb if law == "regularized" else LinearizedCoulomb)(mu, eps)
        if not ok:
            continue
        impact = Plastic() if not e else Newton(e)
        torques = torque_keys(c, check, where)   # spin, rolling and their lengths
        if torques is None:
            continue
        given = dict(body=c["body"], shape=c["shape"], surface=c.get("surface")) if geometric else \
            dict(gap=c["gap"], slip=tuple(c["slip"]) if isinstance(c["slip"], list) else (c["slip"],))
        contacts.append(Contact(c["name"], friction=friction, impact=impact, bilateral=bilateral,
                                **given, **torques))

    bodies = []
    for k, b in enumerate(_array_of_tables(data, "bodies", problems)):
        kind = b.get("type", "particle")
        where = f"[[bodies]] #{k + 1}" + (f" '{b.get('name')}'" if "name" in b else "")
        if not isinstance(kind, str) or kind not in BODY_KEYS:
            problems.append(f"{where}: type {kind!r} unknown{did_you_mean(str(kind), BODY_KEYS)}; "
                            "use \"particle\", \"planar\" or \"rigid\"")
            continue
        problems += unknown_keys(b, BODY_KEYS[kind], where)
        places = [keys for keys in BODY_PLACES[kind] if keys & set(b)]
        place = places[0] if len(places) == 1 else BODY_PLACES[kind][0]
        missing = [key for key in ({"name", "mass", "inertia"} & BODY_KEYS[kind]) | place if key not in b]
        if len(places) > 1:
            problems.append(f"{where}: give either {' and '.join(sorted(BODY_PLACES[kind][0]))} or "
                            f"{' and '.join(sorted(BODY_PLACES[kind][1]))}, not both")
            continue
        if missing:
            problems.append(f"{where}: missing {', '.join(sorted(missing))}" + (
                f" (or {' and '.join(sorted(BODY_PLACES[kind][1]))}, declared in [[frames]] / [[points]])"
                if len(BODY_PLACES[kind]) > 1 and not places else ""))
            continue
        ok = check.name(b, where) & check.expr(b, "mass", where)
        for key in ("frame", "center", "point"):
            if key in b and not isinstance(b[key], str):
                problems.append(f"{where}: {key} must be the name of a declared "
                                f"{'frame' if key == 'frame' else 'point'} (got {describe(b[key])})")
                ok = False
        if kind == "particle" and "point" in b:
            if ok:
                bodies.append(Particle(b["name"], b["mass"], point=b["point"]))
        elif kind == "particle":
            ok &= check.expr_list(b, "position", where, (2, 3))
            if ok:
                bodies.append(Particle(b["name"], b["mass"], b["position"]))
        elif kind == "planar":
            ok &= check.expr_list(b, "position", where, (2,))
            ok &= check.expr(b, "inertia", where) & check.expr(b, "angle", where)
            if ok:
                bodies.append(PlanarBody(b["name"], b["mass"], b["inertia"], b["position"], b["angle"]))
        elif "frame" in b:
            ok &= check.matrix(b, "inertia", where, 3)
            if ok:
                bodies.append(RigidBody(b["name"], b["mass"], b["inertia"], frame=b["frame"],
                                        center=b["center"]))
        else:
            ok &= check.expr_list(b, "position", where, (3,))
            ok &= check.matrix(b, "inertia", where, 3) & check.matrix(b, "rotation", where, 3)
            if ok:
                bodies.append(RigidBody(b["name"], b["mass"], b["inertia"], b["position"], b["rotation"]))

    loads = []
    for k, ld in enumerate(_array_of_tables(data, "loads", problems)):
        kind = ld.get("type", "force")
        where = f"[[loads]] #{k + 1}" + (f" '{ld.get('name')}'" if "name" in ld else "")
        if not isinstance(kind, str) or kind not in LOAD_KEYS:
            problems.append(f"{where}: type {kind!r} unknown{did_you_mean(str(kind), LOAD_KEYS)}; "
                            "use \"force\" or \"torque\"")
            continue
        problems += unknown_keys(ld, LOAD_KEYS[kind], where)
        if kind == "force":
            missing = [key for key in ("name", "point", "force") if key not in ld]
            if missing:
                problems.append(f"{where}: missing {', '.join(missing)}")
                continue
            ok = check.name(ld, where) & check.expr_list(ld, "point", where, (2, 3))
            ok &= check.expr_list(ld, "force", where, (2, 3))
            if ok:
                loads.append(Force(ld["name"], ld["point"], ld["force"]))
        else:
            missing = [key for key in ("name", "torque") if key not in ld]
            if missing:
                problems.append(f"{where}: missing {', '.join(missing)}")
                continue
            ok = check.name(ld, where)
            if "body" in ld and isinstance(ld["torque"], list):   # on a rigid body in space
                ok &= check.expr_list(ld, "torque", where, (3,))
            else:                                                  # planar: a scalar torque
                ok &= check.expr(ld, "torque", where)
            if "body" in ld and not isinstance(ld["body"], str):
                problems.append(f"{where}: body must be the name of a body")
                ok = False
            if "angle" in ld:
                ok &= check.expr(ld, "angle", where)
            if ok:
                loads.append(Torque(ld["name"], ld["torque"], ld.get("angle"), ld.get("body")))

    frames, points = read_frames_and_points(data, check, problems)
    members = read_members(_array_of_tables(data, "members", problems), check, problems)

    t0, settings = read_simulation(table("simulation"), check, problems)
    initial = data.get("initial", {})
    if not isinstance(initial, dict):
        problems.append("[initial]: must be a table name = value")
        initial = {}
    initial = {k: v for k, v in initial.items()   # lambda_<c> = [..]: a third-order ideal constraint's R(t0)
               if (check.expr_list(initial, k, f"[initial] {k}") if isinstance(v, list) and str(k).startswith("lambda_")
                   else check.expr(initial, k, f"[initial] {k}"))}
    forms = table("forms")
    independent = None
    if "independent" in forms:
        independent = forms["independent"]
        if not isinstance(independent, list) or not all(isinstance(v, str) for v in independent):
            problems.append(f"[forms] independent: must be a list of coordinate names (got {describe(independent)})")
            independent = None
    speeds, outputs = read_speeds_and_outputs(data, check, problems)
    gravity = table("gravity").get("vector")
    if gravity is not None and not check.expr_list(table("gravity"), "vector", "[gravity]", (2, 3)):
        gravity = None

    model = None
    if coords_ok:
        try:
            model = Model(
                name=name,
                description=description,
                coordinates=tuple(coords),
                parameters=params,
                kinetic=energy.get("kinetic", 0),
                potential=energy.get("potential", 0),
                forces=forces,
                bodies=tuple(bodies),
                loads=tuple(loads),
                gravity=tuple(gravity) if gravity is not None else None,
                constraints=tuple(c.build() for c in constraints),
                contacts=tuple(contacts),
                initial=initial,
                t0=float(t0),
                independent=tuple(independent) if independent is not None else None,
                simulation=settings,
                source=source,
                units=data.get("units"),
                controls=tuple(controls),
                frames=frames,
                points=points,
                speeds=speeds, outputs=outputs,
                members=members,
            )
        except ModelError as exc:
            problems += [p for p in exc.problems if p not in problems]
    if problems:
        raise ModelError(problems, source)
    return model


def read_frames_and_points(data: dict, check: Checker, problems: list[str]) -> tuple[tuple, tuple]:
    """``[[frames]]`` and ``[[points]]`` as :class:`Frame` and :class:`Point` declarations
    (their types checked here, their meaning by the model)."""
    frames = []
    for k, f in enumerate(_array_of_tables(data, "frames", problems)):
        where = f"[[frames]] #{k + 1}" + (f" '{f.get('name')}'" if "name" in f else "")
        problems.extend(unknown_keys(f, FRAME_KEYS, where))
        ok = check.name(f, where)
        for key in ("parent", "rotation"):
            if key in f and not isinstance(f[key], str):
                problems.append(f"{where}: {key} must be a string (got {describe(f[key])})")
                ok = False
        for key, size in (("angles", (1, 2, 3)), ("axis", (3,)), ("quaternion", (4,))):
            ok &= check.expr_list(f, key, where, size) if key in f else True
        ok &= check.expr(f, "angle", where) if "angle" in f else True
        ok &= check.matrix(f, "matrix", where, 3) if "matrix" in f else True
        if ok:
            frames.append(Frame(f["name"], f.get("parent", FIXED), f.get("rotation"), f.get("angles"),
                                f.get("axis"), f.get("angle"), f.get("quaternion"), f.get("matrix")))
    points = []
    for k, p in enumerate(_array_of_tables(data, "points", problems)):
        where = f"[[points]] #{k + 1}" + (f" '{p.get('name')}'" if "name" in p else "")
        problems.extend(unknown_keys(p, POINT_KEYS, where))
        if "position" not in p:
            problems.append(f"{where}: missing position (3 components in the axes of frame, "
                            "from the point 'from')")
            continue
        ok = check.name(p, where) & check.expr_list(p, "position", where, (3,))
        for key in ("frame", "from"):
            if key in p and not isinstance(p[key], str):
                problems.append(f"{where}: {key} must be the name of a "
                                f"{'frame' if key == 'frame' else 'point'} (got {describe(p[key])})")
                ok = False
        if ok:
            points.append(Point(p["name"], p["position"], p.get("frame", FIXED), p.get("from", ORIGIN)))
    return tuple(frames), tuple(points)


class _ConstraintSpec(dict):
    def build(self) -> Constraint:
        return Constraint(self["name"], self["expr"], self["kind"], self["unilateral"],
                          self["reaction"], self["transform"], restitution=self["restitution"],
                          losses=self["losses"], root=self["root"], cost=self["cost"])


def _array_of_tables(data: dict, key: str, problems: list[str]) -> list[dict]:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        problems.append(f"[[{key}]]: must be an array of tables ([[{key}]] blocks)")
        return []
    return value
