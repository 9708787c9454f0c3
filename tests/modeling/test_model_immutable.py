"""A Model is immutable: what later stages derive from it (its dynamics, kernels, evaluations)
stays valid.  Changing its initial values in place after an evaluation gave the answer of the
old values; now it is refused, and the ways to change them are named."""

import math
import pickle

import pytest

from nonideal import evaluate, simulate
from nonideal.errors import ModelError
from nonideal.modeling.model import Model

G = 9.81


def pendulum(th=0.5):
    return Model(name="pendulum", coordinates=["th"], parameters={"g": G, "l": 1.0},
                 kinetic="l^2*th'^2/2", potential="-g*l*cos(th)",
                 initial={"th": th, "th'": 0.0}, simulation={"t_end": 1.0})


def test_changing_the_initial_values_in_place_is_refused_and_replace_gives_the_new_answer():
    m = pendulum()
    assert evaluate(m).qdd[0] == pytest.approx(-G * math.sin(0.5), rel=1e-12)
    for mapping in (m.initial, m.parameters):
        with pytest.raises(TypeError, match="a Model is immutable"):
            mapping["th"] = 1.0
    with pytest.raises(TypeError, match=r"model.replace\(initial=\{...\}\)"):
        m.initial.update({"th": 1.0})
    assert evaluate(m).qdd[0] == pytest.approx(-G * math.sin(0.5), rel=1e-12)
    moved = m.replace(initial={"th": 1.0, "th'": 0.0})
    assert evaluate(moved).qdd[0] == pytest.approx(-G * math.sin(1.0), rel=1e-12)
    assert simulate(m, initial={"th": 1.0}, times=[0.0]).q[0, 0] == 1.0


def test_a_model_still_pickles_and_compares():
    m = pendulum()
    again = pickle.loads(pickle.dumps(m))
    assert again == m and dict(again.initial) == dict(m.initial)


@pytest.mark.parametrize("option", ["parameters", "initial"])
def test_a_value_that_is_not_a_number_is_refused_naming_the_key(option):
    key = "g" if option == "parameters" else "th"
    with pytest.raises(ModelError, match=rf"simulate: {option}\['{key}'\] must be a number, got 'abc'"):
        simulate(pendulum(), **{option: {key: "abc"}})
