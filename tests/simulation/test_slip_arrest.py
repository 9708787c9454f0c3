"""A rigid body sliding in two tangential directions under exact Coulomb friction stops in
finite time, its slip direction turning as the slip vanishes; and a slide that starts where a
slip stopped starts from the stop's residue (1e-10 of the speeds), which has a direction of its
own.  The rattleback of Kane & Levinson 1982's moments (the gallery's paraboloid model) with
mu = 0.1 sticks and slips 30-40 times in 5 s from each of these starts; before, four of the
five failed ("the step size collapsed", or a Painleve refusal at mu = 0.1) and the fifth took
26 s.  What made them run: below ``SLIP_FLOOR`` of the speeds the friction acts along the
slip's reference (its direction at the start of the step, or the onset's), not along the
rounding of the slip; the mode selection tries each onset with its own direction; a slide that
starts from a stop takes that direction as its reference."""

from pathlib import Path

import numpy as np
import pytest

import nonideal
from nonideal import gallery
from nonideal.errors import IntegrationFailed
from nonideal.modeling.modelfile import load_model
from nonideal.modes.types import ContactState, Mode, SLIDE
from nonideal.numeric import contact_integrator
from nonideal.simulation.events import SlipStop
from nonideal.simulation.guards import ARREST_STEPS
from nonideal.simulation.hybrid import Simulation
from nonideal.simulation.slipstall import slip_stall
from tests.systems import rough_rattleback, sphere_on_plane

STARTS = [(0.05, -2.0), (0.1, -2.0), (0.2, -2.0), (0.1, -5.0), (0.3, -1.0)]


def check(tr):
    assert tr.t[-1] == 5.0
    kinds = [e["type"] for e in tr.events]
    assert kinds.count("stick") >= 10 and kinds.count("slip") >= 10
    E = tr.energy
    assert tr.diagnostics["energy_balance_relative"] < 1e-7
    assert np.max(np.diff(E["friction_work"])) <= 1e-12  # friction never does positive work
    assert E["friction_work"][-1] < -1e-4                 # and it did work: the body slid
    assert tr.diagnostics["constraint_residual_max"] < 1e-9


@pytest.mark.slow
@pytest.mark.parametrize("pitch, spin", STARTS, ids=[f"pitch {p} rad, {w} rad/s" for p, w in STARTS])
def test_a_rough_rattleback_sticks_and_slips_through_its_stops(tmp_path, pitch, spin):
    pytest.importorskip("numba")
    check(nonideal.simulate(rough_rattleback(tmp_path, pitch, spin), native=True))


@pytest.mark.slow
def test_the_same_on_the_python_path(tmp_path):
    """The start that failed natively but not in Python before: both paths now."""
    check(nonideal.simulate(rough_rattleback(tmp_path, 0.1, -5.0), native=False))


def test_a_slip_that_vanishes_in_a_stall_is_named():
    """Where an integration stalls in a slide whose slip is at the level of rounding, the
    message names the contact and the vanishing slip, not a right-hand side that is not smooth."""
    model = sphere_on_plane(spin=(1e-10, 0.0))
    sim = Simulation(model)
    q, qd = sim.initial_state()
    mode = Mode(frozenset(), (("plane", ContactState(SLIDE, (1.0, 0.0))),))

    class Stalled:  # the integrator's state where it stalled
        t, y = 0.05, np.concatenate((q, qd))
    with pytest.raises(IntegrationFailed, match=r"slip of the sliding contact 'plane' is vanishing \(\|U\| = 1e-11\)"):
        slip_stall(sim, Stalled, mode)
    Stalled.y = np.concatenate((q, qd + np.r_[0.5, 0, 0, 0, 0, 0]))  # sliding at 0.5 m/s: not this
    slip_stall(sim, Stalled, mode)


def test_the_tippe_top_under_exact_coulomb_friction_stops_slipping_and_sticks(tmp_path):
    """Leine & Glocker 2003's tippe top (the gallery's) with the exact Coulomb law at a point,
    mu = 0.3, tilted 0.5 rad: its slip dies at t = 0.17466 s and the contact sticks (it then
    rolls and spins without turning over).  It failed there with 'the step size fell below the
    floating-point resolution' while the slip hovered at the level of rounding."""
    import re

    text = Path(gallery.__file__).with_name("tippe_top.toml").read_text(encoding="utf-8")
    assert 'friction = "regularized"' in text and "theta0 = { value = 0.1," in text
    text = re.sub(r'\neps = [^\n]*', "\n", text.replace('friction = "regularized"', ""))
    path = tmp_path / "tippe_top_coulomb.toml"
    path.write_text(text.replace("theta0 = { value = 0.1,", "theta0 = { value = 0.5,"), encoding="utf-8")
    tr = nonideal.simulate(load_model(path), t_end=1.0)
    assert [e["type"] for e in tr.events] == ["stick"]
    assert tr.events[0]["t"] == pytest.approx(0.174662, abs=1e-5)
    assert tr.diagnostics["energy_balance_relative"] < 1e-8
    assert np.max(np.diff(tr.energy["friction_work"])) <= 1e-12


class _Stop(SlipStop):
    """A slip-stop whose value along the step's tangent is given (no mode to solve)."""

    def value(self, motion):
        return motion


class _Step:
    def __init__(self, a, b, before_end):
        self.a, self.b, self.before_end = a, b, before_end

    def tangents(self):
        return 1e-3 * (self.b - self.a), None, self.before_end


@pytest.mark.parametrize("g_end, g_before, armed, level, expected", [
    (1e-10, 1e-10 + 1e-2 * 1e-9, True, 0.0, 1.0 + 1e-10 / 1e-2),  # falling at 1e-2: zero 1e-8 on
    (5e-9, 5e-9, True, 1e-8, 1.0),          # hovering below the level: stopped where the steps are
    (5e-9, 5e-9, True, 1e-9, None),         # hovering above it: not stopped
    (5e-9, 4e-9, True, 1e-8, 1.0),          # rising below the level: stopped too
    (1e-10, 2e-10, False, 1e-8, None),      # a guard not armed is never hit
    (1e-6, 1e-6 + 1e-12, True, 1e-8, None)])  # falling, but its zero is far beyond the step
def test_the_arrest_of_a_slip_the_steps_cannot_reach(g_end, g_before, armed, level, expected):
    """``guards.arrest`` after a run of tiny steps: a falling slip's zero by linear extrapolation
    (within ARREST_REACH step lengths), or, for a slip that hovers below the vanishing level,
    the end of the step."""
    from nonideal.simulation.guards import arrest

    step = _Step(1.0 - 1e-6, 1.0, g_before)
    stop = _Stop("stop", "table", 0)
    hits = arrest(step, [stop], [armed], [g_end], level)
    if expected is None:
        assert hits == []
    else:
        assert len(hits) == 1 and hits[0][1] == 0 and hits[0][0] == pytest.approx(expected, rel=1e-15)


def test_the_native_loop_takes_an_onsets_short_steps(tmp_path, monkeypatch):
    """The steps shorter than 1e-9 of the span at a slip's onset are taken natively; the
    native loop hands them back only when ARREST_STEPS - 1 of them come in a row (the hybrid
    loop then looks for a slip's arrest), with that count."""
    model = rough_rattleback(tmp_path, 0.2)
    phase, ends, short = contact_integrator.phase, [], []

    class Recording:
        overloads = phase.overloads

        def __call__(self, *args):
            out = phase(*args)
            ends.append((out[0], out[-1]))
            T = out[6][:out[8]]
            short.append(int(np.sum(np.diff(T) < 1e-9)))
            return out

    monkeypatch.setattr(contact_integrator, "phase", Recording())
    tr = nonideal.simulate(model, native=True, every_step=True, t_end=1.3)
    assert [e["type"] for e in tr.events][:4] == ["stick", "slip", "stick", "slip"]
    assert sum(short) > 0  # short steps taken natively
    assert all(run >= ARREST_STEPS - 1 for status, run in ends if status == 4)
