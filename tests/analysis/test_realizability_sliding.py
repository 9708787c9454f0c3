"""``realizability`` asked about a contact that slides at the state says so: the friction f*
it reports is what sticking would need if the slip were stopped there, not a verdict on the
motion (the rod's end A slides back at t0); a contact at rest sticks (the disk), and rounding
noise is printed as 0."""

import nonideal
from nonideal.analysis.contact.realizability import realizability
from tests.helpers import DATA_DIR, run_cli

ROD = DATA_DIR.parent.parent / "docs" / "rod.toml"


def test_a_sliding_contact_is_said_not_to_stick():
    report = realizability(nonideal.load_model(ROD))
    a = report.contacts["A"]
    assert not a.sticking and list(a.slip) == [-1.0]
    assert a.to_dict()["sticking"] is False
    assert "NOT sticking at this state: it slides (slip U = [-1])" in report.as_text()


def test_a_contact_at_rest_sticks_and_zero_is_printed_as_zero(gallery_model):
    report = realizability(gallery_model("disk-rolling-torque"))
    plane = report.contacts["plane"]
    assert plane.sticking and plane.to_dict()["slip"] == [0.0]
    text = report.as_text()
    assert "f* = [0] " in text and "NOT sticking" not in text


def test_cli_text():
    proc = run_cli("realizability", ROD)
    assert proc.returncode == 0 and "NOT sticking" in proc.stdout
