"""What a notebook shows of each result (``_repr_html_``, ``_repr_latex_``): the numbers of the
result itself, escaped HTML, LaTeX that a typesetter reads; tables as pandas reads them."""

import math
import re
from html.parser import HTMLParser

import numpy as np
import pytest
import sympy as sp

import nonideal
from nonideal.analysis.stability.linearize import linearize
from nonideal.analysis.studies.sweep import Axis, sweep


class _Table(HTMLParser):
    """The cells of every table of an HTML fragment; fails on unbalanced tags."""

    def __init__(self):
        super().__init__()
        self.tables, self.stack = [], []

    def handle_starttag(self, tag, attrs):
        if tag in ("br", "hr", "img"):
            return
        self.stack.append(tag)
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self.tables[-1][-1].append("")

    def handle_endtag(self, tag):
        assert self.stack and self.stack[-1] == tag, (self.stack, tag)
        self.stack.pop()

    def handle_data(self, data):
        if self.stack and self.stack[-1] in ("td", "th"):
            self.tables[-1][-1][-1] += data


def tables(html: str):
    p = _Table()
    p.feed(html)
    p.close()
    assert not p.stack, p.stack
    return p.tables


def test_evaluation_shows_its_accelerations_and_the_contact(gallery_model):
    model = gallery_model("block-on-incline")
    ev = nonideal.evaluate(model)
    html = ev._repr_html_()
    state, contacts = tables(html)
    assert state[0] == ["coordinate", "q", "q'", "q''"]
    row = dict((r[0], r) for r in state[1:])["x"]
    # sliding up: x'' = -g (sin(alpha) + mu cos(alpha))
    g, a, mu = 9.81, 0.4, 0.3
    assert float(row[3]) == pytest.approx(-g * (math.sin(a) + mu * math.cos(a)), rel=1e-9)
    assert contacts[1][0] == "plane" and float(contacts[1][2]) == pytest.approx(2 * g * math.cos(a))
    latex = ev._repr_latex_()
    assert latex.startswith("$$\\begin{aligned}") and r"\ddot{x} &=" in latex


def test_linearization_shows_polynomial_eigenvalues_and_verdict(gallery_model):
    pend = nonideal.Model("pendulum", ["phi"], parameters={"g": 9.81, "l": 2.0, "c": 0.5},
                          kinetic="l**2*phi'**2/2", potential="-g*l*cos(phi)",
                          forces={"phi": "-c*phi'"}, initial={"phi": 0.1, "phi'": 0})
    lin = linearize(pend)
    html = lin._repr_html_()
    assert "<b>asymptotically stable</b>" in html
    (eig,) = tables(html)
    values = [complex(float(r[1]), float(r[2])) for r in eig[1:]]
    s = np.roots([1, 0.5 / 4, 9.81 / 2])     # l^2 s^2 + c s + g l = 0
    assert np.allclose(sorted(values, key=lambda z: z.imag), sorted(s, key=lambda z: z.imag), rtol=1e-8)
    latex = lin._repr_latex_()
    assert "&= 0" in latex and r"\,i" in latex
    # the polynomial as typeset is the one of the result
    assert sp.latex(lin.characteristic_polynomial) in latex
    assert "$$A = " in html


def test_sweep_result_is_a_table_and_a_typed_frame(gallery_model):
    from nonideal import gallery

    path = str(gallery.model_path("block-on-incline"))
    res = sweep(path, [Axis("m", (-1.0, 2.0))], "evaluate", workers=1)
    (table,) = tables(res._repr_html_())
    assert table[0][:3] == ["m", "exit_code", "message"]
    assert [r[1] for r in table[1:]] == ["2", "0"]
    names = [n for n, _, _ in res.typed_columns()]
    kinds = {n: k for n, _, k in res.typed_columns()}
    assert names == res.columns() and kinds["exit_code"] == "int" and kinds["message"] == "str"
    assert kinds["qddot.x"] == "float" and kinds["contacts.plane.mode"] == "str"
    pd = pytest.importorskip("pandas")
    df = res.to_pandas()
    assert list(df.columns) == res.columns()
    assert df["exit_code"].dtype == np.int64 and df["qddot.x"].dtype == np.float64
    assert math.isnan(df["qddot.x"][0]) and df["qddot.x"][1] == res.rows[1]["summary"]["qddot"]["x"]
    assert isinstance(df, pd.DataFrame)


def test_eom_display_typesets_its_equations(gallery_model):
    eom = nonideal.derive(gallery_model("chaplygin-sleigh"), "maggi")
    html = eom._repr_html_()
    assert "$$\\begin{aligned}" in html and re.search(r"\\ddot\{", html)
    assert "<b>" in html and html.count("<div>") == html.count("</div>")
