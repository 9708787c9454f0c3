"""The documentation site builds with warnings as errors -- the tutorial and the Python API
page executed, the reference generated from every module, and the pages of a representative
set of gallery examples executed (``NONIDEAL_DOCS_GALLERY``; the full site builds every
example the same way, in about 16 minutes on two shared cores; this subset takes about 3.5) -- and what a reader sees: a gallery
page typesets its equations (MathJax output, no raw ``$...$``) and shows its images.

Both need the ``docs`` extra (Sphinx, MyST-NB); the browser check also needs Chromium and a
MathJax that loads without a network (Debian's ``libjs-mathjax``)."""

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
#: a contact example (events, modes), a nonholonomic one, and a stability one
GALLERY = "block-on-incline,chaplygin-sleigh,watt-governor"
MATHJAX = Path("/usr/share/javascript/mathjax/MathJax.js")

# the build runs notebooks in kernels of their own: on a loaded machine it exceeds the suite's
# 300 s per test (3.5 min here alone, over 5 min under a load of 17)
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1800)]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    pytest.importorskip("sphinx", reason="the documentation needs the 'docs' extra: pip install '.[docs]'")
    pytest.importorskip("myst_nb", reason="the documentation needs the 'docs' extra: pip install '.[docs]'")
    out = tmp_path_factory.mktemp("html")
    # the build writes its generated pages into the source tree: each test process builds a
    # copy of it (with the package beside it, as the pages include the gallery's files), so
    # that two processes of a parallel run do not remove each other's pages
    tree = tmp_path_factory.mktemp("tree")
    source = tree / "docs"
    shutil.copytree(DOCS, source, ignore=shutil.ignore_patterns("generated", "_build"))
    (tree / "nonideal").symlink_to(ROOT / "nonideal", target_is_directory=True)
    env = dict(os.environ, NONIDEAL_DOCS_GALLERY=GALLERY, PYTHONPATH=str(ROOT))
    if MATHJAX.exists():     # typeset offline, for the browser check below
        env["NONIDEAL_DOCS_MATHJAX"] = MATHJAX.as_uri() + "?config=TeX-AMS-MML_HTMLorMML"
    r = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
                        str(source), str(out)], capture_output=True, text=True, env=env, timeout=1500)
    warnings = [line for line in r.stderr.splitlines()
                if re.search(r"WARNING|ERROR", line) and "IPKernelApp" not in line]
    assert r.returncode == 0 and not warnings, "\n".join(warnings) or r.stderr[-3000:]
    return out


def test_site_builds_every_page(site):
    pages = {p.relative_to(site).as_posix() for p in site.rglob("*.html")}
    assert {"index.html", "guide/model_file.html", "guide/sweeps.html", "guide/code.html",
            "tutorials/stick_slip.html", "generated/commands.html"} <= pages
    assert len([p for p in pages if p.startswith("generated/gallery/")]) == len(GALLERY.split(","))
    # the reference mirrors the folders: a page per module, every stage's folder among them
    api = {p.split("/")[-1][:-5] for p in pages if p.startswith("generated/api/")}
    for folder in ("modeling", "equations", "numeric", "modes", "simulation", "analysis",
                   "analysis.stability", "analysis.studies", "analysis.contact", "cli", "gallery"):
        assert f"nonideal.{folder}" in api
    import pkgutil

    import nonideal

    modules = {m.name for m in pkgutil.walk_packages(nonideal.__path__, "nonideal.")
               if not m.name.split(".")[-1].startswith("_")}
    assert modules - api == set()
    # every public class and function of a module has its entry
    text = (site / "generated/api/nonideal.simulation.trajectory.html").read_text()
    assert 'id="nonideal.simulation.trajectory.Trajectory.to_pandas"' in text
    text = (site / "generated/api/nonideal.equations.codegen.html").read_text()
    assert 'id="nonideal.equations.codegen.generate"' in text


def test_command_reference_holds_every_option(site):
    text = (site / "generated/commands.html").read_text()
    for option in ("--parquet", "--code", "--scheduler", "--contact", "--animate"):
        assert option in text


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.text, self.skip = [], [], 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a)
        if tag in ("script", "style", "pre", "code") or "MathJax" in a.get("class", "") \
                or a.get("class", "").startswith("math"):
            self.skip += 1

    def handle_endtag(self, tag):
        if self.skip and tag in ("script", "style", "pre", "code", "span", "div", "mjx-container"):
            self.skip -= 1

    def handle_data(self, data):
        if not self.skip:
            self.text.append(data)


def test_gallery_page_typesets_equations_and_shows_plots(site, tmp_path):
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        pytest.skip("Chromium is not installed (apt-get install chromium): the page is not "
                    "opened in a browser")
    if not MATHJAX.exists():
        pytest.skip("no MathJax without a network (apt-get install libjs-mathjax): the page "
                    "would typeset from a CDN this machine cannot reach")
    page = next((site / "generated/gallery").glob("*block_on_incline.html"))
    html = page.read_text()
    # what the page holds before any script runs: the images are files of the build
    static = _Page()
    static.feed(html)
    images = [im["src"] for im in static.images]
    assert any(src.endswith(".png") for src in images), images
    for src in images:     # each a PNG file of the build (a browser would show a broken image)
        if not src.startswith(("http", "data:")):
            path = page.parent / src
            assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"broken image {src}"
    # what a browser shows: MathJax has typeset every formula, none is left as raw TeX
    dom = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu",
                          "--allow-file-access-from-files", "--virtual-time-budget=20000",
                          "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120)
    assert dom.returncode == 0, dom.stderr[-2000:]
    shown = dom.stdout
    formulas = len(re.findall(r'<div class="[^"]*\bmath\b', html))
    typeset = len(re.findall(r'class="MathJax_Display"|<mjx-container[^>]*display', shown))
    assert formulas >= 1 and typeset == formulas, f"{typeset} of {formulas} formulas typeset"
    assert 'class="MathJax_Error"' not in shown and "<merror" not in shown
    reader = _Page()
    reader.feed(shown)
    visible = " ".join(reader.text)
    assert not re.search(r"\$\$|\\begin\{aligned\}|\\ddot\{|\\frac\{", visible), \
        "raw TeX shown to the reader"
    # the page as a reader sees it (kept for a look: pytest --basetemp=DIR)
    shot = tmp_path / "page.png"
    r = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu",
                        "--allow-file-access-from-files", "--virtual-time-budget=20000",
                        "--window-size=1200,3000", f"--screenshot={shot}", page.as_uri()],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and shot.stat().st_size > 20000
