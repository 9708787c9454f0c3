"""``evaluate`` on a contact with a friction torque: the torque is reported as a contact of its
own with its contact's normal force, and the Painlevé split of the reactions counts the normal
force once -- the torque is all friction part (Manglieva & Beknazarov 2022, (1.52))."""

import numpy as np
import pytest

from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR


@pytest.mark.parametrize("w, torque", [(10.0, "sliding"), (0.0, "sticking")])
def test_split_of_a_pivoting_disk(w, torque):
    model = load_model(DATA_DIR / "torques" / "spinning_disk.toml")
    p = model.parameter_values
    ev = evaluate(model, at={"psi'": w})
    N = p["m"] * p["g"]
    spin = ev.contacts["floor_spin"]
    assert spin["normal"] == pytest.approx(N, rel=1e-12)
    expected = -p["l"] * N if torque == "sliding" else 0.0
    assert spin["friction"][0] == pytest.approx(expected, abs=1e-12)
    total = ev.reaction_total()
    assert np.allclose(total["generalized"], [0, 0, N, expected], atol=1e-12)
    assert np.allclose(total["constraint_part"], [0, 0, N, 0], atol=1e-12)
    assert np.allclose(total["friction_part"], [0, 0, 0, expected], atol=1e-12)
    I = p["m"] * p["R"] ** 2 / 2
    assert ev.qdd[3] == pytest.approx(expected / I, abs=1e-12)
