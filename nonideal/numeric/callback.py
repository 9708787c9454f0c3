"""A model's compiled kernel (a numba ``cfunc``) as an argument of the generic native loops,
typed once instead of at every call.

numba types a ``cfunc`` argument afresh at each call of a compiled function (it builds the
first-class :class:`~numba.core.types.FunctionType` of its signature: ~6 us, several times
per event of a contact run).  :class:`Callback` implements numba's documented wrapper-address
protocol (:class:`~numba.core.types.WrapperAddressProtocol`) for the same C function and
carries its type, registered with :func:`numba.extending.typeof_impl`: the loops see the same
type as for the ``cfunc`` itself (their compiled and cached versions are reused) and call the
same address.
"""

from __future__ import annotations

from numba.core.types import FunctionType, WrapperAddressProtocol
from numba.extending import typeof_impl

__all__ = ["Callback"]


class Callback(WrapperAddressProtocol):
    """The C function of a numba ``cfunc`` *fn* (kept alive here), with its numba type."""

    __slots__ = ("fn", "address", "sig", "type")

    def __init__(self, fn):
        self.fn = fn
        self.address = fn.address
        self.sig = fn._sig  # (numba's own typeof reads the same attribute)
        self.type = FunctionType(self.sig)

    def __wrapper_address__(self) -> int:
        return self.address

    def signature(self):
        return self.sig


@typeof_impl.register(Callback)
def _typeof_callback(val, c):
    return val.type
