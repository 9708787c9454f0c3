"""The onset of a two-component slip (:mod:`nonideal.modes.onset`): the directions found from
the linear-fractional model of the slip acceleration are the scan's, and at a located slip
event the marginal onset follows, not the sticking the event ended."""

import math

import numpy as np
import pytest

import nonideal
from nonideal.modes import onset
from nonideal.modes.switching import select_mode
from nonideal.modes.types import SLIDE, STICK, ContactState, Mode
from nonideal.simulation.hybrid import Simulation
from tests.systems import rough_rattleback


@pytest.fixture(scope="module")
def slipping(tmp_path_factory):
    """The rough rattleback pitched 0.2 rad over 5 s (native), its events' states."""
    model = rough_rattleback(tmp_path_factory.mktemp("onset"), 0.2)
    tr = nonideal.simulate(model, native=True)
    states = []
    for e in tr.events:
        k = int(np.flatnonzero(tr.t == e["t"])[0])  # the state at the event, before the switch
        states.append((e, tr.t[k], tr.q[k], tr.qd[k]))
    return model, tr, states


def test_at_a_located_slip_event_the_marginal_onset_follows(slipping):
    """At the instant the sticking friction reaches the cone, sliding starts with a slip
    acceleration zero to rounding (kappa ~ 0): that onset is consistent, and it -- not the
    sticking the event ended -- is selected.  (Before, a kappa of -1e-16 rejected it, the
    run went on sticking, and the onset was found again 1e-10 s later: two events, the first
    one recorded as a slip into sticking.)"""
    model, tr, states = slipping
    solver = Simulation(model).solver
    stick = Mode(frozenset(), (("table", ContactState(STICK)),))
    slips = [(t, q, qd) for e, t, q, qd in states if e["type"] == "slip"]
    assert len(slips) >= 10
    for t, q, qd in slips:
        mode = select_mode(solver, t, q, qd, exclude=stick, previous=stick, concerned="table")
        assert mode.contact("table").state == SLIDE
        s = np.array(mode.contact("table").direction)
        motion = solver.motion(t, np.concatenate((q, qd)), mode)
        kappa = motion.slip_acc(0) @ s
        assert abs(kappa) <= 1e-6 * (1 + np.abs(motion.qdd).max())  # marginal: the cone just reached
    # the event log: every slip goes into sliding, every stick into sticking, alternately
    kinds = [e["type"] for e in tr.events]
    assert all(("slide" in e["mode"]) == (e["type"] == "slip") for e in tr.events)
    assert all(a != b for a, b in zip(kinds, kinds[1:]))


def test_the_model_of_the_slip_acceleration_finds_the_scans_directions(slipping, monkeypatch):
    model, _, states = slipping
    solver = Simulation(model).solver
    probe = Mode(frozenset(), (("table", ContactState(SLIDE, (1.0, 0.0))),))
    scans = []
    original = onset._scanned_roots
    monkeypatch.setattr(onset, "_scanned_roots", lambda cross: scans.append(1) or original(cross))

    def directions():
        out = []
        for _, t, q, qd in states:  # as select_mode asks: each candidate slides its own way
            solver.selecting = 1e-8 * (1.0 + np.abs(qd).max())
            out.append(onset.onset_directions(solver, t, q, qd, probe, 0))
        solver.selecting = 0.0
        return out
    found = directions()
    assert not scans  # the model held at every state
    monkeypatch.setattr(onset, "_model_roots", lambda udot, cross: None)
    scanned = directions()
    assert len(scans) == len(states)
    assert sum(len(d) for d in found) >= len(states) // 2  # the slip events have their onset
    for a, b in zip(found, scanned):
        assert len(a) == len(b)
        for u, v in zip(sorted(a), sorted(b)):
            assert np.allclose(u, v, rtol=0, atol=1e-12)


def test_the_linear_fractional_fit_and_its_check():
    rng = np.random.default_rng(7)
    P0, P1, P2 = rng.normal(size=(3, 2))
    b = 0.3 * rng.normal(size=2)

    def udot(phi, law=lambda s: 1.0):
        s = np.array([math.cos(phi), math.sin(phi)])
        return law(s) * (P0 + s[0] * P1 + s[1] * P2) / (1.0 + b @ s), s, None

    def cross(phi, law=lambda s: 1.0):
        ud, s, _ = udot(phi, law)
        return float(ud[0] * s[1] - ud[1] * s[0])

    fitted = onset._fit([udot(phi)[:2] for phi in onset._FIT])
    for got, want in zip(fitted, (P0, P1, P2, b)):
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12)
    roots = onset._model_roots(udot, cross)
    assert sorted(roots) == pytest.approx(sorted(onset._scanned_roots(cross)), abs=1e-12)
    assert all(abs(cross(r)) < 1e-12 for r in roots)

    def anisotropic(s):  # a friction not affine in the direction: the check refuses the model
        return 1.0 + 0.2 * s[0] ** 2

    assert onset._model_roots(lambda phi: udot(phi, anisotropic), lambda phi: cross(phi, anisotropic)) is None
