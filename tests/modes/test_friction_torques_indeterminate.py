"""A friction torque in a statically indeterminate contact set: a block on two pads at the same
height (their normal forces are not determined) turned by a torque T below the combined bound.
The split shown is the widest-margin one (the smallest of N and the margins ``mu_s N - |F|``,
``l N - |M|`` maximized), which now includes the torque cones: with ``l_a < l_b`` it is
``M_a = 0``, ``N_a = t/l_a``, ``t = (l_b m g - T)/(1 + l_b/l_a)``."""

import numpy as np
import pytest

from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR


def test_widest_margin_split_with_pivoting_torques():
    model = load_model(DATA_DIR / "torques" / "two_pads_torque.toml")
    p = model.parameter_values
    ev = evaluate(model)
    la, lb, T, W = 0.01, 0.03, p["T"], p["m"] * p["g"]
    t = (lb * W - T) / (1 + lb / la)
    a, b = ev.contacts["a_spin"], ev.contacts["b_spin"]
    assert ev.contacts["a"]["normal"] + ev.contacts["b"]["normal"] == pytest.approx(W, rel=1e-10)
    assert a["friction"][0] + b["friction"][0] == pytest.approx(-T, rel=1e-10)
    assert a["normal"] == pytest.approx(t / la, rel=1e-6)
    assert abs(a["friction"][0]) < 1e-6
    for c, l in ((a, la), (b, lb)):
        assert l * c["normal"] - abs(c["friction"][0]) == pytest.approx(t, rel=1e-6)
    assert np.all(np.abs(ev.qdd) < 1e-12)
