"""Parameters written with a unit (``alpha = "30 deg"``, ``m = "250 g"``) are converted to the
model's base units; an angle in degrees written without its unit that keeps a contact open at
t0 is warned about by name."""

import math
import warnings

import pytest

import nonideal
from nonideal.errors import ModelError, UnitWarning
from nonideal.modeling.modelfile import load_model
from nonideal.modeling.quantities import parse_quantity, parse_unit
from tests.helpers import run_cli

RAMP = """
[model]
name = "block on a ramp"
format = 1

[parameters]
m = "250 g"
g = 9.81
alpha = ALPHA

[coordinates]
q = ["x", "y"]

[energy]
kinetic = "m*(x'^2 + y'^2)/2"
potential = "m*g*y"

[[contacts]]
name = "ramp"
gap = "y*cos(alpha) - x*sin(alpha)"
slip = ["x'*cos(alpha) + y'*sin(alpha)"]
mu = 0.2

[initial]
x = 1.0
y = 0.5773502691896257
"x'" = 0
"y'" = 0
"""


@pytest.mark.parametrize("text, value, dimension", [
    ("30 deg", math.pi / 6, (0, 0, 0, 1)), ("250 g", 0.25, (0, 1, 0, 0)),
    ("9.81 m/s^2", 9.81, (1, 0, -2, 0)), ("120 rpm", 4 * math.pi, (0, 0, -1, 1)),
    ("2 kg m^2", 2.0, (2, 1, 0, 0)), ("1.5e3 N m", 1500.0, (2, 1, -2, 0)),
    ("5 mm/s", 0.005, (1, 0, -1, 0)), ("0.3 kg*cm**2", 3e-5, (2, 1, 0, 0)),
])
def test_quantities_in_si(text, value, dimension):
    q = parse_quantity(text)
    assert q.in_base() == pytest.approx(value, rel=1e-15) and q.dimension == dimension


def test_expressions_and_numbers_are_not_quantities():
    for text in ("sqrt(g/l)", "2*pi", "0.5", 3.0, "m*g"):
        assert parse_quantity(text) is None


def test_unknown_units_are_refused_with_the_nearest():
    with pytest.raises(ValueError, match="unknown unit 'gg'.*did you mean 'g'"):
        parse_unit("gg")
    with pytest.raises(ModelError, match=r"\[parameters\] m = '250 kgs'.*unknown unit 'kgs'"):
        nonideal.Model("p", ["x"], parameters={"m": "250 kgs"}, kinetic="m*x'^2/2")


def test_model_converts_to_its_base_units_and_keeps_what_was_written():
    m = nonideal.Model("p", ["x"], kinetic="m*x'^2/2", parameters={
        "m": "250 g", "alpha": "30 deg", "l": {"value": 50, "unit": "cm"},
        "g": {"value": 9.81, "unit": "m/s^2"}, "w": "2*alpha"})
    p = m.parameters
    assert p["m"].value == 0.25 and p["m"].unit == "kg" and p["m"].given == "250 g"
    assert p["alpha"].value == pytest.approx(math.pi / 6, rel=1e-15) and p["alpha"].unit == "rad"
    assert p["l"].value == 0.5 and p["l"].given == "50 cm"
    assert p["g"].value == 9.81 and p["g"].given == ""          # already in the base units
    assert p["w"].value == pytest.approx(math.pi / 3, rel=1e-15)  # derived from the converted one
    assert "0.25 kg (250 g)" in m._repr_html_()
    # declared base units: grams stay grams, a metre becomes 100 cm
    g = nonideal.Model("p", ["x"], kinetic="m*x'^2/2", units={"mass": "g", "length": "cm"},
                       parameters={"m": "250 g", "l": "1 m"})
    assert g.parameters["m"].value == 250.0 and g.parameters["l"].value == 100.0


def test_degrees_without_unit_that_open_a_contact_are_warned(tmp_path):
    plain = tmp_path / "ramp.toml"
    plain.write_text(RAMP.replace("ALPHA", "30"))
    with pytest.warns(UnitWarning, match=r"alpha = 30 is used as an angle.*contact 'ramp' is open "
                      r"at t0 \(gap 1.077.*30 deg would close it \(gap 0\)"):
        load_model(plain)
    given = tmp_path / "ramp_deg.toml"
    given.write_text(RAMP.replace("ALPHA", '"30 deg"'))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = load_model(given)
    ev = nonideal.evaluate(model)       # on the ramp, sliding down: x'' = -g cos a (sin a - mu cos a)
    a = math.pi / 6
    assert ev.mode == "ramp:slide-"
    assert ev.qdd[0] == pytest.approx(-9.81 * math.cos(a) * (math.sin(a) - 0.2 * math.cos(a)), rel=1e-12)
    # an angle above 2 pi that changes no contact is left alone (a spinning rotor's angle)
    far = tmp_path / "far.toml"
    far.write_text(RAMP.replace("ALPHA", "30").replace("x = 1.0", "x = -5.0"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_model(far)


def test_cli_prints_the_warning_and_the_conversions(tmp_path):
    plain = tmp_path / "ramp.toml"
    plain.write_text(RAMP.replace("ALPHA", "30"))
    r = run_cli("evaluate", plain)
    assert r.returncode == 0 and r.stderr.count("warning:") == 1 and "'ramp'" in r.stderr
    given = tmp_path / "ramp_deg.toml"
    given.write_text(RAMP.replace("ALPHA", '"30 deg"'))
    r = run_cli("check", given)
    assert r.returncode == 0 and "warning" not in r.stderr
    assert "m = 250 g = 0.25 kg, alpha = 30 deg = 0.5235987756 rad" in r.stdout


def test_set_gives_base_units_for_a_parameter_declared_in_degrees(tmp_path):
    path = tmp_path / "ramp.toml"
    path.write_text(RAMP.replace("ALPHA", '{ value = 30, unit = "deg" }'))
    assert load_model(path).parameters["alpha"].value == pytest.approx(math.pi / 6, rel=1e-15)
    # --set (and a sweep's --vary) give the base unit, radians here -- or a quantity
    assert load_model(path, parameters={"alpha": 0.6}).parameters["alpha"].value == 0.6
    assert load_model(path, parameters={"alpha": "45 deg"}).parameters["alpha"].value == \
        pytest.approx(math.pi / 4, rel=1e-15)
