"""evaluate says when the split of the contact forces is not unique: a rod lying at rest on a
rough floor (two sticking ends, F_A + F_B = 0 the only condition of equilibrium) reports the
rule of the split it shows and the admissible range of each friction force,
|F| <= mu_s N = mu_s m g/2 (Coulomb statics); a determinate state reports nothing."""

import pytest

import nonideal
from nonideal.analysis.evaluation import evaluate
from tests.helpers import DATA_DIR

G = 9.81


def test_rod_at_rest_friction_range_is_mu_s_n():
    model = nonideal.load_model(DATA_DIR / "friction" / "rod_flat_pushed.toml")
    p = model.parameter_values
    ev = evaluate(model)
    ind = ev.to_dict()["indeterminate"]
    assert "widest margin" in ind["rule"]
    limit = p["mu_s"] * p["m"] * G / 2
    for label in ("F A", "F B"):
        lo, hi, shown = ind["ranges"][label]
        assert lo == pytest.approx(-limit, rel=1e-9) and hi == pytest.approx(limit, rel=1e-9)
        assert shown == pytest.approx(0.0, abs=1e-9)
    assert "the split of these forces is NOT unique" in ev.as_text()


def test_a_determinate_state_has_no_note():
    ev = evaluate(nonideal.load_model(DATA_DIR.parent.parent / "docs" / "rod.toml"))
    assert ev.to_dict()["indeterminate"] == {} and "NOT unique" not in ev.as_text()
