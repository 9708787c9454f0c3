"""The user's declaration of a mechanical system: :class:`Model` (immutable once built).

A model holds coordinates, parameters, the kinetic energy (an expression, bodies, or both),
the potential energy, generalized forces and loads, constraints and contacts, an initial state
and simulation settings.  Expressions may be given as strings (parsed by the safe parser of
:mod:`nonideal.modeling.expressions`) or as SymPy expressions -- including
``sympy.physics.mechanics.dynamicsymbols`` -- and are normalized to plain SymPy symbols named
``x``, ``x'``, ``x''`` (see :mod:`nonideal.modeling.symbols`).

Everything that can be checked without mechanics is checked here, and every problem is
reported at once (:class:`~nonideal.errors.ModelError`).

Examples
--------
>>> from nonideal import Model, Constraint
>>> m = Model(
...     name="particle on a rotating line",
...     coordinates=["x", "y"],
...     parameters={"m": 1.0, "w": 2.0},
...     kinetic="m/2*(x'^2 + y'^2)",
...     constraints=[Constraint.holonomic("line", "y*cos(w*t) - x*sin(w*t)")],
...     initial={"x": 1.0, "y": 0.0, "x'": 0.0},
... )
>>> m.n_q, [c.kind for c in m.constraints]
(2, ['holonomic'])
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp

from .contacts import Contact
from ..errors import ModelError, did_you_mean
from .symbols import coordinate_symbols, t

from .declarations import RESERVED_NAMES, Constraint, Control, Parameter, SimulationSettings, split_problems
from .normalize import Normalizer
from .units import Units, units_of
from .expressions import float_value
from .values import resolve_parameters, to_expr

__all__ = ["Parameter", "Constraint", "SimulationSettings", "Model", "RESERVED_NAMES",
           "resolve_parameters"]


class FrozenMapping(Mapping):
    """A read-only view of a model's mapping (its parameters, initial values, forces): a
    Model is immutable, and what later stages derived from it stays valid.

    Examples
    --------
    >>> view = FrozenMapping("initial", {"th": 0.5})
    >>> view["th"] = 1.0
    Traceback (most recent call last):
    ...
    TypeError: a Model is immutable: its initial cannot be changed in place; use model.replace(initial={...}) for a new model, or simulate(model, initial={...}) for one run
    """

    __slots__ = ("_name", "_data")

    def __init__(self, name: str, data: Mapping):
        self._name, self._data = name, dict(data)

    def __getitem__(self, key):
        return self._data[key]

    def __iter__(self):
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __repr__(self) -> str:
        return repr(self._data)

    def __getstate__(self):
        return (self._name, self._data)

    def __setstate__(self, state):
        self._name, self._data = state

    def copy(self) -> dict:
        return dict(self._data)

    def _refuse(self, *args, **kwargs):
        run = f", or simulate(model, {self._name}={{...}}) for one run" \
            if self._name in ("initial", "parameters") else ""
        raise TypeError(f"a Model is immutable: its {self._name} cannot be changed in place; use "
                        f"model.replace({self._name}={{...}}) for a new model{run}")

    __setitem__ = __delitem__ = update = pop = popitem = clear = setdefault = _refuse


@dataclass(frozen=True)
class Model:
    """A mechanical system as the user declared it.

    Parameters
    ----------
    name : str
    coordinates : sequence of str
        Names of the generalized coordinates (functions of time).
    parameters : mapping name -> number or :class:`Parameter`
    kinetic : expression, optional
        Kinetic energy in the coordinates, their velocities (``x'``) and time.
    potential : expression, optional
    forces : mapping coordinate -> expression, optional
        Extra (non-potential) generalized forces.
    bodies : sequence of Particle, PlanarBody, RigidBody
        Added to ``kinetic``.
    loads : sequence of Force, Torque
        Added to ``forces`` by virtual work.
    gravity : sequence of expressions, optional
        Uniform gravity vector; adds ``-sum m g . r`` over the bodies to the potential.
    constraints : sequence of Constraint
    contacts : sequence of Contact
    speeds : mapping name -> expression, optional
        Generalized speeds (quasi-velocities), each linear in the velocities; together with the
        derivatives of the holonomic constraints they must determine every velocity.  Their
        names may be used in every other expression (:mod:`nonideal.modeling.speeds`).
    outputs : mapping name -> expression, optional
        Named quantities reported along a simulation (may use the speeds, ``T``, ``V`` and the
        multipliers ``lambda_<constraint>``).
    controls : sequence of Control, optional
        Controls shared by the servo-constraints declared without ``reaction`` (Béghin 1922:
        r programs, j controls; impossible if r > j, the least-cost controls if r < j).
    initial : mapping
        Coordinate and velocity (``"x'"``) values at ``t0``; numbers or expressions in the
        parameters.  Missing dependent values are completed from the constraints.
    t0 : float
    independent : sequence of str, optional
        Coordinates whose velocities are kept as independent by the reduced forms (Maggi,
        Appell, Shulgin) and coordinates kept by Lagrange II.
    simulation : SimulationSettings or mapping
    source : str
        Where the model came from (a file name), used in error messages.
    description : str
    units : Units or mapping, optional
        Declared units (``length``, ``mass``, ``time``, ``angle``, ``coordinates``: the kind
        or unit of a coordinate), for labels and outputs only (:mod:`nonideal.modeling.units`).
    frames : sequence of Frame, optional
        Reference frames rotated from their parents (:mod:`nonideal.modeling.frames`).
    points : sequence of Point, optional
        Points placed from other points (:mod:`nonideal.modeling.points`).  Frames and points
        are usable in every expression through the vector functions (``omega(B)``,
        ``vel(P)``, ``dot(a, b)`` ...; :attr:`kinematics`).
    members : sequence of Member, optional
        Elastic beams, rods and shafts expanded in Bubnov–Galerkin shape functions
        (:mod:`nonideal.modeling.members`).  They are expanded at construction: their amplitudes
        are appended to :attr:`coordinates`, their points to :attr:`points`, their energies
        added to :attr:`kinetic` and :attr:`potential`; :attr:`elastic_members` lists them
        afterwards and ``members`` is empty (so :meth:`replace` does not add them twice).
    """

    name: str
    coordinates: tuple[str, ...]
    parameters: Mapping[str, Parameter] = field(default_factory=dict)
    kinetic: Any = 0
    potential: Any = 0
    forces: Any = field(default_factory=dict)
    bodies: tuple[Any, ...] = ()
    loads: tuple[Any, ...] = ()
    gravity: tuple[Any, ...] | None = None
    constraints: tuple[Constraint, ...] = ()
    contacts: tuple[Contact, ...] = ()
    initial: Mapping[str, Any] = field(default_factory=dict)
    t0: float = 0.0
    independent: tuple[str, ...] | None = None
    simulation: SimulationSettings = field(default_factory=SimulationSettings)
    source: str = "<api>"
    description: str = ""
    units: Units | Mapping[str, Any] | None = None
    controls: tuple[Control, ...] = ()
    frames: tuple[Any, ...] = ()
    points: tuple[Any, ...] = ()
    speeds: Mapping[str, Any] = field(default_factory=dict)
    outputs: Mapping[str, Any] = field(default_factory=dict)
    members: tuple[Any, ...] = ()

    # ------------------------------------------------------------------ construction
    def __post_init__(self):
        problems: list[str] = []
        Normalizer(self, problems).run()
        if not problems:
            problems += split_problems(self.simulation, [c.name for c in self.constraints],
                                       [c.name for c in self.contacts])
        units, more = units_of(self.units, self.coordinates)
        object.__setattr__(self, "units", units)
        for name in ("parameters", "initial", "forces"):  # read-only: the model is immutable
            if isinstance(getattr(self, name), Mapping):
                object.__setattr__(self, name, FrozenMapping(name, getattr(self, name)))
        problems += more
        if problems:
            raise ModelError(problems, None if self.source == "<api>" else self.source)

    @property
    def kinematics(self):
        """The frames and points with their derived rotations, angular velocities, positions,
        velocities and accelerations (:class:`~nonideal.modeling.kinematics.Kinematics`)."""
        return self.__dict__["_kinematics"]

    def cached(self, key, build: Callable[[], Any]) -> Any:
        """``build()``, once per model and *key*: the one cache of what later stages derive
        from a model (its dynamics, compiled kernels, mode systems, compiled forms, states
        already checked).  A model is immutable, so what is derived from it stays valid; it
        lives as long as the model, and a changed model (:meth:`replace`) starts empty."""
        cache = self.__dict__.setdefault("_derived", {})
        try:
            return cache[key]
        except KeyError:
            value = cache[key] = build()
            return value

    def clear_cache(self) -> None:
        """Forget what was derived from this model (benchmarks of cold runs)."""
        self.__dict__.pop("_derived", None)

    def __getstate__(self):
        # compiled callables are not pickled: a model sent to another process derives anew
        state = dict(self.__dict__)
        state.pop("_derived", None)
        return state

    def replace(self, **changes) -> "Model":
        """A new model with some fields changed (the model itself never changes)."""
        new = replace(self, **changes)
        if "members" not in changes and "_members" in self.__dict__:
            new.__dict__["_members"] = self.__dict__["_members"]
        return new

    @property
    def elastic_members(self) -> tuple:
        """The elastic members the model was built with (:class:`~nonideal.modeling.members.Member`)."""
        return self.__dict__.get("_members", ())

    # ------------------------------------------------------------------ symbols
    @property
    def n_q(self) -> int:
        return len(self.coordinates)

    @property
    def q(self) -> tuple[sp.Symbol, ...]:
        return self._symbols()[0]

    @property
    def qd(self) -> tuple[sp.Symbol, ...]:
        return self._symbols()[1]

    @property
    def qdd(self) -> tuple[sp.Symbol, ...]:
        return self._symbols()[2]

    def _symbols(self):
        """``(q, qd, qdd)``, made once per model (the normalization asks for them often)."""
        hit = self.__dict__.get("_coordinate_symbols")
        if hit is None or hit[0] != self.coordinates:
            hit = (self.coordinates, coordinate_symbols(self.coordinates))
            self.__dict__["_coordinate_symbols"] = hit
        return hit[1]

    @property
    def parameter_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(sp.Symbol(n) for n in self.parameters)

    @property
    def parameter_values(self) -> dict[str, float]:
        return {n: p.value for n, p in self.parameters.items()}

    def constraint(self, name: str) -> Constraint:
        for c in self.constraints:
            if c.name == name:
                return c
        raise ModelError(
            f"no constraint named '{name}'"
            + did_you_mean(name, [c.name for c in self.constraints])
        )

    @property
    def velocity_names(self) -> tuple[str, ...]:
        return tuple(n + "'" for n in self.coordinates)

    # ------------------------------------------------------------------ parsing helpers
    def names(self, order: int = 1, time: bool = True) -> dict[str, sp.Expr]:
        """Names usable in an expression: parameters, coordinates, derivatives up to *order*."""
        q, qd, qdd = self._symbols()
        out: dict[str, sp.Expr] = {n: sp.Symbol(n) for n in self.parameters}
        out.update({s.name: s for s in q})
        if order >= 1:
            out.update({s.name: s for s in qd})
        if order >= 2:
            out.update({s.name: s for s in qdd})
        if order >= 3:  # third derivatives: a constraint's expr only
            out.update({s.name + "'": sp.Symbol(s.name + "'") for s in qdd})
        if time:
            out["t"] = t
        if order >= 1 and self.__dict__.get("_speeds_ready"):
            out.update(self.speeds)   # a speed name stands for its definition
        return out

    def parse(self, text: Any, where: str, order: int = 1) -> sp.Expr:
        """Parse a string (safely) or normalize a SymPy expression of this model."""
        return to_expr(text, self.names(order), where, self.coordinates, self.kinematics)

    def numeric_initial(self) -> dict[str, float]:
        """The initial values given, evaluated with the parameter values (computed once: the
        model is immutable)."""
        cached = self.__dict__.get("_numeric_initial")
        if cached is None:
            values = {n: float(p.value) for n, p in self.parameters.items()}
            cached = {key: float_value(expr, f"[initial] {key}", values) for key, expr in self.initial.items()}
            self.__dict__["_numeric_initial"] = cached
        return dict(cached)

    # ------------------------------------------------------------------ Jupyter
    def _latex_rows(self) -> list[str]:
        from .symbols import latex_names

        def tex(expr) -> str:
            expr = sp.sympify(expr)
            return sp.latex(expr, symbol_names=latex_names(expr.free_symbols))

        rows = []
        if self.kinetic != 0:
            rows.append("T &= " + tex(self.kinetic))
        if self.potential != 0:
            rows.append("V &= " + tex(self.potential))
        for c in self.constraints:
            rows.append(tex(c.expr) + (r" &\ge 0" if c.unilateral else " &= 0")
                        + rf"\quad\text{{({c.name}, {c.kind})}}")
        for c in self.contacts:
            rows.append(tex(c.gap) + rf" &\ge 0\quad\text{{(contact {c.name})}}")
        return rows

    def _repr_latex_(self) -> str:
        """Jupyter: the declared energy, constraints (``= 0``) and contact gaps (``>= 0``)."""
        rows = self._latex_rows() or [r"\text{(energy from the bodies)}"]
        return "$$\\begin{aligned}\n" + " \\\\\n".join(rows) + "\n\\end{aligned}$$"

    def _repr_html_(self) -> str:
        """Jupyter: name, coordinates, parameters, bodies, constraints and contacts."""
        from html import escape

        params = ", ".join(f"{escape(k)} = {p.value:g}" + (f" {escape(p.unit)}" if p.unit else "")
                           + (f" ({escape(p.given)})" if p.given else "")
                           for k, p in self.parameters.items())
        items = [f"<b>{escape(self.name)}</b>",
                 f"coordinates: {escape(', '.join(self.coordinates))}",
                 f"parameters: {params or '(none)'}"]
        if self.bodies:
            items.append("bodies: " + escape(", ".join(f"{b.name} ({type(b).__name__})" for b in self.bodies)))
        items.append(f"constraints: {len(self.constraints)}, contacts: {len(self.contacts)}")
        return "<div>" + "<br>".join(items) + "<br>" + self._repr_latex_() + "</div>"
