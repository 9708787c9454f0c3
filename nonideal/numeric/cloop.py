"""DOP853 in C behind ctypes: the event-free integration loop without numba, SciPy or SymPy
at run time (the piece a cached command-line run needs to start in a fraction of a second).

The loop is the arithmetic of :func:`nonideal.numeric.integrator.phase` (SciPy's
``DOP853._step_impl``: Hairer, Norsett & Wanner 1993, II.10, the tableau, error norm,
step-size control and the 7-coefficient dense output) written in C.  The coefficients are
written into the C source as hexadecimal floats, so the compiled tableau is the double
precision tableau of :class:`scipy.integrate.DOP853` bit for bit.

The right-hand side is C source too, a function ``int nonideal_rhs(double t, const double
*y, double *dy)`` (nonzero when the state is inadmissible or the system singular) compiled
into the same shared library.  :func:`build` compiles with the system C compiler (``cc -O2
-fPIC -shared -ffp-contract=off``, no fast-math: IEEE arithmetic as in NumPy) into a
directory keyed by the source's SHA-256; :func:`compiler` is ``None`` when no compiler is
found and then nothing here can run (callers fall back silently).

This module imports only the standard library; the tableau is needed (SciPy imported) only
to *generate* the source, never to load or run a compiled library.
"""

import ctypes
import functools
import hashlib
import os
import shutil
import subprocess
import tempfile

__all__ = ["compiler", "source", "build", "Loop"]

FLAGS = ("-O2", "-fPIC", "-shared", "-ffp-contract=off")


def compiler():
    """The system C compiler's path (``$CC``, ``cc``, ``gcc``, ``clang``), or ``None``;
    looked up once per value of ``$CC`` and ``$PATH``."""
    return _compiler(os.environ.get("CC"), os.environ.get("PATH"))


@functools.lru_cache(maxsize=8)
def _compiler(cc, path):
    for name in (cc, "cc", "gcc", "clang"):
        if name:
            found = shutil.which(name, path=path)
            if found:
                return found
    return None


def _array(name, values):
    flat = [float(v).hex() for v in values]
    return "static const double %s[%d] = {%s};\n" % (name, len(flat), ", ".join(flat))


def _tableau():
    import numpy as np
    from scipy.integrate import DOP853 as D
    return ("".join([
        _array("A_", np.asarray(D.A).ravel()), _array("B_", D.B), _array("C_", D.C),
        _array("E3_", D.E3), _array("E5_", D.E5), _array("DD_", np.asarray(D.D).ravel()),
        _array("AX_", np.asarray(D.A_EXTRA).ravel()), _array("CX_", D.C_EXTRA)]),
        D.A.shape[1], D.B.shape[0], D.D.shape[0], D.D.shape[1], D.A_EXTRA.shape[0],
        D.A_EXTRA.shape[1])


_LOOP = r"""
#include <math.h>
#include <stdlib.h>
#include <string.h>
#define NS %(ns)d
#define NA %(na)d
#define ND %(nd)d
#define NDK %(ndk)d
#define NX %(nx)d
#define NAX %(nax)d
%(tab)s
static int stages(int ny, double t, const double *y, const double *f, double h, double *K,
                  double *tmp, double *y_new)
{
    for (int i = 0; i < ny; i++) K[i] = f[i];
    for (int s = 1; s < NS; s++) {
        for (int i = 0; i < ny; i++) {
            double v = 0.0;
            for (int k = 0; k < s; k++) v += K[k * ny + i] * A_[s * NA + k];
            tmp[i] = y[i] + v * h;
        }
        if (nonideal_rhs(t + C_[s] * h, tmp, K + s * ny)) return 0;
    }
    for (int i = 0; i < ny; i++) {
        double v = 0.0;
        for (int k = 0; k < NS; k++) v += K[k * ny + i] * B_[k];
        y_new[i] = y[i] + h * v;
    }
    return !nonideal_rhs(t + h, y_new, K + NS * ny);
}

static int dense(int ny, double t_old, double h, const double *y_old, const double *y_new,
                 const double *f_new, double *K, double *F, double *tmp)
{
    for (int e = 0; e < NX; e++) {
        int s = NS + 1 + e;
        for (int i = 0; i < ny; i++) {
            double v = 0.0;
            for (int k = 0; k < s; k++) v += K[k * ny + i] * AX_[e * NAX + k];
            tmp[i] = y_old[i] + v * h;
        }
        if (nonideal_rhs(t_old + CX_[e] * h, tmp, K + s * ny)) return 0;
    }
    for (int i = 0; i < ny; i++) {
        double dlt = y_new[i] - y_old[i];
        F[i] = dlt;
        F[ny + i] = h * K[i] - dlt;
        F[2 * ny + i] = 2 * dlt - h * (f_new[i] + K[i]);
        for (int p = 0; p < ND; p++) {
            double v = 0.0;
            for (int k = 0; k < NDK; k++) v += DD_[p * NDK + k] * K[k * ny + i];
            F[(3 + p) * ny + i] = h * v;
        }
    }
    return 1;
}

static double error_norm(int ny, const double *K, const double *y, const double *y_new,
                         const double *atol, double rtol, double h)
{
    double e5 = 0.0, e3 = 0.0;
    for (int i = 0; i < ny; i++) {
        double sc = atol[i] + fmax(fabs(y[i]), fabs(y_new[i])) * rtol;
        double v5 = 0.0, v3 = 0.0;
        for (int k = 0; k < NS + 1; k++) {
            v5 += K[k * ny + i] * E5_[k];
            v3 += K[k * ny + i] * E3_[k];
        }
        e5 += (v5 / sc) * (v5 / sc);
        e3 += (v3 / sc) * (v3 / sc);
    }
    if (e5 == 0 && e3 == 0) return 0.0;
    return fabs(h) * e5 / sqrt((e5 + 0.01 * e3) * ny);
}

static void interpolate(int ny, double t, double t_old, double h, const double *y_old,
                        const double *F, double *out)
{
    double x = (t - t_old) / h;
    for (int i = 0; i < ny; i++) out[i] = 0.0;
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < ny; i++) {
            out[i] += F[(6 - j) * ny + i];
            if (j %% 2 == 0) out[i] *= x; else out[i] *= 1 - x;
        }
    for (int i = 0; i < ny; i++) out[i] += y_old[i];
}

int nonideal_eval(double t, const double *y, double *dy) { return nonideal_rhs(t, y, dy); }

/* st: [t, h_abs] in/out; y, f: the state and its derivative in/out; ni: [next_time, count,
   steps] in/out.  Returns 0 t_end reached, 1 max_steps, 2 step too small, 3 singular or
   inadmissible, 4 a step shorter than tiny, 5 the output buffers (cap rows) full: call again
   with the same arguments (and emptied buffers) to continue with the same arithmetic. */
int nonideal_phase(int ny, double *st, double *y, double *f, double t_end, double rtol,
                   const double *atol, double max_step, const double *times, int ntimes,
                   int *ni, int max_steps, double tiny, double *T, double *Y, double *DY,
                   int cap)
{
    double t = st[0], h_abs = st[1];
    int next_time = ni[0], count = 0, steps = ni[2], status = 0;
    double *K = malloc(sizeof(double) * ny * (NS + 1 + NX + 9 + 3));
    if (!K) return 3;
    double *F = K + ny * (NS + 1 + NX), *tmp = F + 7 * ny, *yb = tmp + ny, *fb = yb + ny;
    double *yc = fb + ny, *yn = yc;
    memcpy(yc, y, sizeof(double) * ny);
    yn = yb;
    memcpy(fb, f, sizeof(double) * ny);
    const double exponent = -1.0 / 8.0;
    double *ycur = yc;
    while (t < t_end) {
        if (steps >= max_steps) { status = 1; break; }
        if (count == cap) { status = 5; break; }
        double min_step = 10 * fabs(nextafter(t, INFINITY) - t);
        if (h_abs > max_step) h_abs = max_step;
        else if (h_abs < min_step) h_abs = min_step;
        double h_start = h_abs;
        int rejected = 0;
        double t_new, h;
        for (;;) {
            if (h_abs < min_step) { status = 2; break; }
            t_new = t + h_abs;
            if (t_new - t_end > 0) t_new = t_end;
            h = t_new - t;
            h_abs = fabs(h);
            if (!stages(ny, t, ycur, fb, h, K, tmp, yn)) { status = 3; break; }
            double err = error_norm(ny, K, ycur, yn, atol, rtol, h);
            if (err < 1) {
                double factor = err == 0 ? 10.0 : fmin(10.0, 0.9 * pow(err, exponent));
                if (rejected) factor = fmin(1.0, factor);
                h_abs *= factor;
                break;
            }
            h_abs *= fmax(0.2, 0.9 * pow(err, exponent));
            rejected = 1;
        }
        if (status != 0) break;
        steps++;
        const double *f_new = K + NS * ny;
        if (ntimes > 0) {
            if (next_time < ntimes && times[next_time] <= t_new) {
                /* a grid sample may not fit: count the samples of this step first */
                int fit = 0;
                for (int j = next_time; j < ntimes && times[j] <= t_new; j++)
                    if (times[j] >= t) fit++;
                if (count + fit > cap) { h_abs = h_start; steps--; status = 5; break; }
                if (!dense(ny, t, h, ycur, yn, f_new, K, F, tmp)) { status = 3; break; }
                while (next_time < ntimes && times[next_time] <= t_new) {
                    if (times[next_time] >= t) {
                        T[count] = times[next_time];
                        interpolate(ny, times[next_time], t, h, ycur, F, Y + count * ny);
                        if (nonideal_rhs(T[count], Y + count * ny, DY + count * ny)) {
                            status = 3; break;
                        }
                        count++;
                    }
                    next_time++;
                }
                if (status != 0) break;
            }
        } else {
            T[count] = t_new;
            memcpy(Y + count * ny, yn, sizeof(double) * ny);
            memcpy(DY + count * ny, f_new, sizeof(double) * ny);
            count++;
        }
        t = t_new;
        memcpy(fb, f_new, sizeof(double) * ny);
        double *sw = ycur; ycur = yn; yn = sw;
        if (h < tiny && t < t_end) { status = 4; break; }
    }
    st[0] = t; st[1] = h_abs;
    memcpy(y, ycur, sizeof(double) * ny);
    memcpy(f, fb, sizeof(double) * ny);
    ni[0] = next_time; ni[1] = count; ni[2] = steps;
    free(K);
    return status;
}
"""


def source(rhs_c):
    """C source of a shared library: the right-hand side *rhs_c* (defining ``static int
    nonideal_rhs(double t, const double *y, double *dy)``) and the DOP853 loop
    ``nonideal_phase``.  Imports SciPy (the tableau)."""
    tab, na, ns, nd, ndk, nx, nax = _tableau()
    return ("/* generated by nonideal: DOP853 (Hairer, Norsett & Wanner 1993) */\n"
            + rhs_c + "\n" + _LOOP % dict(tab=tab, na=na, ns=ns, nd=nd, ndk=ndk, nx=nx, nax=nax))


def build(src, directory):
    """Compile *src* into ``directory/<sha256>.so`` (reused when present) and return its path;
    ``None`` when no C compiler is found or compiling fails."""
    key = hashlib.sha256(src.encode()).hexdigest()[:32]
    target = os.path.join(directory, key + ".so")
    if os.path.exists(target):
        return target
    cc = compiler()
    if cc is None:
        return None
    os.makedirs(directory, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=directory) as tmp:
        c = os.path.join(tmp, "loop.c")
        with open(c, "w") as fh:
            fh.write(src)
        out = os.path.join(tmp, "loop.so")
        done = subprocess.run([cc, *FLAGS, "-o", out, c, "-lm"], capture_output=True)
        if done.returncode != 0 or not os.path.exists(out):
            return None
        os.replace(out, target)  # atomic: a concurrent run sees the whole file or none
    return target


_D = ctypes.POINTER(ctypes.c_double)
_I = ctypes.POINTER(ctypes.c_int)


class Loop:
    """A compiled library's loop, called through ctypes (no NumPy needed: lists in, lists out).

    Parameters
    ----------
    path : str
        The shared library made by :func:`build`.
    ny : int
        The state's length.
    """

    def __init__(self, path, ny):
        self.path = path
        self.lib = ctypes.CDLL(path)
        self.ny = ny
        self.lib.nonideal_phase.restype = ctypes.c_int
        self.lib.nonideal_phase.argtypes = [
            ctypes.c_int, _D, _D, _D, ctypes.c_double, ctypes.c_double, _D, ctypes.c_double,
            _D, ctypes.c_int, _I, ctypes.c_int, ctypes.c_double, _D, _D, _D, ctypes.c_int]
        self.lib.nonideal_eval.restype = ctypes.c_int
        self.lib.nonideal_eval.argtypes = [ctypes.c_double, _D, _D]

    def rhs(self, t, y):
        """``y'(t)`` as a list, or ``None`` where the right-hand side refuses the state."""
        ny = self.ny
        yb, dy = (ctypes.c_double * ny)(*y), (ctypes.c_double * ny)()
        return None if self.lib.nonideal_eval(t, yb, dy) else list(dy)

    def phase(self, t, y, f, h_abs, t_end, rtol, atol, max_step=float("inf"), times=(),
              max_steps=10 ** 9, tiny=0.0, cap=4096):
        """DOP853 from (t, y, f = y'(t)), first step *h_abs*, to *t_end*; every accepted step
        (no *times*) or the dense output at the sorted *times*.  Returns ``(status, t, y, f,
        h_abs, T, Y, DY, steps)`` as :func:`nonideal.numeric.integrator.phase` (status 0-4;
        the buffers are grown here, so status 5 never reaches the caller)."""
        ny = self.ny
        st = (ctypes.c_double * 2)(t, h_abs)
        yb, fb = (ctypes.c_double * ny)(*y), (ctypes.c_double * ny)(*f)
        ab = (ctypes.c_double * ny)(*atol)
        tb = (ctypes.c_double * max(len(times), 1))(*times)
        ni = (ctypes.c_int * 3)(0, 0, 0)
        T, Y, DY = [], [], []
        bt, by, bd = (ctypes.c_double * cap)(), (ctypes.c_double * (cap * ny))(), \
            (ctypes.c_double * (cap * ny))()
        while True:
            status = self.lib.nonideal_phase(
                ny, st, yb, fb, t_end, rtol, ab, max_step, tb, len(times), ni,
                max_steps, tiny, bt, by, bd, cap)
            c = ni[1]
            T.extend(bt[:c])
            flat_y, flat_d = by[:c * ny], bd[:c * ny]
            Y.extend(flat_y[k * ny:(k + 1) * ny] for k in range(c))
            DY.extend(flat_d[k * ny:(k + 1) * ny] for k in range(c))
            if status != 5:
                return status, st[0], list(yb), list(fb), st[1], T, Y, DY, ni[2]
            if c == 0:  # one step's samples exceed the buffers: larger ones
                cap *= 2
                bt, by, bd = (ctypes.c_double * cap)(), (ctypes.c_double * (cap * ny))(), \
                    (ctypes.c_double * (cap * ny))()


    def phase_arrays(self, t, y, f, h_abs, t_end, rtol, atol, max_step, times, next_time,
                     max_steps, tiny):
        """:meth:`phase` with NumPy arrays in and out, the signature and result of
        :func:`nonideal.numeric.integrator.phase` without its kernel and work arrays:
        ``(status, t, y, f, h_abs, T, Y, DY, count, next_time, steps)``; *times* from index
        *next_time* on are sampled (none: every step)."""
        import numpy as np

        ny = self.ny
        y, f = np.array(y, dtype=float), np.array(f, dtype=float)
        st = np.array([t, h_abs], dtype=float)
        ni = np.array([next_time, 0, 0], dtype=np.intc)
        atol = np.ascontiguousarray(np.broadcast_to(atol, (ny,)), dtype=float)
        times = np.ascontiguousarray(times, dtype=float)
        # the samples of the phase: those left in the grid (none beyond them), else a chunk of steps
        cap = max(1, int(np.searchsorted(times, t_end, side="right")) - next_time) if times.size \
            else max(1, min(int(max_steps), 4096))
        parts = []
        while True:
            T, Y, DY = np.empty(cap), np.empty((cap, ny)), np.empty((cap, ny))
            status = self.lib.nonideal_phase(
                ny, _ptr(st), _ptr(y), _ptr(f), float(t_end), float(rtol), _ptr(atol),
                float(max_step), _ptr(times), times.size, ni.ctypes.data_as(_I), int(max_steps),
                float(tiny), _ptr(T), _ptr(Y), _ptr(DY), cap)
            c = int(ni[1])
            parts.append((T[:c], Y[:c], DY[:c]))
            if status != 5:
                break
            if c == 0:
                cap *= 2
        if len(parts) == 1:
            T, Y, DY = parts[0]
        else:
            T, Y, DY = (np.concatenate(a) for a in zip(*parts))
        return status, float(st[0]), y, f, float(st[1]), T, Y, DY, len(T), int(ni[0]), int(ni[2])


def _ptr(a):
    return a.ctypes.data_as(_D)

