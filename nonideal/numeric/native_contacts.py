"""The model's dynamics *and* contacts as one native function (numba), cached on disk.

:mod:`nonideal.numeric.native` compiles the model's kernel (``M``, ``F``, the constraint rows,
the powers).  A mode with contact rows needs the contacts' outputs too (gaps, normal rows, slip
velocities and their Jacobians: :class:`~nonideal.numeric.contact_kernel.ContactKernel`).
:func:`native_contacts_of` writes both as one numba ``cfunc`` ``kernel(x, z)`` whose flat
output ``z = [kernel outputs | contact outputs]`` has exactly the layout of the mode solver's
buffer (:class:`~nonideal.modes.solver.ModeSolver`: ``z``), so that the index arrays of a
:class:`~nonideal.modes.system.ModeSystem` gather the saddle-point system from it unchanged.
The generic loop that calls it is :mod:`nonideal.numeric.contact_integrator`.

The source is generated, checked and cached exactly as the kernel's
(:mod:`nonideal.numeric.native`: the same checks of every expression, the same cache
directory, names keyed by the SHA-256 of the source, the library's and numba's versions and
the generic loop's source).  A contact that rolls ideally has ``mu = mu_s = inf``: those
entries are not compiled but are constants of the work array (:attr:`NativeContacts.constants`).
"""

from __future__ import annotations

import hashlib
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import symengine as se

from .native import NotNative, available, cache_dir, import_module, kernel_body, write_atomic

__all__ = ["NativeContacts", "native_contacts_of", "contacts_source"]


def _combined(kernel, ck):
    """An object with the attributes :func:`~nonideal.numeric.native.kernel_body` reads
    (``dynamics._exprs``, ``dynamics._where``, ``dynamics.size``, ``symbols``) for the
    concatenated outputs ``[kernel | contacts]``; and the constant entries ``{position:
    value}`` (infinite friction coefficients) left out of the compiled ones."""
    kd, cf = kernel.dynamics, ck.fn
    exprs, where, constants = [], [], {}
    for compiled, offset in ((kd, 0), (cf, kd.size)):
        positions = compiled._where.tolist() if compiled._where is not None else range(len(compiled._exprs))
        for pos, e in zip(positions, compiled._exprs):
            e = se.sympify(e)
            if e == se.oo:
                constants[offset + int(pos)] = np.inf
            elif e == -se.oo:
                constants[offset + int(pos)] = -np.inf
            else:
                exprs.append(e)
                where.append(offset + int(pos))
    size = kd.size + cf.size
    dynamics = SimpleNamespace(_exprs=exprs, _where=np.array(where, dtype=np.intp), size=size)
    return SimpleNamespace(dynamics=dynamics, symbols=kernel.symbols), constants


def contacts_source(kernel, ck) -> tuple[str, dict]:
    """The source of the native module of *kernel* with its contacts *ck*, and its constants."""
    from .. import __version__

    combined, constants = _combined(kernel, ck)
    body = "\n".join(kernel_body(combined))
    return _TEMPLATE.format(version=__version__, nx=len(kernel.symbols), nz=combined.dynamics.size,
                            body=body), constants


class NativeContacts:
    """The native kernel-and-contacts function of one model (:attr:`kernel`, a numba C
    callback), its output size :attr:`nz`, and the entries it leaves to the caller
    (:attr:`constants`, ``{position in z: value}``)."""

    def __init__(self, module, kernel, constants):
        from . import contact_integrator
        from .callback import Callback

        self.kernel = Callback(module.kernel)
        self.loop = contact_integrator
        self.nx = len(kernel.symbols)
        self.nz = module.NZ
        self.constants = constants


_LOADED: dict[str, object] = {}


def _load(source: str, key: str):
    if key in _LOADED:
        return _LOADED[key]
    name = f"nonideal_contacts_{key[:24]}"
    last_error = None
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
            if current != source:
                write_atomic(path, source)
            module = import_module(path, name)
            module.kernel  # noqa: B018 - compiled (or read from numba's cache) at import
            _LOADED[key] = module
            return module
        except Exception as exc:  # an unusable cache: try the next place
            last_error = exc
            sys.modules.pop(name, None)
    raise NotNative(f"numba could not compile the contacts ({type(last_error).__name__}: {last_error})")


def native_contacts_of(kernel, ck) -> NativeContacts | None:
    """The (cached) :class:`NativeContacts` of *kernel* and its contact kernel *ck*, or None
    (numba absent, no contacts, or an expression the native code does not write)."""
    def build():
        if not available() or not ck:
            return None
        try:
            import numba

            from .. import __version__

            source, constants = contacts_source(kernel, ck)
            here = Path(__file__)
            loop = here.with_name("contact_integrator.py").read_bytes() + here.with_name("contact_system.py").read_bytes()
            key = hashlib.sha256(f"{__version__}\0{numba.__version__}\0{source}".encode() + loop).hexdigest()
            return NativeContacts(_load(source, key), kernel, constants)
        except NotNative:
            return None

    return kernel.model.cached("native contacts kernel", build)


_TEMPLATE = '''\
"""Native kernel and contacts of one model, generated by nonideal {version}
(nonideal/numeric/native_contacts.py).  Do not edit: the file is named by the hash of its content."""

import math

from numba import carray, cfunc, njit, types

NX, NZ = {nx}, {nz}


@njit(cache=True)
def _sign(v):
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)


@cfunc(types.void(types.CPointer(types.float64), types.CPointer(types.float64)), cache=True)
def kernel(xp, zp):
    x = carray(xp, (NX,))
    z = carray(zp, (NZ,))
{body}
'''
