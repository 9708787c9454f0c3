"""A block dropped at rest onto a belt moving at v_b (Coulomb, mu): it slides with x'' = mu g
until x' = v_b at t1 = v_b/(mu g), then rides along.  Friction does the work m v_b^2/2 on the
block, but the heat -int F (x' - v_b) dt = m v_b^2/2 is dissipated and the belt's drive puts in
int F v_b dt = m v_b^2: ``friction_work`` is the heat (never positive, SPEC), the belt's part
is in ``reaction_work``.  (friction_work once was the work on the block, +m v_b^2/2.)"""


import numpy as np
import pytest

from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "friction" / "conveyor_belt.toml"


@pytest.mark.parametrize("form", ["lagrange1", "maggi", "gauss"])
def test_heat_and_the_belts_work(form):
    model = load_model(PATH)
    p = model.parameter_values
    m, g, mu, vb = p["m"], p["g"], p["mu"], p["Vb"]
    t1 = vb / (mu * g)
    tr = simulate(model, times=np.linspace(0, 1, 101), form=form)
    assert [e["type"] for e in tr.events] == ["stick"] and tr.events[0]["t"] == pytest.approx(t1, rel=1e-12)
    E = tr.energy
    sliding = tr.t < t1
    U = tr.qd[:, 0] - vb
    heat = -mu * m * g * (vb * tr.t - mu * g * tr.t ** 2 / 2)          # int F U dt, F = mu m g
    assert np.allclose(E["friction_work"][sliding], heat[sliding], rtol=1e-10, atol=1e-12)
    assert E["friction_work"][-1] == pytest.approx(-m * vb ** 2 / 2, rel=1e-10)
    assert E["reaction_work"][-1] == pytest.approx(m * vb ** 2, rel=1e-10)
    assert np.all(np.diff(E["friction_work"]) <= 1e-13) and np.all(U <= 1e-12)
    assert tr.diagnostics["energy_balance_relative"] < 1e-10
