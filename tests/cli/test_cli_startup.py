"""The commands that need no SymPy answer without importing it (``--help``, ``--version``,
``examples list``; nor NumPy), and what they show without importing is what the imports would
give."""

import subprocess
import sys

import pytest

from nonideal import gallery
from nonideal.cli.common import FORM_NAMES
from tests.helpers import cli_env, run_cli

PROBE = """
import runpy, sys
sys.argv = ['nonideal'] + {argv!r}
try:
    runpy.run_module('nonideal', run_name='__main__')
except SystemExit:
    pass
print('SYMPY-LOADED' if 'sympy' in sys.modules else 'SYMPY-NOT-LOADED', file=sys.stderr)
print('NUMPY-LOADED' if 'numpy' in sys.modules else 'NUMPY-NOT-LOADED', file=sys.stderr)
"""


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["examples", "list"], ["derive", "--help"]])
def test_light_commands_do_not_import_sympy(argv):
    proc = subprocess.run([sys.executable, "-c", PROBE.format(argv=argv)], capture_output=True,
                          text=True, env=cli_env(), timeout=120)
    assert "SYMPY-NOT-LOADED" in proc.stderr, proc.stderr
    assert "NUMPY-NOT-LOADED" in proc.stderr, proc.stderr
    assert proc.stdout.strip()


def test_version():
    proc = run_cli("--version")
    assert proc.returncode == 0 and proc.stdout.startswith("nonideal ")


def test_the_parser_knows_every_form():
    from nonideal.equations.formalisms import FORMS

    assert list(FORM_NAMES) == list(FORMS)


def test_gallery_metadata_read_without_import_is_the_modules():
    for name in gallery.names():
        module, info = gallery.module(name), gallery.info(name)
        assert (module.NAME, module.TITLE, module.FILE) == (info.name, info.title, info.file)
        assert getattr(module, "ORDER", 100) == info.order


def test_examples_list_columns_are_aligned():
    lines = run_cli("examples", "list").stdout.splitlines()
    assert len(lines) == len(gallery.names())
    starts = {len(line) - len(line[len(name):].lstrip()) for line, name in zip(lines, gallery.names())}
    assert len(starts) == 1, starts


def test_bare_json_before_the_model_is_standard_output(tmp_path):
    import shutil

    from tests.helpers import DATA_DIR

    model = tmp_path / "r.toml"
    shutil.copy(DATA_DIR / "servo_parabola.toml", model)
    before = model.read_text()
    proc = run_cli("check", "--json", model)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.lstrip().startswith("{") and '"model"' in proc.stdout
    assert model.read_text() == before                 # the model was not taken as the output


def test_one_typo_in_mu_gives_one_error(tmp_path):
    from tests.helpers import DATA_DIR

    text = (DATA_DIR.parent.parent / "docs" / "rod.toml").read_text()
    model = tmp_path / "typo.toml"
    model.write_text(text.replace('mu = "mu"', 'mu = "muu"', 1))
    proc = run_cli("check", model)
    assert proc.returncode == 2
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    assert "contact 'A': mu: unknown symbol 'muu' (did you mean 'mu'?)" in lines[0]
    assert "mu_static" not in proc.stderr
