"""Units for labels and outputs (``[units]``) and which coordinates are angles.

The friction speed regulator's angles phi1, phi2, phi enter only through their velocities, in
rotational kinetic energy terms J1 phi1'^2/2 (no trigonometric function, no planar body):
they are angles, rho (m rho'^2/2) a length.  Declared units give every derived unit (N, J,
N m for SI; composed otherwise); without them lengths are "model units" and angles rad."""

import json

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

import nonideal  # noqa: E402
from nonideal import Model, gallery  # noqa: E402
from nonideal.errors import ModelError  # noqa: E402
from nonideal.modeling.units import coordinate_kinds, units_report  # noqa: E402
from nonideal.plotting import plot_trajectory  # noqa: E402
from tests.helpers import DATA_DIR, run_cli  # noqa: E402

REGULATOR = gallery.model_path("friction-speed-regulator")
SI = '\n[units]\nlength = "m"\nmass = "kg"\ntime = "s"\n'


def labels_of(traj, model, tmp_path, monkeypatch):
    saved = {}
    monkeypatch.setattr(plt, "close", lambda fig: saved.setdefault("fig", fig))
    plot_trajectory(traj, tmp_path / "plot.png", model=model)
    axes = saved["fig"].axes
    return [a.get_ylabel() for a in axes], [a.get_xlabel() for a in axes if a.get_xlabel()]


def test_regulator_angles_enter_through_velocities_only():
    model = nonideal.load_model(REGULATOR)
    assert coordinate_kinds(model) == {"phi1": "angle", "phi2": "angle", "phi": "angle", "rho": "length"}
    rep = units_report(model)
    assert rep["declared"] is False and rep["q"] == {"phi1": "rad", "phi2": "rad", "phi": "rad", "rho": None}
    assert rep["force"] is None and rep["energy"] is None


def test_regulator_plot_without_and_with_declared_units(tmp_path, monkeypatch):
    model = nonideal.load_model(REGULATOR)
    traj = nonideal.simulate(model, t_end=0.05)
    ylabels, xlabel = labels_of(traj, model, tmp_path, monkeypatch)
    assert ylabels[:4] == ["lengths (model units)", "velocities (model units/time unit)",
                           "angles (rad)", "angular velocities (rad/time unit)"]
    assert xlabel == ["t (time, model units)"] and "energy (model units)" in ylabels
    path = tmp_path / "regulator.toml"
    path.write_text(REGULATOR.read_text() + SI)
    declared = nonideal.load_model(path)
    traj = nonideal.simulate(declared, t_end=0.05)
    ylabels, xlabel = labels_of(traj, declared, tmp_path, monkeypatch)
    assert ylabels[:4] == ["lengths (m)", "velocities (m/s)", "angles (rad)", "angular velocities (rad/s)"]
    assert xlabel == ["t (s)"] and "energy (J)" in ylabels


def test_units_in_the_simulate_json_and_text(tmp_path):
    path = tmp_path / "regulator.toml"
    path.write_text(REGULATOR.read_text() + SI)
    proc = run_cli("simulate", path, "--t-end", "0.05", "--json", "-")
    assert proc.returncode == 0, proc.stderr
    units = json.loads(proc.stdout)["units"]
    assert units["declared"] is True and units["time"] == "s"
    assert units["q"]["phi1"] == "rad" and units["q"]["rho"] == "m"
    assert units["qdot"]["phi2"] == "rad/s" and units["qddot"]["rho"] == "m/s^2"
    assert units["generalized_force"] == {"phi1": "N m", "phi2": "N m", "phi": "N m", "rho": "N"}
    assert units["energy"] == "J" and units["contacts"]["normal"] == "N"
    text = run_cli("simulate", path, "--t-end", "0.05").stdout
    assert "rad/s" in text and " m/s" in text


def test_declared_units_compose_and_decide():
    base = dict(name="cart", coordinates=["theta", "s"], parameters={"m": 1.0, "J": 2.0},
                kinetic="m/2*theta'^2 + J/2*s'^2")
    # evidence before names: theta moves a mass (a length), s turns an inertia (an angle)
    assert coordinate_kinds(Model(**base)) == {"theta": "length", "s": "angle"}
    model = Model(**base, units={"length": "cm", "mass": "g", "time": "min",
                                 "coordinates": {"theta": "angle", "s": "m^2"}})
    assert coordinate_kinds(model) == {"theta": "angle", "s": "other"}
    rep = units_report(model)
    assert rep["q"] == {"theta": "rad", "s": "m^2"} and rep["qdot"]["s"] == "m^2/min"
    assert rep["force"] == "g cm/min^2" and rep["energy"] == "g cm^2/min^2"
    assert rep["generalized_force"] == {"theta": "g cm^2/min^2", "s": "g cm^2/min^2/m^2"}
    polar = nonideal.load_model(DATA_DIR / "polar_coordinates.toml")   # m r^2 phi'^2/2: an angle
    assert coordinate_kinds(polar) == {"r": "length", "phi": "angle"}


def test_units_table_is_checked(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(REGULATOR.read_text() + '\n[units]\nlenght = "m"\ntime = 1\n'
                    'coordinates = { phi3 = "angle", rho = "" }\n')
    with pytest.raises(ModelError) as err:
        nonideal.load_model(path)
    text = str(err.value)
    assert "unknown key 'lenght' (did you mean 'length'?)" in text
    assert "time must be a unit in quotes" in text
    assert "'phi3' is not a coordinate" in text and "rho must be" in text
