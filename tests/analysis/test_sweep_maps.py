"""Maps built on the sweep, checked point by point against their closed forms: the Painleve
paradox region of the rod over (theta, mu), the stick/slip outcome of a block over
(alpha, mu_s), the realizability margin of a resting block over (alpha, mu_s); and the PNG of a
map from the command line."""

import math

import pytest

from nonideal import gallery
from nonideal.analysis.studies.sweep import parse_vary, sweep
from nonideal.gallery.painleve_rod import critical_mu
from tests.helpers import run_cli


def test_painleve_paradox_region_of_the_rod():
    """Exit 3 (paradox) exactly where mu > mu_c(theta) = (1 + 3 cos^2)/(3 sin cos)."""
    result = sweep(gallery.model_path("painleve-rod"),
                   [parse_vary("theta0=0.5,0.9,1.1,1.4"), parse_vary("mu=1.0,1.4,1.9,2.5")],
                   "evaluate", workers=1)
    paradox = []
    for row in result.rows:
        th, mu = row["parameters"]["theta0"], row["parameters"]["mu"]
        assert row["exit_code"] == (3 if mu > critical_mu(th) else 0), row
        paradox.append(row["exit_code"] == 3)
    assert 3 <= sum(paradox) <= 13   # the grid straddles the boundary
    assert all("Painleve paradox" in r["message"] for r in result.rows if r["exit_code"] == 3)


def test_block_stick_or_slip_after_the_stop():
    result = sweep(gallery.model_path("block-on-incline"),
                   [parse_vary("alpha=0.3,0.45,0.6"), parse_vary("mu_s=0.35,0.55")],
                   "simulate", workers=1)
    for row in result.rows:
        a, mu_s = row["parameters"]["alpha"], row["parameters"]["mu_s"]
        first = row["summary"]["events"][0]["type"]
        assert first == ("stick" if math.tan(a) <= mu_s else "reverse")


def test_realizability_margin_of_a_resting_block():
    """Sticking at rest on the incline needs F = m g sin(alpha) of mu_s N = mu_s m g cos(alpha):
    the margin m g (mu_s cos(alpha) - sin(alpha)) (Kalinin & Novozhilov's condition)."""
    result = sweep(gallery.model_path("block-on-incline"),
                   [parse_vary("alpha=0.2,0.5"), parse_vary("mu_s=0.3,0.8")], "realizability",
                   options={"at": {"x'": 0.0}}, workers=1)
    m, g = 2.0, 9.81
    for row in result.rows:
        a, mu_s = row["parameters"]["alpha"], row["parameters"]["mu_s"]
        margin = m * g * (mu_s * math.cos(a) - math.sin(a))
        assert row["summary"]["margin"] == pytest.approx(margin, rel=1e-12)
        assert row["summary"]["realizable"] == (margin > 0)


def test_map_png_from_the_command_line(tmp_path):
    png = tmp_path / "map.png"
    r = run_cli("sweep", "block-on-incline", "--vary", "alpha=0.2,0.5", "--vary", "mu_s=0.3,0.8",
                "--what", "realizability", "--at", "x'=0", "--csv", tmp_path / "m.csv",
                "--plot", png, "--workers", "1")
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    r = run_cli("sweep", "block-on-incline", "--vary", "alpha=0.2,0.5", "--what", "evaluate",
                "--csv", tmp_path / "e.csv", "--plot", tmp_path / "e.png", "--quantity", "qddot.z",
                "--workers", "1")
    assert r.returncode == 2 and "qddot.x" in r.stderr and not (tmp_path / "e.png").exists()
