"""Sphinx configuration of the nonideal documentation.

Build (from the repository root)::

    pip install '.[docs]'
    python -m sphinx -W -b html docs docs/_build/html

Notebooks and gallery pages are MyST-NB documents executed at build time (a failing example
fails the build).  MyST-NB rather than sphinx-gallery: the gallery is model files with a module
each, not scripts with comment blocks, and one tool executes both the generated example pages
(MyST Markdown notebooks) and the tutorial (.ipynb), with MyST Markdown for the guide pages.  ``NONIDEAL_DOCS_GALLERY=name1,name2`` builds the pages of those gallery
examples only (the test suite builds a representative subset this way).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
# the notebooks' kernels are other processes: they import this checkout's nonideal too
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
os.environ.setdefault("MPLBACKEND", "Agg")

sys.path.insert(0, str(HERE))
import _pages  # noqa: E402  (the generated pages: gallery, command reference)

import nonideal  # noqa: E402

project = "nonideal"
author = "the nonideal authors"
copyright = "the nonideal authors"
release = version = nonideal.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]

_pages.write_all(HERE, os.environ.get("NONIDEAL_DOCS_GALLERY"))

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "_templates", "MODEL_FORMAT.md", "**.ipynb_checkpoints",
                    "rod.toml"]
templates_path = ["_templates"]

# -- MyST / MyST-NB
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3
nb_execution_mode = os.environ.get("NONIDEAL_DOCS_EXECUTE", "force")
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# -- API reference
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_mock_imports: list[str] = []
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False

# MathJax from elsewhere than its CDN (e.g. Debian's libjs-mathjax, offline):
# NONIDEAL_DOCS_MATHJAX=file:///usr/share/javascript/mathjax/MathJax.js?config=TeX-AMS-MML_HTMLorMML
if os.environ.get("NONIDEAL_DOCS_MATHJAX"):
    mathjax_path = os.environ["NONIDEAL_DOCS_MATHJAX"]
    # MathJax 2 (Debian's) ignores MathJax 3's processHtmlClass: the notebooks' outputs sit in
    # sections marked tex2jax_ignore, so name the classes it must typeset in MathJax 2's terms
    mathjax2_config = {"tex2jax": {"processClass": "tex2jax_process|mathjax_process|math|output_area"}}

# -- HTML
html_theme = "alabaster"
html_title = f"nonideal {release}"
html_static_path: list[str] = []
html_theme_options = {"description": "Analytical dynamics of constrained mechanical systems",
                      "page_width": "1100px", "sidebar_width": "240px"}

# An ambiguous type name in a numpydoc field ("settings : tuple of (name, value)": two classes
# have an attribute `name`) is a python-domain warning; with nitpicky off these are the only
# ones of that kind, and a plain-text type is what those fields mean.
suppress_warnings = ["ref.python"]
nitpicky = False


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _formulas_as_literal(lines: list[str]) -> None:
    """The gallery's module docstrings set formulas off as indented blocks after a blank line
    (plain text, as in a paper): show them as literal blocks, not as block quotes."""
    out, k, last = [], 0, None
    while k < len(lines):
        line = lines[k]
        if line.strip() and last is not None and k > 0 and not lines[k - 1].strip() \
                and _indent(line) > _indent(last) and not last.rstrip().endswith("::") \
                and not line.lstrip().startswith(("* ", "- ", ">>>")):
            base = _indent(last)
            out += [" " * base + "::", ""]
            while k < len(lines) and (not lines[k].strip() or _indent(lines[k]) > base):
                out.append(lines[k])
                k += 1
            last = out[-1] if out[-1].strip() else last
            continue
        out.append(line)
        if line.strip():
            last = line
        k += 1
    lines[:] = out


def _docstring(app, what, name, obj, options, lines):
    """Docstrings are written for readers of the source: formulas in the gallery as indented
    plain text, and absolute values and norms as ``|x|``, which reStructuredText would read as
    a substitution -- escape the bars outside literal blocks and doctests."""
    if what == "module" and name.startswith("nonideal.gallery."):
        _formulas_as_literal(lines)
    literal = None      # indentation of the paragraph that opened a literal block
    previous = ""
    for k, line in enumerate(lines):
        if literal is not None and line.strip() and _indent(line) <= literal:
            literal = None
        if literal is None and "|" in line and not line.lstrip().startswith((">>>", "...", "|", "+-", "+=")):
            parts = line.split("``")      # inside ``inline literals`` a bar is a bar
            lines[k] = "``".join(p.replace("|", "\\|") if i % 2 == 0 else p for i, p in enumerate(parts))
        if line.rstrip().endswith("::") and literal is None:
            literal = _indent(line)
        if line.strip():
            previous = line
    del previous


def setup(app):
    app.connect("autodoc-process-docstring", _docstring, priority=600)
