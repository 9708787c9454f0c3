"""Model files (TOML) -> :class:`~nonideal.model.Model`.

The format is the one of the SPEC (``format = 1``), extended -- never broken -- with:

* ``[[bodies]]`` (``type = "particle" | "planar" | "rigid"``) and ``[gravity] vector`` to
  assemble the kinetic and potential energy from geometry;
* ``[[loads]]`` (``type = "force" | "torque"``) turned into generalized forces;
* ``restitution`` for unilateral constraints (impact law; 0 = plastic, the default);
* contacts: ``friction = "coulomb" | "regularized" | "linearized"``, ``eps``,
  ``restitution``, ``bilateral``;
* ``[forms] independent`` -- independent coordinates for the reduced forms;
* ``[parameters]`` values may be tables ``{value, unit, description}``.

Every key is checked; unknown keys are rejected with a suggestion, and every problem in the
file is reported at once with the file name.  Expressions go through the safe parser only.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from .bodies import Force, Particle, PlanarBody, RigidBody, Torque
from .contacts import Contact, Coulomb, LinearizedCoulomb, Newton, Plastic, RegularizedCoulomb
from .errors import ModelError, did_you_mean
from .model import Constraint, Model, SimulationSettings

__all__ = ["load_model", "model_from_dict", "FORMAT_VERSION"]

FORMAT_VERSION = 1

TOP_KEYS = {"model", "parameters", "coordinates", "energy", "forces", "bodies", "gravity", "loads",
            "constraints", "contacts", "initial", "simulation", "forms"}
SECTION_KEYS = {
    "model": {"name", "format", "description", "source"},
    "coordinates": {"q"},
    "energy": {"kinetic", "potential"},
    "gravity": {"vector"},
    "simulation": {"t_end", "rtol", "atol", "method", "max_step", "t0"},
    "forms": {"independent"},
}
CONSTRAINT_KEYS = {"name", "type", "expr", "reaction", "transform", "unilateral", "restitution",
                   "description"}
CONTACT_KEYS = {"name", "gap", "slip", "mu", "mu_static", "friction", "eps", "restitution",
                "bilateral", "description"}
BODY_KEYS = {
    "particle": {"type", "name", "mass", "position"},
    "planar": {"type", "name", "mass", "inertia", "position", "angle"},
    "rigid": {"type", "name", "mass", "inertia", "position", "rotation"},
}
LOAD_KEYS = {
    "force": {"type", "name", "point", "force"},
    "torque": {"type", "name", "torque", "angle", "body"},
}
FRICTION_LAWS = ("coulomb", "regularized", "linearized")


def load_model(path: str | Path) -> Model:
    """Read and validate a model file.

    Raises
    ------
    ModelError
        With the file name, the key and the fix, for every problem found.
    """
    path = Path(path)
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ModelError(f"model file not found: {source}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"cannot read the model file: {exc}", source) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(f"not valid TOML: {exc}", source) from None
    return model_from_dict(data, source, default_name=path.stem)


def _unknown(keys, allowed, where: str) -> list[str]:
    out = []
    for k in keys:
        if k not in allowed:
            out.append(f"{where}: unknown key '{k}'{did_you_mean(str(k), allowed)}; allowed: "
                       + ", ".join(sorted(allowed)))
    return out


def model_from_dict(data: dict[str, Any], source: str = "<dict>", default_name: str = "model") -> Model:
    """Build a :class:`Model` from the parsed TOML structure (see :func:`load_model`)."""
    problems: list[str] = []
    problems += _unknown(data, TOP_KEYS, "top level")
    for section, allowed in SECTION_KEYS.items():
        if section in data:
            if not isinstance(data[section], dict):
                problems.append(f"[{section}]: must be a table")
            else:
                problems += _unknown(data[section], allowed, f"[{section}]")
    header = data.get("model", {}) if isinstance(data.get("model", {}), dict) else {}
    fmt = header.get("format", FORMAT_VERSION)
    if fmt != FORMAT_VERSION:
        problems.append(f"[model] format: this version reads format {FORMAT_VERSION} (got {fmt!r})")
    coords = data.get("coordinates", {}).get("q") if isinstance(data.get("coordinates"), dict) else None
    if coords is None:
        problems.append('[coordinates] q: missing; list the generalized coordinates, e.g. q = ["x", "theta"]')
    elif not isinstance(coords, list) or not all(isinstance(c, str) for c in coords):
        problems.append("[coordinates] q: must be a list of names")
    params = data.get("parameters", {})
    if not isinstance(params, dict):
        problems.append("[parameters]: must be a table of name = value")
        params = {}
    for name, value in params.items():
        if isinstance(value, dict):
            problems += _unknown(value, {"value", "unit", "description"}, f"[parameters] {name}")
            if "value" not in value:
                problems.append(f"[parameters] {name}: missing 'value'")
    energy = data.get("energy", {}) if isinstance(data.get("energy", {}), dict) else {}
    forces = data.get("forces", {})
    if not isinstance(forces, dict):
        problems.append("[forces]: must be a table coordinate = expression")
        forces = {}

    constraints = []
    for k, c in enumerate(_array_of_tables(data, "constraints", problems)):
        where = f"[[constraints]] #{k + 1}" + (f" '{c.get('name')}'" if "name" in c else "")
        problems += _unknown(c, CONSTRAINT_KEYS, where)
        missing = [key for key in ("name", "expr") if key not in c]
        if missing:
            problems.append(f"{where}: missing {', '.join(missing)}")
            continue
        restitution = c.get("restitution", 0.0)
        if not isinstance(restitution, (int, float)) or not 0 <= restitution <= 1:
            problems.append(f"{where}: restitution must be a number in [0, 1]")
            restitution = 0.0
        constraints.append(_ConstraintSpec(
            name=c["name"], expr=c["expr"], kind=c.get("type", "auto"),
            unilateral=bool(c.get("unilateral", False)),
            reaction=tuple(c["reaction"]) if "reaction" in c else None,
            transform=tuple(tuple(r) for r in c["transform"]) if "transform" in c else None,
            restitution=float(restitution)))

    contacts = []
    for k, c in enumerate(_array_of_tables(data, "contacts", problems)):
        where = f"[[contacts]] #{k + 1}" + (f" '{c.get('name')}'" if "name" in c else "")
        problems += _unknown(c, CONTACT_KEYS, where)
        missing = [key for key in ("name", "gap", "slip") if key not in c]
        if missing:
            problems.append(f"{where}: missing {', '.join(missing)}")
            continue
        law = c.get("friction", "coulomb")
        if law not in FRICTION_LAWS:
            problems.append(f"{where}: friction '{law}' unknown{did_you_mean(str(law), FRICTION_LAWS)}; "
                            "use coulomb, regularized or linearized")
            continue
        mu = c.get("mu", 0)
        if law == "coulomb":
            friction = Coulomb(mu, c.get("mu_static"))
        else:
            if "eps" not in c:
                problems.append(f"{where}: the {law} friction law needs 'eps' (m/s)")
                continue
            friction = (RegularizedCoulomb if law == "regularized" else LinearizedCoulomb)(mu, c["eps"])
        e = c.get("restitution", 0.0)
        impact = Plastic() if not e else Newton(e)
        slip = c["slip"]
        contacts.append(Contact(c["name"], c["gap"], tuple(slip) if isinstance(slip, list) else (slip,),
                                friction, impact, bool(c.get("bilateral", False))))

    bodies = []
    for k, b in enumerate(_array_of_tables(data, "bodies", problems)):
        kind = b.get("type", "particle")
        where = f"[[bodies]] #{k + 1}" + (f" '{b.get('name')}'" if "name" in b else "")
        if kind not in BODY_KEYS:
            problems.append(f"{where}: type '{kind}' unknown{did_you_mean(str(kind), BODY_KEYS)}; "
                            "use particle, planar or rigid")
            continue
        problems += _unknown(b, BODY_KEYS[kind], where)
        missing = [key for key in BODY_KEYS[kind] - {"type"} if key not in b]
        if missing:
            problems.append(f"{where}: missing {', '.join(sorted(missing))}")
            continue
        if kind == "particle":
            bodies.append(Particle(b["name"], b["mass"], b["position"]))
        elif kind == "planar":
            bodies.append(PlanarBody(b["name"], b["mass"], b["inertia"], b["position"], b["angle"]))
        else:
            bodies.append(RigidBody(b["name"], b["mass"], b["inertia"], b["position"], b["rotation"]))

    loads = []
    for k, ld in enumerate(_array_of_tables(data, "loads", problems)):
        kind = ld.get("type", "force")
        where = f"[[loads]] #{k + 1}" + (f" '{ld.get('name')}'" if "name" in ld else "")
        if kind not in LOAD_KEYS:
            problems.append(f"{where}: type '{kind}' unknown; use force or torque")
            continue
        problems += _unknown(ld, LOAD_KEYS[kind], where)
        if kind == "force":
            missing = [key for key in ("name", "point", "force") if key not in ld]
            if missing:
                problems.append(f"{where}: missing {', '.join(missing)}")
                continue
            loads.append(Force(ld["name"], ld["point"], ld["force"]))
        else:
            if "name" not in ld or "torque" not in ld:
                problems.append(f"{where}: missing name or torque")
                continue
            loads.append(Torque(ld["name"], ld["torque"], ld.get("angle"), ld.get("body")))

    sim = data.get("simulation", {}) if isinstance(data.get("simulation", {}), dict) else {}
    t0 = sim.get("t0", 0.0)
    settings = {k: v for k, v in sim.items() if k != "t0"}
    initial = data.get("initial", {})
    if not isinstance(initial, dict):
        problems.append("[initial]: must be a table name = value")
        initial = {}
    forms = data.get("forms", {}) if isinstance(data.get("forms", {}), dict) else {}
    gravity = data.get("gravity", {}).get("vector") if isinstance(data.get("gravity"), dict) else None
    if problems:
        raise ModelError(problems, source)
    try:
        sim_settings = SimulationSettings(**settings)
    except TypeError as exc:  # pragma: no cover - keys already checked
        raise ModelError(f"[simulation]: {exc}", source) from None
    try:
        return Model(
            name=header.get("name", default_name),
            description=header.get("description", ""),
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
            independent=tuple(forms["independent"]) if "independent" in forms else None,
            simulation=sim_settings,
            source=source,
        )
    except ModelError as exc:
        raise exc.with_source(source) if exc.source is None else exc


class _ConstraintSpec(dict):
    def __init__(self, **kw):
        super().__init__(**kw)

    def build(self) -> Constraint:
        return Constraint(self["name"], self["expr"], self["kind"], self["unilateral"],
                          self["reaction"], self["transform"], restitution=self["restitution"])


def _array_of_tables(data: dict, key: str, problems: list[str]) -> list[dict]:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        problems.append(f"[[{key}]]: must be an array of tables ([[{key}]] blocks)")
        return []
    return value
