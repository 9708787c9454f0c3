"""A rigid body sliding on two tangential directions under exact Coulomb friction stops in finite
time, its slip direction turning as the slip vanishes: the integrator's steps shrink with the
time left and never reach the stop.  The rattleback of Kane & Levinson 1982's moments (the
gallery's paraboloid model) with mu = 0.1, pitched by 0.2 rad and spun at -2 rad/s, sticks and
slips about 35 times in 5 s: a stop whose steps collapse is located by extrapolation of the slip
to zero (``guards.arrest``), and each slide that starts from a stop takes the direction the
mode selection chose, not that of the slip left by the stop.  A stall that remains (other
starts of the same body) is named as a vanishing slip."""

from pathlib import Path

import numpy as np
import pytest

import nonideal
from nonideal import gallery
from nonideal.errors import IntegrationFailed
from nonideal.modeling.modelfile import load_model

pytestmark = pytest.mark.slow


def rough_rattleback(tmp_path, pitch, spin):
    text = Path(gallery.__file__).with_name("rattleback.toml").read_text(encoding="utf-8")
    for old, new in (('mu = "inf"', 'mu = "0.1"'), ("b = 0.01", f"b = {pitch}"),
                     ('value = -2.0, unit = "rad/s"', f'value = {spin}, unit = "rad/s"')):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "rough_rattleback.toml"
    path.write_text(text, encoding="utf-8")
    return load_model(path)


def test_a_rough_rattleback_sticks_and_slips_through_its_arrests(tmp_path):
    pytest.importorskip("numba")
    tr = nonideal.simulate(rough_rattleback(tmp_path, 0.2, -2.0), native=True)
    assert tr.t[-1] == 5.0
    kinds = [e["type"] for e in tr.events]
    assert kinds.count("stick") >= 5 and kinds.count("slip") >= 5
    # every stick ends a slide and every slip starts one: the modes around each event agree
    for e in tr.events:
        assert e["mode"] in ("table:stick", "table:slide")
    E = tr.energy
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    assert np.max(np.diff(E["friction_work"])) <= 1e-12  # friction never does positive work
    assert E["friction_work"][-1] < -1e-4                 # and it did work: the body slid
    assert tr.diagnostics["constraint_residual_max"] < 1e-9


def test_a_slip_that_vanishes_without_a_stop_is_named(tmp_path):
    """Where the slip hovers at the level of rounding (no stop ahead to extrapolate to), the
    stall says so instead of blaming a right-hand side that is not smooth."""
    pytest.importorskip("numba")
    with pytest.raises(IntegrationFailed, match=r"slip of the sliding contact 'table' is vanishing"):
        nonideal.simulate(rough_rattleback(tmp_path, 0.1, -2.0), native=True, t_end=1.0)
