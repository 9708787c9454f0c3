"""The saddle-point system and the event guards of a mode with contacts, natively (numba; the
optional extra ``fast``): the compiled core of :mod:`nonideal.numeric.contact_integrator`.

* :func:`rhs` -- ``y' = [q', q'', W']`` of one mode: the saddle-point system ``[[M, B], [G,
  0]] [q''; -lambda] = [F; -gamma]`` gathered by the :class:`~nonideal.modes.system.ModeSystem`'s
  index arrays, each sliding contact's friction column ``-sigma mu s W`` (``s`` the slip
  direction: its sign with one component, ``U/|U|`` oriented by the step's reference with two,
  as :meth:`ModeSolver.friction_shape <nonideal.modes.solver.ModeSolver.friction_shape>`),
  LU with partial pivoting (the factors kept for the compliance), and the powers of the
  reactions and of friction as :meth:`ModeSystem.solve_with_powers
  <nonideal.modes.system.ModeSystem.solve_with_powers>`;
* :func:`guards` -- the values of the mode's events (:mod:`nonideal.simulation.events`: gap,
  normal force, margin of the friction cone, slip along its direction, effective normal
  compliance) and their scales at the state of the last :func:`rhs`;
* the contacts' residuals and the test of the mass matrix's definiteness of the hybrid loop.

The arrays are described in :mod:`nonideal.numeric.contact_integrator`.
"""

import math

import numpy as np

from .contact_kernel import SLIP_FLOOR
from .integrator import njit

__all__ = ["rhs", "guards", "residuals", "definite"]


@njit(cache=True)
def _lu(K, r, piv, s):
    """LU with partial pivoting of K (s x s, column-major) in place, r solved; False if singular."""
    for j in range(s):
        p, big = j, abs(K[j + j * s])
        for i in range(j + 1, s):
            a = abs(K[i + j * s])
            if a > big:
                p, big = i, a
        if big == 0.0:
            return False
        piv[j] = p
        if p != j:
            for k in range(s):
                K[j + k * s], K[p + k * s] = K[p + k * s], K[j + k * s]
            r[j], r[p] = r[p], r[j]
        d = K[j + j * s]
        for i in range(j + 1, s):
            f = K[i + j * s] / d
            K[i + j * s] = f
            if f != 0.0:
                for k in range(j + 1, s):
                    K[i + k * s] -= f * K[j + k * s]
                r[i] -= f * r[j]
    for i in range(s - 1, -1, -1):
        v = r[i]
        for k in range(i + 1, s):
            v -= K[i + k * s] * r[k]
        r[i] = v / K[i + i * s]
    for i in range(s):
        if not math.isfinite(r[i]):
            return False
    return True


@njit(cache=True)
def _inverse_entry(K, piv, s, i):
    """(K^-1)_{ii} from the LU factors of :func:`_lu`: ``P K = L U`` with whole rows (their
    multipliers included) interchanged, so the interchanges all come first (LAPACK's
    ``dgetrs``), then the two triangular solves."""
    e = np.zeros(s)
    e[i] = 1.0
    for j in range(s):
        p = piv[j]
        if p != j:
            e[j], e[p] = e[p], e[j]
    for j in range(s):
        for k in range(j + 1, s):
            e[k] -= K[k + j * s] * e[j]
    for k in range(s - 1, -1, -1):
        v = e[k]
        for l in range(k + 1, s):
            v -= K[k + l * s] * e[l]
        e[k] = v / K[k + k * s]
    return e[i]


@njit(cache=True)
def rhs(kern, S, t, y, dy):
    """dy = [q', q'', W'] of the mode of S at (t, y); False if the system is singular."""
    x, z, K, r, piv, bq, fq, src, dst, rsrc, slide, slidef, ref, hasref, tang, hdr = S
    n, m = hdr[0], hdr[1]
    power = hdr[2]
    s = n + m
    x[0] = t
    for i in range(2 * n):
        x[1 + i] = y[i]
    kern(x.ctypes, z.ctypes)
    K[:] = 0.0
    for k in range(src.shape[0]):
        K[dst[k]] = z[src[k]]
    for i in range(s):
        r[i] = z[rsrc[i]]
    for i in range(n, s):
        r[i] = -r[i]
    q2 = 0.0
    qmax = 0.0
    for i in range(n):
        v = y[n + i]
        q2 += v * v
        qmax = max(qmax, abs(v))
    sh = np.zeros(3)
    for k in range(slide.shape[0]):
        j, u0, d, w0, mu = slide[k, 0], slide[k, 1], slide[k, 2], slide[k, 3], slide[k, 4]
        if d == 1:
            sh[0] = slidef[k, 1]
        else:
            nrm = 0.0
            for l in range(d):
                nrm += z[u0 + l] * z[u0 + l]
            nrm = math.sqrt(nrm)
            if nrm > 2.0 * SLIP_FLOOR * (1.0 + math.sqrt(q2)) or nrm > SLIP_FLOOR * (1.0 + qmax):
                dot = 0.0
                for l in range(d):
                    sh[l] = z[u0 + l] / nrm
                    dot += sh[l] * ref[k, l]
                if hasref[k] and dot < 0:
                    for l in range(d):
                        sh[l] = -sh[l]
            elif hasref[k]:
                for l in range(d):
                    sh[l] = ref[k, l]
            else:
                for l in range(d):
                    sh[l] = 0.0
        coef = slidef[k, 0] * z[mu]
        col = (n + j) * s
        for i in range(n):
            v = 0.0
            for l in range(d):
                v += sh[l] * z[w0 + l * n + i]
            K[col + i] -= coef * v
        v = 0.0
        for l in range(d):
            v += sh[l] * z[u0 + l]
        fq[k] = coef * v
    for j in range(m):
        v = 0.0
        for i in range(n):
            v += y[n + i] * K[i + (n + j) * s]
        bq[j] = v
    if not _lu(K, r, piv, s):
        return False
    total = 0.0
    for j in range(m):
        total -= r[n + j] * bq[j]
    friction = 0.0
    for k in range(slide.shape[0]):
        friction += r[n + slide[k, 0]] * fq[k]
    for k in range(tang.shape[0]):
        friction -= r[n + tang[k, 0]] * z[tang[k, 1]]
    for i in range(n):
        dy[i] = y[n + i]
        dy[n + i] = r[i]
    dy[2 * n] = z[power] if power >= 0 else 0.0
    dy[2 * n + 1] = total - friction
    dy[2 * n + 2] = z[power + 1] if power >= 0 else 0.0
    dy[2 * n + 3] = friction
    dy[2 * n + 4] = 0.0
    for i in range(2 * n + 5, y.shape[0]):
        dy[i] = 0.0
    return True


@njit(cache=True)
def guards(S, E, g, scale):
    """The event values g and their scales (the hybrid loop's :meth:`Event.scale
    <nonideal.simulation.events.Event.scale>`) at the state of the last :func:`rhs`."""
    x, z, K, r, piv, bq, fq, src, dst, rsrc, slide, slidef, ref, hasref, tang, hdr = S
    ev, evf, resid = E
    n, m = hdr[0], hdr[1]
    s = n + m
    force = 0.0
    for i in range(n):
        force = max(force, abs(z[hdr[4] + i]))
    force += 1.0
    for k in range(ev.shape[0]):
        kind, j, t0, d, sl, at, mus = ev[k, 0], ev[k, 1], ev[k, 2], ev[k, 3], ev[k, 4], ev[k, 5], ev[k, 6]
        scale[k] = force
        if kind == 0:
            g[k] = z[at]
        elif kind == 1:
            g[k] = evf[k, 0] * (-r[n + j])
        elif kind == 2:
            mu_s = z[mus]
            if mu_s == math.inf:
                g[k] = math.inf
            else:
                F2 = 0.0
                for l in range(d):
                    F2 += r[n + t0 + l] * r[n + t0 + l]
                cone = mu_s * abs(r[n + j])
                g[k] = cone - math.sqrt(F2)
                scale[k] = max(force, cone)
        elif kind == 3:
            if d == 1:
                g[k] = evf[k, 0] * z[at]
            elif hasref[sl]:
                v = 0.0
                for l in range(d):
                    v += z[at + l] * ref[sl, l]
                g[k] = v
            else:
                v = 0.0
                for l in range(d):
                    v += z[at + l] * z[at + l]
                g[k] = math.sqrt(v)
        else:
            inv = _inverse_entry(K, piv, s, n + j)
            g[k] = -1.0 / inv if inv != 0 else math.inf


@njit(cache=True)
def residuals(z, resid):
    """Position and velocity residuals of the touching contacts (gap, gap rate, sticking slip)."""
    rp = 0.0
    rv = 0.0
    for k in range(resid.shape[0]):
        rp = max(rp, abs(z[resid[k, 0]]))
        rv = max(rv, abs(z[resid[k, 1]]))
        for l in range(resid[k, 3]):
            rv = max(rv, abs(z[resid[k, 2] + l]))
    return rp, rv


@njit(cache=True)
def definite(z, n, at, floor):
    """Whether the symmetric part of M (row-major at z[at:]) less floor I is positive definite."""
    L = np.empty((n, n))
    for i in range(n):
        for k in range(n):
            L[i, k] = 0.5 * (z[at + i * n + k] + z[at + k * n + i])
        L[i, i] -= floor
    for j in range(n):
        d = L[j, j]
        for k in range(j):
            d -= L[j, k] * L[j, k]
        if not d > 0.0:
            return False
        d = math.sqrt(d)
        L[j, j] = d
        for i in range(j + 1, n):
            v = L[i, j]
            for k in range(j):
                v -= L[i, k] * L[j, k]
            L[i, j] = v / d
    return True
