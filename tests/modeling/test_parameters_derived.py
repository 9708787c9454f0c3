"""Derived parameters: [parameters] values given as expressions in the other parameters, and
numeric settings (restitution, eps, [simulation] t_end) given as expressions in the parameters."""

import math

import pytest

from nonideal import Model, ModelError
from nonideal.modeling.modelfile import load_model

FILE = """
[model]
name = "ball on a floor"
[parameters]
g = 9.81
l = 0.5
w = "sqrt(g/l)"
T = {{ value = "2*pi/w", unit = "s" }}
e = "{e}"
[coordinates]
q = ["x", "y"]
[energy]
kinetic = "(x'^2 + y'^2)/2"
potential = "g*y"
[[contacts]]
name = "floor"
gap = "y"
slip = ["x'"]
mu = 0
restitution = "e"
[initial]
x = 0
y = 1
"x'" = 0
"y'" = 0
[simulation]
t_end = "T"
"""


def load(tmp_path, e="0.5 + 0.25"):
    path = tmp_path / "ball.toml"
    path.write_text(FILE.format(e=e))
    return load_model(path)


def test_values_in_dependency_order(tmp_path):
    m = load(tmp_path)
    w = math.sqrt(9.81 / 0.5)
    assert m.parameters["w"].value == pytest.approx(w, rel=1e-15)
    assert m.parameters["T"].value == pytest.approx(2 * math.pi / w, rel=1e-15)
    assert m.parameters["T"].unit == "s"
    assert m.simulation.t_end == pytest.approx(2 * math.pi / w, rel=1e-15)
    assert m.contacts[0].impact.restitution == 0.75


@pytest.mark.parametrize("e, message", [
    ("e + 1", "[parameters] e: cannot be evaluated -- it is defined in terms of itself"),
    ("ee", "[parameters] e: unknown parameter 'ee'"),
    ("sqrt(-g)", "[parameters] e: the expression sqrt(-g) has no finite real value"),
    ("__import__('os')", "[parameters] e:"),
])
def test_bad_definitions_are_named(tmp_path, e, message):
    with pytest.raises(ModelError) as info:
        load(tmp_path, e)
    text = str(info.value)
    assert message in text, text
    assert "restitution" not in text   # no follow-on error where the parameter is used


def test_cycles_through_the_api():
    with pytest.raises(ModelError, match=r"\[parameters\] a: cannot be evaluated -- it depends on b: "
                                         "the definitions form a cycle"):
        Model(name="x", coordinates=["x"], parameters={"a": "2*b", "b": "a/2"},
              kinetic="x'^2/2", initial={"x": 0, "x'": 0})
    m = Model(name="x", coordinates=["x"], parameters={"k": 4.0, "w": "sqrt(k)"},
              kinetic="x'^2/2", potential="k*x^2/2", initial={"x": 0, "x'": 0})
    assert m.parameters["w"].value == 2.0
