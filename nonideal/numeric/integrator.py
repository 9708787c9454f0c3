"""Native phase integration (numba; the optional extra ``fast``): the right-hand side of a
mode without contact rows and SciPy's DOP853 looped over a phase without events.

Generic code, compiled once and cached by numba for every model: the model enters as its
compiled kernel (:mod:`nonideal.numeric.native`: a C callback ``kernel(x, z)`` writing the
nonzero entries of the kernel's flat output ``z`` from the input ``x = [t, q, q',
parameters]``).  Used only when numba is installed.

* :func:`rhs` -- ``y' = [q', q'', W']``: the saddle-point system ``[[M, B], [G, 0]] [q'';
  -lambda] = [F; -gamma]`` gathered from ``z`` by the mode's index arrays (those of
  :class:`~nonideal.modes.system.ModeSystem`) and solved in place (Cholesky without rows, LU
  with partial pivoting with them), the powers of the forces and reactions as the NumPy path;
* :func:`phase` -- SciPy's DOP853 (the tableau of :class:`scipy.integrate.DOP853`, its error
  norm, step-size control and dense output) from a state to the end of a phase, every
  accepted step recorded or the dense output at requested times.

The index array ``ix`` is ``[n, m, power, track, len(src), nx, nz, src, dst, rsrc]`` and the
work array ``w`` is ``[x | z | K | r | B^T q']`` (:meth:`nonideal.numeric.native.Native.buffers`).
"""

import math

import numpy as np
from scipy.integrate import DOP853 as _D

try:
    from numba import njit
except ImportError:  # the extra 'fast' absent: importable (documentation, doctests), never called
    def njit(*args, **kwargs):
        return args[0] if args and callable(args[0]) else (lambda fn: fn)

__all__ = ["rhs", "phase", "evaluate"]

_A, _B, _C = _D.A.copy(), _D.B.copy(), _D.C.copy()
_E3, _E5, _DD = _D.E3.copy(), _D.E5.copy(), _D.D.copy()
_AX, _CX = _D.A_EXTRA.copy(), _D.C_EXTRA.copy()
_STAGES = _B.shape[0]


@njit(cache=True)
def evaluate(kern, x, z):
    """The kernel's outputs ``z`` at the input ``x`` (a test of the generated code)."""
    kern(x.ctypes, z.ctypes)


@njit(cache=True)
def _solve(K, r, s, m):
    """K (s x s, column-major, entry (i, k) at i + k s) in place; r becomes the solution.
    Cholesky without rows (LU when M is not positive definite), LU with partial pivoting
    with them; False when singular."""
    if m == 0:
        ok = True
        for j in range(s):
            d = K[j + j * s]
            for k in range(j):
                d -= K[j + k * s] * K[j + k * s]
            if not d > 0.0:
                ok = False
                break
            d = math.sqrt(d)
            K[j + j * s] = d
            for i in range(j + 1, s):
                v = K[i + j * s]
                for k in range(j):
                    v -= K[i + k * s] * K[j + k * s]
                K[i + j * s] = v / d
        if ok:
            for i in range(s):
                v = r[i]
                for k in range(i):
                    v -= K[i + k * s] * r[k]
                r[i] = v / K[i + i * s]
            for i in range(s - 1, -1, -1):
                v = r[i]
                for k in range(i + 1, s):
                    v -= K[k + i * s] * r[k]
                r[i] = v / K[i + i * s]
            return True
        return False  # the caller's NumPy path decides (LU, or a named error)
    for j in range(s):
        p, big = j, abs(K[j + j * s])
        for i in range(j + 1, s):
            a = abs(K[i + j * s])
            if a > big:
                p, big = i, a
        if big == 0.0:
            return False
        if p != j:
            for k in range(s):
                K[j + k * s], K[p + k * s] = K[p + k * s], K[j + k * s]
            r[j], r[p] = r[p], r[j]
        d = K[j + j * s]
        for i in range(j + 1, s):
            f = K[i + j * s] / d
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
def _views(w, ix):
    """The parts of the work array ``w`` and of the index array ``ix`` (views, made once per
    phase rather than at every right-hand side)."""
    n, m, ns, nx, nz = ix[0], ix[1], ix[4], ix[5], ix[6]
    s = n + m
    x = w[:nx]
    z = w[nx:nx + nz]
    K = w[nx + nz:nx + nz + s * s]
    r = w[nx + nz + s * s:nx + nz + s * s + s]
    bq = w[nx + nz + s * s + s:nx + nz + s * s + s + m]
    return x, z, K, r, bq, ix[7:7 + ns], ix[7 + ns:7 + 2 * ns], ix[7 + 2 * ns:7 + 2 * ns + s]


@njit(cache=True, inline='always')
def _eval(kern, t, y, dy, x, z, K, r, bq, src, dst, rsrc, n, m, power, track):
    """:func:`rhs` on the views of :func:`_views`."""
    s = n + m
    x[0] = t
    for i in range(2 * n):
        x[1 + i] = y[i]
    kern(x.ctypes, z.ctypes)
    for k in range(s * s):
        K[k] = 0.0
    for k in range(src.shape[0]):
        K[dst[k]] = z[src[k]]
    for i in range(s):
        r[i] = z[rsrc[i]]
    for i in range(n, s):
        r[i] = -r[i]
    if track:
        for j in range(m):
            v = 0.0
            for i in range(n):
                v += y[n + i] * K[i + (n + j) * s]
            bq[j] = v
    if not _solve(K, r, s, m):
        return False
    for i in range(n):
        dy[i] = y[n + i]
        dy[n + i] = r[i]
    if track:
        total = 0.0
        for j in range(m):
            total -= r[n + j] * bq[j]
        dy[2 * n] = z[power] if power >= 0 else 0.0
        dy[2 * n + 1] = total
        dy[2 * n + 2] = z[power + 1] if power >= 0 else 0.0
        dy[2 * n + 3] = 0.0
        dy[2 * n + 4] = 0.0
    return True


@njit(cache=True)
def rhs(kern, t, y, w, ix, dy):
    """dy = [q', q'', W'] of the mode whose gather is in ix; False if the system is singular."""
    x, z, K, r, bq, src, dst, rsrc = _views(w, ix)
    return _eval(kern, t, y, dy, x, z, K, r, bq, src, dst, rsrc, ix[0], ix[1], ix[2], ix[3])


@njit(cache=True, inline='always')
def _f(kern, t, y, dy, V):
    """The right-hand side on the views *V* of a phase (``_views(w, ix) + (n, m, power, track)``)."""
    return _eval(kern, t, y, dy, V[0], V[1], V[2], V[3], V[4], V[5], V[6], V[7], V[8], V[9], V[10], V[11])


@njit(cache=True)
def _stages(kern, t, y, f, h, V, K, tmp, y_new):
    """One DOP853 step from (t, y) with derivative f: K rows 0..12 as SciPy's rk_step, the
    new state in y_new; False if the system is singular."""
    ny = y.shape[0]
    for i in range(ny):
        K[0, i] = f[i]
    for s in range(1, _STAGES):
        for i in range(ny):
            v = 0.0
            for k in range(s):
                v += K[k, i] * _A[s, k]
            tmp[i] = y[i] + v * h
        if not _f(kern, t + _C[s] * h, tmp, K[s], V):
            return False
    for i in range(ny):
        v = 0.0
        for k in range(_STAGES):
            v += K[k, i] * _B[k]
        y_new[i] = y[i] + h * v
    return _f(kern, t + h, y_new, K[_STAGES], V)


@njit(cache=True)
def _dense(kern, t_old, h, y_old, y_new, f_new, V, K, F, tmp):
    """SciPy's Dop853DenseOutput coefficients F (7 x ny) of the step; K extended by 3 stages."""
    ny = y_old.shape[0]
    for e in range(_AX.shape[0]):
        s = _STAGES + 1 + e
        for i in range(ny):
            v = 0.0
            for k in range(s):
                v += K[k, i] * _AX[e, k]
            tmp[i] = y_old[i] + v * h
        if not _f(kern, t_old + _CX[e] * h, tmp, K[s], V):
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


@njit(cache=True, inline='always')
def error_norm(K, y, y_new, atol, rtol, h):
    """DOP853's scaled error norm of a step (SciPy's DOP853._estimate_error_norm)."""
    ny = y.shape[0]
    e5 = 0.0
    e3 = 0.0
    for i in range(ny):
        sc = atol[i] + max(abs(y[i]), abs(y_new[i])) * rtol
        v5 = 0.0
        v3 = 0.0
        for k in range(_STAGES + 1):
            v5 += K[k, i] * _E5[k]
            v3 += K[k, i] * _E3[k]
        e5 += (v5 / sc) ** 2
        e3 += (v3 / sc) ** 2
    if e5 == 0 and e3 == 0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * ny)


@njit(cache=True)
def interpolate(t, t_old, h, y_old, F, out):
    x = (t - t_old) / h
    ny = y_old.shape[0]
    for i in range(ny):
        out[i] = 0.0
    P = F.shape[0]
    for j in range(P):
        for i in range(ny):
            out[i] += F[P - 1 - j, i]
            if j % 2 == 0:
                out[i] *= x
            else:
                out[i] *= 1 - x
    for i in range(ny):
        out[i] += y_old[i]


@njit(cache=True)
def _grow(T, Y, DY, count, cap):
    T2 = np.empty(cap)
    Y2 = np.empty((cap, Y.shape[1]))
    D2 = np.empty((cap, Y.shape[1]))
    T2[:count] = T[:count]
    Y2[:count] = Y[:count]
    D2[:count] = DY[:count]
    return T2, Y2, D2


@njit(cache=True)
def phase(kern, t, y, f, h_abs, t_end, rtol, atol, max_step, w, ix, times, next_time, max_steps, tiny):
    """DOP853 from (t, y, f = y'(t)) with the next step h_abs towards t_end, as SciPy's
    DOP853._step_impl; every accepted step recorded (times empty) or the dense output at the
    requested times.  Returns (status, t, y, f, h_abs, T, Y, DY, count, next_time, steps), DY the derivatives at the samples:
    status 0 reached t_end, 1 max_steps taken, 2 step too small, 3 singular system, 4 a step
    shorter than tiny taken (the caller's watch of collapsing steps decides).  No array is
    allocated per step (the stages, the states and the dense output live in buffers made once)."""
    ny = y.shape[0]
    V = _views(w, ix) + (ix[0], ix[1], ix[2], ix[3])
    K = np.empty((_STAGES + 1 + _AX.shape[0], ny))
    F = np.empty((7, ny))
    tmp = np.empty(ny)
    y = y.copy()          # the state (the caller's array is not modified)
    y_new = np.empty(ny)  # the trial state; the two are swapped at each accepted step
    f = f.copy()
    grid = times.shape[0] > 0
    cap = 256
    T = np.empty(cap)
    Y = np.empty((cap, ny))
    DY = np.empty((cap, ny))
    count = 0
    steps = 0
    status = 0
    exponent = -1.0 / 8.0
    while t < t_end:
        if steps >= max_steps:
            status = 1
            break
        min_step = 10 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                status = 2
                break
            t_new = t + h_abs
            if t_new - t_end > 0:
                t_new = t_end
            h = t_new - t
            h_abs = abs(h)
            if not _stages(kern, t, y, f, h, V, K, tmp, y_new):
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
                h_abs *= factor
                break
            h_abs *= max(0.2, 0.9 * err ** exponent)
            rejected = True
        if status != 0:
            break
        steps += 1
        f_new = K[_STAGES]  # (not overwritten by the dense output's stages)
        if grid:
            if next_time < times.shape[0] and times[next_time] <= t_new:
                if not _dense(kern, t, h, y, y_new, f_new, V, K, F, tmp):
                    status = 3
                    break
                while status == 0 and next_time < times.shape[0] and times[next_time] <= t_new:
                    if times[next_time] >= t:
                        if count == cap:
                            cap *= 2
                            T, Y, DY = _grow(T, Y, DY, count, cap)
                        T[count] = times[next_time]
                        interpolate(times[next_time], t, h, y, F, Y[count])
                        if not _f(kern, T[count], Y[count], DY[count], V):
                            status = 3
                            break
                        count += 1
                    next_time += 1
                if status != 0:
                    break
        else:
            if count == cap:
                cap *= 2
                T, Y, DY = _grow(T, Y, DY, count, cap)
            T[count] = t_new
            for i in range(ny):
                Y[count, i] = y_new[i]
                DY[count, i] = f_new[i]
            count += 1
        t = t_new
        for i in range(ny):
            f[i] = f_new[i]
        y, y_new = y_new, y
        if h < tiny and t < t_end:
            status = 4
            break
    return status, t, y, f, h_abs, T[:count], Y[:count], DY[:count], count, next_time, steps
