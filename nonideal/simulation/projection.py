"""Projection of a state onto the rows of a mode: the active constraints, the closed gaps of
the touching contacts and the slip rows of the sticking ones (least-norm Newton corrections,
the constraints kept while the contacts are corrected)."""

from __future__ import annotations

import numpy as np

from ..modes.types import SEPARATED, STICK, Mode
from ..numeric.consistency import project_state
from ..numeric.kernel import max_abs

__all__ = ["project_mode"]


def project_mode(sim, mode: Mode, t, q, qd):
    """``(q, q')`` projected onto the rows of *mode* for the simulation *sim*."""
    rows = sim.solver.rows(mode)
    if rows:
        q, qd = project_state(sim.kernel, rows, t, q, qd, sim.params)
    if not sim.contacts:
        return q, qd
    ck = sim.solver.ck
    for _ in range(4):
        cout = ck(sim.solver.input(t, q, qd))
        Gp, rp, Gv, rv = [], [], [], []
        for c, (name, cs) in enumerate(mode.contacts):
            if cs.state == SEPARATED:
                continue
            o = ck.offsets[c]
            Gp.append(cout["Gn"][c].copy())
            rp.append(float(cout["gap"][c]))
            Gv.append(cout["Gn"][c].copy())
            rv.append(float(cout["gap_rate"][c]))
            if cs.state == STICK:
                for k in range(ck.dims[c]):
                    Gv.append(cout["W"][o + k].copy())
                    rv.append(float(cout["U"][o + k]))
        if not Gp:
            break
        scale = 1.0 + max_abs(q)
        if max(map(abs, rp + rv)) < 1e-14 * scale:
            break
        out = sim.kernel.dynamics(sim.solver.input(t, q, qd)) if rows else None
        G = sim.kernel.dense(out, "G") if rows else None
        for i in rows:  # keep the constraints while correcting the contacts
            r = sim.kernel.rows[i]
            if r.position is not None:
                Gp.append(G[i].copy())
                rp.append(0.0)
            if r.velocity is not None:
                Gv.append(G[i].copy())
                rv.append(0.0)
        q = q + np.linalg.lstsq(np.array(Gp), -np.array(rp), rcond=None)[0]
        qd = qd + np.linalg.lstsq(np.array(Gv), -np.array(rv), rcond=None)[0]
    return q, qd

