"""The events of a step of a native phase with contacts, scanned and located as the hybrid loop's
scan does (:class:`~nonideal.simulation.guards.StepScan`): where a guard's samples would make
the scan look closer (:func:`issue`), the minimum of a dip (:func:`dip`, golden section), the
first zero of a guard in the step (:func:`first_root`, Brent's method, :func:`root`), each
value read on the step's dense output (:func:`guard_at`).  Used by
:func:`nonideal.numeric.contact_integrator.phase`; the model enters as its native function
``kern`` and the arrays ``S``, ``E`` described there.
"""

import math

from .contact_system import guards, rhs
from .integrator import interpolate, njit

__all__ = ["issue", "guard_at", "dip", "root", "first_root", "scan_root", "peak", "unarmed_root"]


@njit(cache=True)
def issue(s, g, start):
    """``(kind, i)``: the first sample ``i >= start`` of the step at which the hybrid loop's
    scan (:meth:`StepScan._scan <nonideal.simulation.guards.StepScan>`) would look closer --
    kind 1 a sign change or a non-finite value (an event), kind 2 an interior dip that its
    minimization would have to look into; kind 0 none."""
    for i in range(start, s.shape[0]):
        if i < s.shape[0] - 1 and 0 < g[i] < g[i - 1] and g[i] < g[i + 1]:
            if g[i] < max(g[i - 1], g[i + 1]) - g[i]:
                return 2, i
            d01 = (g[i] - g[i - 1]) / (s[i] - s[i - 1])
            curvature = ((g[i + 1] - g[i]) / (s[i + 1] - s[i]) - d01) / (s[i + 1] - s[i - 1])
            slope = d01 + curvature * (s[i] - s[i - 1])
            if g[i] - slope * slope / (4.0 * curvature) <= 0:
                return 2, i
        if g[i - 1] > 0 >= g[i] or not math.isfinite(g[i]):
            return 1, i
    return 0, 0


@njit(cache=True)
def guard_at(kern, S, E, k, x, t, h, y, F, tmp, dy, gv, sv):
    """Guard k at time x of the step (its dense output F); NaN where the system is singular."""
    interpolate(x, t, h, y, F, tmp)
    if not rhs(kern, S, x, tmp, dy):
        return math.nan
    guards(S, E, gv, sv)
    return gv[k]


@njit(cache=True)
def dip(kern, S, E, k, lo, hi, t, h, y, F, tmp, dy, gv, sv):
    """Guard k over the dip ``[lo, hi]`` of the step: a golden-section search for its minimum
    to the hybrid loop's tolerance (:meth:`StepScan._extremum
    <nonideal.simulation.guards.StepScan>`), stopped at the first value that is not positive.
    Returns ``(found, x, g(x))``: found 1 such a value at x (an event in the dip), 0 the dip
    stays positive, -1 a value that is not a number."""
    return _golden(kern, S, E, k, lo, hi, 1.0, True, t, h, y, F, tmp, dy, gv, sv)


@njit(cache=True)
def _golden(kern, S, E, k, lo, hi, sign, stop, t, h, y, F, tmp, dy, gv, sv):
    """Golden section for the minimum of ``sign g`` (guard k) over ``[lo, hi]`` to the hybrid
    loop's tolerance; with *stop*, stopped at the first g that is not positive.  Returns
    ``(found, x, g(x))``: 1 stopped there, 0 converged (the better of the last two points), -1
    a value that is not a number."""
    xatol = 1e-12 * max(1.0, abs(hi)) + 1e-9 * (hi - lo)
    w = 0.5 * (math.sqrt(5.0) - 1.0)
    a, b = lo, hi
    c, d = b - w * (b - a), a + w * (b - a)
    fc = guard_at(kern, S, E, k, c, t, h, y, F, tmp, dy, gv, sv)
    fd = guard_at(kern, S, E, k, d, t, h, y, F, tmp, dy, gv, sv)
    while True:
        if math.isnan(fc) or math.isnan(fd):
            return -1, c, math.nan
        if stop:
            if not fc > 0.0:
                return 1, c, fc
            if not fd > 0.0:
                return 1, d, fd
        if b - a <= xatol:
            return (0, c, fc) if sign * fc <= sign * fd else (0, d, fd)
        if sign * fc < sign * fd:
            b, d, fd = d, c, fc
            c = b - w * (b - a)
            fc = guard_at(kern, S, E, k, c, t, h, y, F, tmp, dy, gv, sv)
        else:
            a, c, fc = c, d, fd
            d = a + w * (b - a)
            fd = guard_at(kern, S, E, k, d, t, h, y, F, tmp, dy, gv, sv)


@njit(cache=True)
def root(kern, S, E, k, xa, xb, fa, fb, t, h, y, F, tmp, dy, gv, sv, shift=0.0):
    """The zero of guard k plus *shift* in ``[xa, xb]`` (``fa > 0 >= fb``, the values with the
    shift) on the dense output: Brent's
    method (inverse quadratic interpolation and secant steps safeguarded by bisection) to the
    tolerances of the hybrid loop's ``brentq`` (:meth:`StepScan._root
    <nonideal.simulation.guards.StepScan>`); NaN where a value is not a number."""
    if fb == 0.0:
        return xb
    xtol, rtol = 1e-15 * max(1.0, abs(xb)), 8.9e-16
    a, b, c = xa, xb, xa  # b the estimate, c on the other side of the zero, a the previous b
    fc = fa
    d = e = b - a
    for _ in range(200):
        if (fb > 0.0) == (fc > 0.0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 0.5 * (xtol + rtol * abs(b))
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            r = fb / fa
            if a == c:
                p, q = 2.0 * m * r, 1.0 - r
            else:
                q0, r1 = fa / fc, fb / fc
                p = r * (2.0 * m * q0 * (q0 - r1) - (b - a) * (r1 - 1.0))
                q = (q0 - 1.0) * (r1 - 1.0) * (r - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0.0 else -tol)
        fb = guard_at(kern, S, E, k, b, t, h, y, F, tmp, dy, gv, sv) + shift
        if math.isnan(fb):
            return math.nan
    return b


@njit(cache=True)
def first_root(kern, S, E, k, probed, s, g, t, h, y, F, tmp, dy, gv, sv):
    """The first zero of guard k (armed) in the step, as the hybrid loop's scan finds it
    (:meth:`StepScan.first_root <nonideal.simulation.guards.StepScan>`): from its values at
    the ends, or, where it is probed, from its samples g at the times s (a sign change, or a
    dip whose minimum is not positive); inf if none, NaN where a value is not a number."""
    last = s.shape[0] - 1
    if not probed:
        if g[0] > 0.0 >= g[last]:
            return root(kern, S, E, k, s[0], s[last], g[0], g[last], t, h, y, F, tmp, dy, gv, sv)
        return math.inf
    return scan_root(kern, S, E, k, s, g, 1, t, h, y, F, tmp, dy, gv, sv)


@njit(cache=True)
def scan_root(kern, S, E, k, s, g, start, t, h, y, F, tmp, dy, gv, sv):
    """The first zero of guard k from its samples g at the times s, looking from sample
    ``start`` on (:meth:`StepScan._scan <nonideal.simulation.guards.StepScan>` of the samples
    from ``start - 1``); inf if none, NaN where a value is not a number."""
    i = start
    while True:
        kind, i = issue(s, g, i)
        if kind == 0:
            return math.inf
        if kind == 1:
            if not math.isfinite(g[i]):
                return math.nan
            return root(kern, S, E, k, s[i - 1], s[i], g[i - 1], g[i], t, h, y, F, tmp, dy, gv, sv)
        found, x, gx = dip(kern, S, E, k, s[i - 1], s[i + 1], t, h, y, F, tmp, dy, gv, sv)
        if found < 0:
            return math.nan
        if found > 0:
            return root(kern, S, E, k, s[i - 1], x, g[i - 1], gx, t, h, y, F, tmp, dy, gv, sv)
        i += 1


@njit(cache=True)
def peak(kern, S, E, k, lo, hi, t, h, y, F, tmp, dy, gv, sv):
    """``(x, g(x))``: the maximum of guard k over ``[lo, hi]`` of the step by golden section to
    the hybrid loop's tolerance (:meth:`StepScan._maximum <nonideal.simulation.guards.StepScan>`);
    g NaN where a value is not a number."""
    _, x, gx = _golden(kern, S, E, k, lo, hi, -1.0, False, t, h, y, F, tmp, dy, gv, sv)
    return x, gx


@njit(cache=True)
def unarmed_root(kern, S, E, k, tol, rising, s, g, t, h, y, F, tmp, dy, gv, sv, s2, g2):
    """``(te, armed)`` of guard k, not armed at the step's start, as the hybrid loop's scan
    and ``event_hits`` treat it (:meth:`StepScan.first_root
    <nonideal.simulation.guards.StepScan>`): armed from the first sample above *tol* (the
    scan looks for a zero from there), or at an interior peak above it (from the peak on:
    near the start, between the first samples where they rise, or before the first interior
    one where the guard rises at the start, *rising*); not armed and below ``-tol`` at the
    end, the event where the guard passes ``-tol/2``.  te inf if none, NaN where a value is
    not a number.  s2, g2 are scratch of the samples' length."""
    last = s.shape[0] - 1
    for i in range(last + 1):
        if g[i] > tol:
            return scan_root(kern, S, E, k, s, g, i + 1, t, h, y, F, tmp, dy, gv, sv), True
    hi = -1.0
    if g[1] > g[0]:
        hi = s[2]
    elif rising:
        hi = s[1]
    if hi > s[0]:
        x, gx = peak(kern, S, E, k, s[0], hi, t, h, y, F, tmp, dy, gv, sv)
        if math.isnan(gx):
            return math.nan, False
        if gx > tol:  # the scan from the peak on, over the samples after it
            s2[0], g2[0] = x, gx
            m = 1
            for i in range(last + 1):
                if s[i] > x:
                    s2[m], g2[m] = s[i], g[i]
                    m += 1
            return scan_root(kern, S, E, k, s2[:m], g2[:m], 1, t, h, y, F, tmp, dy, gv, sv), True
    if g[last] < -tol:  # a guard that left zero on the wrong side (a force zero at the switch)
        shift = 0.5 * tol
        ga = guard_at(kern, S, E, k, s[0], t, h, y, F, tmp, dy, gv, sv)
        if math.isnan(ga):
            return math.nan, False
        if ga + shift <= 0.0:
            return s[0], False
        return root(kern, S, E, k, s[0], s[last], ga + shift, g[last] + shift, t, h, y, F, tmp, dy, gv, sv,
                    shift), False
    return math.inf, False
