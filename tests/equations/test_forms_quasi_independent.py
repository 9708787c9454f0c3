"""``[forms] independent`` naming declared speeds: the quasi-velocity forms (and Gibbs-Appell in
the speeds) keep the listed speeds first, in the listed order; a coordinate whose velocity is a
declared speed stands for it; the coordinate forms read only the coordinates of the list; a
speed the constraints fix is refused naming the key and the fix (exit 2)."""

from pathlib import Path

import pytest

from nonideal import derive, gallery
from nonideal.analysis.crosscheck import compare_forms
from nonideal.errors import FormNotApplicable, ModelError
from tests.helpers import run_cli

SPEED_FORMS = ["kane", "boltzmann_hamel", "poincare_chetaev", "appell"]


@pytest.fixture(scope="module")
def sleigh():
    return gallery.load("chaplygin-sleigh-speeds")   # speeds v, w, s; the knife fixes s


@pytest.mark.parametrize("form", SPEED_FORMS)
def test_listed_speeds_come_first_in_their_order(sleigh, form):
    default = derive(sleigh, form)
    assert default.unknowns == ("v'", "w'")
    chosen = derive(sleigh.replace(independent=["w", "v"]), form)
    assert chosen.unknowns == ("w'", "v'")
    # the same equations, in the other order
    assert chosen.readable() == ["(I + a**2*m)*w' + a*m*w*v = 0", "m*(v' - a*w**2) = 0"]


def test_a_coordinate_stands_for_its_own_speed(sleigh):
    """w = theta': listing theta keeps w first."""
    assert derive(sleigh.replace(independent=["theta"]), "kane").unknowns == ("w'", "v'")


def test_coordinate_forms_read_the_coordinates_of_the_list(sleigh):
    m = sleigh.replace(independent=["w", "v", "x", "theta"])
    assert derive(m, "maggi").unknowns == ("x''", "theta''")
    report = compare_forms(m, forms=["kane", "appell", "maggi", "lagrange2"], count=5)
    assert report.worst() < 1e-10 and not report.skipped


@pytest.mark.parametrize("form", SPEED_FORMS)
def test_a_speed_fixed_by_the_constraints_is_refused(sleigh, form):
    with pytest.raises(FormNotApplicable, match=r"\[forms\] independent = \['s'\]: the speed 's' is fixed "
                                                r"by the constraints knife .* list 2 speeds .*\(e.g. v, w\)"):
        derive(sleigh.replace(independent=["s"]), form)
    # a form that reads coordinates only is not concerned
    assert derive(sleigh.replace(independent=["s"]), "maggi").unknowns


def test_an_unknown_name_is_refused_with_the_choices(sleigh):
    with pytest.raises(ModelError, match="'vv' is not a coordinate or a speed \\(did you mean 'v'\\?\\); "
                                         "list coordinates or, for the quasi-velocity forms, speeds "
                                         "\\(x, y, theta, v, w, s\\)"):
        sleigh.replace(independent=["vv"])


def test_cli_exit_2_for_a_fixed_speed(tmp_path):
    source = (Path(gallery.__file__).parent / "chaplygin_sleigh_speeds.toml").read_text()
    assert "[forms]" not in source
    f = tmp_path / "sleigh.toml"
    f.write_text(source + '\n[forms]\nindependent = ["s"]\n')
    r = run_cli("derive", str(f), "--form", "kane")
    assert r.returncode == 2, r.stderr
    assert "[forms] independent = ['s']" in r.stderr and "list 2 speeds" in r.stderr
