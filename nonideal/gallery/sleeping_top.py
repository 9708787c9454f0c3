"""The sleeping top: Maievski's condition C^2 w^2 > 4 (A + m l^2) m g l.

Classic (Maievski 1870s; Klein & Sommerfeld, *Theorie des Kreisels*; Chetaev's proof of
stability).  A symmetric heavy top on a fixed point O: central moments A (transverse) and C
(axial), centre of mass at distance l from O.  The orientation R = Rx(a) Ry(b) Rz(c) has no
singularity at the vertical (Euler angles have one there): a, b tilt the axis, c is the spin.

Steady motion: a = b = 0, c' = w.  The spin angle c is ignorable and c' is held (a family of
steady motions: its zero eigenvalue is named, not counted).  With A_O = A + m l^2 the first
approximation in (a, b, a', b') has the characteristic polynomial (derived here, by hand from
the Euler equations and by the library from the model file)

    A_O^2 s^4 + (C^2 w^2 - 2 A_O m g l) s^2 + (m g l)^2 = 0,

even in s (no dissipation): the roots are on the imaginary axis iff the roots z = s^2 are real
and negative, i.e. C^2 w^2 > 4 A_O m g l (Maievski's condition; the library's condition with
``--symbolic`` is the discriminant of the polynomial in z, the same inequality).  Then the
verdict is "critical" (first approximation stable, not asymptotically); below it one root has
a positive real part: "unstable".

    nonideal stability sleeping-top --about steady --at "c'=w" --symbolic w
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import RigidBody
from ..modeling.model import Model

NAME = "sleeping-top"
ORDER = 200
TITLE = "Sleeping top: Maievski's condition C^2 w^2 > 4 (A + m l^2) m g l (first approximation)"
FILE = "sleeping_top.toml"

ROTATION = [
    ["cos(b)*cos(c)", "-sin(c)*cos(b)", "sin(b)"],
    ["sin(a)*sin(b)*cos(c) + sin(c)*cos(a)", "-sin(a)*sin(b)*sin(c) + cos(a)*cos(c)", "-sin(a)*cos(b)"],
    ["sin(a)*sin(c) - sin(b)*cos(a)*cos(c)", "sin(a)*cos(c) + sin(b)*sin(c)*cos(a)", "cos(a)*cos(b)"],
]


def build(m: float = 1.0, A: float = 0.02, C: float = 0.03, l: float = 0.1, g: float = 9.81,
          w: float = 30.0) -> Model:
    """The top with the Python API (same as the model file for the default values)."""
    return Model(
        name="sleeping top", coordinates=["a", "b", "c"],
        parameters={"m": m, "A": A, "C": C, "l": l, "g": g, "w": w},
        bodies=[RigidBody("top", "m", [["A", 0, 0], [0, "A", 0], [0, 0, "C"]],
                          ["l*sin(b)", "-l*sin(a)*cos(b)", "l*cos(a)*cos(b)"], ROTATION)],
        gravity=["0", "0", "-g"],
        initial={"a": 0.0, "b": 0.0, "c": 0.0, "a'": 0.0, "b'": 0.0, "c'": "w"},
        simulation={"t_end": 2.0})


def closed_form(w: float, m=1.0, A=0.02, C=0.03, l=0.1, g=9.81) -> np.ndarray:
    """The four eigenvalues of the first approximation (the polynomial in the docstring)."""
    A_O, mgl = A + m * l * l, m * g * l
    z = np.roots([A_O ** 2, C ** 2 * w ** 2 - 2 * A_O * mgl, mgl ** 2]).astype(complex)
    s = np.concatenate([np.sqrt(z), -np.sqrt(z)])
    return np.array(sorted(s, key=lambda x: (-x.real, -x.imag)))


def critical_spin(m=1.0, A=0.02, C=0.03, l=0.1, g=9.81) -> float:
    """Maievski: w_c = 2 sqrt((A + m l^2) m g l) / C."""
    return 2.0 * np.sqrt((A + m * l * l) * m * g * l) / C


def run(verbose: bool = True) -> dict:
    import sympy as sp

    from ..analysis.stability.linearize import linearize
    from . import load

    model = load(NAME)
    wc = critical_spin()
    out = {"critical_spin": wc, "cases": []}
    ok = True
    for w in (1.05 * wc, 0.95 * wc, 30.0):
        lin = linearize(model, about="steady", at={"c'": w})
        ref = closed_form(w)
        err = max(min(abs(z - r) for r in ref) for z in lin.eigenvalues) / max(1.0, abs(ref).max())
        expected = "critical" if w > wc else "unstable"
        case_ok = (err < 1e-9 and lin.verdict == expected and lin.family == ("c'",)
                   and lin.variables == ("a", "b", "a'", "b'"))
        ok &= case_ok
        out["cases"].append({"w": w, "verdict": lin.verdict, "eigenvalue_error": err, "ok": case_ok})
    lin = linearize(model, about="steady", at="c'=w", symbolic=["w"])
    w = sp.Symbol("w")
    # the boundaries of the conditions (in w^2) must be Maievski's critical spin
    roots = sorted({float(abs(r)) for c in lin.conditions for r in sp.solve(sp.Eq(c.lhs - c.rhs, 0), w)
                    if r.is_real})
    symbolic_ok = any(abs(r - wc) < 1e-9 * wc for r in roots)
    ok &= symbolic_ok
    out.update({"conditions": [str(c) for c in lin.conditions], "boundaries": roots,
                "symbolic_ok": symbolic_ok, "ok": bool(ok)})
    if verbose:
        print(TITLE)
        print(f"  Maievski's critical spin w_c = 2 sqrt((A + m l^2) m g l)/C = {wc:.10g} rad/s")
        for c in out["cases"]:
            print(f"  w = {c['w']:.6g}: {c['verdict']} (eigenvalues vs closed form: {c['eigenvalue_error']:.2e})")
        print(f"  conditions in w (library): {'; '.join(out['conditions'])}; boundary |w| = {roots}")
        print(f"  ok: {out['ok']}")
    return out
