"""The friction torque keys of ``[[contacts]]`` (``spin``, ``spin_friction``, ``rolling``,
``rolling_friction``): what is accepted and every bad input refused by name with the fix."""

import pytest

from nonideal.cli import main
from nonideal.errors import ModelError
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

SPIN = (DATA_DIR / "torques" / "spinning_disk.toml").read_text()
CONTACT = '''spin = "psi'"
spin_friction = "l"'''


def _load(tmp_path, replacement):
    path = tmp_path / "model.toml"
    path.write_text(SPIN.replace(CONTACT, replacement))
    return load_model(path)


def test_accepted_keys_give_the_torques(tmp_path):
    model = _load(tmp_path, CONTACT + '''
rolling = ["x'", "y'"]
rolling_friction = "l/10"''')
    c = model.contacts[0]
    assert str(c.spin) == "psi'" and len(c.rolling) == 2 and str(c.rolling_friction) == "l/10"


@pytest.mark.parametrize("replacement, words", [
    ('spin_friction = "l"', ["spin_friction needs the relative spin angular velocity", "give spin ="]),
    ('''spin = "psi'"''', ["spin is given without spin_friction", "add spin_friction"]),
    ('rolling_friction = "l"', ["rolling_friction needs the relative rolling angular velocity",
                                "give rolling ="]),
    ('''spin = "psi'^2"
spin_friction = "l"''', ["spin = psi'**2 is not linear in the velocities"]),
    ('''spin = "psi"
spin_friction = "l"''', ["spin = psi contains no velocity"]),
    ('''spin = "psi'"
spin_friction = "-0.1"''', ["spin_friction = -0.1 is negative"]),
    ('''spin = "psi'"
spin_friction = "inf"''', ["spin_friction = inf would forbid the motion"]),
    ('''spin = ["psi'"]
spin_friction = "l"''', ["spin must be an expression"]),
    ('''rolling = ["x'", "y'", "psi'"]
rolling_friction = "l"''', ["rolling must have 1 or 2 entries"]),
    ('''spin = "psi'"
spin_friction = "l"
bilateral = true''', ["spin_friction on a bilateral contact"]),
])
def test_bad_torque_keys_are_refused_by_name(tmp_path, replacement, words):
    with pytest.raises(ModelError) as info:
        _load(tmp_path, replacement)
    message = str(info.value)
    assert "'floor'" in message
    for w in words:
        assert w in message


def test_torque_name_taken_by_another_contact(tmp_path):
    text = SPIN + '''
[[contacts]]
name = "floor_spin"
gap = "z + 1"
slip = ["x'"]
'''
    path = tmp_path / "model.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match="the friction torque of contact 'floor' is reported under that name"):
        load_model(path)


def test_cli_exit_2_names_the_key(tmp_path, capsys):
    path = tmp_path / "model.toml"
    path.write_text(SPIN.replace(CONTACT, 'spin_friction = "l"'))
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "spin_friction" in err and "give spin" in err


def test_other_forms_are_refused_for_friction_torques(capsys):
    assert main(["evaluate", str(DATA_DIR / "torques" / "spinning_disk.toml"), "--form", "maggi"]) == 2
    assert "use --form lagrange1" in capsys.readouterr().err
