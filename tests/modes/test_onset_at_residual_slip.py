"""A slide that starts where a slip has just stopped: the slip left there (1e-10, the residue of
the stop's location) has a direction of its own, which may be the opposite of the one the
slide starts in.  The mode selection tries each candidate onset with its own sliding
direction (the slip is zero within the switching tolerance), not with the residue's: with
the residue's, no direction is consistent and the state was refused as Painleve's paradox
at mu = 0.1, where there is none."""

import numpy as np
import pytest

from nonideal.modes.switching import select_mode
from nonideal.modes.types import SLIDE
from nonideal.simulation.hybrid import Simulation
from tests.systems import sphere_on_plane


def pulled_sphere(residue):
    """A sphere at rest on a plane, pulled along x by 0.5 m g: rolling would need friction
    (2/7) 0.5 m g = 0.143 m g > mu m g (mu = 0.1), so it slides, along +x."""
    return sphere_on_plane(pull=0.5, spin=residue)


@pytest.mark.parametrize("residue", [(0.0, 0.0), (1e-9, 0.0), (0.0, 1e-9), (-1e-9, 7e-10)],
                         ids=["none", "slip -1e-10 along x (against the pull)", "across", "oblique"])
def test_the_slide_starts_along_the_pull_whatever_the_residue(residue):
    sim = Simulation(pulled_sphere(residue))
    q, qd = sim.initial_state()
    mode = select_mode(sim.solver, 0.0, q, qd, tol_pos=1e-8, tol_vel=1e-8)
    (name, cs), = mode.contacts
    assert cs.state == SLIDE
    assert np.allclose(cs.direction, (1.0, 0.0), atol=1e-6)
    assert sim.solver.selecting == 0.0  # the selection's tolerance is not left behind
