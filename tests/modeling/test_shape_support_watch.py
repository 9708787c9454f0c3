"""A contact whose support point stops being unique along the motion is refused there.

A thin disk released at rest from a tilt of 0.3 rad on a smooth plane falls flat on its face:
its rim's touching point is unique while the tilt theta (from lying flat) is positive and jumps
to the opposite side of the rim through theta = 0.  The run stops with SingularMotion (exit code
3) naming the contact, the time and the state, at the first accepted state with sin^2 theta <=
LEVEL -- not after integrating into the kink of the gap (where the steps collapsed after
thousands of tiny steps, a generic integration failure).
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from nonideal import gallery
from nonideal.gallery import chaplygin_ball
from nonideal.errors import SingularMotion
import tomllib

from nonideal.modeling.modelfile import model_from_dict
from nonideal.modeling.shapes.watch import LEVEL, SupportWatch
from nonideal.simulation.hybrid import simulate

ROOT = Path(__file__).resolve().parents[2]

COIN = """
[model]
name = "coin falling flat"
format = 1
[parameters]
m = 0.0085
r = 0.0129
g = 9.81
[coordinates]
q = ["x", "y", "z", "psi", "theta", "phi"]
[[frames]]
name = "B"
rotation = "body ZXY"
angles = ["psi", "theta", "phi"]
[[points]]
name = "G"
position = ["x", "y", "z"]
[[bodies]]
type = "rigid"
name = "coin"
mass = "m"
inertia = [["m*r^2/4", "0", "0"], ["0", "m*r^2/4", "0"], ["0", "0", "m*r^2/2"]]
frame = "B"
center = "G"
[gravity]
vector = ["0", "0", "-g"]
[[contacts]]
name = "table"
body = "coin"
shape = { type = "disk", radius = "r", axis = [0, 0, 1] }
mu = 0
[initial]
x = 0.0
y = 0.0
z = "r*sin(0.3)"
psi = 0.0
theta = 0.3
phi = 0.0
"x'" = 0.0
"y'" = 0.0
"psi'" = 0.0
"theta'" = 0.0
"phi'" = 0.0
[simulation]
t_end = 0.1
rtol = 1e-10
atol = 1e-13
"""


def _model():
    return model_from_dict(tomllib.loads(COIN), "coin_flat.toml")


def test_a_coin_falling_flat_is_refused_at_the_time_it_lands():
    with pytest.raises(SingularMotion) as info:
        simulate(_model())
    err = info.value
    assert "contact 'table'" in str(err) and "disk" in str(err) and "lies flat" in str(err)
    # the fall to theta = 0 takes about 0.0313 s (the integration stalled at 0.03132 without it)
    assert 0.030 < err.t < 0.0314
    assert abs(np.sin(err.state["theta"])) ** 2 <= LEVEL
    assert err.state["theta"] > 0  # stopped on the regular side, before the rim's point jumps


def test_the_watch_passes_regular_states_and_refuses_only_singular_ones():
    model = _model()
    watch = SupportWatch(model, list(model.parameter_values.values()))
    assert watch
    q = np.zeros(6)
    q[4] = 0.3
    watch.check(0.0, q)  # tilted: unique
    q[4] = 1e-5
    with pytest.raises(SingularMotion, match="t = 0.5 "):
        watch.check(0.5, q)


def test_contacts_with_unique_support_everywhere_are_not_watched():
    # the ellipsoid and sphere have a unique support point for every orientation
    model = gallery.load(chaplygin_ball.NAME)
    assert not SupportWatch(model, list(model.parameter_values.values()))


def test_the_command_line_exits_3_naming_the_contact_and_time(tmp_path):
    path = tmp_path / "coin_flat.toml"
    path.write_text(COIN)
    out = subprocess.run([sys.executable, "-m", "nonideal", "simulate", str(path), "--csv",
                          str(tmp_path / "out.csv")], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 3
    assert "contact 'table'" in out.stderr + out.stdout and "loses its unique support point" in out.stderr + out.stdout
    assert not (tmp_path / "out.csv").exists()


def test_a_rolling_coin_falling_flat_is_refused_too():
    # rolling without slipping (the compiled contacts loop may carry the phase): refused at the
    # sample or step where it lands, not continued through the singular support point
    model = model_from_dict(tomllib.loads(COIN.replace("mu = 0", 'mu = "inf"')), "coin_roll.toml")
    with pytest.raises(SingularMotion, match="contact 'table'") as info:
        simulate(model, times=np.linspace(0.0, 0.1, 601))
    assert 0.02 < info.value.t < 0.05 and info.value.state["theta"] > 0
