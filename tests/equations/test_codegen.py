"""``derive --code``: the generated right-hand side gives the library's accelerations and
multipliers at random admissible states -- the C file compiled with the system's compiler and
called through ctypes, the Python file run -- for a pendulum, a nonholonomic system (the
Chaplygin sleigh) and a contact in a fixed mode (the block sliding up the rough incline)."""

import ctypes
import runpy
import shutil
import subprocess

import numpy as np
import pytest

import nonideal
from tests.helpers import run_cli

CASES = {
    # example -> random admissible state (the evaluated state completes dependent velocities)
    "nlink-pendulum": lambda rng: {**{f"q{i}": rng.uniform(-2, 2) for i in (1, 2, 3)},
                                   **{f"q{i}'": rng.uniform(-2, 2) for i in (1, 2, 3)}},
    "chaplygin-sleigh": lambda rng: {"x": rng.uniform(-1, 1), "y": rng.uniform(-1, 1),
                                     "theta": rng.uniform(-3, 3), "x'": rng.uniform(-2, 2),
                                     "theta'": rng.uniform(-2, 2)},
    # touching, sliding up the slope (slide+): the mode the file is generated for
    "block-on-incline": lambda rng: {"x": rng.uniform(-1, 1), "y": 0.0, "x'": rng.uniform(0.2, 3),
                                     "y'": 0.0},
}


def reference(model, at):
    ev = nonideal.evaluate(model, at=at)
    y = np.concatenate((ev.q, ev.qd))
    return y, ev.qdd, np.array([float(np.ravel(v)[0]) for v in ev.multipliers.values()])


def states(gallery_model, name, count=5):
    model = gallery_model(name)
    rng = np.random.default_rng(7)
    return model, [reference(model, CASES[name](rng)) for _ in range(count)]


def compiler():
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if cc is None:
        pytest.skip("no C compiler (cc, gcc or clang) on this machine to compile the generated C")
    return cc


@pytest.mark.parametrize("name", list(CASES))
def test_c_file_compiles_and_agrees(name, gallery_model, tmp_path):
    cc = compiler()
    model, cases = states(gallery_model, name)
    src = tmp_path / "rhs.c"
    r = run_cli("derive", name, "--code", "c", "--output", src)
    assert r.returncode == 0, r.stderr
    lib = tmp_path / "librhs.so"
    build = subprocess.run([cc, "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-shared", "-fPIC",
                            "-o", str(lib), str(src), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    text = src.read_text()
    if name == "block-on-incline":   # the mode is written in the file
        assert "contact 'plane': sliding (slide+)" in text and "No events" in text
    fname = next(line.split("(")[0].split()[-1] for line in text.splitlines()
                 if line.startswith("int rhs_"))
    dll = ctypes.CDLL(str(lib))
    rhs = getattr(dll, fname)
    D = ctypes.POINTER(ctypes.c_double)
    rhs.argtypes = [ctypes.c_double, D, D, D, D]
    rhs.restype = ctypes.c_int
    n = len(model.coordinates)
    p = np.array(list(model.parameter_values.values()), dtype=float)
    defaults = np.ctypeslib.as_array((ctypes.c_double * len(p)).in_dll(dll, fname + "_parameters"))
    assert np.array_equal(defaults, p)
    for y, qdd, mult in cases:
        y = np.ascontiguousarray(y, dtype=float)
        dydt, mu = np.zeros(2 * n), np.zeros(max(len(mult), 1))
        assert rhs(0.0, y.ctypes.data_as(D), p.ctypes.data_as(D), dydt.ctypes.data_as(D),
                   mu.ctypes.data_as(D)) == 0
        assert np.allclose(dydt[:n], y[n:], rtol=0, atol=0)
        assert np.allclose(dydt[n:], qdd, rtol=1e-10, atol=1e-10 * max(1, np.abs(qdd).max()))
        assert np.allclose(mu[:len(mult)], mult, rtol=1e-10, atol=1e-10)
    # and the multipliers pointer may be NULL
    assert rhs(0.0, y.ctypes.data_as(D), p.ctypes.data_as(D), dydt.ctypes.data_as(D), None) == 0


@pytest.mark.parametrize("name", list(CASES))
def test_python_file_agrees(name, gallery_model, tmp_path):
    model, cases = states(gallery_model, name)
    src = tmp_path / "rhs.py"
    assert run_cli("derive", name, "--code", "python", "--output", src).returncode == 0
    ns = runpy.run_path(str(src))
    solve = next(v for k, v in ns.items() if k.startswith("rhs_") and k.endswith("_solve"))
    f = ns[solve.__name__[:-len("_solve")]]
    assert ns["COORDINATES"] == tuple(model.coordinates)
    assert ns["PARAMETER_NAMES"] == tuple(model.parameters)
    n = len(model.coordinates)
    for y, qdd, mult in cases:
        a, mu = solve(0.0, y)
        assert np.allclose(a, qdd, rtol=1e-10, atol=1e-10 * max(1, np.abs(qdd).max()))
        assert np.allclose(mu, mult, rtol=1e-10, atol=1e-10)
        assert np.allclose(f(0.0, y), np.concatenate((y[n:], qdd)), rtol=1e-10, atol=1e-10)
    # other parameters: the pendulum's masses doubled change nothing, g doubled doubles q''
    if name == "nlink-pendulum":
        y = cases[0][0].copy()
        y[n:] = 0
        p = ns["PARAMETERS"].copy()
        base = solve(0.0, y, p)[0]
        p[list(model.parameters).index("g")] *= 2
        assert np.allclose(solve(0.0, y, p)[0], 2 * base, rtol=1e-12)


@pytest.mark.parametrize("language", ["julia", "matlab"])
def test_julia_and_matlab_files_document_the_state_and_fill_every_entry(language, tmp_path):
    suffix = {"julia": ".jl", "matlab": ".m"}[language]
    out = tmp_path / f"sleigh_rhs{suffix}"
    r = run_cli("derive", "chaplygin-sleigh", "--code", language, "--output", out)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    for line in ("y[0] = x", "y[5] = theta'", "p[0] = m = 2.0 [kg]", "lambda_knife"):
        assert line in text
    fill = "K(" if language == "matlab" else "K["
    # the sleigh's saddle-point system has 11 nonzero entries (A: 7, B: 2, G: 2)
    assert sum(line.strip().startswith(fill) for line in text.splitlines()) == 11
    if language == "matlab":
        assert text.startswith("function [dydt, mu] = sleigh_rhs(t, y, p)")


def test_code_options_are_checked(tmp_path):
    r = run_cli("derive", "chaplygin-sleigh", "--output", tmp_path / "x.c")
    assert r.returncode == 2 and "--code" in r.stderr
    r = run_cli("derive", "chaplygin-sleigh", "--code", "fortran")
    assert r.returncode == 2 and "invalid choice" in r.stderr
    assert not (tmp_path / "x.c").exists()
