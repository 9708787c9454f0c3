"""Plots of a trajectory: coordinates, velocities, reactions, energy balance, modes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["plot_trajectory", "mode_colors", "angle_coordinates", "mode_intervals"]

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
    """The coordinates that are angles (:func:`~nonideal.modeling.units.coordinate_kinds`: the
    model's ``[units] coordinates``, a planar body's or a torque's ``angle``, a trigonometric
    argument, a rotational kinetic energy term ``I q'^2/2``, a name like ``phi`` when nothing
    else decides); the rest are lengths or have units of their own."""
    from .modeling.units import coordinate_kinds

    if model is None:
        return set()
    return {n for n, k in coordinate_kinds(model).items() if k == "angle"}


def _groups(traj, model):
    """``(kind, names, unit, velocity label)`` per panel pair: lengths, angles, then each other
    declared unit; units from the model's ``[units]`` ("model units" where not declared)."""
    from .modeling.units import Units, coordinate_kinds

    units = getattr(model, "units", None) or Units()
    kinds = coordinate_kinds(model) if model is not None else {c: "length" for c in traj.coordinates}
    time = units.time or "time unit"
    out = []
    lengths = [c for c in traj.coordinates if kinds.get(c) == "length"]
    if lengths:
        u = units.length or "model units"
        out.append(("lengths", lengths, u, f"velocities ({u}/{time})"))
    angles = [c for c in traj.coordinates if kinds.get(c) == "angle"]
    if angles:
        out.append(("angles", angles, units.angle, f"angular velocities ({units.angle}/{time})"))
    others: dict[str, list[str]] = {}
    for c in traj.coordinates:
        if kinds.get(c) == "other":
            others.setdefault(units.coordinates[c], []).append(c)
    for u, names in others.items():
        out.append(("coordinates", names, u, f"rates ({u}/{time})"))
    return out, units


def plot_trajectory(traj, path, title: str | None = None, model=None) -> None:
    """Write a PNG: the coordinates and velocities (lengths, angles and coordinates with units
    of their own on separate axes, with the units the model declares in ``[units]``, rad for
    angles, "model units" where nothing is declared -- the library does not convert units), the
    multipliers and contact forces (named: normal, friction along each slip direction), the
    energy terms, the energy balance residual in its own panel, the control forces of
    servo-constraints with their work, and the contact modes.

    Event times are marked with vertical lines; contact modes (when there are contacts) are
    drawn as a timeline whose legend, above the bars, lists the states that occur
    (:func:`mode_colors`).  *model* tells the angles from the lengths
    (:func:`angle_coordinates`) and gives the units.
    """
    has_contacts = bool(traj.contacts)
    kinds, units = _groups(traj, model)
    controls = getattr(traj, "controls", {}) or {}
    panels = 2 * len(kinds) + 3 + (1 if has_contacts else 0) + (1 if controls else 0)
    fig, axes = plt.subplots(panels, 1, figsize=(8, 2.1 * panels), sharex=True)
    t = traj.t
    index = {c: i for i, c in enumerate(traj.coordinates)}
    tt, q = _hermite(t, traj.q, traj.qd)
    tv, qd = _hermite(t, traj.qd, traj.qdd)
    k = 0
    for kind, names, unit, rate in kinds:
        ax = axes[k]
        for c in names:
            ax.plot(tt, q[:, index[c]], label=c)
        ax.set_ylabel(f"{kind} ({unit})")
        ax.legend(loc="best", fontsize=8, ncol=min(4, len(names)))
        ax = axes[k + 1]
        for c in names:
            ax.plot(tv, qd[:, index[c]], label=c + "'")
        ax.set_ylabel(rate)
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
    force = units.force()
    if force is None:
        ax.set_ylabel("reactions (model units)")
    elif traj.multipliers:
        ax.set_ylabel(f"reactions\n(contact forces in {force})" if traj.contacts else "reactions (model units)")
    else:
        ax.set_ylabel(f"contact forces ({force})")
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
    ax.set_ylabel(f"energy ({units.energy() or 'model units'})")
    ax.legend(loc="best", fontsize=8)
    ax = axes[k + 2]
    ax.plot(t, e["balance"], color="0.4", lw=0.8)
    ax.set_ylabel("energy balance\nresidual")
    if controls:
        ax = axes[k + 3]
        for name, c in controls.items():
            if "force" in c:        # a program realized by shared controls has none
                ax.plot(t, c["force"], label=f"u {name}")
        ax.set_ylabel("control force\n(model units)")
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
        for j, name in enumerate(names):
            for left, right, mode in mode_intervals(traj, name):
                ax.barh(j, right - left, left=left, color=colors[mode.replace("(N<0)", "")],
                        edgecolor="none")
        ax.set_yticks(range(len(names)), names)
        handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colors.values()]
        ax.legend(handles, list(colors), fontsize=7, ncol=len(colors), loc="lower left",
                  bbox_to_anchor=(0.0, 1.0), frameon=False)     # above the bars, never on them
        ax.set_ylabel("contact mode")
    for a in axes:
        for ev in traj.events:
            a.axvline(ev["t"], color="k", lw=0.5, alpha=0.4)
        a.grid(alpha=0.3)
    axes[-1].set_xlabel(f"t ({units.time})" if units.time else "t (time, model units)")
    fig.suptitle(title or traj.model)
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)


def mode_intervals(traj, name: str) -> list[tuple[float, float, str]]:
    """``(start, end, mode)`` of contact *name* over the run: a change of mode between two
    samples is put at the instant of the event between them (the last such), not at a sample.
    """
    t = np.asarray(traj.t, dtype=float)
    modes = traj.contacts[name]["mode"]
    if not len(t):
        return []
    events = sorted(float(e["t"]) for e in traj.events)
    out, start, left = [], 0, float(t[0])
    for i in range(1, len(t) + 1):
        if i == len(t):
            out.append((left, float(t[-1]), modes[start]))
        elif modes[i] != modes[start]:
            inside = [te for te in events if t[i - 1] < te <= t[i]]
            switch = inside[-1] if inside else float(t[i])
            out.append((left, switch, modes[start]))
            start, left = i, switch
    return out


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
    """A quantity of a sweep (:class:`~nonideal.analysis.studies.sweep.SweepResult`) against its one
    varied parameter, or as a map over two (the first on the horizontal axis).

    *quantity* is a column of the sweep's CSV (``q.x``, ``margin``, ``events.count``,
    ``exit_code``...); text values (the type of the first event, a verdict) are drawn as
    categories.  Failed points (exit code != 0) are marked with their exit code."""
    from .analysis.studies.sweep import flatten

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
    mode coloured as in the plot's timeline, the time in the title.  A model with contacts from
    geometry is drawn in 3-D (:func:`_animate_3d`: its shapes, the planes they touch and the
    path of each contact point); ``.png`` writes the last frame only."""
    from matplotlib import animation

    if any(c.geometry is not None for c in model.contacts):
        return _animate_3d(traj, model, path, frames, fps)
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
    length = getattr(getattr(model, "units", None), "length", None) or "model units"
    ax.set_xlabel(f"x ({length})")
    ax.set_ylabel(f"y ({length})")
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

    suffix = str(path).rsplit(".", 1)[-1].lower()
    if suffix == "png":
        update(len(idx) - 1)
        fig.savefig(path)
        plt.close(fig)
        return
    anim = animation.FuncAnimation(fig, update, frames=len(idx), blit=False)
    writer = animation.PillowWriter(fps=fps) if suffix == "gif" else animation.FFMpegWriter(fps=fps)
    anim.save(str(path), writer=writer)
    plt.close(fig)


def _surface_points(shape, values, n_grid: int = 24):
    """Points of a shape in its own axes about its centre (*values*: the parameters' numbers by
    symbol): ``(X, Y, Z)`` grids for a surface, ``None, polygon`` for a disk, ``None, None`` for
    a point."""
    import sympy as sp

    num = lambda e: float(sp.sympify(e).xreplace(values))
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n_grid), np.linspace(0, np.pi, n_grid // 2))
    kind = shape.TYPE
    if kind in ("sphere", "ellipsoid"):
        a, b, c = [num(shape.radius)] * 3 if kind == "sphere" else [num(x) for x in shape.semi_axes]
        return a * np.cos(u) * np.sin(v), b * np.sin(u) * np.sin(v), c * np.cos(v)
    if kind == "paraboloid":
        a, b = (num(x) for x in shape.curvature_radii)
        H = max(2 * abs(num((shape.center or (0, 0, 0))[2])), 0.05 * min(a, b))
        s = np.sqrt(H) * v / np.pi
        return np.sqrt(2 * a) * s * np.cos(u), np.sqrt(2 * b) * s * np.sin(u), s ** 2
    if kind == "disk":
        ax = np.array([num(x) for x in shape.axis])
        ax /= np.linalg.norm(ax)
        e1 = np.cross(ax, [1.0, 0.0, 0.0] if abs(ax[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        th = np.linspace(0, 2 * np.pi, 2 * n_grid)
        return None, num(shape.radius) * (np.outer(np.cos(th), e1) + np.outer(np.sin(th), np.cross(ax, e1)))
    return None, None


def _animate_3d(traj, model, path, frames: int, fps: int) -> None:
    """The 3-D animation of a model with contacts from geometry (see :func:`animate_trajectory`)."""
    import sympy as sp
    from matplotlib import animation
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    q = [sp.Symbol(c) for c in model.coordinates]
    params = [sp.Symbol(p) for p in model.parameter_values]
    p = list(model.parameter_values.values())
    t = sp.Symbol("t")
    bodies = {b.name: b for b in model.bodies}
    drawn = []
    for c in model.contacts:
        if c.geometry is None:
            continue
        b = bodies[c.body]
        f_R = sp.lambdify([t, q, params], sp.Matrix(b.rotation), "numpy")
        f_G = sp.lambdify([t, q, params], list(b.position), "numpy")
        f_P = sp.lambdify([t, q, params], list(c.geometry.support), "numpy")
        offset = np.array([float(sp.sympify(x).xreplace(dict(zip(params, p)))) for x in c.shape.offset])
        plane = [np.array([float(sp.sympify(x).xreplace(dict(zip(params, p)))) for x in v])
                 for v in (c.geometry.normal, *c.geometry.tangents, sp.Matrix(c.surface.point))]
        drawn.append((c, f_R, f_G, f_P, offset, plane, _surface_points(c.shape, dict(zip(params, p)))))
    idx = np.unique(np.linspace(0, len(traj.t) - 1, min(frames, len(traj.t))).round().astype(int))
    if str(path).lower().endswith(".png"):
        idx = idx[-1:]
    contact_paths = [np.array([np.asarray(f_P(traj.t[k], traj.q[k], p), float).ravel() for k in range(len(traj.t))])
                     for _, _, _, f_P, _, _, _ in drawn]
    centres = np.array([np.asarray(f_G(tk, qk, p), float).ravel() for tk, qk in zip(traj.t, traj.q)
                        for _, _, f_G, _, _, _, _ in drawn])
    moved = np.vstack([centres, *contact_paths])
    extent = max((np.max(np.abs(g[1])) if g[0] is None else max(np.max(np.abs(x)) for x in g))
                 for *_, g in drawn if g[1] is not None) if any(g[1] is not None for *_, g in drawn) else 0.0
    mid = 0.5 * (moved.max(axis=0) + moved.min(axis=0))
    half = 0.6 * max(np.ptp(moved, axis=0).max() + 2 * extent, 1e-6)
    grids = [g for *_, g in drawn]
    zlim = (moved[:, 2].min() - 0.3 * extent, max(moved[:, 2].max() + 1.3 * extent, moved[:, 2].min() + 0.2 * half))
    fig = plt.figure(figsize=(6.4, 5.6))
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=24, azim=-125)
    colors = mode_colors(traj) if traj.contacts else {}

    def update(i):
        k = idx[i]
        ax.cla()
        ax.view_init(elev=24, azim=-125)
        for j, (c, f_R, f_G, f_P, offset, (n, t1, t2, p0), (X, Y, *_)) in enumerate(drawn):
            R = np.asarray(f_R(traj.t[k], traj.q[k], p), float)
            O = np.asarray(f_G(traj.t[k], traj.q[k], p), float).ravel() + R @ offset
            # the plane: a square around the motion, in its own tangent axes
            s = np.linspace(-half, half, 2)
            S1, S2 = np.meshgrid(s, s)
            base = p0 + ((mid - p0) - ((mid - p0) @ n) * n)
            ax.plot_surface(*(base[d] + S1 * t1[d] + S2 * t2[d] for d in range(3)), color="0.85", alpha=0.5)
            if c.shape.TYPE == "disk":
                poly = O + Y @ R.T
                ax.add_collection3d(Poly3DCollection([poly], facecolor="tab:orange", edgecolor="k", alpha=0.8))
                ax.plot(*np.vstack([O, poly[0]]).T, color="k", lw=1)     # a radius, to see it turn
            elif Y is not None:
                P = np.einsum("ij,abj->abi", R, np.stack(grids[j], axis=-1)) + O
                ax.plot_surface(P[..., 0], P[..., 1], P[..., 2], color="tab:blue", alpha=0.55, edgecolor="k", lw=0.2)
                if c.shape.TYPE == "paraboloid":      # the deck closing the bowl
                    ax.add_collection3d(Poly3DCollection([P[-1]], facecolor="tab:cyan", edgecolor="k", alpha=0.7))
            else:
                ax.scatter(*O, color="tab:blue")
            ax.plot(*contact_paths[j][: k + 1].T, color="tab:red", lw=1.2)
            mode = c.name + ":" + traj.contacts[c.name]["mode"][k].replace("(N<0)", "")
            ax.text2D(0.02, 0.95 - 0.05 * j, f"contact {mode}", transform=ax.transAxes, fontsize=9,
                      bbox=dict(boxstyle="round", fc=colors.get(mode, "white"), ec="0.6"))
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_zlim(*zlim)
        ax.set_box_aspect((1, 1, (zlim[1] - zlim[0]) / (2 * half)))
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
        ax.set_title(f"{traj.model}   t = {traj.t[k]:.3f}")
        return []

    if str(path).lower().endswith(".png"):
        update(0)
        fig.savefig(path, dpi=110)
        plt.close(fig)
        return
    anim = animation.FuncAnimation(fig, update, frames=len(idx), blit=False)
    suffix = str(path).rsplit(".", 1)[-1].lower()
    anim.save(str(path), writer=animation.PillowWriter(fps=fps) if suffix == "gif" else animation.FFMpegWriter(fps=fps))
    plt.close(fig)
