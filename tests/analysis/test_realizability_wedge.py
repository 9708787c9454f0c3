"""Realizability with a contact that is not asked about: a block slides down the smooth face of
a wedge, the wedge rests on a rough floor.  The floor must hold the wedge against the block's
push ``N_face sin(a)``: ``f* = m g cos(a) sin(a)``, ``N = M g + m g cos^2(a)`` -- whether the
face contact is named or not (naming only the floor once released the face, and the block's
load with it)."""


import numpy as np
import pytest

from nonideal.analysis.contact.realizability import realizability
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "friction" / "wedge_on_rough_floor.toml"


@pytest.fixture(scope="module")
def model():
    return load_model(PATH)


@pytest.mark.parametrize("contacts", [None, ["floor"], ["floor", "face"]])
def test_floor_holds_the_wedge(model, contacts):
    p = model.parameter_values
    m, M, g, a = p["m"], p["M"], p["g"], p["alpha"]
    rep = realizability(model, contacts=contacts)
    floor = rep.contacts["floor"]
    assert floor.needed[0] == pytest.approx(m * g * np.cos(a) * np.sin(a), rel=1e-12)
    assert floor.normal == pytest.approx(M * g + m * g * np.cos(a) ** 2, rel=1e-12)
    assert floor.realizable and floor.margin == pytest.approx(p["mu_fs"] * floor.normal - abs(floor.needed[0]), rel=1e-12)
    assert "face" not in rep.contacts                      # frictionless: nothing to realize
    assert rep.to_dict().get("other_contacts", {}) == ({"face": "smooth"} if contacts == ["floor"] else {})


def test_simulation_agrees_the_wedge_stays(model):
    p = model.parameter_values
    tr = simulate(model, t_end=0.3)
    assert tr.events == [] and set(tr.contacts["floor"]["mode"]) == {"stick"}
    X = tr.q[:, model.coordinates.index("X")]
    assert np.max(np.abs(X)) < 1e-12
    F = np.array(tr.contacts["floor"]["friction"])[:, 0]
    assert np.allclose(np.abs(F), p["m"] * p["g"] * np.cos(p["alpha"]) * np.sin(p["alpha"]), rtol=1e-10)


def test_contact_with_along_is_refused(capsys):
    from nonideal.cli import main

    assert main(["realizability", str(PATH), "--contact", "floor", "--along"]) == 2
    assert "--contact: --along follows the motion" in capsys.readouterr().err
