"""The model's dynamics and the phase integration as native code (numba), cached on disk.

With the optional extra ``fast`` (numba) installed, :func:`native_of` writes the kernel of a
model (:class:`~nonideal.numeric.kernel.Kernel`: ``M``, ``F``, the constraint rows, the powers)
as the source of a small Python module, compiles it with numba and keeps both in the cache
directory (:func:`cache_dir`).  The module holds, for the model:

* ``kernel(x, z)`` (a numba ``cfunc``): the nonzero entries of the kernel's flat output from the input
  ``[t, q, q', parameters]`` (SymEngine's common subexpressions);

and :mod:`nonideal.numeric.integrator` (generic, compiled once for every model) takes it as a
C callback: the right-hand side of a mode without contact rows (the saddle-point solve
included) and SciPy's DOP853 looped over a whole phase without events.

**Same results without it.**  The NumPy/SciPy path (LAPACK ``dposv``/``dgesv``, SymEngine's
LLVM callables, SciPy's DOP853) computes the same formulas; the right-hand sides agree to
rounding (the order of the floating-point operations in the solves and in the stage sums
differs), not bit for bit.  At tight tolerances DOP853's error estimate is itself at the level
of the stages' rounding (rtol 1e-10: a difference of 1e-15 in the stages changes it by 20 %),
so the two paths take slightly different steps; the motions agree within the tolerance.  Each
path alone is reproducible bit for bit between runs.

**Safety.**  The source is generated from the model's derived expressions, never from user
text: the symbols are renamed to ``a<k>`` (inputs) and ``c<k>`` (subexpressions), floats are
written with ``repr`` (exact), and every expression is checked with :mod:`ast` to contain only
arithmetic, numbers, those names and a fixed set of math functions before it is written.

**Cache.**  Files are named by the SHA-256 of their source with the library's and numba's
versions and the generic loop's source, so a changed model, library or numba never reads a
stale entry; a source is written
to a temporary file and renamed into place (concurrent writers race harmlessly), and numba's
own cache files (``__pycache__`` beside it) are written the same way.  A cache entry that does
not load (corrupt, unwritable directory) is rebuilt in a private temporary directory; if numba
fails altogether the simulation keeps the NumPy path.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import symengine as se

__all__ = ["available", "cache_dir", "native_of", "Native", "NotNative", "module_source", "renamed_dynamics",
           "CACHE_ENV"]

CACHE_ENV = "NONIDEAL_CACHE_DIR"
"""Environment variable overriding the cache directory (default ``$XDG_CACHE_HOME/nonideal``,
else ``~/.cache/nonideal``)."""


class NotNative(Exception):
    """The kernel uses a function the native code does not write (the NumPy path is kept)."""


def available() -> bool:
    """Whether numba can be imported (the optional extra ``fast``)."""
    try:
        import numba  # noqa: F401
    except Exception:  # pragma: no cover - depends on the environment
        return False
    return True


def cache_dir() -> Path:
    """The directory of the compiled models: ``$NONIDEAL_CACHE_DIR``, else
    ``$XDG_CACHE_HOME/nonideal``, else ``~/.cache/nonideal``."""
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg else Path.home() / ".cache"
    return base / "nonideal"


# ----------------------------------------------------------------------------- source
_FUNCTIONS = {"sin": "math.sin", "cos": "math.cos", "tan": "math.tan", "asin": "math.asin",
              "acos": "math.acos", "atan": "math.atan", "atan2": "math.atan2", "sinh": "math.sinh",
              "cosh": "math.cosh", "tanh": "math.tanh", "asinh": "math.asinh", "acosh": "math.acosh",
              "atanh": "math.atanh", "exp": "math.exp", "log": "math.log", "sqrt": "math.sqrt",
              "abs": "abs", "sign": "_sign", "max": "max", "min": "min"}
_CONSTANTS = {"pi": "math.pi", "E": "math.e"}
_OPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)


def _checked(text: str, names: set[str]) -> str:
    """*text* (SymEngine's printing of one expression) as checked Python source: only
    numbers, the given names, the constants and the functions of :data:`_FUNCTIONS`."""
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError as exc:
        raise NotNative(f"unprintable expression ({exc.msg})") from None

    class Rewrite(ast.NodeTransformer):
        def visit_Call(self, node):
            if not isinstance(node.func, ast.Name) or node.func.id not in _FUNCTIONS or node.keywords:
                raise NotNative(f"function {ast.unparse(node.func)!r}")
            node.args = [self.visit(a) for a in node.args]
            node.func = ast.parse(_FUNCTIONS[node.func.id], mode="eval").body
            return node

        def visit_Name(self, node):
            if node.id in _CONSTANTS:
                return ast.parse(_CONSTANTS[node.id], mode="eval").body
            if node.id not in names:
                raise NotNative(f"name {node.id!r}")
            return node

        def visit_Constant(self, node):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise NotNative(f"constant {v!r}")
            if isinstance(v, int) and abs(v) >= 2 ** 53:  # not exact as a double
                return ast.Constant(float(v))
            return node

        def generic_visit(self, node):
            if not isinstance(node, (ast.Expression, ast.BinOp, ast.UnaryOp, *_OPS, ast.Load)):
                raise NotNative(f"construct {type(node).__name__}")
            return super().generic_visit(node)

    tree = Rewrite().visit(tree)
    return ast.unparse(tree.body)


def renamed_dynamics(kernel):
    """The compiled entries of ``kernel.dynamics`` with the inputs renamed ``a<k>`` (the input
    vector's order) and the floats ``f<k>``: ``(exprs, where, inputs, floats)``, *where* the
    entries' positions in the flat output, *inputs* ``{symbol: a<k>}``, *floats* ``{value:
    f<k>}`` (the source generators of the numba and the C kernels).

    Raises
    ------
    NotNative
        A symbol that is not an input of the kernel.
    """
    compiled = kernel.dynamics
    exprs = [se.sympify(e) for e in compiled._exprs]
    where = compiled._where.tolist() if compiled._where is not None else list(range(len(exprs)))
    inputs = {s: se.Symbol(f"a{i}") for i, s in enumerate(kernel.symbols)}
    floats: dict[float, se.Symbol] = {}

    def rename(e):
        e = e.xreplace({s: inputs[s] for s in e.free_symbols if s in inputs})
        for f in e.atoms(se.RealDouble):
            v = float(f)
            if v not in floats:
                floats[v] = se.Symbol(f"f{len(floats)}")
        return e.xreplace({f: floats[float(f)] for f in e.atoms(se.RealDouble)}) if floats else e

    exprs = [rename(e) for e in exprs]
    free = [s for s in (set().union(*(e.free_symbols for e in exprs)) if exprs else set())]
    unknown = [s for s in free if not (str(s).startswith(("a", "f")) and str(s)[1:].isdigit())]
    if unknown:
        raise NotNative(f"symbols {sorted(map(str, unknown))}")
    return exprs, where, inputs, floats


def _kernel_body(kernel) -> list[str]:
    """The lines of ``kernel(x, z)``: locals for the inputs used, the common subexpressions,
    then ``z[k] = ...`` for every compiled entry."""
    exprs, where, inputs, floats = renamed_dynamics(kernel)
    replacements, reduced = se.cse(exprs) if exprs else ([], [])
    names = {str(v) for v in inputs.values()} | {str(v) for v in floats.values()}
    lines = [f"    {v} = x[{i}]" for i, (s, v) in enumerate(inputs.items())
             if any(v in e.free_symbols for e in exprs)]
    lines += [f"    {s} = {v!r}" for v, s in floats.items()]
    for sym, e in replacements:  # SymEngine's temporaries x0, x1, ... (never a<k>, f<k>)
        lines.append(f"    {sym} = {_checked(str(e), names)}")
        names.add(str(sym))
    for pos, e in zip(where, reduced):
        lines.append(f"    z[{pos}] = {_checked(str(e), names)}")
    if not exprs:
        lines.append("    pass")
    return lines


def module_source(kernel) -> str:
    """The source of the native module of *kernel* (see the module docstring)."""
    from .. import __version__

    body = "\n".join(_kernel_body(kernel))
    return _TEMPLATE.format(version=__version__, nx=len(kernel.symbols),
                            nz=kernel.dynamics.size, body=body)


# ----------------------------------------------------------------------------- loading
class Native:
    """The native kernel of one model (a numba C callback, :data:`kernel`) with the generic
    loop of :mod:`nonideal.numeric.integrator`: :meth:`buffers` for a mode structure, and
    ``rhs``, ``phase``, ``evaluate`` of that module."""

    def __init__(self, module, kernel):
        from . import integrator
        from .callback import Callback

        self.kernel = Callback(module.kernel)
        self.rhs = module.rhs
        self.integrator = integrator
        self.n = kernel.n
        self.nx = len(kernel.symbols)
        self.nz = kernel.dynamics.size

    def buffers(self, system, params: np.ndarray, track: bool):
        """:func:`buffers` of this module's sizes."""
        return buffers(self.nx, self.nz, system, params, track)

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """The kernel's flat output at *x* (zeros where the kernel compiles nothing)."""
        z = np.zeros(self.nz)
        self.integrator.evaluate(self.kernel, np.ascontiguousarray(x, dtype=float), z)
        return z


def buffers(nx: int, nz: int, system, params: np.ndarray, track: bool):
    """``(w, ix)``: the work array ``[x | z | K | r | B^T q']`` with the parameters in
    place, and the index array ``[n, m, power, track, len(src), nx, nz, src, dst, rsrc]``
    of the mode structure *system* (:class:`~nonideal.modes.system.ModeSystem`), for a
    kernel of *nx* inputs and *nz* outputs."""
    n, m, s = system.n, system.m, system.s
    w = np.zeros(nx + nz + s * s + s + m)
    w[1 + 2 * n:1 + 2 * n + len(params)] = params
    power = system.power.start if system.power is not None else -1
    head = np.array([n, m, power, int(track), len(system.src), nx, nz], dtype=np.int64)
    ix = np.concatenate((head, system.src, system.dst, system.rsrc)).astype(np.int64)
    return w, ix


def numba_version() -> str | None:
    """numba's version from its installed metadata, without importing it (0.3-0.5 s); None
    when it is not installed."""
    try:
        from importlib.metadata import version

        return version("numba")
    except Exception:  # pragma: no cover - depends on the environment
        return None


def identity_of(kernel):
    """``(key, source, nx, nz)`` of the native module of *kernel* -- the hash naming it (the
    library's and numba's versions, its source, the generic loop's source), its source and
    sizes -- computed without importing numba; None when numba is not installed or the kernel
    is not written natively.  (A library compiled from the same module, found on disk, needs
    no numba: :meth:`~nonideal.simulation.fast.FastPhases.c_loop`.)"""
    def build():
        version = numba_version()
        if version is None or kernel.compact:  # many coordinates: the sparse solves of the NumPy path
            return None
        try:
            source = module_source(kernel)
        except NotNative:
            return None
        from .. import __version__

        # the generic loop is linked into the module's wrapper: its source is part of the key
        loop = Path(__file__).with_name("integrator.py").read_bytes()
        key = hashlib.sha256(f"{__version__}\0{version}\0{source}".encode() + loop).hexdigest()
        return key, source, len(kernel.symbols), kernel.dynamics.size

    return kernel.model.cached("native identity", build)


def _warm(module, kernel) -> None:
    """Compile (or load from numba's cache) the kernel and the generic loop for it now, not
    inside a step."""
    from . import integrator

    n = kernel.n
    nx, nz = len(kernel.symbols), kernel.dynamics.size
    y = np.zeros(2 * n)
    w = np.zeros(nx + nz + n * n + n)
    # module.rhs, the wrapper for calls from Python, is compiled on its first call
    ix = np.concatenate((np.array([n, 0, -1, 0, 0, nx, nz], dtype=np.int64), np.zeros(n, dtype=np.int64)))
    # a generic point, not zero: a parameter or angle in a denominator (EI/L**3, 1/sin(th))
    # would make the compiled kernel print an ignored ZeroDivisionError at zero
    integrator.evaluate(module.kernel, np.full(nx, 0.6180339887498949), np.zeros(nz))
    integrator.phase(module.kernel, 0.0, y, np.zeros(2 * n), 1.0, 0.0, 1e-3, np.ones(2 * n), np.inf,
                     w, ix, np.zeros(0), 0, 0, 0.0)


_LOADED: dict[str, object] = {}


def _write(path: Path, text: str) -> None:
    """Write *text* to *path* atomically (a temporary file in the same directory renamed)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.stem, suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _import(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # numba's cache finds the module's globals by its name
    spec.loader.exec_module(module)
    return module


def _load(source: str, key: str, kernel):
    """Import the module of *source* from the cache (writing it first when absent or
    different) and compile its functions (from numba's cache when present)."""
    if key in _LOADED:
        return _LOADED[key]
    name = f"nonideal_native_{key[:24]}"
    last_error = None
    # the cache directory; the same once more after removing the module's compiled files (a
    # corrupt or stale entry); a private temporary directory
    for directory, purge in ((cache_dir(), False), (cache_dir(), True), (None, False)):
        try:
            base = Path(tempfile.mkdtemp(prefix="nonideal-")) if directory is None else directory
            path = base / f"{name}.py"
            if purge:
                for stale in (base / "__pycache__").glob(f"{name}.*"):
                    stale.unlink(missing_ok=True)
            try:
                current = path.read_text(encoding="utf-8") if path.exists() else None
            except (OSError, UnicodeDecodeError):
                current = None
            if current != source:  # absent, or not what it should be (corrupt)
                _write(path, source)
            module = _import(path, name)
            _warm(module, kernel)
            _LOADED[key] = module
            return module
        except Exception as exc:  # an unusable cache: try the next place
            last_error = exc
            sys.modules.pop(name, None)
    raise NotNative(f"numba could not compile the model ({type(last_error).__name__}: {last_error})")


def native_of(kernel) -> Native | None:
    """The (cached) :class:`Native` module of *kernel*, or None when numba is not installed or
    the kernel uses a function the native code does not write."""
    def build():
        ident = identity_of(kernel)
        if ident is None or not available():
            return None
        key, source = ident[:2]
        try:
            return Native(_load(source, key, kernel), kernel)
        except NotNative:
            return None

    return kernel.model.cached("native kernel", build)


# ----------------------------------------------------------------------------- template
_TEMPLATE = '''\
"""Native kernel of one model, generated by nonideal {version} (nonideal/numeric/native.py).
Do not edit: the file is named by the hash of its content."""

import math

from numba import carray, cfunc, njit, types

from nonideal.numeric.integrator import rhs as _rhs

NX, NZ = {nx}, {nz}


@njit(cache=True)
def _sign(v):
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)


@cfunc(types.void(types.CPointer(types.float64), types.CPointer(types.float64)), cache=True)
def kernel(xp, zp):
    x = carray(xp, (NX,))
    z = carray(zp, (NZ,))
{body}


@njit
def rhs(t, y, w, ix, dy):
    """The right-hand side with this kernel, called from Python (passing the callback from
    Python costs its typing, ~30 us, at every call).  Not cached by numba (the callback's
    address is a constant of the process): compiled on first use."""
    return _rhs(kernel, t, y, w, ix, dy)
'''


# the writing, loading and checking of generated modules, shared with native_contacts.py
kernel_body, write_atomic, import_module = _kernel_body, _write, _import
