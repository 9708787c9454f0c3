"""An inverted double pendulum on a cart, stabilized by LQR; the nonlinear closed loop.

Classic control benchmark.  Cart (mass mc, position x, force u), two point masses m1, m2 on
massless rods l1, l2, angles th1, th2 from the upward vertical.  The upright equilibrium is
unstable (two real positive eigenvalues); x is kept in the state (``keep=["x"]``) so that the
regulator also brings the cart back.

Optimal stabilization (Letov, Kalman; Krasovskii): u = -K x minimizes
int (x^T Q x + u^T R u) dt, K = R^-1 B^T P with P from the algebraic Riccati equation, and
V = x^T P x is the closed loop's Lyapunov function.  The library computes K with
python-control (``control.lqr``); run() checks it against SciPy's independent Riccati solver,
checks that the closed-loop eigenvalues are those of A - B K and lie in the left half-plane,
and simulates the *nonlinear* model with the feedback u = -K (x - x0) written into its
[forces]: from th1 = 0.1 rad the pendulum comes back upright (t = 20), and a small perturbation follows
the linear closed-loop solution exp((A - B K) t) x0.

    nonideal stability double-pendulum-cart-lqr --controls u --keep x --lqr 1,1
"""

from __future__ import annotations

import numpy as np

from ..modeling.bodies import Particle
from ..modeling.model import Model

NAME = "double-pendulum-cart-lqr"
ORDER = 203
TITLE = "Inverted double pendulum on a cart: LQR gain, Lyapunov function, nonlinear closed loop"
FILE = "double_pendulum_cart_lqr.toml"


def build(mc: float = 1.0, m1: float = 0.5, m2: float = 0.5, l1: float = 0.6, l2: float = 0.6,
          g: float = 9.81, u: float = 0.0) -> Model:
    """The cart with the Python API (same as the model file for the default values)."""
    return Model(
        name="inverted double pendulum on a cart", coordinates=["x", "th1", "th2"],
        parameters={"mc": mc, "m1": m1, "m2": m2, "l1": l1, "l2": l2, "g": g, "u": u},
        bodies=[Particle("cart", "mc", ["x", "0"]),
                Particle("P1", "m1", ["x + l1*sin(th1)", "l1*cos(th1)"]),
                Particle("P2", "m2", ["x + l1*sin(th1) + l2*sin(th2)", "l1*cos(th1) + l2*cos(th2)"])],
        gravity=["0", "-g"], forces={"x": "u"},
        initial={"x": 0.0, "th1": 0.0, "th2": 0.0, "x'": 0.0, "th1'": 0.0, "th2'": 0.0},
        simulation={"t_end": 5.0})


def run(verbose: bool = True) -> dict:
    from scipy.linalg import expm, solve_continuous_are

    from ..analysis.stability.control import lqr, simulate_closed_loop
    from ..analysis.stability.linearize import linearize
    from . import load

    model = load(NAME)
    lin = linearize(model, controls=["u"], keep=["x"])
    reg = lqr(lin, 1.0, 1.0)
    P = solve_continuous_are(lin.A, lin.B, np.eye(6), np.eye(1))
    K_ref = lin.B.T @ P
    gain_err = float(np.max(np.abs(reg.K - K_ref)) / np.max(np.abs(K_ref)))
    cl = np.linalg.eigvals(lin.A - lin.B @ reg.K)
    cl_err = max(min(abs(z - c) for c in reg.closed_loop_eigenvalues) for z in cl)
    Pr = reg.P
    riccati = float(np.max(np.abs(lin.A.T @ Pr + Pr @ lin.A - Pr @ lin.B @ lin.B.T @ Pr + np.eye(6))))
    big = simulate_closed_loop(model, lin, reg, {"th1": 0.1}, t_end=20.0, times=[0.0, 10.0, 20.0])
    final = float(np.max(np.abs(big.q[-1])))
    eps = 1e-4
    times = np.linspace(0.0, 2.0, 5)
    small = simulate_closed_loop(model, lin, reg, {"th1": eps}, t_end=2.0, times=times)
    x0 = np.zeros(6)
    x0[lin.variables.index("th1")] = eps
    linear = np.array([expm((lin.A - lin.B @ reg.K) * t) @ x0 for t in times])[:, :3]
    follow = float(np.max(np.abs(small.q - linear)) / eps)
    ok = (lin.verdict == "unstable" and lin.controllability == {"rank": 6, "n": 6} and gain_err < 1e-6
          and riccati < 1e-6 * np.abs(Pr).max()
          and cl_err < 1e-8 and max(cl.real) < 0 and final < 1e-3 and follow < 1e-3)
    out = {"open_loop": [[z.real, z.imag] for z in lin.eigenvalues], "K": reg.K.tolist(),
           "gain_error_vs_scipy": gain_err, "riccati_residual": riccati, "closed_loop": [[z.real, z.imag] for z in reg.closed_loop_eigenvalues],
           "final_deviation_from_0.1rad": final, "linear_vs_nonlinear": follow, "ok": bool(ok)}
    if verbose:
        print(TITLE)
        print("  open loop eigenvalues: " + ", ".join(f"{z.real:.6g}" for z in lin.eigenvalues))
        print(f"  K = {np.array2string(reg.K, precision=5)} (vs SciPy's Riccati solution: {gain_err:.1e})")
        print("  closed loop: " + ", ".join(f"{z.real:.5g}{z.imag:+.5g}i" for z in reg.closed_loop_eigenvalues))
        print(f"  Riccati residual |A'P + PA - PBR^-1B'P + Q| = {riccati:.1e}")
        print(f"  nonlinear closed loop from th1 = 0.1 rad: max |q| at t = 20 is {final:.2e}")
        print(f"  small perturbation: nonlinear vs exp((A - BK) t) x0: {follow:.2e} of it")
        print(f"  ok: {ok}")
    return out
