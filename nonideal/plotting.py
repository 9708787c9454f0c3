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


#: the quantity a sweep plots when none is named, by command
SWEEP_QUANTITY = {"realizability": "margin", "check": "determinacy", "stability": "verdict"}


def _sweep_default(result) -> str:
    if result.what in SWEEP_QUANTITY:
        return SWEEP_QUANTITY[result.what]
    ok = next((r for r in result.rows if r["exit_code"] == 0), None)
    if ok is None:
        return "exit_code"
    key = "q" if result.what == "simulate" else "qddot"
    return f"{key}.{next(iter(ok['summary'][key]))}"


def plot_sweep(result, path, quantity: str | None = None) -> None:
    """A quantity of a sweep (:class:`~nonideal.analysis.sweep.SweepResult`) against its one
    varied parameter, or as a map over two (the first on the horizontal axis).

    *quantity* is a column of the sweep's CSV (``q.x``, ``margin``, ``events.count``,
    ``exit_code``...); text values (the type of the first event, a verdict) are drawn as
    categories.  Failed points (exit code != 0) are marked with their exit code."""
    from .analysis.sweep import flatten

    quantity = quantity or _sweep_default(result)
    flat = [flatten(r) for r in result.rows]
    if not any(quantity in f for f in flat):
        from .errors import ModelError, did_you_mean

        columns = sorted({k for f in flat for k in f})
        raise ModelError(f"--quantity {quantity}: not a column of this sweep"
                         f"{did_you_mean(quantity, columns)}; columns: {', '.join(columns)}")
    raw = [f.get(quantity) if r["exit_code"] == 0 or quantity in ("exit_code", "message") else None
           for f, r in zip(flat, result.rows)]
    if quantity == "exit_code":   # codes are categories, not a scale
        raw = [None if v is None else f"exit {v}" for v in raw]
    text = any(isinstance(v, str) for v in raw)
    categories = sorted({v for v in raw if isinstance(v, str)}) if text else []
    values = np.array([np.nan if v is None else (categories.index(v) if text else float(v))
                       for v in raw], dtype=float)
    failed = np.array([r["exit_code"] != 0 for r in result.rows])
    axes = result.axes
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    if len(axes) == 1:
        x = np.array(axes[0].values)
        ax.plot(x, values, "o-" if len(x) < 40 else "-", color="C0")
        if text:
            ax.set_yticks(range(len(categories)), categories)
        for xi, r in zip(x[failed], [r for r, f in zip(result.rows, failed) if f]):
            ax.axvline(xi, color="0.8", lw=0.8)
            ax.annotate(f"exit {r['exit_code']}", (xi, 0), xycoords=("data", "axes fraction"),
                        rotation=90, fontsize=7, va="bottom", color="C3")
        ax.set_xlabel(axes[0].name)
        ax.set_ylabel(quantity)
        ax.grid(alpha=0.3)
    else:
        x, y = np.array(axes[0].values), np.array(axes[1].values)
        Z = values.reshape(len(x), len(y)).T
        if text:
            from matplotlib.colors import ListedColormap

            cmap = ListedColormap(plt.get_cmap("tab10").colors[:max(len(categories), 1)])
        else:
            cmap = plt.get_cmap("viridis")
        mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(Z), shading="nearest", cmap=cmap,
                             vmin=-0.5 if text else None,
                             vmax=(len(categories) - 0.5) if text else None)
        bar = fig.colorbar(mesh, ax=ax, label=quantity)
        if text:
            bar.set_ticks(range(len(categories)), labels=categories)
        elif np.nanmin(Z) < 0 < np.nanmax(Z) and min(len(x), len(y)) > 2:
            ax.contour(x, y, Z, levels=[0.0], colors="k", linewidths=1.2)
        F = failed.reshape(len(x), len(y)).T
        if F.any():
            X, Y = np.meshgrid(x, y)
            codes = np.array([r["exit_code"] for r in result.rows]).reshape(len(x), len(y)).T
            for code in sorted(set(codes[F])):
                sel = F & (codes == code)
                ax.plot(X[sel], Y[sel], "x", color="C3" if code == 3 else "k", ms=5,
                        label=f"exit {code}")
            ax.legend(loc="upper right", fontsize=8)
        ax.set_xlabel(axes[0].name)
        ax.set_ylabel(axes[1].name)
    ax.set_title(f"{result.model}\n{result.what}: {quantity}", fontsize=9)
    fig.savefig(path)
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


def plot_locus(locus: dict, title: str, path) -> None:
    """A parameter study of ``nonideal stability --vary``: with one parameter the root locus
    (eigenvalues in the complex plane coloured by the parameter, and the largest real part
    against it); with two the stable region (asymptotically stable / critical / unstable)."""
    names = list(locus["vary"])
    rows = locus["rows"]
    if len(names) == 1:
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.5))
        vals = np.array([r["parameters"][names[0]] for r in rows])
        for r, v in zip(rows, vals):
            eig = np.array(r["eigenvalues"]).reshape(-1, 2)
            sc = ax1.scatter(eig[:, 0], eig[:, 1], c=np.full(len(eig), v), cmap="viridis",
                             vmin=vals.min(), vmax=vals.max(), s=12)
        fig.colorbar(sc, ax=ax1, label=names[0])
        ax1.axvline(0.0, color="k", lw=0.8)
        ax1.set_xlabel("Re s")
        ax1.set_ylabel("Im s")
        ax1.set_title("root locus")
        worst = [max((e[0] for e in r["eigenvalues"]), default=np.nan) for r in rows]
        ax2.plot(vals, worst, "o-", ms=3)
        ax2.axhline(0.0, color="k", lw=0.8)
        ax2.set_xlabel(names[0])
        ax2.set_ylabel("largest Re s")
    else:
        fig, ax2 = plt.subplots(figsize=(6.4, 5))
        code = {"asymptotically stable": 0, "critical": 1, "unstable": 2, None: 3}
        xs, ys = locus["vary"][names[0]], locus["vary"][names[1]]
        grid = np.array([code[r["verdict"]] for r in rows]).reshape(len(xs), len(ys)).T
        from matplotlib.colors import ListedColormap
        cmap = ListedColormap(["#2a9d8f", "#e9c46a", "#e76f51", "#dddddd"])
        ax2.pcolormesh(xs, ys, grid, cmap=cmap, vmin=-0.5, vmax=3.5, shading="nearest")
        ax2.set_xlabel(names[0])
        ax2.set_ylabel(names[1])
        from matplotlib.patches import Patch
        ax2.legend(handles=[Patch(color=c, label=l) for c, l in zip(cmap.colors, ["asymptotically stable",
                   "critical", "unstable", "undefined"])], fontsize=8, loc="best")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
