"""The right-hand side of a phase of the hybrid simulation: ``y' = f(t, y)`` with
``y = [q, q', W]`` (the coordinates, the velocities and the works of the active forces, the
reactions, the explicit time dependence, friction and impacts, then of each servo-constraint's
control), for one mode.

Lagrange I (the saddle-point route) evaluates the mode's
:class:`~nonideal.modes.system.ModeSystem` by index, or its compiled
:class:`~nonideal.modes.system.ModeFunction` once the mode has been integrated long enough,
with the powers of the reactions from the same solve; the other routes, and a singular system,
take the general path of :meth:`ModeSolver.accelerations
<nonideal.modes.solver.ModeSolver.accelerations>`.
"""

from __future__ import annotations

import numpy as np

from ..modes.types import SEPARATED, Mode
from ..numeric.kernel import SingularMatrix

__all__ = ["phase_rhs", "saddle_point_rhs", "general_rhs"]


def phase_rhs(sim, mode: Mode):
    """The right-hand side ``f(t, y)`` of a phase in *mode*, ``y = [q, q', W]``.

    Lagrange I evaluates the mode's :class:`~nonideal.modes.system.ModeSystem` (assembled
    by index; the powers of the reactions from the same solve); the other forms, and a
    singular system, take the general path of :meth:`ModeSolver.accelerations`.  A mode
    the native kernel computes takes it once it is loaded (:mod:`nonideal.simulation.fast`).
    """
    if sim.solver.route.saddle_point:
        return sim.fast.rhs(mode, general_rhs(sim, mode)) or saddle_point_rhs(sim, mode)
    return general_rhs(sim, mode)

def saddle_point_rhs(sim, mode: Mode):
    n, solver = sim.n, sim.solver
    system = solver.system(mode)
    general = general_rhs(sim, mode)  # singular: minimum-norm contact forces or a named error

    if not sim.track:
        def fun(t, y):
            try:
                sol = system.solve(solver, t, y, mode)
            except SingularMatrix:
                return general(t, y)
            return np.concatenate((y[n:2 * n], sol[:n]))
        return fun

    # the compiled system, once this mode structure has been integrated long enough
    function = system.specialized(sim.kernel, mode, solver) if solver.specialize else None
    controls = sim.control_rows
    columns = [system.row_col.get(i) for i in controls]
    x = function.inputs(solver, mode) if function else None

    def fun(t, y):
        try:
            out = function.solve_with_powers(solver, x, t, y, mode) if function else None
            if out is None:
                out = system.solve_with_powers(solver, t, y, mode)
        except SingularMatrix:
            return general(t, y)
        sol, P_R, P_f, P = out
        dy = np.empty_like(y)
        dy[:n] = y[n:2 * n]
        dy[n:2 * n] = sol[:n]
        # works: active, reactions, explicit time, friction, impacts (changed at switches)
        dy[2 * n:2 * n + 5] = (0.0, P_R, 0.0, P_f, 0.0) if P is None else (P[0], P_R, P[1], P_f, 0.0)
        if controls:    # each control's power lambda_j B_j . q' (from the same solve)
            powers = solver.column_powers
            dy[2 * n + 5:] = [powers[j] if j is not None else 0.0 for j in columns]
        return dy
    return fun

def general_rhs(sim, mode: Mode):
    n, solver, track = sim.n, sim.solver, sim.track
    kernel = sim.kernel

    if not track:
        def fun(t, y):
            qdd = solver.accelerations(t, y[:n], y[n:2 * n], mode)[0]
            return np.concatenate((y[n:2 * n], qdd))
        return fun

    powers = kernel.has_nc_forces or kernel.explicit_time
    friction = sim.contacts and any(cs.state != SEPARATED for _, cs in mode.contacts)
    controls = sim.control_rows

    def fun(t, y):
        q, qd = y[:n], y[n:2 * n]
        dy = np.empty_like(y)
        dy[:n] = qd
        if friction:
            qdd, values, layout, out, cout = solver.accelerations(t, q, qd, mode)
            if values is None:  # a reduced form: recover the multipliers
                sol = solver.solve(t, q, qd, mode)
                R = sol.M @ sol.qdd - sol.F
                qdd, P_f = sol.qdd, sum(float(cf.F @ cf.U) for cf in sol.contacts.values() if cf.F.size)
            else:
                P_f = solver.friction_power(mode, layout, values, cout)
                R = kernel.mass(out) @ qdd - out["F"]
        else:
            qdd, values, layout, out, cout = solver.accelerations(t, q, qd, mode)
            P_f = 0.0
            R = kernel.mass(out) @ qdd - out["F"] if layout else None
        dy[n:2 * n] = qdd
        # power of the total generalized reaction R = M q'' - F, split into the friction's
        # power on the slips, sum F . U (never positive), and the rest (ideal and servo
        # reactions, and what moving supports put in through friction)
        dy[2 * n + 1] = (R @ qd - P_f) if R is not None else 0.0
        dy[2 * n + 3] = P_f
        dy[2 * n + 4] = 0.0  # impacts change it only at switches
        if powers:
            P = kernel.dynamics(solver.input(t, q, qd))["P"]
            dy[2 * n], dy[2 * n + 2] = P
        else:
            dy[2 * n] = dy[2 * n + 2] = 0.0
        if controls:    # each control's power lambda_j B_j . q'
            sol = solver.solve(t, q, qd, mode, distribute=False)
            dy[2 * n + 5:] = [sol.multiplier(i) * float(sol.B[:, sol.rows.index(i)] @ qd)
                              if i in sol.rows else 0.0 for i in controls]
        return dy
    return fun
