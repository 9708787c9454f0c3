"""A ball (I = 2/5 m R^2) dropped from h0 with horizontal speed vx0 and no spin onto a rough
floor (Newton restitution e, Coulomb mu).  At t1 = sqrt(2 h0/g), vz- = -g t1, the normal
impulse is P_n = m (1 + e) |vz-|; the sticking impulse would need |P_t| = m U-/(1 + m R^2/I),
more than mu P_n for mu = 0.1, so the impact slides: P_t = -mu P_n, vx+ = vx0 - mu (1 + e)|vz-|,
psi'+ = (5/2) mu (1 + e)|vz-|/R.  With mu = 0.3 it sticks: the ball rebounds rolling,
vx+ = vx0 - (2/7) vx0.  The event records both impulses in either case."""


import numpy as np
import pytest

from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "friction" / "ball_oblique_bounce.toml"


@pytest.mark.parametrize("mu", [0.1, 0.3])
def test_impulses_and_rebound(mu):
    model = load_model(PATH)
    p = model.parameter_values
    m, R, g, h0, vx0, e = p["m"], p["R"], p["g"], p["h0"], p["vx0"], 0.6
    t1 = np.sqrt(2 * h0 / g)
    vz = g * t1
    tr = simulate(model, parameters={"mu": mu}, t_end=t1 + 0.01)
    hit = tr.events[0]
    assert hit["t"] == pytest.approx(t1, rel=1e-11)
    Pn = m * (1 + e) * vz
    assert hit["impulses"]["floor"] == pytest.approx(Pn, rel=1e-11)
    if mu * Pn < m * vx0 / (1 + 2.5):        # sliding impact
        Pt, vx, spin = -mu * Pn, vx0 - mu * (1 + e) * vz, 2.5 * mu * (1 + e) * vz / R
    else:                                     # sticking impact: rolls off
        Pt = -m * vx0 / 3.5
        vx = vx0 - 2 / 7 * vx0
        spin = vx / R
    assert hit["impulses"]["floor_t1"] == pytest.approx(Pt, rel=1e-11)
    k = int(np.searchsorted(tr.t, t1 + 1e-9))
    assert tr.qd[k, 0] == pytest.approx(vx, rel=1e-10)
    assert tr.qd[k, 2] == pytest.approx(spin, rel=1e-10)
    assert tr.qd[k, 1] == pytest.approx(e * vz - g * (tr.t[k] - t1), rel=1e-9)   # in flight
