"""Plots of a trajectory: coordinates, velocities, reactions, energy balance, modes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["plot_trajectory", "mode_colors", "angle_coordinates"]

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


def angle_coordinates(model) -> set[str]:
    """The coordinates that are angles: a planar body's ``angle``, or a coordinate inside the
    argument of a trigonometric function anywhere in the model (the rest are lengths)."""
    import sympy as sp

    if model is None:
        return set()
    names = set(model.coordinates)
    found: set[str] = set()
    exprs = [model.kinetic, model.potential, *model.forces.values()] if isinstance(model.forces, dict) \
        else [model.kinetic, model.potential]
    for b in model.bodies:
        if getattr(b, "angle", None) is not None:
            found |= {s.name for s in sp.sympify(b.angle).free_symbols} & names
        exprs += [*getattr(b, "position", ()), *(x for row in (getattr(b, "rotation", None) or ()) for x in row)]
    exprs += [c.expr for c in model.constraints] + [c.gap for c in model.contacts]
    exprs += [u for c in model.contacts for u in c.slip]
    trig = (sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)
    for e in exprs:
        for f in sp.sympify(e).atoms(*trig):
            found |= {s.name for s in f.args[0].free_symbols} & names
    return found


def plot_trajectory(traj, path, title: str | None = None, model=None) -> None:
    """Write a PNG: the coordinates and velocities (lengths and angles on separate axes, with
    units: rad for angles, "model units" otherwise -- the library does not convert units), the
    multipliers and contact forces (named: normal, friction along each slip direction), the
    energy terms, the energy balance residual in its own panel, and the contact modes.

    Event times are marked with vertical lines; contact modes (when there are contacts) are
    drawn as a timeline whose legend, above the bars, lists the states that occur
    (:func:`mode_colors`).  *model* tells the angles from the lengths.
    """
    has_contacts = bool(traj.contacts)
    angles = angle_coordinates(model)
    lengths = [c for c in traj.coordinates if c not in angles]
    kinds = [("lengths", lengths, "model units"), ("angles", [c for c in traj.coordinates if c in angles], "rad")]
    kinds = [k for k in kinds if k[1]]
    panels = 2 * len(kinds) + 3 + (1 if has_contacts else 0)
    fig, axes = plt.subplots(panels, 1, figsize=(8, 2.1 * panels), sharex=True)
    t = traj.t
    index = {c: i for i, c in enumerate(traj.coordinates)}
    tt, q = _hermite(t, traj.q, traj.qd)
    tv, qd = _hermite(t, traj.qd, traj.qdd)
    k = 0
    for kind, names, unit in kinds:
        ax = axes[k]
        for c in names:
            ax.plot(tt, q[:, index[c]], label=c)
        ax.set_ylabel(f"{kind} ({unit})")
        ax.legend(loc="best", fontsize=8, ncol=min(4, len(names)))
        ax = axes[k + 1]
        for c in names:
            ax.plot(tv, qd[:, index[c]], label=c + "'")
        ax.set_ylabel(f"{'velocities' if kind == 'lengths' else 'angular velocities'} "
                      f"({unit}/time unit)" if unit != "rad" else "angular velocities (rad/time unit)")
        ax.legend(loc="best", fontsize=8, ncol=min(4, len(names)))
        k += 2
    ax = axes[k]
    for name, values in traj.multipliers.items():
        ax.plot(t, values, label=f"multiplier {name}")
    for name, c in traj.contacts.items():
        ax.plot(t, c["normal"], label=f"normal force {name}")
        fr = np.asarray(c["friction"], dtype=float)
        if fr.ndim == 2:
            for j in range(fr.shape[1]):
                along = "" if fr.shape[1] == 1 else f" along slip {j + 1}"
                ax.plot(t, fr[:, j], "--", label=f"friction {name}{along}")
    ax.set_ylabel("reactions (model units)")
    if ax.lines:
        ax.legend(loc="best", fontsize=8, ncol=2)
    ax = axes[k + 1]
    e = traj.energy
    ax.plot(t, e["kinetic"], label="T")
    ax.plot(t, e["potential"], label="V")
    if np.any(e["friction_work"]):
        ax.plot(t, e["friction_work"], label="friction work")
    if np.any(e["reaction_work"]):
        ax.plot(t, e["reaction_work"], label="reaction work")
    if np.any(e.get("impact_work", 0)):
        ax.plot(t, e["impact_work"], label="impact work")
    ax.set_ylabel("energy (model units)")
    ax.legend(loc="best", fontsize=8)
    ax = axes[k + 2]
    ax.plot(t, e["balance"], color="0.4", lw=0.8)
    ax.set_ylabel("energy balance\nresidual")
    if has_contacts:
        ax = axes[k + 3]
        names = list(traj.contacts)
        colors = mode_colors(traj)
        for j, name in enumerate(names):
            modes = traj.contacts[name]["mode"]
            start = 0
            for i in range(1, len(t) + 1):
                if i == len(t) or modes[i] != modes[start]:
                    ax.barh(j, t[min(i, len(t) - 1)] - t[start], left=t[start],
                            color=colors[modes[start].replace("(N<0)", "")], edgecolor="none")
                    start = i
        ax.set_yticks(range(len(names)), names)
        handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colors.values()]
        ax.legend(handles, list(colors), fontsize=7, ncol=len(colors), loc="lower left",
                  bbox_to_anchor=(0.0, 1.0), frameon=False)     # above the bars, never on them
        ax.set_ylabel("contact mode")
    for a in axes:
        for ev in traj.events:
            a.axvline(ev["t"], color="k", lw=0.5, alpha=0.4)
        a.grid(alpha=0.3)
    axes[-1].set_xlabel("t (time, model units)")
    fig.suptitle(title or traj.model)
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)


def _geometry(model):
    """Numeric functions of (q, params) for what can be drawn: particles (points), planar
    bodies (the segment of the uniform rod with the same mass and central inertia, length
    sqrt(12 J/m), through the centre along the body's angle), rigid bodies (the centre)."""
    import sympy as sp

    q = [sp.Symbol(c) for c in model.coordinates]
    params = [sp.Symbol(p) for p in model.parameter_values]
    t = sp.Symbol("t")
    shapes = []
    for b in model.bodies:
        pos = [sp.sympify(x) for x in b.position][:2]
        if len(pos) < 2:
            continue
        f_pos = sp.lambdify([t, q, params], pos, "numpy")
        if getattr(b, "angle", None) is not None and getattr(b, "inertia", None) is not None:
            length = sp.sqrt(12 * sp.sympify(b.inertia) / sp.sympify(b.mass))
            f_ang = sp.lambdify([t, q, params], [sp.sympify(b.angle), length], "numpy")
            shapes.append((b.name, "segment", f_pos, f_ang))
        else:
            shapes.append((b.name, "point", f_pos, None))
    return shapes


def animate_trajectory(traj, model, path, frames: int = 80, fps: int = 20) -> None:
    """Write an animation of the motion (``.gif`` with Pillow, ``.mp4`` with ffmpeg): the
    bodies drawn from the model's geometry (:func:`_geometry`), the contacts listed with their
    mode coloured as in the plot's timeline, the time in the title."""
    from matplotlib import animation

    shapes = _geometry(model)
    if not shapes:
        from .errors import ModelError

        raise ModelError("--animate: the model has no [[bodies]] to draw (its energy is written "
                         "out); give the bodies' geometry in [[bodies]]")
    p = list(model.parameter_values.values())
    idx = np.unique(np.linspace(0, len(traj.t) - 1, min(frames, len(traj.t))).round().astype(int))
    drawn = []
    for k in idx:
        items = []
        for name, kind, f_pos, f_ang in shapes:
            x, y = (float(v) for v in f_pos(traj.t[k], traj.q[k], p))
            if kind == "segment":
                ang, length = (float(v) for v in f_ang(traj.t[k], traj.q[k], p))
                dx, dy = 0.5 * length * np.cos(ang), 0.5 * length * np.sin(ang)
                items.append(([x - dx, x + dx], [y - dy, y + dy]))
            else:
                items.append(([x], [y]))
        drawn.append(items)
    xs = [v for fr in drawn for it in fr for v in it[0]]
    ys = [v for fr in drawn for it in fr for v in it[1]]
    span = max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
    pad = 0.1 * span
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.set_xlim(min(xs) - pad, max(xs) + pad)
    ax.set_ylim(min(ys) - pad, max(ys) + pad)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlabel("x (model units)")
    ax.set_ylabel("y (model units)")
    artists = []
    for name, kind, _, _ in shapes:
        (line,) = ax.plot([], [], "-o" if kind == "segment" else "o", lw=3, ms=5, label=name)
        artists.append(line)
    colors = mode_colors(traj) if traj.contacts else {}
    labels = [ax.text(0.02, 0.97 - 0.06 * j, "", transform=ax.transAxes, fontsize=9, va="top",
                      bbox=dict(boxstyle="round", fc="white", ec="0.6"))
              for j, _ in enumerate(traj.contacts)]
    title = ax.set_title("")

    def update(i):
        k = idx[i]
        for line, (xv, yv) in zip(artists, drawn[i]):
            line.set_data(xv, yv)
        for label, (name, c) in zip(labels, traj.contacts.items()):
            mode = c["mode"][k].replace("(N<0)", "")
            label.set_text(f"contact {name}: {mode}")
            label.get_bbox_patch().set_facecolor(colors.get(mode, "white"))
        title.set_text(f"{traj.model}   t = {traj.t[k]:.3f}")
        return [*artists, *labels, title]

    anim = animation.FuncAnimation(fig, update, frames=len(idx), blit=False)
    suffix = str(path).rsplit(".", 1)[-1].lower()
    writer = animation.PillowWriter(fps=fps) if suffix == "gif" else animation.FFMpegWriter(fps=fps)
    anim.save(str(path), writer=writer)
    plt.close(fig)
