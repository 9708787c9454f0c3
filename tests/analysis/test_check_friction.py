"""``check`` on a model with Coulomb contacts says what friction makes of the determinacy:
the critical friction coefficient of Painleve's paradox at t0 (the rod: the closed form
(1 + 3 cos^2 theta)/(3 sin theta cos theta)), and exit 3 when mu is above it."""

import math

import pytest

import nonideal
from nonideal.analysis.checks import check_model
from tests.helpers import DATA_DIR, cli_json, run_cli

ROD = DATA_DIR.parent.parent / "docs" / "rod.toml"


def test_rod_critical_friction_is_the_closed_form():
    report = check_model(nonideal.load_model(ROD))
    a = next(c for c in report.contacts if c["name"] == "A")
    theta = 1.1
    closed = (1 + 3 * math.cos(theta) ** 2) / (3 * math.sin(theta) * math.cos(theta))
    assert a["critical_mu"] == pytest.approx(closed, rel=1e-9)
    assert a["mu"] == 0.5 and a["critical_direction"] == "-"
    b = next(c for c in report.contacts if c["name"] == "B")
    assert b["state_at_t0"] == "separated" and b["critical_mu"] is None
    text = report.as_text()
    assert "determinate only while each sliding contact's effective normal compliance" in text
    assert f"critical mu = {closed:.6g} at t0 (sliding -)" in text
    assert "motion is determinate\n" not in text


def test_cli_check_json_and_the_paradox_above_the_critical_value():
    d = cli_json("check", ROD, "--json")
    assert d["contacts"][0]["critical_mu"] == pytest.approx(1.33354, rel=1e-5)
    proc = run_cli("check", ROD, "--set", "mu=2")
    assert proc.returncode == 3 and "critical friction coefficient: 1.33354" in proc.stderr


def test_a_block_on_a_plane_has_no_critical_friction(gallery_model):
    report = check_model(gallery_model("block-on-incline"))
    assert report.contacts[0]["critical_mu"] is None
    assert "no value of mu does" in report.determinacy
