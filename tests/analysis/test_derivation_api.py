"""The Python API derives what the command line prints: ``nonideal.derive(model, form)`` on a
model with contacts puts them in their states at t0, as ``nonideal derive`` does (a sliding
contact's normal force carries -mu N s); the symbolic stage, asked without rows, says that it
leaves the contacts out.  The three result types show themselves in Jupyter."""

import pytest

import nonideal
from nonideal.equations.formalisms import derive as derive_symbolic
from tests.helpers import DATA_DIR, cli_json

ROD = DATA_DIR.parent.parent / "docs" / "rod.toml"


@pytest.fixture(scope="module")
def rod():
    return nonideal.load_model(ROD)


@pytest.mark.parametrize("form", ["appell", "lagrange1"])
def test_api_and_cli_give_the_same_equations(rod, form):
    api = nonideal.derive(rod, form).to_dict()
    cli = cli_json("derive", ROD, "--form", form, "--json")
    assert api["equations"] == cli["equations"]
    assert api["multipliers"] == cli["multipliers"] == ["lambda_A"]        # A slides, B is off
    assert any("mu" in eq for eq in api["equations"])                      # friction -mu N s


def test_contact_states_are_chosen_alike(rod):
    api = nonideal.derive(rod, "lagrange1", contacts={"A": "stick"}).to_dict()
    cli = cli_json("derive", ROD, "--contact", "A=stick", "--json")
    assert api["equations"] == cli["equations"]
    assert len(api["multipliers"]) == 2                                     # N and the friction


def test_symbolic_stage_says_it_leaves_the_contacts_out(rod):
    eom = derive_symbolic(rod, "appell")
    assert eom.multipliers == ()
    assert "'A', 'B' are not in these equations" in eom.notes[0]
    assert "not in these equations" in eom.as_text()


def test_contacts_on_a_model_without_any_is_an_error():
    with pytest.raises(nonideal.ModelError, match="no \\[\\[contacts\\]\\]"):
        nonideal.derive(nonideal.load_model(DATA_DIR / "pendulum_xy.toml"), contacts={"A": "stick"})


def test_jupyter_representations(rod):
    eom = nonideal.derive(rod, "appell")
    latex = eom._repr_latex_()
    assert latex.startswith("$$") and r"\ddot{\theta}" in latex and "&=" in latex
    assert "Gibbs-Appell" in eom._repr_html_()
    assert r"\ge 0" in rod._repr_latex_() and "contact A" in rod._repr_latex_()
    assert "coordinates: x, y, theta" in rod._repr_html_()
    tr = nonideal.simulate(rod, t_end=0.3)
    assert r"\dot{x}(t_1)" in tr._repr_latex_()
    html = tr._repr_html_()
    assert "stick" in html and "<table>" in html
