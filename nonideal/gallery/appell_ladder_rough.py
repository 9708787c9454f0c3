"""Appell's ladder with friction on the wall and the floor: equation (1.106), the quadrature
(1.109), the reactions (1.110), the stop, the slide back and the release from the wall.

Source: Manglieva & Beknazarov (2022), sec. 1.3, problem 2, eqs. (1.101)-(1.110) (Appell,
*Traite de mecanique rationnelle*, ref. [22] of the paper).  The smooth case (f = 0) is the
example ``appell-ladder``.

Model.  A uniform ladder AB, mass m, length 2l, J = m l^2/3 about its centre G; alpha is its
angle with the wall.  Coordinates G = (x, y) and alpha (Oy UP here, gravity -g along y); the
top A = G + l(-sin(alpha), cos(alpha)) on the rough wall x = 0 (coefficient f_A), the foot
B = G + l(sin(alpha), -cos(alpha)) on the rough floor y = 0 (f_B).  Contacts (gap = physical
distance, so the multipliers are the normal forces R_A^n, R_B^n; slip = velocity of the end
along its support):

    wall:   gap x - l sin(alpha),   slip y_A' = y' - l sin(alpha) alpha',
    floor:  gap y - l cos(alpha),   slip x_B' = x' + l cos(alpha) alpha',
    top:    gap y + l cos(alpha),   slip x_A' (A reaching the floor when the ladder falls flat).

Direction of sliding.  The paper states that the ladder is pushed "so that B approaches O"
(alpha' < 0), but then directs the friction at B from B to O and the friction at A along OA
(upwards) -- the friction of a ladder sliding DOWN (alpha' > 0, B moving away from O) -- and
(1.104)-(1.109) are written for that case.  With sigma = sign(alpha') (slip of B = 2 l cos(alpha)
alpha', of A = -2 l sin(alpha) alpha'), Newton-Euler gives Manglieva & Beknazarov's equations with f_A, f_B
replaced by sigma f_A, sigma f_B.  The example follows Manglieva & Beknazarov's statement literally: the
ladder is pushed up (alpha0 = 0.9, alpha0' = -1, B approaching O), rises with the friction
reversed (sigma = -1), stops, slides back down with Manglieva & Beknazarov's friction directions
(sigma = +1), leaves the wall and falls on the floor.

Equation of motion (1.106), checked (Newton-Euler for the ladder with Coulomb friction at both
ends, sigma = +1; for sigma = -1 replace f_A, f_B by -f_A, -f_B):

    (m l^2 + J + 2 l^2 m ((f_A - f_B) s c - f_A f_B)/(1 + f_A f_B)) alpha''
        = 2 m l^2 (f_A s^2 + f_B c^2) alpha'^2/(1 + f_A f_B) - 2 m l f_B g (f_A s + c)/(1 + f_A f_B)
          + m g l s,                                                             (1.106)

with the normal forces (1.105) (correct as printed).  (1.101)-(1.105) are right; the sentence
after (1.104) says "substituting into (1.103) with (1.104)" and "solving for R_A^tau, R_B^tau"
where R_A^n, R_B^n are meant.  f_A = f_B = f, a = 2/(1 + f^2), J = m l^2/3: (1.107)-(1.108)
are right,

    (a - 2/3) alpha'' = a f alpha'^2 - (g/l) ((a f^2 - 1) sin(alpha) + a f cos(alpha)).     (1.108)

Quadrature (1.109), corrected.  Linear in u = alpha'^2:  u' - k u = -(2 g/(l (a - 2/3))) ((a f^2 - 1)
sin + a f cos), k = 2 a f/(a - 2/3) = -b (Manglieva & Beknazarov's b), so

    alpha'^2 = 2 g/(l (1 + b^2)(2/3 - a)) [((a f^2 - 1) b + a f) sin(alpha)
               + (b a f - (a f^2 - 1)) cos(alpha)] + C e^{-b alpha},
    C = e^{b alpha0} [alpha0'^2 - (the same bracket term at alpha0)].

**Misprints (1.109)**: the factor is printed ``g^2`` (it is 2 g: alpha'^2 has the dimension of
g/l), the homogeneous term ``C e^{b alpha}`` (it is ``e^{-b alpha}``: the printed one is not a
solution), and ``C = e^{-b alpha}[...]`` (it is ``e^{+b alpha0}``); in the intermediate step the
right side of the equation for C_1 C_1' has ``e^{+2 a f alpha/(a - 2/3)}`` for ``e^{-...}`` (the
integrals I_1, I_2 with b are then right).  For sigma = -1 replace f by -f (b changes sign).

Reactions (1.110), corrected (substituting alpha'' of (1.108) in (1.105), f_A = f_B = f):

    R_A^n = m/(1 + f^2) [ ((a l f/(a - 2/3) - f l) c - (a l f^2/(a - 2/3) + l) s) alpha'^2
            - g/(a - 2/3) (c - f s)((a f^2 - 1) s + a f c) + f g ],
    R_B^n = m/(1 + f^2) [ -((a l f/(a - 2/3) - f l) s + (a l f^2/(a - 2/3) + l) c) alpha'^2
            + g/(a - 2/3) (s + f c)((a f^2 - 1) s + a f c) + g ].

**Misprints (1.110)**: in R_A^n the last factor is printed ``(a f^2 - 1) s + a c`` (f missing);
R_B^n's alpha'^2 coefficient is printed ``-(a/2 - 1) l f s + (a f^2/2 + 1) l c`` -- a/2 for
a/(a - 2/3) and the wrong sign of the cos term (garbled); the rest is right.  ``run`` evaluates
both printed forms along the simulated motion.

The stop, the slide back, the release.  Rising (sigma = -1) the ladder stops where the
quadrature gives alpha'^2 = 0 (alpha_s, time by quadrature); it slides back iff
tan(alpha_s) > 2 f_B/(1 - f_A f_B) (static friction cannot hold it; 0.5830 rad here), then falls
(sigma = +1) from rest at alpha_s along the quadrature, and leaves the wall where R_A^n of
(1.110) vanishes (alpha_r: root of R_A^n(alpha, alpha'^2(alpha)); t_r by quadrature).  ``run``
compares alpha_s, t_s, alpha_r, t_r with the library's events ("reverse" -- the slip
velocities vanish and change sign without sticking -- and "lift-off" of the wall),
alpha'^2(alpha) of (1.109) with the simulated motion in both phases, R_A^n, R_B^n with (1.110)
and (1.106) with the simulated alpha'' for unequal f_A, f_B.  Painleve's split: the constraint parts of the reactions are the
smooth reactions at the same state (R_A = m(3/4 g s c - l s alpha'^2), R_B = m g - m(3/4 g s^2 +
l c alpha'^2)), whatever f -- Manglieva & Beknazarov's answer to Appell ("the normal component depends on the
tangential one" holds for the physical normal forces, not for the constraint forces).  After
the release the ladder slides on the floor and lands flat (plastic impact with friction at A:
the energy balance includes the impact); ``run`` checks that it ends at rest with all its
energy dissipated by friction and the impact.

Forms.  While both ends slide, both contacts are non-ideal rows which every form keeps with its
multiplier, so ``compare_forms`` in the physical representation compares Lagrange I with itself
(bit-identical) and only the Gauss solver is independent.  The non-trivial cross-check is the
Manglieva & Beknazarov's representation (``--friction painleve``: both contacts ideal, friction as ``M V mu``,
mu from the split of the physical reaction): every form eliminates the contacts there and must
give the physical accelerations (``run``: 3e-15).  Both ends sticking, the rows are dependent
(four on three coordinates: both no-slip rows say alpha' = 0) and the reactions of a ladder at
rest are statically indeterminate: it stays at rest iff some distribution satisfies both
friction cones, and the library reports the one with the widest margins
(:mod:`nonideal.modes.indeterminate`); at alpha = 0.4 (tested) F_A = 0, R_A^n = (m g/2) tan(alpha),
R_B^n = m g, F_B = -R_A^n, the wall's margin f_A R_A^n binding (steeper, F_A > 0 balances the
two margins).  The forms agree on the accelerations (the reduced ones are derived without the
dependent row).  A stronger push (alpha0 = 0.7,
alpha0' = -1.2) stops the ladder below alpha_lim and static friction holds it (tested).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from ..modeling.bodies import PlanarBody
from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "appell-ladder-rough"
ORDER = 41
TITLE = ("Ladder sliding on a rough wall and floor: equation of motion, its quadrature, the "
         "reactions, release from the wall (Manglieva & Beknazarov 2022, (1.106)-(1.110))")
FILE = "appell_ladder_rough.toml"

KEYS = ("m", "l", "g", "f_A", "f_B", "alpha0", "alphad0")


def build(m: float = 2.0, l: float = 1.25, g: float = 9.81, f_A: float = 0.3, f_B: float = 0.3,
          alpha0: float = 0.9, alphad0: float = -1.0, t_end: float = 0.9, top: bool = True) -> Model:
    """The ladder with the Python API (same as the model file for the default values);
    ``top=False`` leaves out the contact of A with the floor."""
    contacts = [Contact("wall", "x - l*sin(alpha)", ("y' - l*sin(alpha)*alpha'",), Coulomb("f_A")),
                Contact("floor", "y - l*cos(alpha)", ("x' + l*cos(alpha)*alpha'",), Coulomb("f_B"))]
    if top:
        contacts.append(Contact("top", "y + l*cos(alpha)", ("x' - l*cos(alpha)*alpha'",), Coulomb("f_B")))
    return Model(
        name="Appell's ladder: rough wall and floor",
        coordinates=["x", "y", "alpha"],
        parameters={"m": m, "l": l, "g": g, "f_A": f_A, "f_B": f_B, "alpha0": alpha0, "alphad0": alphad0},
        bodies=[PlanarBody("ladder", "m", "m*l^2/3", ["x", "y"], "alpha")],
        gravity=["0", "-g"],
        contacts=contacts,
        initial={"x": "l*sin(alpha0)", "y": "l*cos(alpha0)", "alpha": "alpha0",
                 "x'": "l*cos(alpha0)*alphad0", "y'": "-l*sin(alpha0)*alphad0", "alpha'": "alphad0"},
        simulation={"t_end": t_end},
    )


def state(alpha, alphad, l):
    """Both ends in contact: the state for ``evaluate(at=...)``."""
    return {"x": l * np.sin(alpha), "y": l * np.cos(alpha), "alpha": alpha,
            "x'": l * np.cos(alpha) * alphad, "y'": -l * np.sin(alpha) * alphad, "alpha'": alphad}


# ------------------------------------------------------------------ (1.105)-(1.106), any f_A, f_B

def alpha_dd_1_106(alpha, alphad, sigma, p):
    """alpha'' of (1.106) (J = m l^2/3), friction coefficients sigma f_A, sigma f_B."""
    m, l, g = p["m"], p["l"], p["g"]
    fA, fB = sigma * p["f_A"], sigma * p["f_B"]
    s, c = np.sin(alpha), np.cos(alpha)
    d = 1 + fA * fB
    lhs = m * l * l * 4 / 3 + 2 * l * l * m * ((fA - fB) * s * c - fA * fB) / d
    rhs = 2 * m * l * l * (fA * s * s + fB * c * c) * alphad ** 2 / d - 2 * m * l * fB * g * (fA * s + c) / d \
        + m * g * l * s
    return rhs / lhs


def normal_forces_1_105(alpha, alphad, alphadd, sigma, p):
    """``(R_A^n, R_B^n)`` of (1.105), friction coefficients sigma f_A, sigma f_B."""
    m, l, g = p["m"], p["l"], p["g"]
    fA, fB = sigma * p["f_A"], sigma * p["f_B"]
    s, c = np.sin(alpha), np.cos(alpha)
    d = 1 + fA * fB
    RB = -m / d * (l * (s + fA * c) * alphadd + l * (c - fA * s) * alphad ** 2 - g)
    RA = m / d * ((c - fB * s) * l * alphadd - l * (fB * c + s) * alphad ** 2 + fB * g)
    return RA, RB


def smooth_reactions(alpha, alphad, p):
    """The reactions of the smooth ladder at the same state (Manglieva & Beknazarov's f = 0 formulas)."""
    m, l, g = p["m"], p["l"], p["g"]
    s, c = np.sin(alpha), np.cos(alpha)
    return m * (0.75 * g * c * s - l * s * alphad ** 2), m * g - m * (0.75 * g * s * s + l * c * alphad ** 2)


def alpha_limit(p):
    """The ladder can rest at alpha iff tan(alpha) <= 2 f_B/(1 - f_A f_B)."""
    return float(np.arctan2(2 * p["f_B"], 1 - p["f_A"] * p["f_B"]))


# ------------------------------------------------------------------ f_A = f_B = f: (1.108)-(1.110)

def _coefficients(sigma, p):
    f = p["f_A"]
    fe = sigma * f
    a = 2 / (1 + f * f)
    k = 2 * a * fe / (a - 2 / 3)                    # = -b of the paper
    P, Q = a * f * f - 1, a * fe
    K0 = 2 * p["g"] / (p["l"] * (2 / 3 - a))
    A = K0 * (Q - k * P) / (1 + k * k)
    B = -K0 * (P + k * Q) / (1 + k * k)
    return a, fe, k, P, Q, A, B


def _particular(alpha, sigma, p):
    _, _, _, _, _, A, B = _coefficients(sigma, p)
    return A * np.sin(alpha) + B * np.cos(alpha)


def rate2(alpha, alpha_ref, rate2_ref, sigma, p):
    """alpha'^2 of the corrected (1.109) through (alpha_ref, alpha'^2 = rate2_ref), written
    without cancellation near a stop: ``F(a) - F(a_ref) + r e^{k d} - F(a_ref) expm1(k d)``."""
    _, _, k, _, _, A, B = _coefficients(sigma, p)
    d = np.asarray(alpha, float) - alpha_ref
    h = np.sin(d / 2)
    mid = alpha_ref + d / 2
    dF = 2 * h * (A * np.cos(mid) - B * np.sin(mid))
    F_ref = A * np.sin(alpha_ref) + B * np.cos(alpha_ref)
    return dF + rate2_ref * np.exp(k * d) - F_ref * np.expm1(k * d)


def rate2_printed(alpha, alpha0, alphad0, p):
    """(1.109) as printed (g^2, e^{b alpha}, C = e^{-b alpha0}[...]), sigma = +1."""
    f, g, l = p["f_A"], p["g"], p["l"]
    a = 2 / (1 + f * f)
    b = -2 * a * f / (a - 2 / 3)

    def bracket(al):
        return g * g / (l * (1 + b * b) * (2 / 3 - a)) * (((a * f * f - 1) * b + a * f) * np.sin(al)
                                                          + (b * a * f - (a * f * f - 1)) * np.cos(al))
    C = np.exp(-b * alpha0) * (alphad0 ** 2 - bracket(alpha0))
    return bracket(alpha) + C * np.exp(b * alpha)


def alpha_dd_1_108(alpha, r2, sigma, p):
    """alpha'' of (1.108) (sigma = -1: f -> -f)."""
    a, fe, *_ = _coefficients(sigma, p)
    f = p["f_A"]
    return (a * fe * r2 - p["g"] / p["l"] * ((a * f * f - 1) * np.sin(alpha) + a * fe * np.cos(alpha))) / (a - 2 / 3)


def reactions_1_110(alpha, r2, sigma, p):
    """``(R_A^n, R_B^n)`` of the corrected (1.110) (sigma = -1: f -> -f)."""
    a, fe, *_ = _coefficients(sigma, p)
    f2 = p["f_A"] ** 2
    m, l, g = p["m"], p["l"], p["g"]
    s, c = np.sin(alpha), np.cos(alpha)
    e = a - 2 / 3
    tail = (a * f2 - 1) * s + a * fe * c
    RA = m / (1 + f2) * (((a * l * fe / e - fe * l) * c - (a * l * f2 / e + l) * s) * r2
                         - g / e * (c - fe * s) * tail + fe * g)
    RB = m / (1 + f2) * (-((a * l * fe / e - fe * l) * s + (a * l * f2 / e + l) * c) * r2
                         + g / e * (s + fe * c) * tail + g)
    return RA, RB


def reactions_1_110_printed(alpha, r2, p):
    """(1.110) as printed (sigma = +1)."""
    f = p["f_A"]
    m, l, g = p["m"], p["l"], p["g"]
    a = 2 / (1 + f * f)
    e = a - 2 / 3
    s, c = np.sin(alpha), np.cos(alpha)
    RA = m / (1 + f * f) * (((a * l * f / e - f * l) * c - (a * l * f * f / e + l) * s) * r2
                            - g / e * (c - f * s) * ((a * f * f - 1) * s + a * c) + f * g)
    RB = m / (1 + f * f) * ((-(a / 2 - 1) * l * f * s + (a * f * f / 2 + 1) * l * c) * r2
                            + g / e * (s + f * c) * ((a * f * f - 1) * s + a * f * c) + g)
    return RA, RB


def _time_from_rest(alpha_ref, alpha_end, sigma, p):
    """Time between the rest point alpha_ref and alpha_end on the branch sigma of (1.109)
    (alpha = alpha_ref +- u^2 removes the square-root singularity at the rest point)."""
    _, _, k, _, _, A, B = _coefficients(sigma, p)
    D = abs((A * np.cos(alpha_ref) - B * np.sin(alpha_ref)) - k * (A * np.sin(alpha_ref) + B * np.cos(alpha_ref)))
    side = 1.0 if alpha_end > alpha_ref else -1.0

    def integrand(u):
        if u == 0.0:
            return 2 / np.sqrt(D)
        return 2 * u / np.sqrt(rate2(alpha_ref + side * u * u, alpha_ref, 0.0, sigma, p))
    return quad(integrand, 0.0, np.sqrt(abs(alpha_end - alpha_ref)), epsabs=1e-14, epsrel=1e-14, limit=200)[0]


def closed_form(p: dict) -> dict:
    """Stop, slide back and release from the quadrature (f_A = f_B, pushed up: alphad0 < 0)."""
    a0, ad0 = p["alpha0"], p["alphad0"]
    if p["f_A"] != p["f_B"] or not ad0 < 0:
        raise ValueError("closed form: f_A = f_B and a push with alpha0' < 0 (B approaching O)")

    def rising(al):
        return rate2(al, a0, ad0 * ad0, -1.0, p)
    lo = a0
    while rising(lo) > 0:
        lo -= 0.01
    alpha_s = brentq(rising, lo, a0, xtol=1e-15, rtol=1e-15)
    t_s = _time_from_rest(alpha_s, a0, -1.0, p)         # rising: the branch sigma = -1
    slides_back = bool(np.tan(alpha_s) > 2 * p["f_B"] / (1 - p["f_A"] * p["f_B"]))
    out = {"alpha_stop": float(alpha_s), "t_stop": float(t_s), "slides_back": slides_back,
           "alpha_limit": alpha_limit(p)}
    if not slides_back:          # static friction holds the ladder at alpha_s
        return out

    def wall(al):
        r2 = rate2(al, alpha_s, 0.0, 1.0, p)
        return reactions_1_110(al, r2, 1.0, p)[0]
    hi = alpha_s + 0.01
    while wall(hi) > 0:
        hi += 0.01
    alpha_r = brentq(wall, hi - 0.01, hi, xtol=1e-15, rtol=1e-15)
    t_r = _time_from_rest(alpha_s, alpha_r, 1.0, p)
    out.update({"alpha_release": float(alpha_r), "t_release": float(t_s + t_r),
                "alphad_release": float(np.sqrt(rate2(alpha_r, alpha_s, 0.0, 1.0, p)))})
    return out


# ------------------------------------------------------------------ checks

def random_sliding_states(count=12, seed=3):
    """``(alpha, alpha')`` with both signs of alpha'."""
    rng = np.random.default_rng(seed)
    return [(rng.uniform(0.4, 1.2), rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 1.5)) for _ in range(count)]


def check_1_106(f_A=0.2, f_B=0.45, count=12) -> dict:
    """(1.105)-(1.106) (with sigma f_A, sigma f_B) vs the library at random states where both
    ends slide, unequal coefficients; also the split's constraint parts vs the smooth
    reactions, and Manglieva & Beknazarov's sigma = +1 equation wrongly used for alpha' < 0."""
    from ..analysis.evaluation import evaluate

    model = build(f_A=f_A, f_B=f_B, top=False)
    p = model.parameter_values
    err = {"alpha_dd": 0.0, "R_n": 0.0, "split": 0.0}
    wrong_direction = np.inf
    used = 0
    for alpha, alphad in random_sliding_states(count):
        ev = evaluate(model, at=state(alpha, alphad, p["l"]))
        if "separated" in ev.mode:
            continue
        used += 1
        sigma = float(np.sign(alphad))
        add = alpha_dd_1_106(alpha, alphad, sigma, p)
        RA, RB = normal_forces_1_105(alpha, alphad, add, sigma, p)
        scale = p["m"] * p["g"]
        err["alpha_dd"] = max(err["alpha_dd"], abs(ev.qdd[2] - add) / abs(add))
        err["R_n"] = max(err["R_n"], abs(ev.contacts["wall"]["normal"] - RA) / scale,
                         abs(ev.contacts["floor"]["normal"] - RB) / scale)
        SA, SB = smooth_reactions(alpha, alphad, p)
        err["split"] = max(err["split"], abs(ev.contacts["wall"]["constraint_multiplier"] - SA) / scale,
                           abs(ev.contacts["floor"]["constraint_multiplier"] - SB) / scale)
        if sigma < 0:
            wrong_direction = min(wrong_direction, abs(ev.qdd[2] - alpha_dd_1_106(alpha, alphad, 1.0, p)))
    return {"states": used, "errors": err, "printed_equation_backwards_min_error": float(wrong_direction)}


def painleve_representation(count=8) -> float:
    """Manglieva & Beknazarov's representation (contacts as ideal constraints + friction M V mu, the
    ``--friction painleve`` model) in every form, with mu from the split of the physical
    reaction at random states: the accelerations must be the physical ones.  A non-trivial
    cross-check of the forms here: in the physical representation both sliding contacts are
    non-ideal rows kept by every form."""
    from ..analysis.evaluation import evaluate
    from ..equations.formalisms import FORMS
    from ..analysis.contact.friction_law import painleve_model

    model = build(f_A=0.2, f_B=0.45, top=False)
    p = model.parameter_values
    pm, mus = painleve_model(model)
    J = p["m"] * p["l"] ** 2 / 3
    worst = 0.0
    for alpha, alphad in random_sliding_states(count, seed=5):
        at = state(alpha, alphad, p["l"])
        ev = evaluate(model, at=at)
        if "separated" in ev.mode:
            continue
        fp = sum(np.array(r["friction_part"]) for r in ev.reactions.values())
        mu = fp[2] / J            # M V mu with V = (l cos, -l sin, 1): the alpha component is J mu
        assert np.allclose(fp, mu * np.array([p["m"] * p["l"] * np.cos(alpha), -p["m"] * p["l"] * np.sin(alpha), J]))
        for form in list(FORMS) + ["gauss"]:
            e = evaluate(pm, at=at, form=form, parameters={mus[0]: mu})
            worst = max(worst, float(np.max(np.abs(e.qdd - ev.qdd)) / np.max(np.abs(ev.qdd))))
    return worst


def along(traj, cf, p) -> dict:
    """alpha'^2 of (1.109) and the reactions (1.110) along the simulated motion: rising
    (t < t_stop, sigma = -1) and sliding back (t_stop < t < t_release, sigma = +1)."""
    t = traj.t
    al, ald = traj.coordinate("alpha"), traj.velocity("alpha")
    NA, NB = np.array(traj.contacts["wall"]["normal"]), np.array(traj.contacts["floor"]["normal"])
    up = (t > 0) & (t < cf["t_stop"] - 1e-6)
    down = (t > cf["t_stop"] + 1e-6) & (t < cf["t_release"] - 1e-6)
    scale = p["m"] * p["g"]
    r_up = rate2(al[up], p["alpha0"], p["alphad0"] ** 2, -1.0, p)
    r_down = rate2(al[down], cf["alpha_stop"], 0.0, 1.0, p)
    out = {"samples": (int(up.sum()), int(down.sum()))}
    out["rate2 (1.109)"] = float(max(np.max(np.abs(ald[up] ** 2 - r_up)), np.max(np.abs(ald[down] ** 2 - r_down))))
    RA_u, RB_u = reactions_1_110(al[up], r_up, -1.0, p)
    RA_d, RB_d = reactions_1_110(al[down], r_down, 1.0, p)
    out["reactions (1.110)"] = float(max(np.max(np.abs(NA[up] - RA_u)), np.max(np.abs(NB[up] - RB_u)),
                                         np.max(np.abs(NA[down] - RA_d)), np.max(np.abs(NB[down] - RB_d)))) / scale
    out["alpha_dd (1.108)"] = float(max(
        np.max(np.abs(traj.qdd[up, 2] - alpha_dd_1_108(al[up], ald[up] ** 2, -1.0, p))),
        np.max(np.abs(traj.qdd[down, 2] - alpha_dd_1_108(al[down], ald[down] ** 2, 1.0, p)))))
    # the printed formulas on the slide back (Manglieva & Beknazarov's case, sigma = +1)
    out["printed (1.109)"] = float(np.max(np.abs(ald[down] ** 2 - rate2_printed(al[down], cf["alpha_stop"], 0.0, p))))
    RA_p, RB_p = reactions_1_110_printed(al[down], ald[down] ** 2, p)
    out["printed R_A (1.110)"] = float(np.max(np.abs(NA[down] - RA_p))) / scale
    out["printed R_B (1.110)"] = float(np.max(np.abs(NB[down] - RB_p))) / scale
    out["min R_A, R_B before release"] = float(min(np.min(NA[up | down]), np.min(NB[up | down])))
    return out


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    cf = closed_form(p)
    traj = simulate(model, times=np.linspace(0.0, model.simulation.t_end, 361))
    ev = [(e["t"], e["type"], e["contact"], e["mode"]) for e in traj.events]
    kinds = [(e[1], e[2]) for e in ev]
    stop = next(e for e in traj.events if e["type"] == "reverse")
    release = next(e for e in traj.events if e["type"] == "lift-off")
    full = simulate(model, t_end=0.9)          # states exactly at the events
    alpha_at = {e["type"]: float(full.q[int(np.searchsorted(full.t, e["t"])), 2]) for e in full.events}
    err_t = max(abs(stop["t"] / cf["t_stop"] - 1), abs(release["t"] / cf["t_release"] - 1))
    err_alpha = max(abs(alpha_at["reverse"] - cf["alpha_stop"]), abs(alpha_at["lift-off"] - cf["alpha_release"]))
    mode_after_stop = stop["mode"]
    al = along(traj, cf, p)
    c106 = check_1_106()
    rep = painleve_representation()
    forms = compare_forms(build(top=False), contact_state="slide").worst()
    W, E = traj.energy["friction_work"], traj.energy["energy"]
    d = traj.diagnostics
    # after the release: sliding on the floor, landing flat (plastic impact with friction at A)
    land = simulate(model, t_end=1.2)
    touch = next((e for e in land.events if e["type"] == "touch"), None)
    dl = land.diagnostics
    E_land = land.energy
    at_rest_flat = (abs(land.q[-1, 2] - np.pi / 2) < 1e-9 and np.max(np.abs(land.qd[-1])) < 1e-9)
    checks = [kinds[:2] == [("reverse", "wall"), ("lift-off", "wall")], cf["slides_back"],
              mode_after_stop.startswith("wall:slide-, floor:slide+"), err_t < 1e-9, err_alpha < 1e-9,
              al["rate2 (1.109)"] < 1e-8, al["reactions (1.110)"] < 1e-9, al["alpha_dd (1.108)"] < 1e-9,
              al["printed (1.109)"] > 1e-2, al["printed R_A (1.110)"] > 1e-3, al["printed R_B (1.110)"] > 1e-3,
              al["min R_A, R_B before release"] > 0, c106["states"] >= 8, max(c106["errors"].values()) < 1e-10,
              c106["printed_equation_backwards_min_error"] > 1e-2, rep < 1e-10, forms < 1e-10,
              float(np.max(np.diff(W))) <= 1e-12, abs((E[-1] - E[0]) - W[-1]) < 1e-8 * abs(E[0]),
              d["energy_balance_relative"] < 1e-8, d["constraint_residual_max"] < 1e-8,
              touch is not None, at_rest_flat, dl["energy_balance_relative"] < 1e-8]
    result = {"ok": bool(all(checks)), "closed_form": cf, "events": ev,
              "alpha_at_events": alpha_at, "event_times_relative_error": float(err_t),
              "event_angles_error": float(err_alpha), "along_motion": al, "check_1_106": c106,
              "painleve_representation_forms": rep, "forms_physical_representation": forms,
              "friction_work": float(W[-1]), "energy_change": float(E[-1] - E[0]),
              "energy_balance_relative": d["energy_balance_relative"],
              "constraint_residual_max": d["constraint_residual_max"],
              "landing": {"t": touch["t"] if touch else None,
                          "impact_energy_change": float(E_land["impact_work"][-1]),
                          "friction_work": float(E_land["friction_work"][-1]),
                          "final_energy": float(E_land["energy"][-1]),
                          "energy_balance_relative": dl["energy_balance_relative"], "at_rest_flat": at_rest_flat}}
    if verbose:
        print(TITLE)
        print(f"m = {p['m']}, 2l = {2 * p['l']}, f_A = f_B = {p['f_A']}, pushed at alpha0 = {p['alpha0']} with "
              f"alpha0' = {p['alphad0']} (B approaches O, as the paper states)")
        print(f"(a) (1.105)-(1.106) with sigma f_A, sigma f_B (f_A = 0.2, f_B = 0.45, {c106['states']} states, "
              f"both directions): alpha'' {c106['errors']['alpha_dd']:.1e}, "
              f"R_A^n, R_B^n {c106['errors']['R_n']:.1e}; Manglieva & Beknazarov's (sigma = +1) equation used for alpha' < 0 "
              f"is off by >= {c106['printed_equation_backwards_min_error']:.3f}")
        print("    constraint parts of the split = smooth reactions at the same state: "
              f"{c106['errors']['split']:.1e}")
        print(f"(b) rises (friction reversed) and stops: alpha_s = {cf['alpha_stop']:.12f}, t_s = {cf['t_stop']:.12f}"
              f" (quadrature); library {alpha_at['reverse']:.12f} at {stop['t']:.12f}")
        print(f"    tan(alpha_s) = {np.tan(cf['alpha_stop']):.6f} > 2 f_B/(1 - f_A f_B) = "
              f"{2 * p['f_B'] / (1 - p['f_A'] * p['f_B']):.6f}: slides back; mode after the stop: {mode_after_stop}")
        print(f"(c) leaves the wall (R_A^n = 0 in (1.110)): alpha_r = {cf['alpha_release']:.12f}, t_r = "
              f"{cf['t_release']:.12f}; library {alpha_at['lift-off']:.12f} at {release['t']:.12f}")
        print(f"    relative error of the event times {err_t:.1e}, of the angles {err_alpha:.1e}")
        print(f"(d) along the motion ({al['samples'][0]} rising, {al['samples'][1]} falling samples): "
              f"max |alpha'^2 - (1.109)| {al['rate2 (1.109)']:.1e}, |alpha'' - (1.108)| "
              f"{al['alpha_dd (1.108)']:.1e}, |R - (1.110)|/mg {al['reactions (1.110)']:.1e}")
        print(f"    as printed: (1.109) off by {al['printed (1.109)']:.3f} 1/s^2, R_A (1.110) by "
              f"{al['printed R_A (1.110)']:.3f} mg, R_B by {al['printed R_B (1.110)']:.3f} mg (misprints)")
        print(f"(e) Manglieva & Beknazarov's representation (contacts ideal + M V mu) in every form vs the physical "
              f"accelerations: {rep:.1e}; compare_forms (physical, sliding) {forms:.1e}")
        print(f"(f) friction work {W[-1]:.10f} J = energy change {E[-1] - E[0]:.10f} J; balance "
              f"{d['energy_balance_relative']:.1e}, residual {d['constraint_residual_max']:.1e}")
        if touch:
            print(f"(g) lands flat at t = {touch['t']:.10f} (plastic impact with friction, energy change "
                  f"{E_land['impact_work'][-1]:.6f} J) and stays at rest: {at_rest_flat}; balance "
                  f"{dl['energy_balance_relative']:.1e}")
        print("ok" if result["ok"] else "FAILED")
    return result
