"""The command line on a model with an elastic member: check, simulate, stability and
frequencies end to end; an unstable equilibrium refused with exit code 3."""

import json
from types import SimpleNamespace

import numpy as np
import pytest

from nonideal import gallery
from nonideal.cli import main
from nonideal.gallery.elastic_arm_on_cart import exact_frequencies

FILE = gallery.model_path("elastic-arm-on-cart")


@pytest.fixture
def cli(capsys):
    def run(*argv):
        code = main([str(a) for a in argv])
        out = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=out.out, stderr=out.err)
    return run


def test_check_lists_the_amplitudes_and_the_tip(cli):
    r = cli("check", FILE)
    assert r.returncode == 0, r.stderr
    assert "coordinates (5): x, arm_1, arm_2, arm_3, arm_4" in r.stdout and "point tip" in r.stdout


def test_stability_and_frequencies_give_the_galerkin_frequencies(cli):
    exact = exact_frequencies(2)
    r = cli("stability", FILE, "--at", "x=0", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    imag = sorted(z[1] for z in d["eigenvalues"] if z[1] > 0)
    assert np.allclose(imag[:2], exact, rtol=1e-6) and np.allclose(d["frequencies"][:2], exact, rtol=1e-6)
    r = cli("frequencies", FILE, "--at", "x=0", "--json")
    assert r.returncode == 0, r.stderr
    omega = json.loads(r.stdout)["omega"]
    assert np.allclose(omega[:2], exact, rtol=1e-6) and np.all(np.array(omega[:2]) >= exact)


def test_simulate_writes_the_amplitudes(cli, tmp_path):
    out = tmp_path / "arm.csv"
    r = cli("simulate", FILE, "--csv", out, "--times", "0,0.25,0.5")
    assert r.returncode == 0, r.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert {"x", "arm_1", "arm_4", "arm_1'"} <= set(header)


def test_frequencies_refuse_an_unstable_equilibrium(cli, tmp_path):
    text = FILE.read_text().replace('potential = "k/2*x^2"', 'potential = "-k/2*x^2"')
    f = tmp_path / "unstable.toml"
    f.write_text(text)
    r = cli("frequencies", f, "--at", "x=0")
    assert r.returncode == 3
    assert "off the imaginary axis" in r.stderr and "unstable" in r.stderr
