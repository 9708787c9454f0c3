"""Plots of a trajectory: coordinates, velocities, reactions, energy balance, modes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["plot_trajectory", "mode_colors"]

#: colours of the contact states in the mode timeline ("(N<0)" labels take their state's colour)
PALETTE = {"separated": "#dddddd", "stick": "#2a9d8f", "slide+": "#e76f51", "slide-": "#f4a261",
           "slide": "#e9c46a", "smooth": "#8ab17d"}


def mode_colors(traj) -> dict[str, str]:
    """The contact states that occur in *traj*, with their colours (the timeline's legend).

    Examples
    --------
    >>> from nonideal import gallery, simulate
    >>> mode_colors(simulate(gallery.load("block-on-incline")))
    {'stick': '#2a9d8f', 'slide+': '#e76f51'}
    """
    seen = {label.replace("(N<0)", "") for c in traj.contacts.values() for label in c["mode"]}
    return {state: color for state, color in PALETTE.items() if state in seen}


def _hermite(t: np.ndarray, y: np.ndarray, dy: np.ndarray, points: int = 12):
    """Curves through the samples for drawing: cubic Hermite interpolation of ``y`` with its
    derivative ``dy`` between consecutive samples (the samples are the integrator's steps,
    too far apart for straight segments); a repeated time (a jump at an event) stays a jump.

    Returns ``(t, y)`` with ``points - 1`` points inserted in every interval.
    """
    if len(t) < 2:
        return t, y
    s = np.linspace(0.0, 1.0, points + 1)[:-1]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    ts, ys = [], []
    for k in range(len(t) - 1):
        h = t[k + 1] - t[k]
        if h <= 0:
            ts.append(t[k:k + 1])
            ys.append(y[k:k + 1])
            continue
        ts.append(t[k] + h * s)
        ys.append(np.outer(h00, y[k]) + np.outer(h10 * h, dy[k]) + np.outer(h01, y[k + 1])
                  + np.outer(h11 * h, dy[k + 1]))
    ts.append(t[-1:])
    ys.append(y[-1:])
    return np.concatenate(ts), np.vstack(ys)


def plot_trajectory(traj, path, title: str | None = None) -> None:
    """Write a PNG with the coordinates, velocities, multipliers/contact forces, energy and,
    for servo-constraints, the control forces with their work.

    Event times are marked with vertical lines; contact modes (when there are contacts) are
    drawn as a timeline whose legend lists the states that occur (:func:`mode_colors`).
    """
    has_contacts = bool(traj.contacts)
    controls = getattr(traj, "controls", {}) or {}
    panels = 4 + (1 if has_contacts else 0) + (1 if controls else 0)
    fig, axes = plt.subplots(panels, 1, figsize=(8, 2.3 * panels), sharex=True)
    t = traj.t
    ax = axes[0]
    tt, q = _hermite(t, traj.q, traj.qd)
    for i, c in enumerate(traj.coordinates):
        ax.plot(tt, q[:, i], label=c)
    ax.set_ylabel("coordinates")
    ax.legend(loc="best", fontsize=8, ncol=min(4, len(traj.coordinates)))
    ax = axes[1]
    tt, qd = _hermite(t, traj.qd, traj.qdd)
    for i, c in enumerate(traj.coordinates):
        ax.plot(tt, qd[:, i], label=c + "'")
    ax.set_ylabel("velocities")
    ax.legend(loc="best", fontsize=8, ncol=min(4, len(traj.coordinates)))
    ax = axes[2]
    for name, values in traj.multipliers.items():
        ax.plot(t, values, label=f"λ {name}")
    for name, c in traj.contacts.items():
        ax.plot(t, c["normal"], label=f"N {name}")
        fr = np.asarray(c["friction"], dtype=float)
        if fr.ndim == 2:
            for k in range(fr.shape[1]):
                ax.plot(t, fr[:, k], "--", label=f"F {name}[{k}]")
    ax.set_ylabel("reactions")
    if ax.lines:
        ax.legend(loc="best", fontsize=8, ncol=2)
    ax = axes[3]
    e = traj.energy
    ax.plot(t, e["kinetic"], label="T")
    ax.plot(t, e["potential"], label="V")
    if np.any(e["friction_work"]):
        ax.plot(t, e["friction_work"], label="friction work")
    if np.any(e["reaction_work"]):
        ax.plot(t, e["reaction_work"], label="reaction work")
    if np.any(e.get("impact_work", 0)):
        ax.plot(t, e["impact_work"], label="impact work")
    ax2 = ax.twinx()
    ax2.plot(t, e["balance"], color="0.5", lw=0.8, label="balance residual")
    ax2.set_ylabel("balance residual", color="0.5")
    ax.set_ylabel("energy")
    ax.legend(loc="best", fontsize=8)
    if controls:
        ax = axes[4]
        for name, c in controls.items():
            ax.plot(t, c["force"], label=f"u {name}")
        ax.set_ylabel("control force")
        ax2 = ax.twinx()
        for name, c in controls.items():
            ax2.plot(t, c["work"], "--", lw=0.9, label=f"work of u {name}")
        ax2.set_ylabel("control work")
        handles = ax.get_lines() + ax2.get_lines()
        ax.legend(handles, [h.get_label() for h in handles], loc="best", fontsize=8)
    if has_contacts:
        ax = axes[-1]
        names = list(traj.contacts)
        colors = mode_colors(traj)
        for k, name in enumerate(names):
            modes = traj.contacts[name]["mode"]
            start = 0
            for j in range(1, len(t) + 1):
                if j == len(t) or modes[j] != modes[start]:
                    ax.barh(k, t[min(j, len(t) - 1)] - t[start], left=t[start],
                            color=colors[modes[start].replace("(N<0)", "")], edgecolor="none")
                    start = j
        ax.set_yticks(range(len(names)), names)
        handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colors.values()]
        ax.legend(handles, list(colors), fontsize=7, ncol=len(colors), loc="upper right")
        ax.set_ylabel("contact mode")
    for a in axes:
        for ev in traj.events:
            a.axvline(ev["t"], color="k", lw=0.5, alpha=0.4)
        a.grid(alpha=0.3)
    axes[-1].set_xlabel("t")
    fig.suptitle(title or traj.model)
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)


def plot_stability(result, path) -> None:
    """The eigenvalues of a linearization in the complex plane (the stability boundary is the
    imaginary axis); for a programmed motion the logarithmic norm mu(A(t)) and the real parts
    of the frozen eigenvalues against t (Persidsky's bound needs int mu dt < 0)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    if hasattr(result, "lognorm"):
        t = np.asarray(result.t)
        ax.plot(t, result.lognorm, label="logarithmic norm mu(A(t))")
        re = np.array([np.sort(np.linalg.eigvals(A).real)[::-1] for A in result.A])
        for k in range(re.shape[1]):
            ax.plot(t, re[:, k], "--", lw=1, label=f"Re eig {k + 1} of A(t) (frozen)")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel("t")
        ax.set_title(f"{result.model}: {result.verdict}")
        ax.legend(fontsize=8)
    else:
        eig = np.asarray(result.eigenvalues)
        ax.axvline(0.0, color="k", lw=0.8)
        ax.axhline(0.0, color="k", lw=0.5)
        ax.plot(eig.real, eig.imag, "x", ms=9, mew=2, label="eigenvalues of A")
        reg = getattr(result, "closed_loop", None)
        if reg is not None:
            ax.plot(reg.real, reg.imag, "o", mfc="none", label="closed loop (LQR)")
        ax.set_xlabel("Re s")
        ax.set_ylabel("Im s")
        ax.set_title(f"{result.model}: {result.verdict}")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
