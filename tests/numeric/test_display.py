"""Rounding noise is shown as 0 in the text outputs (never -2.46e-32, -0 or [0.])."""

from nonideal.numeric.display import clean, number, numbers
from tests.helpers import DATA_DIR, run_cli


def test_noise_against_the_scale_is_zero():
    assert clean(-2.46e-32) == 0.0 and str(clean(-1e-17, 3.0)) == "0.0"
    assert clean(1e-6) == 1e-6 and clean(3e-12, 1e6) == 0.0 and clean(3e-12, 1.0) == 3e-12
    assert number(-0.0) == "0" and number(-1e-20, 5.0, 10, True) == " 0"
    assert numbers([1e-17, -1e-17]) == "[0, 0]" and numbers([2.5, -1e-15]) == "[2.5, 0]"


def test_simulate_and_evaluate_text_show_no_noise():
    rod = DATA_DIR.parent.parent / "docs" / "rod.toml"
    out = run_cli("simulate", rod).stdout
    final = [ln for ln in out.splitlines() if "(t_end)" in ln]
    assert len(final) == 3 and not any("e-" in ln for ln in final), final
    assert "y(t_end) =  0 " in out
    ev = run_cli("evaluate", rod).stdout
    assert "friction part          = [0, 0, 0]" in ev and "e-1" not in ev and "e-2" not in ev and "e-3" not in ev
