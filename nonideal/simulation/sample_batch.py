"""The samples of one mode solved natively at once, read as arrays.

A run's output holds, besides the states, the motion at every sample: accelerations,
multipliers, each contact's forces and slip.  The samples the integrator has no motion for
(the output grid's, a native phase's steps) are solved natively all at once per mode
(:meth:`~nonideal.simulation.fast_contacts.FastContacts.sample_motions`); a
:class:`SampleBatch` holds those solutions and gives the trajectory's columns for many samples
in one NumPy operation each, as :meth:`~nonideal.modes.motion.Motion.contact_record` gives
them for one (the test suite checks that they agree).  A mode solved natively has independent
rows (no statically indeterminate reactions) and contacts that are separated, stick or slide.
"""

from __future__ import annotations

import numpy as np

from ..modes.motion import Motion
from ..modes.types import SLIDE, STICK
from ..numeric.contact_kernel import SLIP_FLOOR

__all__ = ["SampleBatch"]


class SampleBatch:
    """Samples ``(T[k], Y[k])`` of *mode*: ``R[k]`` the solution ``[q''; -lambda]`` of the
    saddle-point system (where ``ok[k]``), ``K[k]`` the contact kernel's flat outputs."""

    __slots__ = ("solver", "mode", "system", "T", "Y", "R", "K", "ok")

    def __init__(self, solver, mode, system, T, Y, R, K, ok):
        self.solver, self.mode, self.system = solver, mode, system
        self.T, self.Y, self.R, self.K, self.ok = T, Y, R, K, ok

    def __len__(self) -> int:
        return len(self.T)

    def motion(self, r: int) -> Motion:
        """The :class:`~nonideal.modes.motion.Motion` of sample *r* (solved: no solve)."""
        motion = Motion.in_phase(self.solver, self.mode, self.system, float(self.T[r]), self.Y[r], self.R[r])
        motion._kin = self.K[r]
        return motion

    def qdd(self, rows: np.ndarray) -> np.ndarray:
        return self.R[rows, :self.system.n]

    def values(self, rows: np.ndarray) -> np.ndarray:
        """The multipliers of the mode's rows (``system.layout`` order) at *rows*."""
        n = self.system.n
        return -self.R[rows, n:n + self.system.m]

    def contact_columns(self, c: int, rows: np.ndarray) -> tuple:
        """``(N, F, U, gap, mu_s)`` of contact *c* at *rows*, as ``Motion.contact_record``
        reports them (the slip's own direction for a sliding contact's friction)."""
        solver, system = self.solver, self.system
        ck, n = solver.ck, system.n
        at, d, o = ck.at, ck.dims[c], ck.offsets[c]
        K = self.K[rows]
        values = self.values(rows)
        j = system.normal_of.get(c)
        normal = values[:, j] if j is not None else np.zeros(len(rows))
        slip = K[:, at["U"] + o:at["U"] + o + d]
        cs = self.mode.contacts[c][1]
        if cs.state == STICK:
            friction = values[:, system.tangent_cols[c]]
        elif cs.state == SLIDE:
            if d == 1:
                shape = np.broadcast_to(np.array(cs.direction, dtype=float), (len(rows), 1))
            else:
                shape = np.empty((len(rows), d))
                qd = self.Y[rows, n:2 * n]
                nrm = np.sqrt(np.einsum("ij,ij->i", slip, slip))
                # ModeSolver.friction_shape's test (its cheap first bound implies this one)
                wide = nrm > SLIP_FLOOR * (1.0 + np.abs(qd).max(axis=1))
                if solver.selecting:  # (a selection under way: its rule for small slips)
                    wide[:] = False
                shape[wide] = slip[wide] / nrm[wide, None]
                for r in np.flatnonzero(~wide):  # a slip at the floor: the solver's rule
                    shape[r] = solver.friction_shape(c, cs, slip[r], qd[r], False)
            mu = K[:, at["mu"] + c]
            friction = -cs.sigma * (mu * normal)[:, None] * shape
        else:
            friction = np.zeros((len(rows), d))
        return normal, friction, slip, K[:, at["gap"] + c], K[:, at["mu_s"] + c]
