"""The symbolic dynamics shared by every formalism (SymEngine, computed once per model).

For a :class:`~nonideal.model.Model` it builds

* ``T`` (kinetic energy), ``V`` (potential), ``Q_nc`` (non-potential generalized forces);
* the Lagrange operator ``d/dt dT/dq' - dT/dq = M q'' + h`` split into the mass matrix ``M``
  and the velocity terms ``h``;
* ``F = Q_nc - dV/dq - h`` so that the free motion is ``M q'' = F``;
* the acceleration energy ``S`` (Gibbs--Appell), genuinely from the bodies' accelerations
  when the model is built from bodies, else from Appell's identity
  ``dS/dq'' = d/dt dT/dq' - dT/dq`` (``S = q''^T M q''/2 + q''^T h`` up to q''-free terms);
* for every constraint the row of ``G q'' + gamma = 0``, its reaction column and residuals.

Bodies are handled the way Kane does it (no differentiation of T): for a point at
``r(q, t)`` with Jacobian ``J``, ``a = J q'' + a0`` contributes ``m J^T J`` to M and
``m J^T a0`` to h.  This keeps expression size polynomial in the number of bodies.

Symbols: ``q``, ``qd``, ``qdd`` are SymEngine symbols named like the SymPy ones of
:mod:`nonideal.modeling.symbols`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import symengine as se

from ..modeling.bodies import Force, PlanarBody, RigidBody, Torque
from .servo import (control_rows, directions_dependent, quasi_ideal_direction, reach, root_row,
                    shared_rows)
from ..errors import ModelError, SingularSystem
from ..modeling.model import Constraint, Model
from ..modeling.symbols import to_se
from .algebra import count_ops, cross, pythagorean
from .contact_data import ContactData

__all__ = ["Dynamics", "ConstraintRow", "dynamics_of"]

MAX_OPS = 2_000_000  # size guard for symbolic work (count of operations)


@dataclass(frozen=True)
class ConstraintRow:
    """One scalar constraint at acceleration level ``G . q'' + gamma = 0``.

    Attributes
    ----------
    name : str
    G : list of se.Expr, length n_q
    gamma : se.Expr
    B : list of se.Expr, length n_q -- reaction direction (``G`` for an ideal constraint)
    position : se.Expr or None -- f(q, t) for a holonomic constraint
    velocity : se.Expr or None -- df/dt, or phi(q, q', t) for a first-order one
    order : int
    unilateral : bool
    """

    name: str
    G: tuple
    gamma: object
    B: tuple
    position: object
    velocity: object
    order: int
    unilateral: bool
    reaction_kind: str


class Dynamics:
    """Symbolic kernel of a model.  Never mutates the model; every product is cached."""

    def __init__(self, model: Model):
        self.model = model
        self.t = se.Symbol("t")
        self.q = [se.Symbol(s.name) for s in model.q]
        self.qd = [se.Symbol(s.name) for s in model.qd]
        self.qdd = [se.Symbol(s.name) for s in model.qdd]
        self.params = [se.Symbol(n) for n in model.parameters]
        self.n = model.n_q

    # ------------------------------------------------------------ derivatives
    @cached_property
    def _index(self) -> dict:
        """``{symbol: (coordinate index, level)}``, level 0 for q, 1 for q', 2 for q''."""
        out = {}
        for level, syms in enumerate((self.q, self.qd, self.qdd)):
            out.update({s: (k, level) for k, s in enumerate(syms)})
        return out

    def depends(self, expr, level: int = 0) -> list[int]:
        """Sorted indices of the coordinates whose symbols of *level* (0: q, 1: q', 2: q'')
        occur in *expr*: the nonzero columns of its gradient, found in O(size of expr)."""
        index = self._index
        return sorted(k for k, lv in (index.get(s, (-1, -1)) for s in se.sympify(expr).free_symbols)
                      if lv == level)

    def dt(self, expr, with_acceleration: bool = True):
        """Total time derivative of an expression in (q, q', t) [and q'' if present]; with
        ``with_acceleration=False`` without the q'' terms (the acceleration-free part)."""
        expr = se.sympify(expr)
        free = expr.free_symbols
        out = se.diff(expr, self.t) if self.t in free else se.Integer(0)
        # only the symbols that occur (in coordinate order): O(size of expr), not O(n_q)
        for k, level in sorted(self._index[s] for s in free if s in self._index):
            if level == 0:
                out += se.diff(expr, self.q[k]) * self.qd[k]
            elif level == 1 and with_acceleration:
                out += se.diff(expr, self.qd[k]) * self.qdd[k]
        return out

    def jacobian(self, exprs, wrt):
        return [[se.diff(e, v) for v in wrt] for e in exprs]

    def gradient(self, expr, level: int = 0) -> dict:
        """``{k: d expr/d s_k != 0}`` over the symbols ``s_k`` of *level* (0: q, 1: q', 2: q'')
        in *expr*.  Sums term by term, each coordinate through the terms that contain it:
        O(size of expr) for a sum over many bodies (the potential), not O(n_q * size)."""
        expr = se.sympify(expr)
        syms = (self.q, self.qd, self.qdd)[level]
        if isinstance(expr, se.Mul):  # c * (sum): c times the gradient of the sum
            var = [i for i, f in enumerate(expr.args) if self.depends(f, level)]
            s = expr.args[var[0]] if len(var) == 1 else None
            if isinstance(s, se.Add) and len(s.args) > 8:
                c = se.Mul(*[f for i, f in enumerate(expr.args) if i != var[0]])
                return {k: c * d for k, d in self.gradient(s, level).items()}
        terms = expr.args if isinstance(expr, se.Add) else ()
        parts: dict[int, list] = {}
        if len(terms) > 8:
            for term in terms:
                ks = self.depends(term, level)
                if len(ks) > 8:  # a long term itself (c * a sum): its own gradient, recursively
                    for k, d in self.gradient(term, level).items():
                        parts.setdefault(k, []).append(d)
                    continue
                for k in ks:
                    parts.setdefault(k, []).append((term,))
        else:
            parts = {k: [(expr,)] for k in self.depends(expr, level)}
        out = {}
        for k in sorted(parts):  # (term,): to differentiate; else a derivative already
            d = se.diff(se.Add(*[p[0] for p in parts[k] if isinstance(p, tuple)]), syms[k]) \
                + se.Add(*[p for p in parts[k] if not isinstance(p, tuple)])
            if d != 0:
                out[k] = d
        return out

    def sparse_jacobian(self, exprs, level: int = 0) -> list[dict]:
        return [self.gradient(e, level) for e in exprs]  # the nonzero entries of jacobian()

    # ------------------------------------------------------------ bodies
    def _point(self, position):
        """Jacobian J (rows ``{k: dr_i/dq_k}``, nonzero entries only), velocity v, and
        acceleration a = J q'' + a0 of a point r(q, t)."""
        r = [to_se(c) for c in position]
        J = self.sparse_jacobian(r)
        v = [sum((d * self.qd[k] for k, d in J[i].items()), se.Integer(0)) + se.diff(r[i], self.t)
             for i in range(len(r))]
        a0 = [self.dt(vi, with_acceleration=False) for vi in v]
        return r, J, v, a0

    def _angular(self, body: RigidBody):
        """Body-frame angular velocity Omega = Jw q' + Omega_t (its frame's, if given) and its derivative part."""
        R = [[to_se(x) for x in row] for row in body.rotation]
        if body.omega is not None:
            omega = [to_se(x) for x in body.omega]
        else:
            Rdot = [[self.dt(x, with_acceleration=False) for x in row] for row in R]

            def w(i, j):   # W = R^T Rdot (skew); Omega = (W21, W02, W10)
                return sum((R[k][i] * Rdot[k][j] for k in range(3)), se.Integer(0))
            omega = [se.expand(w(2, 1)), se.expand(w(0, 2)), se.expand(w(1, 0))]
        Jw = self.sparse_jacobian(omega, level=1)
        dom0 = [self.dt(o, with_acceleration=False) for o in omega]
        return R, omega, Jw, dom0

    @cached_property
    def _bodies(self):
        """Per-body kinematics, computed once: list of dicts."""
        out = []
        for b in self.model.bodies:
            r, J, v, a0 = self._point(b.position)
            item = {"body": b, "m": to_se(b.mass), "r": r, "J": J, "v": v, "a0": a0}
            if isinstance(b, PlanarBody):
                phi = to_se(b.angle)
                Jp = self.sparse_jacobian([phi])[0]
                omega = sum((d * self.qd[k] for k, d in Jp.items()), se.Integer(0)) + se.diff(phi, self.t)
                item.update(I=to_se(b.inertia), phi=phi, Jp=Jp, omega=omega,
                            eps0=self.dt(omega, with_acceleration=False))
            elif isinstance(b, RigidBody):
                R, omega, Jw, dom0 = self._angular(b)
                item.update(I=[[to_se(x) for x in row] for row in b.inertia], R=R, Omega=omega,
                            Jw=Jw, dOmega0=dom0)
            out.append(item)
        return out

    # ------------------------------------------------------------ energies and forces
    @cached_property
    def kinetic(self):
        """The model's ``kinetic`` plus the regularization ``c/2 (e . e')^2`` of Euler parameters
        (zero on their unit sphere; :mod:`nonideal.modeling.kinematics`)."""
        return to_se(self.model.kinetic) + to_se(self.model.kinematics.regularization(self.model.bodies))

    @cached_property
    def T(self):
        """Kinetic energy (expression plus bodies)."""
        terms = [self.kinetic]   # one sum at the end: adding term by term is O(bodies^2)
        for it in self._bodies:
            terms.append(it["m"] * sum((vi * vi for vi in it["v"]), se.Integer(0)) / 2)
            b = it["body"]
            if isinstance(b, PlanarBody):
                terms.append(it["I"] * it["omega"] ** 2 / 2)
            elif isinstance(b, RigidBody):
                Om, I = it["Omega"], it["I"]
                terms.append(sum((Om[i] * I[i][j] * Om[j] for i in range(3) for j in range(3)), se.Integer(0)) / 2)
        return se.Add(*terms)

    @cached_property
    def V(self):
        """Potential energy (expression plus uniform gravity on the bodies)."""
        terms = [to_se(self.model.potential)]
        if self.model.gravity is not None:
            g = [to_se(c) for c in self.model.gravity]
            for it in self._bodies:
                r = it["r"]
                if len(r) != len(g):
                    raise ModelError(
                        f"body '{it['body'].name}': position has {len(r)} components but "
                        f"[gravity] vector has {len(g)}; give the gravity vector as many "
                        f"components as the positions ({len(r)})", _source(self.model))
                terms.append(-it["m"] * sum((gi * ri for gi, ri in zip(g, r)), se.Integer(0)))
        return se.Add(*terms)

    @cached_property
    def Q_nc(self):
        """Non-potential generalized forces: declared ones plus loads by virtual work."""
        zero = se.Integer(0)
        Q = [to_se(f) if f != 0 else zero for f in self.model.forces]
        bodies = {it["body"].name: it for it in self._bodies}
        for ld in self.model.loads:
            if isinstance(ld, Force):
                r = [to_se(c) for c in ld.point]
                F = [to_se(c) for c in ld.force]
                for k in self.depends(se.Matrix(r)):
                    Q[k] += sum((Fi * se.diff(ri, self.q[k]) for Fi, ri in zip(F, r)), se.Integer(0))
            elif isinstance(ld, Torque) and ld.body is None:
                tau, phi = to_se(ld.torque), to_se(ld.angle)
                for k in self.depends(phi):
                    Q[k] += tau * se.diff(phi, self.q[k])
            elif isinstance(ld, Torque):
                it = bodies[ld.body]
                tau = [to_se(c) for c in ld.torque]
                R, Jw = it["R"], it["Jw"]
                for k in sorted(set().union(*Jw)):
                    w_world = [sum((R[i][j] * Jw[j][k] for j in range(3) if k in Jw[j]), se.Integer(0))
                               for i in range(3)]
                    Q[k] += sum((tau[i] * w_world[i] for i in range(3)), se.Integer(0))
        return Q

    @cached_property
    def dV(self):
        out = [se.Integer(0)] * self.n
        for k, d in self.gradient(self.V).items():
            out[k] = d
        return out

    @cached_property
    def Q(self):
        """All generalized active forces ``Q_nc - dV/dq``."""
        return [a - b for a, b in zip(self.Q_nc, self.dV)]

    # ------------------------------------------------------------ Lagrange operator
    @cached_property
    def _inertia(self):
        """``({(i, j): M_ij != 0}, h)``: each body adds only over the coordinates it depends
        on, so many bodies that each move few coordinates (block-diagonal M) cost O(n_q)."""
        n = self.n
        M: dict[tuple[int, int], object] = {}
        h = [se.Integer(0)] * n

        def add(i, j, value):
            if value == 0:
                return
            M[i, j] = M[i, j] + value if (i, j) in M else value
            if j != i:
                M[j, i] = M[i, j]

        T = self.kinetic
        if T != 0:
            p = [se.Integer(0)] * n
            for i, d in self.gradient(T, 1).items():
                p[i] = d
            dTq = self.gradient(T)
            accelerations = set(self.qdd)
            for i in range(n):
                for j, d in self.gradient(p[i], 1).items():
                    if j >= i:
                        add(i, j, pythagorean(d))
                h[i] = self.dt(p[i], with_acceleration=False) - dTq.get(i, se.Integer(0))
                if not accelerations.isdisjoint(h[i].free_symbols):  # pragma: no cover (O(n), not n^2)
                    raise SingularSystem("kinetic energy contains accelerations")
        for it in self._bodies:
            m, J, a0 = it["m"], it["J"], it["a0"]
            # only the coordinates the body's position depends on contribute (a body among many:
            # its few nonzero columns, not all n^2 pairs)
            moving = sorted(set().union(*J))
            for a, i in enumerate(moving):
                for j in moving[a:]:
                    add(i, j, m * pythagorean(sum((Jd[i] * Jd[j] for Jd in J if i in Jd and j in Jd), se.Integer(0))))
                h[i] += m * sum((Jd[i] * a0[d] for d, Jd in enumerate(J) if i in Jd), se.Integer(0))
            b = it["body"]
            if isinstance(b, PlanarBody):
                I, Jp, eps0 = it["I"], it["Jp"], it["eps0"]
                turning = sorted(Jp)
                for a, i in enumerate(turning):
                    for j in turning[a:]:
                        add(i, j, I * Jp[i] * Jp[j])
                    h[i] += I * Jp[i] * eps0
            elif isinstance(b, RigidBody):
                I, Jw, Om, dOm0 = it["I"], it["Jw"], it["Omega"], it["dOmega0"]
                IOm = [sum((I[r][c] * Om[c] for c in range(3)), se.Integer(0)) for r in range(3)]
                gyro = cross(Om, IOm)
                eul = [sum((I[r][c] * dOm0[c] for c in range(3)), se.Integer(0)) + gyro[r] for r in range(3)]
                turning = sorted(set().union(*Jw))
                for a, i in enumerate(turning):
                    IJ = [sum((I[r][c] * Jw[c][i] for c in range(3) if i in Jw[c]), se.Integer(0))
                          for r in range(3)]
                    for j in turning[a:]:
                        add(i, j, sum((Jw[r][j] * IJ[r] for r in range(3) if j in Jw[r]), se.Integer(0)))
                    h[i] += sum((Jw[r][i] * eul[r] for r in range(3) if i in Jw[r]), se.Integer(0))
        return M, se.Matrix(h)

    @property
    def mass_entries(self) -> dict[tuple[int, int], object]:
        """The nonzero entries ``{(i, j): M_ij}`` of M (both triangles), what is compiled."""
        return self._inertia[0]

    @cached_property
    def M(self) -> se.DenseMatrix:
        """Mass matrix, shape (n_q, n_q) (dense; see :attr:`mass_entries`)."""
        M = se.zeros(self.n, self.n)
        for (i, j), value in self._inertia[0].items():
            M[i, j] = value
        return M

    @property
    def h(self) -> se.DenseMatrix:
        """Velocity terms of the Lagrange operator, shape (n_q, 1)."""
        return self._inertia[1]

    @cached_property
    def F(self) -> se.DenseMatrix:
        """Forcing ``Q_nc - dV/dq - h``, shape (n_q, 1): free motion is ``M q'' = F``."""
        return se.Matrix([self.Q[i] - self.h[i] for i in range(self.n)])

    @cached_property
    def S(self):
        """Acceleration energy (up to terms without accelerations)."""
        n = self.n
        S = se.Integer(0)
        T = self.kinetic
        if T != 0:
            p = [se.diff(T, v) for v in self.qd]
            for i in range(n):
                Li = self.dt(p[i], with_acceleration=True) - se.diff(T, self.q[i])
                # integrate dS/dq''_i = L_i(T) (linear in q''): S = sum_i q''_i (h_i + 1/2 sum_j M_ij q''_j)
                acc_free = Li.subs({a: 0 for a in self.qdd})
                S += self.qdd[i] * (acc_free + (Li - acc_free) / 2)
        for it in self._bodies:
            m, J, a0 = it["m"], it["J"], it["a0"]
            a = [sum((d * self.qdd[k] for k, d in J[i].items()), se.Integer(0)) + a0[i] for i in range(len(J))]
            S += m * sum((ai * ai for ai in a), se.Integer(0)) / 2
            b = it["body"]
            if isinstance(b, PlanarBody):
                eps = sum((d * self.qdd[k] for k, d in it["Jp"].items()), se.Integer(0)) + it["eps0"]
                S += it["I"] * eps * eps / 2
            elif isinstance(b, RigidBody):
                I, Jw, Om, dOm0 = it["I"], it["Jw"], it["Omega"], it["dOmega0"]
                eps = [sum((d * self.qdd[k] for k, d in Jw[r].items()), se.Integer(0)) + dOm0[r] for r in range(3)]
                Ieps = [sum((I[r][c] * eps[c] for c in range(3)), se.Integer(0)) for r in range(3)]
                IOm = [sum((I[r][c] * Om[c] for c in range(3)), se.Integer(0)) for r in range(3)]
                gyro = cross(Om, IOm)
                S += sum((eps[r] * Ieps[r] for r in range(3)), se.Integer(0)) / 2
                S += sum((eps[r] * gyro[r] for r in range(3)), se.Integer(0))
        return S

    @cached_property
    def T0(self):
        """Kinetic energy at zero velocities (the T0 term of T = T2 + T1 + T0)."""
        return self.T.subs({v: 0 for v in self.qd})

    # ------------------------------------------------------------ constraints
    def constraint_row(self, c: Constraint) -> ConstraintRow:
        return self._rows[c.name]

    @cached_property
    def _rows(self) -> dict[str, ConstraintRow]:
        out = {}
        for c in self.model.constraints:
            if c.root is None:
                out[c.name] = self._row(c)
        for name, (row, _) in self.control_rows.items():
            out[name] = row
        out.update(zip(self.shared_rows[0], self.shared_rows[1]))
        for name in self.servo_reach:
            out[name] = self.servo_reach[name].row
        for name, (row, _, _) in self.root_rows.items():
            out[name] = row
        return out

    @cached_property
    def control_rows(self) -> dict:
        """``{name: (row, coefficients)}`` for every servo-constraint with several control
        directions (Béghin's r < j; :func:`~nonideal.equations.servo.control_rows`)."""
        return control_rows(self, self._row, ConstraintRow)

    @cached_property
    def shared_rows(self) -> tuple:
        """``(names, rows, C)`` of the programs realized by the shared controls (``[[controls]]``;
        :func:`~nonideal.equations.servo.shared_rows`)."""
        return shared_rows(self, self._row, ConstraintRow)

    @cached_property
    def root_rows(self) -> dict:
        """``{name: (row, discriminant, multiplier)}`` for every second-order constraint
        nonlinear in the accelerations: its row at the root chosen by its ``root`` rule, the
        discriminant that must stay positive, and the multiplier as a function of the state."""
        out = {}
        for c in self.model.constraints:
            if c.root is None:
                continue
            others = [self._row(o) for o in self.model.constraints
                      if o.name != c.name and o.root is None and not o.unilateral]
            make = lambda name, G, gamma, B: ConstraintRow(name, G, gamma, B, None, None, 2, False, "servo")
            out[c.name] = root_row(self, c.name, to_se(c.expr), [to_se(r) for r in c.reaction],
                                   c.root, others, make)
        return out

    @cached_property
    def servo_reach(self) -> dict:
        """``{name: ServoReach}`` for every servo-constraint: the order of the derivative of the
        program in which its control appears, the conditions of dynamics that hold along the
        motion, and the row that stands for the program in the equations of motion (the program
        itself when its control appears at acceleration level)."""
        out = {}
        if self.model.contacts or not any(c.reaction is not None and c.root is None
                                          for c in self.model.constraints):
            # (a contact's normal force and friction can carry the control to the program in
            # ways this analysis of the bilateral rows does not see: keep the programs as given)
            return out
        base = {c.name: self._row(c) for c in self.model.constraints if c.root is None}
        base.update({name: row for name, (row, _) in self.control_rows.items()})
        base.update(zip(self.shared_rows[0], self.shared_rows[1]))
        single = [base[c.name] for c in self.model.constraints
                  if c.reaction is not None and c.root is None]
        if directions_dependent(self, single):
            return out          # r > j: Beghin's count, reported by the diagnosis of the system
        for c in self.model.constraints:
            if c.reaction is None or c.root is not None:
                continue
            others = [r for name, r in base.items() if name != c.name and not r.unilateral]
            out[c.name] = reach(self, base[c.name], others, self._condition_row)
        return out

    def servo_conditions(self) -> list:
        """The conditions that hold along the motion besides the rows (programs whose control
        acts through the dynamics, and their intermediate conditions of dynamics)."""
        return [k for r in self.servo_reach.values() for k in r.conditions]

    def _condition_row(self, name: str, expr, order: int, B) -> ConstraintRow:
        """A servo row for a condition of dynamics ``expr(q, q', t) = 0`` (order 1) or
        ``expr(q, t) = 0`` (order 0) realized by the control direction ``B``."""
        if order == 0:
            G = [se.diff(expr, qk) for qk in self.q]
            vel = self.dt(expr, with_acceleration=False)
            gamma = self.dt(vel, with_acceleration=False)
            position = expr
        else:
            G = [se.diff(expr, v) for v in self.qd]
            gamma = self.dt(expr, with_acceleration=False)
            vel, position = expr, None
        return ConstraintRow(name, tuple(G), gamma, tuple(B), position, vel, order, False, "servo")

    def _row(self, c: Constraint) -> ConstraintRow:
        if c.order >= 3:
            what = "third order" if c.order == 3 else f"order {c.order}"
            raise ModelError(f"constraint '{c.name}' is of {what}: the force that realizes it is part of "
                             "the state, and this analysis works with states (q, q') only; simulate, check, "
                             "evaluate and derive handle it", _source(self.model))
        expr = to_se(c.expr)
        if c.order == 0:
            G = self._sparse_gradient(expr, 0)
            vel = self.dt(expr, with_acceleration=False)
            gamma = self.dt(vel, with_acceleration=False)
            position = expr
        elif c.order == 1:
            G = self._sparse_gradient(expr, 1)
            gamma = self.dt(expr, with_acceleration=False)
            vel, position = expr, None
        else:
            G = [se.diff(expr, a) for a in self.qdd]
            gamma = expr.subs({a: 0 for a in self.qdd})
            vel = position = None
        if c.reaction is not None:
            B = [to_se(r) for r in c.reaction]
        elif c.transform is not None:
            B = quasi_ideal_direction([[to_se(x) for x in row] for row in c.transform], G)
            if all(b == 0 for b in B):
                raise SingularSystem(f"constraint '{c.name}': transform matrix is singular and "
                                     "adj(A) grad f = 0 identically, so A R = lambda grad f does not "
                                     "fix the reaction; the transform must be an invertible n x n "
                                     "matrix", _source(self.model))
        else:
            B = list(G)
        return ConstraintRow(c.name, tuple(G), gamma, tuple(B), position, vel, c.order,
                             c.unilateral, c.reaction_kind)

    def _sparse_gradient(self, expr, level: int) -> list:
        """``[d expr / d s_k]`` over the symbols of *level* (0: q, 1: q'), differentiating only
        by the symbols that occur: O(size of expr), not O(n_q) derivatives per constraint (a
        chain of 1000 knife edges: 3000 x 1000 derivatives)."""
        zero = se.Integer(0)
        syms = (self.q, self.qd)[level]
        free = expr.free_symbols
        return [se.diff(expr, v) if v in free else zero for v in syms]

    def rows(self, names=None) -> list[ConstraintRow]:
        """Constraint rows in model order, restricted to *names* if given."""
        return [self._rows[c.name] for c in self.model.constraints if names is None or c.name in names]

    # ------------------------------------------------------------ contacts
    @cached_property
    def contacts(self) -> list[ContactData]:
        """Symbolic data of every contact (gap row, slip rows, friction coefficients), then of
        every friction torque as a contact of its own that shares its contact's gap and normal
        force (``parent``): its "slip" the angular velocity, its coefficient the length."""
        from ..modeling.contacts import Coulomb, torques

        data = [self._contact(c.name, c.gap, c.slip, c.friction, c) for c in self.model.contacts]
        for k, c in enumerate(self.model.contacts):
            data += [self._contact(name, c.gap, rows, Coulomb(length), c, parent=k)
                     for name, rows, length in torques(c)]
        return data

    def _contact(self, name, gap, slip, law, c, parent=None) -> ContactData:
        from ..modeling.contacts import Coulomb

        g = to_se(gap)
        Gn = tuple(se.diff(g, qk) for qk in self.q)
        gdot = self.dt(g, with_acceleration=False)
        gamma_n = self.dt(gdot, with_acceleration=False)
        U = tuple(to_se(u) for u in slip)
        W = tuple(tuple(se.diff(u, v) for v in self.qd) for u in U)
        gamma_U = tuple(self.dt(u, with_acceleration=False) for u in U)
        mu = to_se(law.mu)
        mu_s = to_se(law.mu_static if law.mu_static is not None else law.mu) if isinstance(law, Coulomb) else mu
        return ContactData(name, g, gdot, Gn, gamma_n, U, W, gamma_U, mu, mu_s, law,
                           c.bilateral, float(c.impact.restitution), parent)

    def contact_rows(self, index: int, state: str, sigma: int = 1, direction=None) -> list[ConstraintRow]:
        """Symbolic constraint rows of contact *index* in a contact *state*.

        ``"stick"``: the gap row (ideal, multiplier N) and one ideal nonholonomic row per slip
        component (multiplier = friction force component).  ``"slide"``: the gap row whose
        reaction carries the friction ``B = dg/dq - sigma mu sum_k W_k s_k`` with the slip
        direction ``s`` given by *direction* (numbers for one component, or symbols named
        ``s[name,k]`` supplied at evaluation).  ``"separated"``: no row.
        """
        cd = self.contacts[index]
        if state == "separated":
            return []
        gap = ConstraintRow(cd.name, cd.Gn, cd.gamma_n, cd.Gn, cd.gap, cd.gap_rate, 0,
                            not cd.bilateral, "ideal")
        if state == "stick":
            rows = [gap]
            for k in range(len(cd.U)):
                rows.append(ConstraintRow(f"{cd.name}_t{k + 1}" if len(cd.U) > 1 else f"{cd.name}_t",
                                          cd.W[k], cd.gamma_U[k], cd.W[k], None, cd.U[k], 1, False, "ideal"))
            return rows
        if direction is None:
            direction = [se.Symbol(f"s[{cd.name},{k + 1}]") for k in range(len(cd.U))]
        B = tuple(cd.Gn[j] - sigma * cd.mu * sum((cd.W[k][j] * direction[k] for k in range(len(cd.U))),
                                                se.Integer(0)) for j in range(self.n))
        return [ConstraintRow(cd.name, cd.Gn, cd.gamma_n, B, cd.gap, cd.gap_rate, 0,
                              not cd.bilateral, "friction")]


def _source(model: Model) -> str | None:
    """The model file to name in an error (None for a model built in Python)."""
    return None if model.source == "<api>" else model.source


def dynamics_of(model: Model) -> Dynamics:
    """The (cached) symbolic dynamics of *model*.  Models are immutable, so caching is safe."""
    return model.cached("dynamics", lambda: Dynamics(model))
