"""Stability of a programmed motion: the first approximation ``x' = A(t) x + B(t) u`` along it.

The programmed (servo) motion is followed by the simulation from the model's initial state;
at each sample time the reduced ``A(t)``, ``B(t)`` are computed as for an equilibrium
(:mod:`nonideal.analysis.stability.linearize`: the perturbations stay on the constraint manifold --
the servo-constraints included, so the programme's own constraint drift is not reported as
instability).  A servo-constraint whose control reaches the program only through the dynamics
(relative degree above 1: the friction speed regulator, Manglieva & Beknazarov 2022, (3.3)) is
linearized on the closed loop: its last condition of dynamics stands for it as a row (the control
solved from it), and the program with its earlier conditions -- which the closed loop holds but
does not restore -- restrict the perturbations like the other constraints (the perturbed motions
keep the program, (3.11)); they are named in ``held``.  For a non-autonomous first approximation the eigenvalues of ``A(t)`` decide
nothing; the verdict uses

* Persidsky's criterion (Manglieva & Beknazarov 2022, (3.13)): the first approximation is
  uniformly asymptotically stable when its solutions obey ``|x(t)| <= B e^(-alpha (t - t0))``
  for every ``t0``; a sufficient bound is the logarithmic norm
  ``mu(A) = lambda_max((A + A^T)/2)``: ``|x(t)| <= |x(t0)| exp(int mu dt)`` (Wazewski), so
  ``int_t0^t mu <= -alpha (t - t0) + beta`` over the interval proves it (for one variable this
  is exactly Persidsky's condition);
* the fundamental matrix ``Phi(t, t0)`` (integrated with ``A(t)`` interpolated between the
  samples): its largest characteristic exponent estimate ``ln |Phi(T)| / (T - t0)``.

Controllability of the time-varying system (Krasovskii): ``W(t) = [L1, ..., Ln]`` with
``L1 = B``, ``L(i+1) = dLi/dt - A(t) Li`` (Manglieva & Beknazarov 2022, (3.30)--(3.31)); the
derivatives come from splines through the samples.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ...errors import MechanicsError, ModelError
from ...modeling.model import Model
from .linear_system import Point, check_parameters, clean, ignorable_set, kernel_of, partition, state_matrices
from .routh import analyse

__all__ = ["ProgramLinearization", "linearize_program", "persidsky_bound", "controllability_loss"]


@dataclass(frozen=True)
class ProgramLinearization:
    """``A(t)``, ``B(t)`` along a programmed motion and the verdict (module docstring).

    Attributes
    ----------
    model : str
    t : ndarray, shape (N,)
    variables : tuple of str
    A : ndarray, shape (N, n_x, n_x)
    B : ndarray, shape (N, n_x, n_u)
    q, qdot : dict name -> ndarray (N,)
        The programmed motion at the samples.
    lognorm : ndarray, shape (N,)
        ``mu(A(t))``.
    persidsky_alpha, persidsky_beta : float
        The constants of the bound ``int_s^t mu dt <= -alpha (t - s) + beta`` for every
        sub-interval ``[s, t]`` (:func:`persidsky_bound`): ``alpha > 0`` with a moderate ``beta``
        proves uniform asymptotic stability over the interval.
    average_decay : float
        ``-int mu dt / (T - t0)``, the average decay from t0 (not a uniform bound).
    exponent : float
        ``ln |Phi(T, t0)| / (T - t0)``.
    controllability_rank : ndarray of int, shape (N,)
        Rank of ``W(t)``.
    W : ndarray, shape (N, n_x, n_x * n_u), or None
        ``W(t) = [L1, ..., Ln]`` at the samples (with controls).
    verdict, reason : str
    """

    model: str
    t: np.ndarray
    variables: tuple
    A: np.ndarray
    B: np.ndarray
    controls: tuple
    q: dict
    qdot: dict
    lognorm: np.ndarray
    persidsky_alpha: float
    exponent: float
    controllability_rank: np.ndarray
    verdict: str
    reason: str
    ignorable: tuple = ()
    dependent: tuple = ()
    frozen: dict = field(default_factory=dict)
    persidsky_beta: float = 0.0
    average_decay: float = 0.0
    W: np.ndarray | None = None
    held: tuple = ()

    @property
    def program_note(self) -> str:
        """Why the perturbations are taken on the program when its control acts through the
        dynamics (empty otherwise)."""
        if not self.held:
            return ""
        return ("the control reaches the program only through the dynamics: the closed loop holds the "
                "program's last condition of dynamics, not the program, so a deviation from the "
                "program is neither restored nor amplified by the control (a chain of zero "
                "exponents); the perturbations are taken on the program, as in Manglieva & "
                "Beknazarov 2022, (3.11)")

    def to_dict(self) -> dict:
        n = len(self.variables)
        out = {
            "model": self.model, "about": "program",
            "state": {"q": {k: float(v[0]) for k, v in self.q.items()},
                      "qdot": {k: float(v[0]) for k, v in self.qdot.items()}},
            "variables": list(self.variables), "A": self.A[0].tolist(),
            "eigenvalues": self.frozen.get("eigenvalues", []),
            "verdict": self.verdict, "reason": self.reason,
            "characteristic_polynomial": self.frozen.get("polynomial", ""),
            "hurwitz": self.frozen.get("hurwitz", []), "conditions": [],
            "controllability": {"rank": int(self.controllability_rank.min()) if self.controls else 0, "n": n},
            "t": self.t.tolist(), "A_t": self.A.tolist(), "lognorm": self.lognorm.tolist(),
            "persidsky_alpha": self.persidsky_alpha, "persidsky_beta": self.persidsky_beta,
            "average_decay": self.average_decay, "exponent": self.exponent,
            "ignorable": list(self.ignorable), "dependent": list(self.dependent),
            "held_by_program": [{"name": k, "condition": f"{e} = 0"} for k, e in self.held],
        }
        if self.controls:
            out["controls"] = list(self.controls)
            out["B"] = self.B[0].tolist()
            out["B_t"] = self.B.tolist()
            out["controllability_rank_t"] = self.controllability_rank.tolist()
        return out

    def as_text(self) -> str:
        T = self.t[-1]
        lines = [f"{self.model}: first approximation along the programmed motion, t in [{self.t[0]:g}, {T:g}]",
                 f"  variables: {', '.join(self.variables)}"]
        if self.dependent:
            lines.append(f"  eliminated by the constraints: {', '.join(self.dependent)}")
        if self.ignorable:
            lines.append(f"  ignorable (nothing depends on them): {', '.join(self.ignorable)}")
        if self.held:
            lines.append("  kept on the program: " + "; ".join(f"{k}: {e} = 0" for k, e in self.held)
                         + f" ({self.program_note})")
        for k in sorted({0, len(self.t) // 2, len(self.t) - 1}):
            lines.append(f"  A({self.t[k]:.6g}) = " + np.array2string(self.A[k], precision=6).replace("\n", "\n" + " " * 14))
        lines.append(f"  logarithmic norm mu(A(t)): from {self.lognorm.min():.6g} to {self.lognorm.max():.6g}; "
                     f"uniform bound int_s^t mu dt <= -alpha (t - s) + beta: alpha = "
                     f"{self.persidsky_alpha:.6g}, beta = {self.persidsky_beta:.3g}; average decay "
                     f"-int mu dt/(T - t0) = {self.average_decay:.6g}")
        lines.append(f"  characteristic exponent estimate ln|Phi(T)|/(T - t0) = {self.exponent:.6g}")
        if self.controls:
            lines.append(f"  controllability W(t) = [L1..Ln]: rank {int(self.controllability_rank.min())} "
                         f"to {int(self.controllability_rank.max())} of {len(self.variables)}")
        lines.append(f"  verdict: {self.verdict} -- {self.reason}")
        return "\n".join(lines)


def _lognorm(A: np.ndarray) -> float:
    return float(np.linalg.eigvalsh(0.5 * (A + A.T)).max()) if A.size else 0.0


def persidsky_bound(mu: np.ndarray, times: np.ndarray) -> tuple[float, float, float]:
    """The constants of Persidsky's bound ``int_s^t mu dt <= -alpha (t - s) + beta`` for every
    ``t0 <= s <= t <= T`` (the uniformity the criterion asks for: the same ``alpha``, ``beta``
    from every initial instant), from the logarithmic norm *mu* at the sample *times*.

    With ``beta = 0`` the bound over short sub-intervals forces ``alpha = -max mu`` (the slowest
    instantaneous decay, e.g. the regulator's ``k1/(k rho_max^2)``, Manglieva & Beknazarov
    2022, (3.13)); when that is not positive, ``alpha`` is the average decay ``-int mu / (T -
    t0)`` and ``beta`` the largest rise of ``int mu + alpha t`` over any sub-interval (it is 0
    only when the decay is uniform).  The average alone is not a uniform bound: a decay from
    ``t0`` says nothing about a stretch where ``mu`` is larger.

    Returns
    -------
    alpha, beta, average : float
    """
    integral = _trapezoid(mu, times)
    span = times[-1] - times[0]
    average = -integral[-1] / span if span > 0 else 0.0
    uniform = -float(np.max(mu)) if mu.size else 0.0
    if uniform > 0:
        return uniform, 0.0, average
    J = integral + average * (times - times[0])
    rise = J - np.minimum.accumulate(J)           # J(t) - min_{s <= t} J(s)
    return average, float(max(0.0, rise.max(initial=0.0))), average


def _trapezoid(y, x):
    return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])


def linearize_program(model: Model, t_end: float | None = None, samples: int = 201,
                      controls: Sequence[str] = (), keep: Sequence[str] = (),
                      independent: Sequence[str] | None = None) -> ProgramLinearization:
    """The first approximation along the motion from the model's initial state.

    Parameters
    ----------
    model : Model
    t_end : float, optional
        End of the interval (default: ``[simulation] t_end``).
    samples : int
        Number of sample times.
    controls, keep, independent
        As for :func:`nonideal.analysis.stability.linearize.linearize`.

    Returns
    -------
    ProgramLinearization
    """
    from scipy.integrate import solve_ivp
    from scipy.interpolate import CubicSpline

    from ...simulation import simulate
    check_parameters(model, controls, "--controls")
    t_end = t_end if t_end is not None else model.simulation.t_end
    if t_end is None or not t_end > model.t0:
        raise ModelError(f"--t-end: give the end of the programmed motion (later than t0 = {model.t0:g}), "
                         "or [simulation] t_end")
    times = np.linspace(model.t0, t_end, samples)
    traj = simulate(model, t_end=t_end, times=times)
    if len(traj.t) != len(times) or abs(traj.t[-1] - t_end) > 1e-9 * max(1.0, abs(t_end)):
        raise ModelError(f"the programmed motion stopped at t = {traj.t[-1]:.6g} before --t-end {t_end:g} "
                         f"(events: {[e.get('type') for e in traj.events]}); choose an earlier --t-end")
    values = model.parameter_values
    params = np.array([float(values[n]) for n in model.parameters])
    k = kernel_of(model, tuple(controls))
    n = k.n
    names_q = list(model.coordinates)
    names_v = [c + "'" for c in names_q]
    indep = [names_q.index(c) for c in (independent or model.independent or ()) if c in names_q]
    pt0 = Point(k, params, float(times[0]))
    part = partition(pt0.blocks(traj.q[0], traj.qd[0]), n, indep, model)
    As, Bs = [], []
    for i, t in enumerate(times):
        pt = Point(k, params, float(t))
        _, _, b = pt.motion(traj.q[i], traj.qd[i])
        A, B = state_matrices(b, part, n, True, model)
        As.append(A)
        Bs.append(B)
    As, Bs = np.array(As), np.array(Bs)
    variables = [names_q[j] for j in part.coords_I] + [names_v[j] for j in part.vel_I]
    # ignorable coordinates: nothing else depends on them, all along the motion
    cand = [idx for idx, j in enumerate(part.coords_I) if names_q[j] not in keep]
    S = set(ignorable_set(np.abs(As).max(axis=0), cand))
    stay = [i for i in range(As.shape[1]) if i not in S]
    As = np.array([clean(A[np.ix_(stay, stay)]) for A in As])
    Bs = np.array([clean(B[stay]) for B in Bs])
    nx = len(stay)
    mu = np.array([_lognorm(A) for A in As])
    span = times[-1] - times[0]
    alpha, beta, average = persidsky_bound(mu, times)
    # fundamental matrix with A(t) interpolated
    spline = CubicSpline(times, As.reshape(len(times), -1), axis=0)
    if nx:
        sol = solve_ivp(lambda t, y: (spline(t).reshape(nx, nx) @ y.reshape(nx, nx)).ravel(),
                        (times[0], times[-1]), np.eye(nx).ravel(), rtol=1e-10, atol=1e-12, method="DOP853")
        Phi = sol.y[:, -1].reshape(nx, nx)
        exponent = float(np.log(np.linalg.norm(Phi, 2)) / span)
    else:
        exponent = 0.0
    tol = 1e-6 * max(1.0, float(np.abs(As).max(initial=0.0)))
    if alpha > tol and beta < np.log(1e3):
        verdict = "asymptotically stable"
        reason = (f"int_s^t mu(A) dt <= -alpha (t - s) + beta for every s <= t in the interval with "
                  f"alpha = {alpha:.6g} > 0, beta = {beta:.3g}: Persidsky's criterion (uniform "
                  "exponential decay of the first approximation) holds on the interval computed")
    elif exponent > tol:
        verdict = "unstable"
        reason = (f"the perturbations grow along the motion: ln|Phi(T)|/(T - t0) = {exponent:.6g} > 0 "
                  "(the first approximation's characteristic exponent, estimated on the interval)")
    elif exponent < -tol:
        verdict = "asymptotically stable"
        reason = (f"every perturbation decays along the interval: ln|Phi(T)|/(T - t0) = {exponent:.6g} < 0 "
                  "(the logarithmic-norm bound alone does not prove it: alpha = "
                  f"{alpha:.6g}); an estimate on the interval computed, not a proof")
    else:
        verdict = "critical"
        reason = (f"perturbations neither grow nor decay on the interval (exponent {exponent:.3g}): "
                  "the first approximation does not decide")
    ranks = np.zeros(len(times), int)
    W = None
    if controls and nx:
        bs = CubicSpline(times, Bs.reshape(len(times), -1), axis=0)
        nu = Bs.shape[2]
        Ls = [Bs]
        derivs = [bs]
        for _ in range(nx - 1):
            prev = Ls[-1]
            d = derivs[-1].derivative()(times).reshape(len(times), nx, nu)
            nxt = d - np.einsum("tij,tjk->tik", As, prev)
            Ls.append(nxt)
            derivs.append(CubicSpline(times, nxt.reshape(len(times), -1), axis=0))
        W = np.concatenate(Ls, axis=2)
        for i in range(len(times)):
            sv = np.linalg.svd(W[i], compute_uv=False)
            ranks[i] = int(np.sum(sv > 1e-7 * sv.max())) if sv.max() > 0 else 0
        loss = controllability_loss(times, W, ranks, nx)
        if loss is not None:
            raise _lost_rank(model, loss, times, traj, names_q)
    info = analyse(As[0], variables=[variables[i] for i in stay])
    frozen = {"eigenvalues": [[float(z.real), float(z.imag)] for z in info["eigenvalues"]],
              "polynomial": str(info["polynomial"]), "hurwitz": [float(h) for h in info["hurwitz"]]}
    ign = [part.coords_I[idx] for idx in sorted(S)]
    return ProgramLinearization(
        model=model.name, t=times, variables=tuple(variables[i] for i in stay), A=As, B=Bs,
        controls=tuple(controls), q={c: traj.q[:, j] for j, c in enumerate(names_q)},
        qdot={c: traj.qd[:, j] for j, c in enumerate(names_q)}, lognorm=mu, persidsky_alpha=float(alpha),
        exponent=exponent, persidsky_beta=float(beta), average_decay=float(average),
        controllability_rank=ranks, verdict=verdict, reason=reason, W=W, held=k.held,
        ignorable=tuple(names_q[j] for j in ign),
        dependent=tuple([names_q[j] for j in part.coords_D] + [names_v[j] for j in part.vel_D]), frozen=frozen)


def controllability_loss(times: np.ndarray, W: np.ndarray, ranks: np.ndarray, nx: int) -> float | None:
    """The first instant inside the interval where ``W(t) = [L1, ..., Ln]`` loses the full rank
    it has elsewhere, or None.

    With one control ``W`` is square and its rank drops where ``det W`` changes sign between
    two samples (the instant is interpolated linearly); in any case a sample of lower rank
    between samples of full rank counts.  A ``W`` that is nowhere of full rank is not a loss
    (the rank reported says it).
    """
    if not ranks.size or ranks.max() < nx:
        return None
    if W.shape[1] == W.shape[2]:
        # det W relative to |W|^n: its sign, free of the scale of the variables
        det = np.array([np.linalg.det(w) / max(np.linalg.norm(w, 2), 1e-300) ** nx for w in W])
        for i in range(len(times) - 1):
            a, b = det[i], det[i + 1]
            if a == 0.0 and 0 < i:
                return float(times[i])
            if a * b < 0:
                return float(times[i] - a * (times[i + 1] - times[i]) / (b - a))
    low = np.nonzero(ranks < nx)[0]
    full = np.nonzero(ranks == nx)[0]
    for i in low:
        if full.min() < i < full.max():
            return float(times[i])
    return None


def _lost_rank(model, t_star: float, times, traj, names_q) -> MechanicsError:
    """The error for a first approximation that loses controllability at *t_star*."""
    values = {c: float(np.interp(t_star, times, traj.q[:, j])) for j, c in enumerate(names_q)}
    values.update({c + "'": float(np.interp(t_star, times, traj.qd[:, j])) for j, c in enumerate(names_q)})
    state = ", ".join(f"{c} = {values[c]:.6g}" for c in names_q)
    rates = ", ".join(f"{c}' = {values[c + chr(39)]:.6g}" for c in names_q)
    servo = [c.name for c in model.constraints if c.reaction_kind == "servo"]
    what = (f"the programmed motion of '{model.name}'"
            + (f" (program {', '.join(repr(x) for x in servo)})" if servo else ""))
    return MechanicsError(
        f"{what} loses controllability of its first approximation at t = {t_star:.6g} ({state}; "
        f"{rates}): the matrix W(t) = [L1, ..., Ln], L1 = B, L(i+1) = dLi/dt - A Li (Krasovskii; "
        "Manglieva & Beknazarov 2022, (3.30)-(3.32)) is singular there (det W changes sign), so "
        "'rank W = n' does not hold along the whole motion and the stabilization built on it "
        "fails at that state; analyse an interval that ends before it (--t-end) or starts after it",
        t=t_star, state=values)
