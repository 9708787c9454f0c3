"""``nonideal stability``: the JSON keys of the contract, the text report, exit codes 2 and 3,
nothing written on failure.  In-process (``main``) except one run through ``python -m``."""

import json
from types import SimpleNamespace

import numpy as np
import pytest

from nonideal.cli import main
from tests.helpers import run_cli as run_subprocess


@pytest.fixture
def cli(capsys):
    def run(*argv):
        code = main([str(a) for a in argv])
        out = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=out.out, stderr=out.err)
    return run

KEYS = {"model", "about", "state", "variables", "A", "eigenvalues", "verdict", "characteristic_polynomial",
        "hurwitz", "conditions", "controllability"}


def test_json_keys_and_numbers_of_a_steady_motion():
    r = run_subprocess("stability", "watt-governor", "--about", "steady", "--at", "phi=1, theta'=4", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert KEYS <= set(d) and "B" not in d
    assert d["about"] == "steady" and set(d["state"]) == {"q", "qdot"}
    assert d["variables"] == ["phi", "phi'", "theta'"]
    assert d["state"]["q"]["phi"] == pytest.approx(np.arccos(0.5), abs=1e-9)
    assert d["verdict"] == "asymptotically stable"
    assert all(h > 0 for h in d["hurwitz"]) and len(d["hurwitz"]) == 3
    assert len(d["eigenvalues"]) == 3 and all(re < 0 for re, _ in d["eigenvalues"])


def test_controls_give_B_and_lqr(tmp_path, cli):
    out = tmp_path / "lqr.json"
    r = cli("stability", "double-pendulum-cart-lqr", "--controls", "u", "--keep", "x",
                "--lqr", "1,1", "--json", out)
    assert r.returncode == 0, r.stderr
    d = json.loads(out.read_text())
    assert np.array(d["B"]).shape == (6, 1) and d["controllability"] == {"rank": 6, "n": 6}
    assert all(re < 0 for re, _ in d["lqr"]["closed_loop_eigenvalues"])
    assert np.array(d["lqr"]["K"]).shape == (1, 6)


def test_symbolic_conditions_and_readable_text(cli):
    r = cli("stability", "sleeping-top", "--about", "steady", "--at", "c'=w")
    assert r.returncode == 0, r.stderr
    assert "characteristic polynomial:" in r.stdout and "Hurwitz minors:" in r.stdout
    assert "verdict: critical" in r.stdout and "held (a family of steady motions" in r.stdout
    r = cli("stability", "sleeping-top", "--about", "steady", "--at", "c'=w", "--symbolic", "w", "--json")
    d = json.loads(r.stdout)
    assert d["conditions"] and all("w" in c for c in d["conditions"])


def test_bad_at_is_exit_2_with_the_residual_and_nothing_written(tmp_path, cli):
    out = tmp_path / "never.json"
    r = cli("stability", "watt-governor", "--about", "steady", "--at", "phi=0.5, theta'=4", "--exact",
                "--json", out)
    assert r.returncode == 2
    assert "is not a steady motion" in r.stderr and "phi'' =" in r.stderr and "Fix:" in r.stderr
    assert not out.exists()
    r = cli("stability", "watt-governor", "--symbolic", "JJ")
    assert r.returncode == 2 and "'JJ' is not a parameter" in r.stderr and "did you mean" in r.stderr


def test_singular_constraint_rows_are_exit_3(tmp_path, cli):
    model = tmp_path / "doubled.toml"
    model.write_text('[model]\nname = "doubled"\nformat = 1\n[parameters]\nl = 1.0\n'
                     '[coordinates]\nq = ["x", "y"]\n[energy]\nkinetic = "(x\'^2 + y\'^2)/2"\npotential = "y"\n'
                     '[[constraints]]\nname = "a"\ntype = "holonomic"\nexpr = "x^2 + y^2 - l^2"\n'
                     '[[constraints]]\nname = "b"\ntype = "holonomic"\nexpr = "2*x^2 + 2*y^2 - 2*l^2"\n'
                     '[initial]\nx = 0.0\ny = -1.0\n')
    r = cli("stability", model, "--at", "x=0, y=-1")
    assert r.returncode == 3, r.stderr
    assert "linearization is undefined" in r.stderr and "dependent" in r.stderr


def test_vary_gives_the_root_locus_and_the_plot(tmp_path, cli):
    png = tmp_path / "locus.png"
    r = cli("stability", "watt-governor", "--about", "steady", "--at", "phi=1, theta'=4",
            "--vary", "J=0.40:0.49:2", "--json", "--plot", png)
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)["locus"]["rows"]
    # Vyshnegradsky's boundary J_c = 0.44516 lies between the two points
    assert [row["verdict"] for row in rows] == ["unstable", "asymptotically stable"]
    assert png.stat().st_size > 0
    r = cli("stability", "watt-governor", "--vary", "J=1:2")
    assert r.returncode == 2 and "NAME=START:STOP:N" in r.stderr


def test_model_with_contacts_is_linearized_in_its_contact_mode(cli):
    from tests.helpers import DATA_DIR

    path = DATA_DIR / "contacts" / "rolling_disk_contact.toml"
    r = cli("stability", path, "--about", "steady", "--at", "phi'=5", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["contacts"]["floor"]["mode"] == "stick"
    assert "nonholonomic" in d["contacts"]["floor"]["linearized_as"]
    eig = sorted(complex(re, im).imag for re, im in d["eigenvalues"])
    assert eig[0] == pytest.approx(-np.sqrt(4 / 2.5 * (1.5 * 25 - 9.81)), rel=1e-9)
    text = cli("stability", path, "--about", "steady", "--at", "phi'=5")
    assert text.returncode == 0 and "contact 'floor': stick -- slip = 0 nonholonomic, gap = 0 holonomic" in text.stdout


def test_model_with_an_epsilon_linear_contact_is_refused(cli, tmp_path):
    from tests.helpers import DATA_DIR

    text = (DATA_DIR / "contacts" / "block_on_belt_springs.toml").read_text()
    bad = tmp_path / "belt_linearized.toml"
    bad.write_text(text.replace('mu = "mu"', 'mu = "mu"\nfriction = "linearized"\neps = 0.01'))
    out = tmp_path / "out.json"
    r = cli("stability", bad, "--about", "equilibrium", "--json", out)
    assert r.returncode == 2 and "contact 'belt' uses the epsilon-linear law" in r.stderr
    assert not out.exists()
