"""The smallest realizability margin along a sticking motion, located between the samples.

A block on a rough floor pushed by ``A sin(w t)`` with ``A < mu m g`` sticks; the friction it
needs is ``-A sin(w t)`` and the margin ``mu m g - A |sin(w t)|`` is smallest, ``mu m g - A``,
at ``t = pi/(2 w)`` -- not a sample time of the 201 samples on [0, 1] (the nearest is 0.785).
"""

import numpy as np
import pytest

from nonideal.analysis.contact.realizability import realizability_along
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "friction" / "block_pushed_sinusoid.toml"


@pytest.fixture(scope="module")
def along():
    return realizability_along(load_model(PATH)).along


def test_minimum_located_between_the_samples(along):
    p = load_model(PATH).parameter_values
    exact = p["mu"] * p["m"] * p["g"] - p["A"]
    t_star = np.pi / (2 * p["w"])
    assert along["lost_at"] is None
    assert along["min_margin_located"]
    assert abs(along["min_margin"] - exact) < 1e-8
    assert abs(along["min_margin_t"] - t_star) < 1e-5          # a flat minimum: t to ~sqrt(eps)
    # the sampled minimum is off by A (1 - cos(w dt)) with dt = 0.785 - pi/4
    assert abs(along["min_margin_sampled"] - exact) > 1e-7
    assert along["min_margin_sampled"] > along["min_margin"]


def test_minimum_at_the_end_is_not_refined():
    """Margin still decreasing at t_end: the sampled end value is the minimum, reported as is."""
    model = load_model(PATH)
    along = realizability_along(model, t_end=0.5).along
    p = model.parameter_values
    assert not along["min_margin_located"]
    assert along["min_margin_t"] == pytest.approx(0.5)
    assert along["min_margin"] == pytest.approx(p["mu"] * p["m"] * p["g"] - p["A"] * np.sin(1.0), rel=1e-9)
