"""A coin (the rim of a thin disk) launched sliding on its edge: rolling from t* = U0/(3 mu g)
at v_f = v0 - U0/3 (closed form in the gallery module's docstring)."""

import pytest

from nonideal import gallery
from nonideal.gallery import coin_slide_roll as example


@pytest.mark.parametrize("v0, w0", [(1.0, -50.0), (0.5, 0.0), (-0.3, 40.0)])
def test_event_time_and_rolling_velocity(v0, w0):
    model = gallery.load(example.NAME) if (v0, w0) == (1.0, -50.0) else example.build(v0=v0, w0=w0, t_end=0.4)
    r = example.check(model)
    cf = r["closed_form"]
    assert [e[1] for e in r["events"]] == ["stick"]
    assert r["t_star_error"] < 1e-9 and r["v_f_error"] < 1e-9 and r["w_f_error"] < 1e-9
    assert r["friction_work"] == pytest.approx(-cf["energy_loss"], rel=1e-8)
    assert r["lean_max"] < 1e-12 and abs(r["energy_balance_relative"]) < 1e-8
