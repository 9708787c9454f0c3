"""Native phases of modes with contact rows (numba; the optional extra ``fast``): the
saddle-point system with Coulomb friction columns, the event guards of the contacts, and
SciPy's DOP853 looped over the steps in which no guard can fire.

Generic code, compiled once and cached by numba for every model; the model enters as the
native function of :mod:`nonideal.numeric.native_contacts` (``kernel(x, z)``, ``z = [kernel
outputs | contact outputs]``: the layout of the mode solver's buffer).

* :func:`~nonideal.numeric.contact_system.rhs` and :func:`~nonideal.numeric.contact_system.guards`
  (:mod:`nonideal.numeric.contact_system`): the mode's right-hand side and event values;
* :func:`phase` -- DOP853 steps (SciPy's tableau, error norm and step-size control) as long as
  every step is one in which the hybrid loop's scan (:mod:`nonideal.simulation.guards`) would
  find nothing: every armed guard positive at both ends and, where it comes within
  :data:`PROBE_NEAR` times its change across the step of zero (its slopes at the ends
  included: tangent differences for the kinematic guards, the force guards' rates), positive
  at the scan's samples on the dense output and, where the samples dip as the scan would
  minimize, at the minimum of the dip (a golden-section search to the scan's tolerance); the
  contacts' residuals below the projection threshold and the mass matrix definite.  A step
  that is not such a step is *not taken*: the loop returns the state before it and the step
  size.  Where only a guard's reaching zero makes it such a step, the loop locates the event
  in it as the scan would (the first zero of each guard from its samples or ends, a dip's
  minimum by golden section, Brent's method on the dense output) and returns it with the
  step's dense output; otherwise the hybrid loop takes the step with its scan -- compiled code
  is left only at an event, or where one may be.
  After each step the force guards' rates bound the next one (:func:`~nonideal.simulation.
  guards.step_limit`), as in the hybrid loop.

Arrays (built by :mod:`nonideal.simulation.fast_contacts`): ``S = (x, z, K, r, piv, bq, fq,
src, dst, rsrc, slide, slidef, ref, hasref, tang, hdr)`` the mode's system, ``hdr = [n, m,
power, M_at, F_at]``; ``slide[k] = [layout row, U, d, W, mu]`` (positions in ``z``), ``slidef[k]
= [sigma, direction, fallback direction (3), has fallback]``; ``tang[k] = [layout row, U]``;
``E = (ev, evf, resid)`` the events, ``ev[k] = [type, layout row, first tangent row, d, slide,
z position, mu_s position]`` (types: 0 touch, 1 lift, 2 slip start, 3 slip stop, 4 jam),
``evf[k] = [sigma or direction, tolerance, armed]`` (armed 1: above its tolerance once in the
phase, the hybrid loop's flag), ``resid[k] = [gap, gap rate, U, d]`` of each
touching contact (``d = 0`` unless it sticks).
"""

import math

import numpy as np

from scipy.integrate import DOP853 as _D

from .contact_kernel import SLIP_FLOOR
from .contact_events import dip, first_root, issue, unarmed_root
from .contact_system import definite, guards, residuals, rhs
from .integrator import error_norm, interpolate, njit

__all__ = ["rhs", "guards", "phase", "initial_step", "PROBE_NEAR", "SLOPE_STEP", "RATE_STEP", "RESOLVE"]

# the hybrid loop's constants (nonideal.simulation.guards; tests check they agree)
PROBE_NEAR = 2.0
SLOPE_STEP = 1e-6
RATE_STEP = 1e-3
RESOLVE = 0.25
PROBES = 3
NEAR_END = 1e-3
PROJECTION_TOL = 1e-10  # (nonideal.simulation.hybrid)
_EPS = 2.220446049250313e-16
# SciPy's DOP853 tableau (as nonideal.numeric.integrator)
_A, _B, _C = _D.A.copy(), _D.B.copy(), _D.C.copy()
_DD = _D.D.copy()
_AX, _CX = _D.A_EXTRA.copy(), _D.C_EXTRA.copy()
_STAGES = _B.shape[0]


@njit(cache=True)
def _rates(kern, S, E, t, y, dy, g, scales, span, rate, curv, known):
    """The force guards' rates and curvatures at (t, y) (dy its derivative, g its values):
    central differences over RATE_STEP span along the tangent (q', q''), as
    :meth:`GuardRates.at <nonideal.simulation.guards.GuardRates.at>`."""
    ev = E[0]
    ne = ev.shape[0]
    n = S[15][0]
    known[:] = False
    if not span > 0.0:
        return
    e = RATE_STEP * span
    tan = np.zeros(y.shape[0])
    for i in range(2 * n):
        tan[i] = dy[i]
    tmp = np.empty(y.shape[0])
    out = np.empty(y.shape[0])
    gp = np.empty(ne)
    gm = np.empty(ne)
    sc = np.empty(ne)
    if not rhs(kern, S, t + e, y + e * tan, out):
        return
    guards(S, E, gp, sc)
    for i in range(y.shape[0]):
        tmp[i] = y[i] - e * tan[i]
    if not rhs(kern, S, t - e, tmp, out):
        return
    guards(S, E, gm, sc)
    for k in range(ne):
        if ev[k, 0] == 0 or ev[k, 0] == 3:
            continue
        total = g[k] + gp[k] + gm[k]
        if not math.isfinite(total):
            continue
        c = (gp[k] - 2.0 * g[k] + gm[k]) / (e * e)
        noise = 16 * _EPS * scales[k] / (e * e)
        rate[k] = (gp[k] - gm[k]) / (2.0 * e)
        mag = max(abs(c) - noise, 0.0)
        curv[k] = mag if c > 0 else (-mag if c < 0 else 0.0)
        known[k] = True


@njit(cache=True)
def _limit(rate, curv, known, scales, max_step):
    """The longest next step the force guards allow (step_limit of each), at most max_step."""
    h = max_step
    for k in range(rate.shape[0]):
        if known[k]:
            r, c, budget = abs(rate[k]), abs(curv[k]), RESOLVE * scales[k]
            if r == 0.0 and c == 0.0:
                continue
            h = min(h, 2.0 * budget / (r + math.sqrt(r * r + 2.0 * c * budget)))
    return h


@njit(cache=True)
def _grow(T, Y, count, cap):
    T2 = np.empty(cap)
    Y2 = np.empty((cap, Y.shape[1]))
    T2[:count] = T[:count]
    Y2[:count] = Y[:count]
    return T2, Y2


@njit(cache=True)
def _stages(kern, S, t, y, f, h, K):
    """One DOP853 step from (t, y) with derivative f (K rows as SciPy's rk_step)."""
    ny = y.shape[0]
    K[0] = f
    tmp = np.empty(ny)
    for s in range(1, _STAGES):
        for i in range(ny):
            v = 0.0
            for k in range(s):
                v += K[k, i] * _A[s, k]
            tmp[i] = y[i] + v * h
        if not rhs(kern, S, t + _C[s] * h, tmp, K[s]):
            return tmp, False
    y_new = np.empty(ny)
    for i in range(ny):
        v = 0.0
        for k in range(_STAGES):
            v += K[k, i] * _B[k]
        y_new[i] = y[i] + h * v
    ok = rhs(kern, S, t + h, y_new, K[_STAGES])
    return y_new, ok


@njit(cache=True)
def _dense(kern, S, t_old, h, y_old, y_new, f_new, K, F):
    """SciPy's Dop853DenseOutput coefficients F of the step; K extended by 3 stages."""
    ny = y_old.shape[0]
    tmp = np.empty(ny)
    for e in range(_AX.shape[0]):
        s = _STAGES + 1 + e
        for i in range(ny):
            v = 0.0
            for k in range(s):
                v += K[k, i] * _AX[e, k]
            tmp[i] = y_old[i] + v * h
        if not rhs(kern, S, t_old + _CX[e] * h, tmp, K[s]):
            return False
    for i in range(ny):
        dlt = y_new[i] - y_old[i]
        F[0, i] = dlt
        F[1, i] = h * K[0, i] - dlt
        F[2, i] = 2 * dlt - h * (f_new[i] + K[0, i])
        for p in range(_DD.shape[0]):
            v = 0.0
            for k in range(_DD.shape[1]):
                v += _DD[p, k] * K[k, i]
            F[3 + p, i] = h * v
    return True


@njit(cache=True)
def _references(S, y, z):
    """The slip references of the two-component sliding contacts at a state whose contact
    outputs are z (:meth:`ModeSolver.set_references <nonideal.modes.solver.ModeSolver.set_references>`)."""
    slide, slidef, ref, hasref, hdr = S[10], S[11], S[12], S[13], S[15]
    n = hdr[0]
    qmax = 0.0
    for i in range(n):
        qmax = max(qmax, abs(y[n + i]))
    for k in range(slide.shape[0]):
        u0, d = slide[k, 1], slide[k, 2]
        if d == 1:
            continue
        nrm = 0.0
        for l in range(d):
            nrm += z[u0 + l] * z[u0 + l]
        nrm = math.sqrt(nrm)
        if nrm > SLIP_FLOOR * (1.0 + qmax):
            for l in range(d):
                ref[k, l] = z[u0 + l] / nrm
            hasref[k] = True
        elif hasref[k]:
            pass  # below the floor the slip has no direction: the reference stays
        elif slidef[k, 5] != 0.0:
            for l in range(d):
                ref[k, l] = slidef[k, 2 + l]
            hasref[k] = True
        else:
            hasref[k] = False


@njit(cache=True)
def initial_step(kern, S, t, y, f, t_end, max_step, rtol, atol, y1):
    """SciPy's first step of DOP853 (``select_initial_step``: Hairer, Norsett & Wanner 1993,
    II.4, with the error estimator's order 7) from (t, y, f = y'(t)) towards t_end, at most
    max_step; -1 where the system is singular at the trial state.  y1 is scratch."""
    ny = y.shape[0]
    interval = abs(t_end - t)
    if interval == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(ny):
        scale = atol[i] + abs(y[i]) * rtol
        d0 += (y[i] / scale) ** 2
        d1 += (f[i] / scale) ** 2
    d0 = math.sqrt(d0 / ny)
    d1 = math.sqrt(d1 / ny)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(ny):
        y1[i] = y[i] + h0 * f[i]
    f1 = np.empty(ny)
    if not rhs(kern, S, t + h0, y1, f1):
        return -1.0
    d2 = 0.0
    for i in range(ny):
        scale = atol[i] + abs(y[i]) * rtol
        d2 += ((f1[i] - f[i]) / scale) ** 2
    d2 = math.sqrt(d2 / ny) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100 * h0, h1, interval, max_step)


@njit(cache=True)
def phase(kern, S, E, t, y, f, h_abs, h_last, t_end, rtol, atol, max_step, step_max, floor,
          times, next_time, max_steps, tiny, run, run_max):
    """DOP853 from (t, y, f = y'(t)) towards t_end, the next step h_abs (at most step_max, the
    force guards' limit; max_step the run's), while no event can happen (module docstring).
    A phase that starts natively passes an empty f (evaluated here) and, without a step
    carried over from before its switch, h_abs 0 (SciPy's first step, :func:`initial_step`).

    Returns (status, t, y, f, h_abs, step_max, T, Y, count, next_time, steps, res_p, res_v,
    run, te, ke, ye, Fe): status 0 reached t_end, 1 max_steps taken, 2 step too small, 3
    singular system, 4 run_max steps in a row shorter than tiny taken (run of them before the
    phase, run at its end: the hybrid loop's count, which locates a slip's arrest after
    ARREST_STEPS of them), 5 the next step (h_abs) may hold an event that the loop does not
    locate (a guard not a number, a residual to project, the mass matrix near singular):
    (t, y, f) is the state before it, 6 the step from (t, y, f) of length h_abs holds event
    ke, whose guard reaches zero first at te (ye the state there, Fe the step's dense output:
    the event located as the hybrid loop's scan locates it).  Samples: every accepted step
    (times empty) or the dense output at the requested times; res_p, res_v the largest
    residuals of the contacts at the steps."""
    ny = y.shape[0]
    hdr = S[15]
    n = hdr[0]
    ev, evf = E[0], E[1]
    ne = ev.shape[0]
    K = np.empty((_STAGES + 1 + _AX.shape[0], ny))
    F = np.empty((7, ny))
    grid = times.shape[0] > 0
    cap = 256
    T = np.empty(cap)
    Y = np.empty((cap, ny))
    count = 0
    steps = 0
    status = 0
    res_p = 0.0
    res_v = 0.0
    exponent = -1.0 / 8.0
    ga = np.empty(ne)
    gb = np.empty(ne)
    ka = np.empty(ne)
    kb = np.empty(ne)
    sa = np.empty(ne)
    sb = np.empty(ne)
    ra = np.zeros(ne)
    ca = np.zeros(ne)
    rb = np.zeros(ne)
    cb = np.zeros(ne)
    knowna = np.zeros(ne, dtype=np.bool_)
    knownb = np.zeros(ne, dtype=np.bool_)
    dy = np.empty(ny)
    tmp = np.empty(ny)
    zb = np.empty(S[1].shape[0])
    probe = np.zeros(ne, dtype=np.bool_)
    at_s = np.empty(PROBES + 4)
    gs = np.empty((PROBES + 4, ne))
    gv = np.empty(ne)
    armed = np.empty(ne, dtype=np.bool_)  # armed where above its tolerance once (the hybrid loop's armed)
    tu = np.full(ne, math.inf)  # the zeros of the guards not armed, in the step
    arming = np.zeros(ne, dtype=np.bool_)  # those the step arms
    s2 = np.empty(PROBES + 4)
    g2 = np.empty(PROBES + 4)
    # the guards and rates at the start
    if not rhs(kern, S, t, y, dy):
        return 3, t, y, f, h_abs, step_max, T[:0], Y[:0], 0, next_time, 0, res_p, res_v, run, 0.0, -1, y[:0], F[:0]
    if f.shape[0] != ny:  # a phase that starts here: its derivative, and its first step if not given
        f = dy.copy()
        if not h_abs > 0.0:
            h_abs = initial_step(kern, S, t, y, f, t_end, step_max, rtol, atol, tmp)
            # (its trial evaluation left its outputs in S: the start's again, for the guards)
            if h_abs < 0.0 or not rhs(kern, S, t, y, dy):
                return 3, t, y, f, 0.0, step_max, T[:0], Y[:0], 0, next_time, 0, res_p, res_v, run, 0.0, -1, y[:0], F[:0]
        if not h_last > 0.0:
            h_last = h_abs
    guards(S, E, ga, sa)
    _rates(kern, S, E, t, y, dy, ga, sa, h_last, ra, ca, knowna)
    for k in range(ne):
        armed[k] = evf[k, 2] > 0.5  # (the hybrid loop's: above its tolerance once in the phase)
    while t < t_end:
        if steps >= max_steps:
            status = 1
            break
        min_step = 10 * abs(np.nextafter(t, np.inf) - t)
        h_try = h_abs
        if h_try > step_max:
            h_try = step_max
        elif h_try < min_step:
            h_try = min_step
        rejected = False
        while True:
            if h_try < min_step:
                status = 2
                break
            t_new = t + h_try
            if t_new - t_end > 0:
                t_new = t_end
            h = t_new - t
            h_try = abs(h)
            y_new, ok = _stages(kern, S, t, y, f, h, K)
            if not ok:
                status = 3
                break
            err = error_norm(K, y, y_new, atol, rtol, h)
            if err < 1:
                if err == 0:
                    factor = 10.0
                else:
                    factor = min(10.0, 0.9 * err ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_next = h_try * factor
                break
            h_try *= max(0.2, 0.9 * err ** exponent)
            rejected = True
        if status != 0:
            break
        # the state at the end of the step (the last stage's): guards, residuals, mass matrix
        f_new = K[_STAGES].copy()
        guards(S, E, gb, sb)
        zb[:] = S[1]
        rp, rv = residuals(zb, E[2])
        scale = 1.0
        for i in range(2 * n):
            scale = max(scale, 1.0 + abs(y_new[i]))
        safe = max(rp, rv) <= PROJECTION_TOL * scale
        if safe and floor >= 0.0:
            safe = definite(zb, n, hdr[3], floor)
        crossing = False  # unsafe only where a guard reaches zero (the step is otherwise sound)
        if safe:  # the slopes of the kinematic guards at the ends, the rates of the force guards
            e = SLOPE_STEP * h
            for i in range(ny):
                tmp[i] = y[i] + e * K[0, i]
            if not rhs(kern, S, t + e, tmp, dy):
                status = 3
                break
            guards(S, E, ka, sa)
            for i in range(ny):
                tmp[i] = y_new[i] - e * f_new[i]
            if not rhs(kern, S, t_new - e, tmp, dy):
                status = 3
                break
            guards(S, E, kb, sa)
            _rates(kern, S, E, t_new, y_new, f_new, gb, sb, h, rb, cb, knownb)
            probe[:] = False
            lost = False  # a guard that is not a number: the hybrid loop looks
            for k in range(ne):
                a, b = ga[k], gb[k]
                if not (math.isfinite(a) and math.isfinite(b)):
                    if math.isinf(a) and math.isinf(b) and a > 0 and b > 0:
                        continue  # an unbounded cone (ideal rolling)
                    lost = True
                    break
                change = abs(b - a)
                kind = ev[k, 0]
                if kind == 0 or kind == 3:
                    slope = max(abs((ka[k] - a) / e), abs((b - kb[k]) / e))
                    change = max(change, h * slope)
                elif knowna[k] and knownb[k]:
                    change = max(change, h * max(abs(ra[k]), abs(rb[k])))
                probe[k] = not (armed[k] and min(a, b) > PROBE_NEAR * change)  # (not armed: always)
                if armed[k] and not b > 0.0:  # (a > 0: an armed guard is positive at an accepted step)
                    safe, crossing = False, True
            if lost:
                safe = crossing = False
            elif (probe.any() or crossing) and not _dense(kern, S, t, h, y, y_new, f_new, K, F):
                status = 3
                break
        if (safe and probe.any()) or crossing:  # the scan's times, the guards at the ends
            hh = h / (PROBES + 1)
            at_s[0], at_s[1] = t, t + NEAR_END * hh
            for p in range(PROBES):
                at_s[2 + p] = t + hh * (p + 1)
            at_s[PROBES + 2], at_s[PROBES + 3] = t_new - NEAR_END * hh, t_new
            gs[0, :] = ga
            gs[PROBES + 3, :] = gb
        if (safe or crossing) and probe.any():  # the scan's samples on the dense output
            for p in range(1, PROBES + 3):
                interpolate(at_s[p], t, h, y, F, tmp)
                if not rhs(kern, S, at_s[p], tmp, dy):
                    status = 3
                    break
                guards(S, E, gs[p], sa)
            if status != 0:
                break
            for k in range(ne):  # each guard not armed: armed in the step, or its zero there
                if not armed[k]:
                    rising = (ka[k] > ga[k]) if (ev[k, 0] == 0 or ev[k, 0] == 3) else \
                        (knowna[k] and knownb[k] and ra[k] > 0)
                    tu[k], arming[k] = unarmed_root(kern, S, E, k, evf[k, 1], rising, at_s, gs[:, k], t, h, y, F,
                                                    tmp, dy, gv, sa, s2, g2)
                    if not math.isinf(tu[k]):
                        safe, crossing = False, crossing or not math.isnan(tu[k])
            for k in range(ne):
                if probe[k] and armed[k] and safe:
                    i = 1
                    while safe:
                        kind, i = issue(at_s, gs[:, k], i)
                        if kind == 0:
                            break
                        if kind == 1:
                            safe, crossing = False, math.isfinite(gs[i, k])
                        else:
                            found, _x, _g = dip(kern, S, E, k, at_s[i - 1], at_s[i + 1], t, h, y, F, tmp, dy,
                                                 gv, sa)
                            if found != 0:
                                safe, crossing = False, found > 0
                        i += 1
        if crossing:  # an event in the step: located as the hybrid loop's scan locates it
            te, ke = math.inf, -1
            for k in range(ne):
                tk = tu[k] if not armed[k] else \
                    first_root(kern, S, E, k, probe[k], at_s, gs[:, k], t, h, y, F, tmp, dy, gv, sa)
                if math.isnan(tk):
                    ke = -1
                    break
                if tk < te:
                    te, ke = tk, k
            if ke >= 0:
                interpolate(te, t, h, y, F, tmp)
                return (6, t, y, f, h, step_max, T[:count], Y[:count], count, next_time, steps, res_p, res_v,
                        run, te, ke, tmp.copy(), F.copy())
        if not safe:
            status = 5
            h_abs = h_try
            break
        steps += 1
        for k in range(ne):
            if not armed[k]:
                armed[k] = arming[k]
        res_p = max(res_p, rp)
        res_v = max(res_v, rv)
        if grid:
            if next_time < times.shape[0] and times[next_time] <= t_new:
                if not _dense(kern, S, t, h, y, y_new, f_new, K, F):
                    status = 3
                    break
                while next_time < times.shape[0] and times[next_time] <= t_new:
                    if times[next_time] >= t:
                        if count == cap:
                            cap *= 2
                            T, Y = _grow(T, Y, count, cap)
                        T[count] = times[next_time]
                        interpolate(times[next_time], t, h, y, F, Y[count])
                        count += 1
                    next_time += 1
        else:
            if count == cap:
                cap *= 2
                T, Y = _grow(T, Y, count, cap)
            T[count] = t_new
            Y[count] = y_new
            count += 1
        # the next step starts here: references, guards with them, rates, the step limit
        S[1][:] = zb
        _references(S, y_new, zb)
        for k in range(ne):
            if ev[k, 0] == 3 and ev[k, 3] > 1:
                sl, at, d = ev[k, 4], ev[k, 5], ev[k, 3]
                v = 0.0
                if S[13][sl]:
                    for l in range(d):
                        v += zb[at + l] * S[12][sl, l]
                else:
                    for l in range(d):
                        v += zb[at + l] * zb[at + l]
                    v = math.sqrt(v)
                gb[k] = v
        ga[:] = gb
        ra[:] = rb
        ca[:] = cb
        knowna[:] = knownb
        step_max = _limit(rb, cb, knownb, sb, max_step)
        t = t_new
        y = y_new
        f = f_new
        h_abs = h_next
        run = run + 1 if h < tiny else 0
        if run >= run_max and t < t_end:
            status = 4
            break
    return (status, t, y, f, h_abs, step_max, T[:count], Y[:count], count, next_time, steps, res_p, res_v, run,
            0.0, -1, y[:0], F[:0])



@njit(cache=True)
def evaluate(kern, S, T, Y, Z, R):
    """The mode of S at the states ``(T[k], Y[k])`` (samples of a run): ``Z[k]`` the flat
    outputs, ``R[k]`` the solution ``[q''; -lambda]`` of the saddle-point system; the returned
    flags say where it is regular (elsewhere ``Z[k]``, ``R[k]`` are left as they are)."""
    s = S[15][0] + S[15][1]
    dy = np.empty(Y.shape[1])
    ok = np.zeros(T.shape[0], dtype=np.bool_)
    for k in range(T.shape[0]):
        if rhs(kern, S, T[k], Y[k], dy):
            Z[k, :] = S[1]
            for i in range(s):
                R[k, i] = S[3][i]
            ok[k] = True
    return ok
