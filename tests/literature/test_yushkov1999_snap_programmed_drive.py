"""A sprung mass driven by a constant-snap program x'''' = s0 (a constraint of order four,
Yushkov 1999, ch. IV, secs. 5 and 7): the motion, the drive's force and its rate against the
closed form derived in the example's docstring, the same motion as the jerk program one order
lower, and the CLI's report."""

import json

import numpy as np
import pytest
from numpy.polynomial import Polynomial

from nonideal import gallery
from nonideal.cli import main
from nonideal.gallery import snap_programmed_drive as drive
from nonideal.simulation.hybrid import simulate


def test_model_file_matches_the_closed_form():
    model = gallery.load(drive.NAME)
    p = model.parameter_values
    times = np.linspace(0.0, 2.0, 11)
    tr = simulate(model, times=times)
    x, y, lam = drive.closed_form(times, p)
    assert np.max(np.abs(tr.q[:, 0] - x)) < 1e-9 and np.max(np.abs(tr.q[:, 1] - y)) < 1e-9
    assert np.max(np.abs(tr.multipliers["drive"] - lam)) < 1e-9
    assert np.ptp(tr.q[:, 1]) > 0.1                 # the transverse spring is excited
    # the force's rate, reported beside it: the derivative of the quartic lambda
    dlam = Polynomial.fit(times, lam, 4).deriv()(times)
    assert tr.controls["drive"]["force'"][0] == pytest.approx(p["F1"], abs=1e-12)
    assert np.max(np.abs(tr.controls["drive"]["force'"] - dlam)) < 1e-8
    # the jerk x''' grows by s0 per second: the accelerations' second differences
    d2 = np.diff(tr.qdd[:, 0], 2) / np.diff(times)[0] ** 2
    assert np.max(np.abs(d2 - p["s0"])) < 1e-7
    # the drive's work balances the change of the energy (integrated with the motion)
    E = tr.energy["energy"]
    assert np.max(np.abs(tr.controls["drive"]["work"] - (E - E[0]))) < 1e-10


def test_same_motion_as_the_jerk_program():
    p = gallery.load(drive.NAME).parameter_values
    times = np.linspace(0.0, 2.0, 11)
    a, b = simulate(gallery.load(drive.NAME), times=times), simulate(drive.jerk_program(p), times=times)
    assert np.max(np.abs(a.q - b.q)) < 1e-10
    assert np.max(np.abs(a.multipliers["drive"] - b.multipliers["drive"])) < 1e-9
    assert (a.controls["drive"]["order"], b.controls["drive"]["order"]) == (4, 3)


def test_ideal_variant_keeps_the_transverse_force_rate():
    p = gallery.load(drive.NAME).parameter_values
    times = np.linspace(0.0, 2.0, 11)
    tr = simulate(drive.build(ideal=True), times=times)
    x, y, Rx = drive.closed_form(times, p, ideal=True)
    c = tr.controls["drive"]
    assert np.max(np.abs(tr.q[:, 0] - x)) < 1e-9 and np.max(np.abs(tr.q[:, 1] - y)) < 1e-9
    assert np.max(np.abs(c["u_1"] - Rx)) < 1e-9
    assert np.max(np.abs(c["u_2'"] - drive.R1Y)) < 1e-12     # R_y'' = 0: the rate is kept


def test_cli_reports_the_force_and_its_rate(tmp_path):
    out = tmp_path / "drive.json"
    assert main(["simulate", drive.NAME, "--times", "0,1,2", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    p = gallery.load(drive.NAME).parameter_values
    _, _, lam = drive.closed_form(np.array([0.0, 1.0, 2.0]), p)
    assert data["controls"]["drive"]["force"] == pytest.approx(list(lam), abs=1e-9)
    assert data["controls"]["drive"]["order"] == 4 and list(data["q"]) == ["x", "y"]
    csv = tmp_path / "drive.csv"
    assert main(["simulate", drive.NAME, "--times", "0,1,2", "--csv", str(csv)]) == 0
    assert "u_drive" in csv.read_text().splitlines()[0]
