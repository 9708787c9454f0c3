"""The right-hand side of one mode as C source, for the C loop of :mod:`nonideal.numeric.cloop`.

The C twin of :func:`nonideal.numeric.integrator.rhs`: the compiled kernel's expressions
(SymEngine's common subexpressions, as the numba kernel of :mod:`nonideal.numeric.native`)
printed as C, the mode's saddle-point system ``[[M, B], [G, 0]] [q''; -lambda] = [F; -gamma]``
gathered by the mode's index arrays and solved in place (Cholesky without constraint rows, LU
with partial pivoting with them), and the powers of the forces and reactions when the run
tracks its work.  The parameters and the index arrays are constants of the generated source,
so a compiled library is one model in one mode structure.

Generating needs SymEngine (the kernel's expressions); the compiled library needs nothing.
"""

import symengine as se

from .native import renamed_dynamics

__all__ = ["kernel_source", "rhs_source"]


def _hex(v: float) -> str:
    return float(v).hex()


def kernel_source(kernel) -> str:
    """``static void nonideal_kernel(const double *x, double *z)``: the nonzero entries of the
    kernel's flat output at the input ``x = [t, q, q', parameters]`` (the expressions of
    ``kernel.dynamics``, common subexpressions eliminated)."""
    exprs, where, inputs, floats = renamed_dynamics(kernel)
    replacements, reduced = se.cse(exprs) if exprs else ([], [])
    lines = ["static void nonideal_kernel(const double *x, double *z)", "{"]
    lines += [f"    const double {v} = x[{i}];" for i, v in enumerate(inputs.values())
              if any(v in e.free_symbols for e in exprs)]
    lines += [f"    const double {s} = {_hex(v)};" for v, s in floats.items()]
    for sym, e in replacements:
        lines.append(f"    const double {sym} = {se.ccode(e)};")
    for pos, e in zip(where, reduced):
        lines.append(f"    z[{pos}] = {se.ccode(e)};")
    lines += ["    (void)x; (void)z;", "}"]
    return "\n".join(lines) + "\n"


_RHS = r"""
#include <math.h>
#include <string.h>
#define N %(n)d
#define M %(m)d
#define S (N + M)
#define NX %(nx)d
#define NZ %(nz)d
#define NS %(ns)d
#define POWER %(power)d
#define TRACK %(track)d
static const double X0_[NX] = {%(x0)s};
static const int SRC_[NS] = {%(src)s};
static const int DST_[NS] = {%(dst)s};
static const int RSRC_[S] = {%(rsrc)s};

static int solve(double *K, double *r)
{
    const int s = S;
    if (M == 0) {
        for (int j = 0; j < s; j++) {
            double d = K[j + j * s];
            for (int k = 0; k < j; k++) d -= K[j + k * s] * K[j + k * s];
            if (!(d > 0.0)) return 0;
            d = sqrt(d);
            K[j + j * s] = d;
            for (int i = j + 1; i < s; i++) {
                double v = K[i + j * s];
                for (int k = 0; k < j; k++) v -= K[i + k * s] * K[j + k * s];
                K[i + j * s] = v / d;
            }
        }
        for (int i = 0; i < s; i++) {
            double v = r[i];
            for (int k = 0; k < i; k++) v -= K[i + k * s] * r[k];
            r[i] = v / K[i + i * s];
        }
        for (int i = s - 1; i >= 0; i--) {
            double v = r[i];
            for (int k = i + 1; k < s; k++) v -= K[k + i * s] * r[k];
            r[i] = v / K[i + i * s];
        }
        return 1;
    }
    for (int j = 0; j < s; j++) {
        int p = j;
        double big = fabs(K[j + j * s]);
        for (int i = j + 1; i < s; i++) {
            double a = fabs(K[i + j * s]);
            if (a > big) { p = i; big = a; }
        }
        if (big == 0.0) return 0;
        if (p != j) {
            for (int k = 0; k < s; k++) {
                double u = K[j + k * s]; K[j + k * s] = K[p + k * s]; K[p + k * s] = u;
            }
            double u = r[j]; r[j] = r[p]; r[p] = u;
        }
        double d = K[j + j * s];
        for (int i = j + 1; i < s; i++) {
            double f = K[i + j * s] / d;
            if (f != 0.0) {
                for (int k = j + 1; k < s; k++) K[i + k * s] -= f * K[j + k * s];
                r[i] -= f * r[j];
            }
        }
    }
    for (int i = s - 1; i >= 0; i--) {
        double v = r[i];
        for (int k = i + 1; k < s; k++) v -= K[i + k * s] * r[k];
        r[i] = v / K[i + i * s];
    }
    for (int i = 0; i < s; i++) if (!isfinite(r[i])) return 0;
    return 1;
}

/* dy = [q', q'', W'] (W' only when the run tracks its work); nonzero when singular */
static int nonideal_rhs(double t, const double *y, double *dy)
{
    double x[NX], z[NZ], K[S * S], r[S], bq[M + 1];
    memcpy(x, X0_, sizeof x);
    memset(z, 0, sizeof z);
    x[0] = t;
    for (int i = 0; i < 2 * N; i++) x[1 + i] = y[i];
    nonideal_kernel(x, z);
    memset(K, 0, sizeof K);
    for (int k = 0; k < NS; k++) K[DST_[k]] = z[SRC_[k]];
    for (int i = 0; i < S; i++) r[i] = z[RSRC_[i]];
    for (int i = N; i < S; i++) r[i] = -r[i];
    if (TRACK)
        for (int j = 0; j < M; j++) {
            double v = 0.0;
            for (int i = 0; i < N; i++) v += y[N + i] * K[i + (N + j) * S];
            bq[j] = v;
        }
    if (!solve(K, r)) return 1;
    for (int i = 0; i < N; i++) { dy[i] = y[N + i]; dy[N + i] = r[i]; }
    if (TRACK) {
        double total = 0.0;
        for (int j = 0; j < M; j++) total -= r[N + j] * bq[j];
        dy[2 * N] = POWER >= 0 ? z[POWER < 0 ? 0 : POWER] : 0.0;
        dy[2 * N + 1] = total;
        dy[2 * N + 2] = POWER >= 0 ? z[POWER < 0 ? 0 : POWER + 1] : 0.0;
        dy[2 * N + 3] = 0.0;
        dy[2 * N + 4] = 0.0;
    }
    (void)bq;
    return 0;
}
"""


def rhs_source(kernel, w, ix) -> str:
    """C source defining ``nonideal_rhs`` for the mode whose work and index arrays are *w*,
    *ix* (:meth:`nonideal.numeric.native.Native.buffers`: the parameters are read from ``w``)."""
    ix = [int(v) for v in ix]
    n, m, power, track, ns, nx, nz = ix[:7]
    s = n + m
    src, dst, rsrc = ix[7:7 + ns], ix[7 + ns:7 + 2 * ns], ix[7 + 2 * ns:7 + 2 * ns + s]

    def ints(values):
        return ", ".join(map(str, values)) if values else "0"

    body = _RHS % dict(n=n, m=m, nx=nx, nz=nz, ns=max(ns, 1), power=power, track=track,
                       x0=", ".join(_hex(v) for v in list(w[:nx])), src=ints(src),
                       dst=ints(dst), rsrc=ints(rsrc))
    if ns == 0:
        body = body.replace("for (int k = 0; k < NS; k++)", "for (int k = 0; k < 0; k++)")
    return "#include <math.h>\n" + kernel_source(kernel) + body
