"""The plot separates lengths from angles (the rod's theta is an angle: the argument of its
sines; a planar body's angle), names the contact forces, and gives the energy balance
residual its own panel."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import nonideal  # noqa: E402
from nonideal.plotting import angle_coordinates, plot_trajectory  # noqa: E402
from tests.helpers import DATA_DIR  # noqa: E402


def test_angles_lengths_units_and_names(tmp_path, monkeypatch):
    rod = nonideal.load_model(DATA_DIR.parent.parent / "docs" / "rod.toml")
    assert angle_coordinates(rod) == {"theta"}
    traj = nonideal.simulate(rod, t_end=0.3)
    saved = {}
    monkeypatch.setattr(plt, "close", lambda fig: saved.setdefault("fig", fig))
    plot_trajectory(traj, tmp_path / "rod.png", model=rod)
    assert (tmp_path / "rod.png").stat().st_size > 10_000
    axes = saved["fig"].axes
    labels = [a.get_ylabel() for a in axes]
    assert labels[:4] == ["lengths (model units)", "velocities (model units/time unit)",
                          "angles (rad)", "angular velocities (rad/time unit)"]
    assert "energy balance\nresidual" in labels and axes[-1].get_xlabel() == "t (time, model units)"
    legend = [t.get_text() for t in axes[4].get_legend().get_texts()]
    assert "normal force A" in legend and "friction A" in legend
    assert not any("[" in s for s in legend)


def test_animation_draws_the_bodies_and_the_contact_modes(tmp_path):
    from PIL import Image

    from nonideal.plotting import animate_trajectory

    rod = nonideal.load_model(DATA_DIR.parent.parent / "docs" / "rod.toml")
    traj = nonideal.simulate(rod, t_end=0.6, times=[0.0, 0.1, 0.3, 0.5, 0.6])
    animate_trajectory(traj, rod, tmp_path / "rod.gif", frames=5, fps=5)
    with Image.open(tmp_path / "rod.gif") as im:
        assert im.n_frames == 5 and im.size[0] > 300


def test_animate_option_checks_the_format_before_running(tmp_path):
    from tests.helpers import run_cli

    proc = run_cli("simulate", DATA_DIR.parent.parent / "docs" / "rod.toml", "--animate", tmp_path / "a.avi")
    assert proc.returncode == 2 and "--animate" in proc.stderr and ".gif" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_animation_of_shapes_is_three_dimensional(tmp_path):
    """A model with contacts from geometry is drawn in 3-D: the shape (here a disk's rim), the
    plane, the contact's path; a .png holds the last frame."""
    import numpy as np
    from PIL import Image

    from nonideal import gallery
    from nonideal.plotting import animate_trajectory

    model = gallery.load("euler-disk")
    traj = nonideal.simulate(model, times=np.linspace(0, 0.2, 6))
    animate_trajectory(traj, model, tmp_path / "disk.gif", frames=6, fps=5)
    with Image.open(tmp_path / "disk.gif") as im:
        assert im.n_frames == 6
    animate_trajectory(traj, model, tmp_path / "disk.png")
    with Image.open(tmp_path / "disk.png") as im:
        pixels = np.asarray(im.convert("RGB"), float)
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    orange = ((r > g + 30) & (g > b + 30)).sum()          # the disk's face (orange, shaded)
    assert orange > 500
