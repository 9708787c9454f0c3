"""A flexible arm on a cart: an elastic member (a Bubnov–Galerkin beam) coupled to a rigid body.

Sources: Yushkov 1999, ch. I §5 (the natural frequencies of an elastic system with distributed
parameters from Lagrange's equations of its parts, the multipliers being the forces between
them) and appendix E (the Bubnov–Galerkin approximations as solutions by the Gauss principle
on a family of admissible motions); Timoshenko 1955, *Vibration problems in engineering*,
§§ 59–62 (the uniform beam, its end conditions and the frequency equations); Meirovitch 1967,
*Analytical methods in vibrations*, ch. 5 (Rayleigh–Ritz: the approximate frequencies are upper
bounds that decrease as shape functions are added).

Model.  A cart of mass M on a horizontal track, tied to a wall by a spring k (coordinate x);
clamped on it, a uniform Euler–Bernoulli arm (length L, mass per length rho A, bending
stiffness EI) in the horizontal plane, with a mass m at its free end.  The arm's deflection
relative to the cart, ``w(s, t) = sum a_k(t) phi_k(s/L)`` with ``phi_k`` polynomials that
vanish with their slope at the clamp, adds the coordinates ``arm_1 .. arm_N``; the library forms

    T = (M + rho A L + m) x'^2 / 2 + x' c . a' + a'^T M_a a' / 2 + m (x' + w'(L))^2 / 2 ...,
    V = k x^2 / 2 + a^T K a / 2,   K_ij = EI/L^3 int phi_i'' phi_j'' d xi,

exactly (the file's [[members]] table; ``nonideal check`` prints the tip point).

Closed form.  The absolute deflection ``W(s) = x + w`` of a mode ``e^{i omega t}`` solves
``EI W'''' = rho A omega^2 W``: ``W = A cos bs + B sin bs + C cosh bs + D sinh bs`` with
``b^4 = rho A omega^2 / EI``, and the four end conditions

    W'(0) = 0,  EI W'''(0) = (M omega^2 - k) W(0),  W''(L) = 0,  EI W'''(L) = -m omega^2 W(L)

(the clamp turns with the cart, which does not turn; the shear force of the arm drives the cart
against its spring; the tip mass loads the free end) give a 4x4 determinant whose roots are
the exact frequencies (:func:`exact_frequencies`).  The Galerkin frequencies lie above them
and converge: with the defaults, 4 shape functions give the lowest two to 1e-5 relative.

Run it: ``nonideal stability elastic_arm_on_cart.toml --at "x=0"`` (the frequencies) and
``nonideal simulate elastic_arm_on_cart.toml`` (the cart released from x = 1 cm: energy is
conserved, and every form of the equations gives the same accelerations).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

NAME = "elastic-arm-on-cart"
ORDER = 240
TITLE = "Flexible arm on a cart: a Bubnov-Galerkin beam member, frequencies against the exact determinant"
FILE = "elastic_arm_on_cart.toml"
DEFAULTS = dict(M=2.0, k=200.0, L=1.0, rho_A=0.5, EI=10.0, m_tip=0.25)


def build(modes: int = 4, **params) -> "Model":
    """The arm on the cart with the Python API (the model file's system for the defaults)."""
    from ..modeling.bodies import Particle
    from ..modeling.frames import Frame
    from ..modeling.members import Member
    from ..modeling.model import Model
    from ..modeling.points import Point

    return Model(
        name="Flexible arm on a cart", coordinates=["x"], parameters={**DEFAULTS, **params},
        potential="k/2*x^2",
        frames=[Frame("B", axis=["0", "0", "1"], angle="pi/2")],
        points=[Point("cart", ["x", "0", "0"])],
        members=[Member("arm", "beam", "L", "EI", ("clamped", "free"), modes, mass_per_length="rho_A",
                        frame="B", origin="cart", points={"tip": "L"})],
        bodies=[Particle("cart", "M", point="cart"), Particle("tip_mass", "m_tip", point="tip")],
        initial={"x": 0.01, "x'": 0.0}, simulation={"t_end": 1.0},
    )


def frequency_matrix(b: float, M: float, k: float, L: float, rho_A: float, EI: float,
                     m_tip: float) -> np.ndarray:
    """The 4x4 matrix of the end conditions (module docstring) on (A, B, C, D) at ``b``."""
    w2 = EI * b ** 4 / rho_A
    c, s, ch, sh = np.cos(b * L), np.sin(b * L), np.cosh(b * L), np.sinh(b * L)
    e3 = EI * b ** 3
    return np.array([
        [0.0, 1.0, 0.0, 1.0],
        [-(M * w2 - k), -e3, -(M * w2 - k), e3],
        [-c, -s, ch, sh],
        [e3 * s + m_tip * w2 * c, -e3 * c + m_tip * w2 * s, e3 * sh + m_tip * w2 * ch,
         e3 * ch + m_tip * w2 * sh],
    ])


def exact_frequencies(count: int = 3, **params) -> np.ndarray:
    """The lowest *count* exact natural frequencies (rad/s): the roots of the determinant."""
    p = {**DEFAULTS, **params}

    def det(b):
        A = frequency_matrix(b, **p)
        return np.linalg.det(A / np.abs(A).max(axis=1, keepdims=True))

    grid = np.linspace(1e-3, (count + 2) * np.pi / p["L"], 4000 * (count + 2))
    values = [det(b) for b in grid]
    roots = [brentq(det, grid[i], grid[i + 1], xtol=1e-14)
             for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0]
    return np.array([b ** 2 * (p["EI"] / p["rho_A"]) ** 0.5 for b in roots[:count]])


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.stability.frequencies import natural_frequencies
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    found = natural_frequencies(model, at={"x": 0})
    exact = exact_frequencies(3)
    rel = (np.array(found.omega[:2]) - exact[:2]) / exact[:2]
    traj = simulate(model)
    energy = traj.energy["energy"]
    drift = float(np.abs(energy - energy[0]).max() / abs(energy[0]))
    ok = bool(np.all(rel >= -1e-9) and np.all(rel < 1e-4) and drift < 1e-7)
    if verbose:
        print(f"Galerkin frequencies (4 shapes): {np.round(found.omega[:3], 6)} rad/s")
        print(f"exact (frequency determinant):   {np.round(exact, 6)} rad/s")
        print(f"relative excess of the lowest two: {rel}  (upper bounds)")
        print(f"energy drift over {traj.t[-1]:g} s: {drift:.2e}")
    return {"ok": ok, "frequencies": list(found.omega), "exact": exact.tolist(),
            "relative_excess": rel.tolist(), "energy_drift": drift}
