"""The tippe top in generalized speeds: its equations of motion are Euler's.

The top, the table and the friction of ``tippe-top-contensou`` (Leine & Glocker 2003's
parameters; Coulomb friction over a contact patch), declared with six speeds: the velocity of
the centre of mass u = (x', y', z') and the body's angular velocity in its own axes
w = (omega . B.x, omega . B.y, omega . B.z) (Kane & Levinson 1985, sec. 2.12).  In Gibbs-Appell's
form (``nonideal derive tippe-top-speeds --form appell``; Kane's prints the same) the
equations read

    m u1' = -mu s1 N,   m u2' = -mu s2 N,   m u3' = N - m g,
    A w1' + (C - A) w2 w3 = (moment about G of the table's force and pivoting torque) . B.x,  ...
    C w3' = ...,

N the normal force (``lambda_table``), s the friction shape of the law, and the contact's
gap condition -- lines of at most a few hundred characters, where the same form in the rates
of the Euler parameters fills kilobytes.  The speeds' accelerations are found by solving the
speed matrix group by group (rotation, translation): a 7 x 7 elimination produced pivots
2 e0 + 2 e1^2/e0 that never cancel.

What is checked (``run``; ``tests/literature/test_leine2003_tippe_top_speeds.py``): the
printed equations (their length, Euler's terms), and the motion equal to the model in
coordinate rates (theta(t) to 1e-8 over 0.5 s).
"""

from __future__ import annotations

import numpy as np

from ..modeling.model import Model
from . import tippe_top_contensou

NAME = "tippe-top-speeds"
ORDER = 237
TITLE = "Tippe top in body speeds: Euler's equations with the table's reaction"
FILE = "tippe_top_speeds.toml"

FORMS = ("appell", "kane")
SPEEDS = {"u1": "x'", "u2": "y'", "u3": "z'", "w1": "dot(omega(B), B.x)", "w2": "dot(omega(B), B.y)",
          "w3": "dot(omega(B), B.z)"}


def build(t_end: float = 3.0) -> Model:
    """The model with the Python API (the model file for the defaults)."""
    return tippe_top_contensou.build(t_end=t_end, speeds=SPEEDS, name="tippe top in body speeds")


def equations(form: str = "appell") -> str:
    """The printed equations of the model in *form*."""
    from .. import gallery
    from ..analysis.derivation import derive

    return derive(gallery.load(NAME), form).as_text()


def check(t_end: float = 0.5) -> dict:
    """theta(t) of this model against ``tippe-top-contensou`` (coordinate rates) on 51 times."""
    from .. import gallery
    from ..simulation.hybrid import simulate
    from .tippe_top import invariants

    t = np.linspace(0.0, t_end, 51)
    out = {}
    for name in (NAME, "tippe-top-contensou"):
        model = gallery.load(name)
        out[name] = invariants(simulate(model, times=t), {k: float(v) for k, v in model.parameter_values.items()})
    return {"t": t, "theta": out[NAME]["theta"],
            "theta_difference": float(np.max(np.abs(out[NAME]["theta"] - out["tippe-top-contensou"]["theta"])))}


def run(verbose: bool = True) -> dict:
    texts = {form: equations(form) for form in FORMS}
    longest = {form: max(len(line) for line in text.splitlines()) for form, text in texts.items()}
    euler = all("A*w1' + (-A + C)*w2*w3" in text and "m*u3' = -g*m + lambda_table" in text
                for text in texts.values())
    r = check()
    ok = euler and max(longest.values()) < 700 and r["theta_difference"] < 1e-8
    if verbose:
        print(TITLE)
        print("\n".join(line for line in texts["appell"].splitlines() if "' " in line or "'*" in line))
        print("longest line by form: " + ", ".join(f"{f} {n}" for f, n in longest.items()))
        print(f"theta(t) against the model in coordinate rates: {r['theta_difference']:.1e} rad over 0.5 s")
        print("ok" if ok else "FAILED")
    return {"ok": bool(ok), "longest": longest, "theta_difference": r["theta_difference"]}
