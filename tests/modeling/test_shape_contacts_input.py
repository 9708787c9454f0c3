"""Contacts from geometry: bad input is refused with the key and the fix (exit 2)."""

import tomllib

import pytest

from nonideal.errors import ModelError
from nonideal.modeling.modelfile import model_from_dict
from tests.helpers import DATA_DIR, run_cli

BALL = """
[model]
name = "ball"
[parameters]
m = 1.0
r = 0.1
g = 9.81
[coordinates]
q = ["x", "y", "z", "a", "b", "c"]
[[bodies]]
type = "rigid"
name = "ball"
mass = "m"
inertia = [["0.004", "0", "0"], ["0", "0.004", "0"], ["0", "0", "0.004"]]
position = ["x", "y", "z"]
rotation = [["cos(b)*cos(c)", "sin(a)*sin(b)*cos(c) - sin(c)*cos(a)", "sin(a)*sin(c) + sin(b)*cos(a)*cos(c)"],
            ["sin(c)*cos(b)", "sin(a)*sin(b)*sin(c) + cos(a)*cos(c)", "-sin(a)*cos(c) + sin(b)*sin(c)*cos(a)"],
            ["-sin(b)", "sin(a)*cos(b)", "cos(a)*cos(b)"]]
[gravity]
vector = ["0", "0", "-g"]
[[contacts]]
name = "floor"
body = "ball"
{contact}
mu = "inf"
[initial]
x = 0.0
y = 0.0
a = {a}
b = 0.0
c = 0.0
"a'" = 0.0
"b'" = 0.0
"c'" = 0.0
"""


def _model(contact, a=0.0):
    return model_from_dict(tomllib.loads(BALL.replace("{contact}", contact).replace("{a}", str(a))), "ball.toml")


def _problems(contact, a=0.0):
    with pytest.raises(ModelError) as err:
        _model(contact, a)
    return str(err.value)


@pytest.mark.parametrize("contact, words", [
    ('shape = {type = "sphere"}', ["a sphere needs radius", 'type = "sphere", radius']),
    ('shape = {type = "ellipsoid", semi_axes = [1, 2]}', ["semi_axes must have 3 components (got 2)"]),
    ('shape = {type = "paraboloid", curvature_radii = ["r"], center = [0, 0]}',
     ["curvature_radii must have 2 components", "center must have 3 components"]),
    ('shape = {type = "cube", side = 1}', ["shape type 'cube' unknown", '"sphere"']),
    ('shape = {type = "sphere", radius = "r"}\nsurface = {type = "cylinder"}', ["surface type 'cylinder' unknown"]),
    ('shape = {type = "sphere", radius = "r", radiuss = 1}', ["unknown key 'radiuss'"]),
    ('shape = {type = "sphere", radius = "-r"}', ["radius = -r = -0.1 must be positive"]),
    ('shape = {type = "sphere", radius = "x"}', ["x -- a shape's dimensions"]),
    ('shape = {type = "sphere", radius = "r"}\ngap = "z - r"', ["give either gap and slip or body and shape"]),
    ('shape = "sphere"', ["shape must be an inline table"]),
    ('shape = {type = "sphere", radius = "r"}\nsurface = {velocity = [0, 0, 1]}',
     ["has a component along the normal"]),
    ('shape = {type = "sphere", radius = "r"}\nsurface = {omega = [1, 0, 0]}', ["is not along the normal"]),
    ('shape = {type = "disk", radius = "r", axis = [0, 0, 0]}', ["axis = [0, 0, 0] is the zero vector"]),
])
def test_refused_with_the_key_and_the_fix(contact, words):
    text = _problems(contact)
    assert text.startswith("ball.toml: [[contacts]] #1 'floor'") or "contact 'floor'" in text
    for w in words:
        assert w in text, (w, text)


def test_body_must_be_a_rigid_body_of_the_model():
    text = model_error(BALL.replace('body = "ball"', 'body = "bal"'))
    assert "body 'bal' is not a body of this model" in text and "ball" in text
    particle = BALL.replace('type = "rigid"', 'type = "particle"').replace(
        'inertia = [["0.004", "0", "0"], ["0", "0.004", "0"], ["0", "0", "0.004"]]\n', "")
    particle = particle[:particle.index("rotation =")] + particle[particle.index("[gravity]"):]
    assert "is a Particle; a shape is fixed in a rigid body" in model_error(particle)


def model_error(text):
    with pytest.raises(ModelError) as err:
        model_from_dict(tomllib.loads(text.replace("{contact}", 'shape = {type = "sphere", radius = "r"}')
                                      .replace("{a}", "0.0")), "ball.toml")
    return str(err.value)


def test_no_unique_support_point_is_refused_with_the_state():
    from nonideal.numeric.consistency import complete_state
    from nonideal.numeric.kernel import kernel_of, parameter_vector
    from nonideal.errors import InconsistentInitialConditions

    # a disk of axis z (body) lying flat on the table at a = 0
    model = _model('shape = {type = "disk", radius = "r", axis = [0, 0, 1]}')
    with pytest.raises(InconsistentInitialConditions) as err:
        complete_state(kernel_of(model), model.numeric_initial(), parameter_vector(model), 0.0)
    text = str(err.value)
    assert "no unique support point" in text and "lies flat" in text and "a = 0" in text
    # a paraboloid turned upside down (a = pi): its valid side faces away from the plane
    model = _model('shape = {type = "paraboloid", curvature_radii = [0.2, 0.03]}', a=3.0)
    with pytest.raises(InconsistentInitialConditions) as err:
        complete_state(kernel_of(model), model.numeric_initial(), parameter_vector(model), 0.0)
    assert "paraboloid" in str(err.value) and "vertex down" in str(err.value)


def test_cli_exit_code_two(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BALL.replace("{contact}", 'shape = {type = "ellipsoid", semi_axes = [1, 2]}').replace("{a}", "0.0"))
    out = run_cli("check", path)
    assert out.returncode == 2 and "semi_axes must have 3 components" in out.stderr
    path.write_text(BALL.replace("{contact}", 'shape = {type = "disk", radius = "r", axis = [0, 0, 1]}').replace("{a}", "0.0"))
    out = run_cli("simulate", path, "--t-end", "0.1")
    assert out.returncode == 2 and "lies flat" in out.stderr


def test_python_api_with_shape_objects():
    from nonideal.modeling.contacts import Contact, IdealRolling
    from nonideal.modeling.shapes import Plane, Sphere
    model = _model('shape = {type = "sphere", radius = "r"}')
    api = model.replace(contacts=(Contact("floor", body="ball", shape=Sphere("r"), surface=Plane(),
                                          friction=IdealRolling()),))
    assert api.contacts[0].gap == model.contacts[0].gap
    assert api.contacts[0].slip == model.contacts[0].slip


FRAMES = """
[model]
name = "offset ball"
[parameters]
m = 1.0
r = 0.1
e = 0.03
g = 9.81
[coordinates]
q = ["x", "y", "z", "a", "b", "c"]
[[frames]]
name = "B"
rotation = "body ZYX"
angles = ["c", "b", "a"]
[[points]]
name = "G"
position = ["x", "y", "z"]
[[points]]
name = "K"
frame = "B"
from = "G"
position = [0, 0, "e"]
[[points]]
name = "S"
position = ["x", "y", "z - r"]
[[bodies]]
type = "rigid"
name = "ball"
mass = "m"
inertia = [["0.004", "0", "0"], ["0", "0.004", "0"], ["0", "0", "0.003"]]
frame = "B"
center = "G"
[gravity]
vector = ["0", "0", "-g"]
[[contacts]]
name = "floor"
body = "ball"
shape = {type = "sphere", radius = "r", center = CENTER}
mu = 0.3
[initial]
x = 0.0
y = 0.0
a = 0.2
b = 0.1
c = 0.0
"""


def test_center_may_name_a_point_fixed_in_the_body():
    import sympy as sp
    named = model_from_dict(tomllib.loads(FRAMES.replace("CENTER", '"K"')), "ball.toml")
    listed = model_from_dict(tomllib.loads(FRAMES.replace("CENTER", '[0, 0, "e"]')), "ball.toml")
    assert sp.simplify(named.contacts[0].gap - listed.contacts[0].gap) == 0
    assert all(sp.simplify(u - v) == 0 for u, v in zip(named.contacts[0].slip, listed.contacts[0].slip))
    with pytest.raises(ModelError, match="center 'Q' is not a point of the model"):
        model_from_dict(tomllib.loads(FRAMES.replace("CENTER", '"Q"')), "ball.toml")
    with pytest.raises(ModelError, match="center 'S' moves in the body"):
        model_from_dict(tomllib.loads(FRAMES.replace("CENTER", '"S"')), "ball.toml")
