"""Optimal stabilization (LQR) of a linearized motion and the nonlinear closed loop.

For ``x' = A x + B u`` (a :class:`~nonideal.analysis.stability.linearize.Linearization` with controls)
and the cost ``I = int (x^T Q x + u^T R u) dt`` the optimal feedback is ``u = -K x`` with
``K = R^-1 B^T P``, ``P`` the solution of the algebraic Riccati equation
``A^T P + P A - P B R^-1 B^T P + Q = 0`` (computed by python-control, ``control.lqr``).
``V = x^T P x`` is the Lyapunov (Bellman) function of the closed loop: ``V' = -(x^T Q x +
u^T R u) < 0`` (Krasovskii's optimal stabilization; Manglieva & Beknazarov 2022, (3.33)--(3.37)).

The feedback is applied to the *nonlinear* model: each control parameter in ``[forces]`` is
replaced by ``-K (x - x0)``, ``x`` the perturbation variables named by the linearization
(coordinates and velocities of the model), and the closed loop is simulated by the library.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import sympy as sp

from ...errors import ModelError
from ...modeling.model import Model

__all__ = ["Regulator", "lqr", "closed_loop_model", "simulate_closed_loop", "weights", "ProgramRegulator",
           "program_lqr"]


@dataclass(frozen=True)
class Regulator:
    """The LQR feedback ``u = -K x`` of a linearization.

    Attributes
    ----------
    variables, controls : tuple of str
    Q : ndarray, shape (n_x, n_x)
    R : ndarray, shape (n_u, n_u)
    K : ndarray, shape (n_u, n_x)
        The gain.
    P : ndarray, shape (n_x, n_x)
        The Riccati solution: the Lyapunov function ``V = x^T P x``.
    closed_loop_eigenvalues : ndarray of complex
    x0 : dict name -> float
        The state the perturbations are measured from.
    """

    variables: tuple
    controls: tuple
    Q: np.ndarray
    R: np.ndarray
    K: np.ndarray
    P: np.ndarray
    closed_loop_eigenvalues: np.ndarray
    x0: dict

    def feedback(self) -> dict:
        """``{control: "-(k1*(x - x0) + ...)"}`` as text."""
        out = {}
        for i, u in enumerate(self.controls):
            text = ""
            for j, name in enumerate(self.variables):
                k = -self.K[i, j]
                var = f"({name} - {self.x0[name]:.12g})" if self.x0[name] else name
                text += (" - " if k < 0 else " + ") + f"{abs(k):.12g}*{var}"
            out[u] = text.strip().lstrip("+ ").replace("- ", "-", 1) if text.strip().startswith("-") else text.strip().lstrip("+ ")
        return out

    def lyapunov(self) -> str:
        """``V = x^T P x`` written out."""
        n = len(self.variables)
        parts = []
        for i in range(n):
            for j in range(i, n):
                c = self.P[i, j] * (1 if i == j else 2)
                if abs(c) > 1e-14 * np.abs(self.P).max():
                    a, b = self.variables[i], self.variables[j]
                    parts.append((" - " if c < 0 else " + ") + (f"{abs(c):.6g}*{a}^2" if i == j else f"{abs(c):.6g}*{a}*{b}"))
        text = "".join(parts).strip()
        return text[2:] if text.startswith("+ ") else "-" + text[2:]

    def as_text(self) -> str:
        fb = "; ".join(f"{u} = {e}" for u, e in self.feedback().items())
        return "\n".join([
            "optimal stabilization (LQR, cost int x'Qx + u'Ru dt):",
            "  gain K = " + str(np.array2string(self.K, precision=6)),
            "  feedback: " + fb,
            "  Lyapunov function V = " + self.lyapunov(),
            "  closed-loop eigenvalues: " + ", ".join(
                f"{z.real:.6g}" + (f" {'+' if z.imag > 0 else '-'} {abs(z.imag):.6g}i" if abs(z.imag) > 1e-12 else "")
                for z in self.closed_loop_eigenvalues)])

    def to_dict(self) -> dict:
        return {
            "Q": self.Q.tolist(), "R": self.R.tolist(), "K": self.K.tolist(), "P": self.P.tolist(),
            "closed_loop_eigenvalues": [[float(z.real), float(z.imag)] for z in self.closed_loop_eigenvalues],
            "feedback": self.feedback(), "lyapunov": self.lyapunov(),
        }


def weights(text: str, n_x: int, n_u: int) -> tuple[np.ndarray, np.ndarray]:
    """``--lqr Q,R``: numbers (``Q I``, ``R I``) or diagonals separated by ``;`` (``"1;1;10;10,0.1"``)."""
    parts = [p.strip() for p in str(text).split(",")]
    example = "--lqr 1,0.1 (Q = I, R = 0.1 I) or --lqr \"1;1;10;10,0.1\" (Q = diag(1, 1, 10, 10))"
    if len(parts) != 2:
        raise ModelError(f"--lqr: expected Q,R (got {text!r}); e.g. {example}")
    out = []
    for part, size, name in ((parts[0], n_x, "Q"), (parts[1], n_u, "R")):
        try:
            vals = [float(x) for x in part.split(";")]
        except ValueError:
            raise ModelError(f"--lqr: {name} = {part!r} is not a number or a ';'-list of numbers; e.g. {example}") from None
        if len(vals) == 1:
            vals = vals * size
        if len(vals) != size:
            raise ModelError(f"--lqr: {name} has {len(vals)} diagonal entries, the system needs {size}; e.g. {example}")
        if any(not np.isfinite(v) or v < 0 for v in vals) or (name == "R" and any(v <= 0 for v in vals)):
            raise ModelError(f"--lqr: {name} must be {'positive' if name == 'R' else 'non-negative'} (got {part!r})")
        out.append(np.diag(vals))
    return out[0], out[1]


def lqr(lin, Q=1.0, R=1.0) -> Regulator:
    """The LQR regulator of *lin* (``control.lqr``).

    Parameters
    ----------
    lin : Linearization
        With ``controls``.
    Q, R : float or array
        Weights (a number means that multiple of the identity).
    """
    import control

    if not lin.controls:
        raise ModelError("--lqr: the linearization has no controls; name the parameters that act "
                         "as inputs with --controls (they must enter [forces])")
    A, B = np.asarray(lin.A, float), np.asarray(lin.B, float)
    n, m = A.shape[0], B.shape[1]
    Q = np.eye(n) * Q if np.ndim(Q) == 0 else np.asarray(Q, float)
    R = np.eye(m) * R if np.ndim(R) == 0 else np.asarray(R, float)
    ctrl = lin.controllability or {}
    if ctrl and ctrl.get("rank", n) < n:
        from ...errors import LinearizationUndefined
        raise LinearizationUndefined(
            f"the system is not controllable (Kalman rank {ctrl['rank']} of {n}): no feedback of "
            f"{', '.join(lin.controls)} stabilizes every variable; choose other controls")
    K, P, E = control.lqr(A, B, Q, R)
    x0 = {}
    for name in lin.variables:
        x0[name] = lin.qdot[name[:-1]] if name.endswith("'") else lin.q[name]
    return Regulator(tuple(lin.variables), tuple(lin.controls), Q, R, np.asarray(K, float),
                     np.asarray(P, float), np.asarray(E, complex), x0)


def closed_loop_model(model: Model, reg: Regulator) -> Model:
    """*model* with each control parameter replaced in ``[forces]`` (and the potential) by the
    feedback ``-K (x - x0)``."""
    syms = {name: sp.Symbol(name) for name in model.coordinates}
    syms.update({name + "'": sp.Symbol(name + "'") for name in model.coordinates})
    law = {}
    for i, u in enumerate(reg.controls):
        law[sp.Symbol(u)] = -sum(sp.Float(reg.K[i, j]) * (syms[name] - sp.Float(reg.x0[name]))
                                 for j, name in enumerate(reg.variables))
    elsewhere = []
    for u in law:
        for what, expr in (("[energy] kinetic", model.kinetic),):
            if u in sp.sympify(expr).free_symbols:
                elsewhere.append(f"{u} in {what}")
        for c in model.constraints:
            if u in sp.sympify(c.expr).free_symbols:
                elsewhere.append(f"{u} in constraint '{c.name}'")
    if elsewhere:
        raise ModelError(f"closed loop: a control must enter only [forces] or the potential ({'; '.join(elsewhere)})")
    forces = tuple(sp.sympify(f).xreplace(law) for f in model.forces)
    potential = sp.sympify(model.potential).xreplace(law)
    return model.replace(forces=forces, potential=potential, name=model.name + " (LQR closed loop)")


def simulate_closed_loop(model: Model, lin, reg: Regulator, perturbation: Mapping[str, float],
                         t_end: float, times: Sequence[float] | None = None, **options):
    """Simulate the nonlinear closed loop from the linearized state plus *perturbation*
    (``{variable: delta}``).  Returns the :class:`Trajectory`."""
    from ...simulation import simulate

    cl = closed_loop_model(model, reg)
    initial = {}
    for name in model.coordinates:
        initial[name] = lin.q[name]
        initial[name + "'"] = lin.qdot[name]
    for key, d in perturbation.items():
        if key not in initial:
            raise ModelError(f"perturbation: '{key}' is not a coordinate or velocity")
        initial[key] += d
    for key in lin.dependent:       # completed from the constraints by the simulation
        initial.pop(key, None)
    return simulate(cl.replace(initial=initial), t_end=t_end, times=times, **options)


@dataclass(frozen=True)
class ProgramRegulator:
    """Optimal stabilization of a programmed motion on ``[t0, T]``: the differential Riccati
    equation ``-P' = A^T P + P A - P B R^-1 B^T P + Q``, ``P(T) = 0``, integrated backwards
    along ``A(t), B(t)``; ``K(t) = R^-1 B^T P(t)``; ``V = x^T P(t) x`` is the Lyapunov (Bellman)
    function (Manglieva & Beknazarov 2022, (3.35)--(3.37)).

    Attributes
    ----------
    t : ndarray, shape (N,)
    P : ndarray, shape (N, n_x, n_x)
    K : ndarray, shape (N, n_u, n_x)
    exponent_open, exponent_closed : float
        ``ln |Phi(T, t0)| / (T - t0)`` of the open and the closed loop (``A - B K``).
    """

    t: np.ndarray
    P: np.ndarray
    K: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    exponent_open: float
    exponent_closed: float


def program_lqr(prog, Q=1.0, R=1.0) -> ProgramRegulator:
    """The finite-horizon LQR of a :class:`~nonideal.analysis.stability.program.ProgramLinearization`
    with controls (see :class:`ProgramRegulator`)."""
    from scipy.integrate import solve_ivp
    from scipy.interpolate import CubicSpline

    if not prog.controls:
        raise ModelError("optimal stabilization: the programmed motion has no controls; name them "
                         "with --controls")
    t = np.asarray(prog.t)
    n, m = prog.A.shape[1], prog.B.shape[2]
    Q = np.eye(n) * Q if np.ndim(Q) == 0 else np.asarray(Q, float)
    R = np.eye(m) * R if np.ndim(R) == 0 else np.asarray(R, float)
    Ri = np.linalg.inv(R)
    As = CubicSpline(t, prog.A.reshape(len(t), -1), axis=0)
    Bs = CubicSpline(t, prog.B.reshape(len(t), -1), axis=0)

    def riccati(s, p):
        A, B = As(s).reshape(n, n), Bs(s).reshape(n, m)
        P = p.reshape(n, n)
        return -(A.T @ P + P @ A - P @ B @ Ri @ B.T @ P + Q).ravel()

    sol = solve_ivp(riccati, (t[-1], t[0]), np.zeros(n * n), t_eval=t[::-1], rtol=1e-10, atol=1e-12,
                    method="DOP853")
    P = sol.y.T[::-1].reshape(len(t), n, n)
    P = 0.5 * (P + P.transpose(0, 2, 1))
    K = np.einsum("ij,tkj,tkl->til", Ri, prog.B, P)
    Ks = CubicSpline(t, K.reshape(len(t), -1), axis=0)

    def exponent(closed: bool) -> float:
        def rhs(s, y):
            A = As(s).reshape(n, n)
            if closed:
                A = A - Bs(s).reshape(n, m) @ Ks(s).reshape(m, n)
            return (A @ y.reshape(n, n)).ravel()
        y = solve_ivp(rhs, (t[0], t[-1]), np.eye(n).ravel(), rtol=1e-10, atol=1e-12, method="DOP853").y[:, -1]
        return float(np.log(np.linalg.norm(y.reshape(n, n), 2)) / (t[-1] - t[0]))

    return ProgramRegulator(t, P, K, Q, R, exponent(False), exponent(True))
