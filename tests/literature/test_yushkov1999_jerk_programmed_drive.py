"""A sprung mass driven by a constant-jerk program x''' = j0 (a third-order constraint, Yushkov
1999, ch. IV; appendix D for the ideal one): the motion and the drive's force against the
closed form derived in the example's docstring, through the model file and the CLI."""

import json

import numpy as np
import pytest

from nonideal import gallery
from nonideal.cli import main
from nonideal.gallery import jerk_programmed_drive as drive
from nonideal.simulation.hybrid import simulate


def test_model_file_matches_the_closed_form():
    model = gallery.load(drive.NAME)
    p = model.parameter_values
    times = np.linspace(0.0, 2.0, 11)
    tr = simulate(model, times=times)
    x, y, lam = drive.closed_form(times, p)
    assert np.max(np.abs(tr.q[:, 0] - x)) < 1e-8 and np.max(np.abs(tr.q[:, 1] - y)) < 1e-8
    assert np.max(np.abs(tr.multipliers["drive"] - lam)) < 1e-8
    assert np.ptp(tr.q[:, 1]) > 0.1                 # the transverse spring is excited
    # the third derivative of x is the program: the accelerations grow by j0 per second
    assert np.max(np.abs(np.diff(tr.qdd[:, 0]) / np.diff(times) - p["j0"])) < 1e-8


def test_cli_reports_the_drive_force_as_a_control(tmp_path):
    out = tmp_path / "drive.json"
    assert main(["simulate", drive.NAME, "--times", "0,1,2", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    p = gallery.load(drive.NAME).parameter_values
    _, _, lam = drive.closed_form(np.array([0.0, 1.0, 2.0]), p)
    assert data["controls"]["drive"]["force"] == pytest.approx(list(lam), abs=1e-8)
    assert data["controls"]["drive"]["order"] == 3 and list(data["q"]) == ["x", "y"]
