"""Compiled contact quantities: gaps, normal rows, slip velocities and their Jacobians.

For every contact ``c`` (in model order) the callable returns ``gap[c]``, ``gap_rate[c]``,
``Gn[c]`` (``dg/dq``), ``gamma_n[c]`` (``g'' = Gn q'' + gamma_n``), ``mu[c]``, ``mu_s[c]``;
and for every slip component ``r`` (contacts' components concatenated; ``offsets[c]`` is the
first of contact ``c``) ``U[r]``, ``W[r]`` (``dU/dq'``), ``gamma_U[r]`` (``U' = W q'' + gamma_U``).
``at[name]`` is where each output starts in the flat output array (``W`` row-major, shape
``(components, n_q)``), for the index-based fast path of :mod:`nonideal.modes.system`.
A contact that rolls ideally (``mu = inf``, :class:`~nonideal.modeling.contacts.IdealRolling`)
has ``mu = mu_s = inf``; :attr:`ContactKernel.rolling` lists them.  The friction torques follow
the contacts (:attr:`ContactKernel.torques`, each with its contact in :attr:`ContactKernel.parents`):
their ``U`` is the angular velocity, ``mu = mu_s`` the length.
"""

from __future__ import annotations

import numpy as np

from ..equations.dynamics import dynamics_of
from ..modeling.contacts import IdealRolling
from ..modeling.model import Model
from .kernel import Compiled

__all__ = ["ContactKernel", "contact_kernel_of", "SLIP_FLOOR", "SLIP_LEVEL"]

SLIP_FLOOR = 1e-9
"""A two-component slip below this fraction of the speeds (``1 + max |q'|``; the cheap bound
``2 SLIP_FLOOR (1 + |q'|)`` decides all but the smallest) has no direction of its own: the
friction of a sliding contact then acts along the slip's reference -- the direction of the
slip at the start of the step, or the mode's own where the slide starts -- not along the
slip's rounding or the residue of a stop (1e-10 of the speeds), whose direction flips from
one evaluation to the next.  Near a stop the friction is thus constant over the last
``SLIP_FLOOR`` of the slip, which passes through zero smoothly (its stop located as any
event); after an onset it acts along the onset's direction until the slip has grown."""
SLIP_LEVEL = 1e-8
"""A slip below this fraction of the speeds (``1 + max |q'|``) counts as vanishing: the
switching tolerance of a slip (a phase that starts there takes its mode's direction as the
slip's reference; a stop the steps cannot reach is taken there)."""


class ContactKernel:
    def __init__(self, model: Model):
        dyn = dynamics_of(model)
        self.model = model
        self.data = dyn.contacts
        self.names = [c.name for c in self.data]
        self.index = {c.name: i for i, c in enumerate(self.data)}
        self.dims = [len(c.U) for c in self.data]
        self.offsets = list(np.cumsum([0] + self.dims[:-1])) if self.data else []
        self.n = dyn.n
        self.params = dyn.params
        #: the contacts that roll ideally while closed (``mu = inf``): no slide state, no slip event
        self.rolling = frozenset(c for c, d in enumerate(self.data) if isinstance(d.law, IdealRolling))
        #: the contact each friction torque acts at (None for a contact): a torque has its
        #: contact's gap and normal force, no normal row of its own
        self.parents = [d.parent for d in self.data]
        self.torques = frozenset(c for c, p in enumerate(self.parents) if p is not None)
        symbols = [dyn.t] + dyn.q + dyn.qd + dyn.params
        if not self.data:
            self.fn = None
            self.size = 0
            self.at = {}
            return
        outputs = {
            "gap": [c.gap for c in self.data],
            "gap_rate": [c.gap_rate for c in self.data],
            "Gn": [list(c.Gn) for c in self.data],
            "gamma_n": [c.gamma_n for c in self.data],
            "mu": [c.mu for c in self.data],
            "mu_s": [c.mu_s for c in self.data],
            "U": [u for c in self.data for u in c.U],
            "W": [list(w) for c in self.data for w in c.W],
            "gamma_U": [g for c in self.data for g in c.gamma_U],
        }
        self.fn = Compiled(symbols, outputs)
        self.size = self.fn.size
        self.at = {name: sl.start for name, (sl, _) in self.fn.slices.items()}

    def __bool__(self) -> bool:
        return bool(self.data)

    def __call__(self, x: np.ndarray) -> dict:
        return self.fn(x)

    def frictionless(self, params: np.ndarray) -> frozenset[int]:
        """The contacts with Coulomb's law whose ``mu`` and ``mu_static`` vanish identically
        (whatever the state) at the parameter values *params*, shape (n_parameters,).

        Examples
        --------
        >>> from nonideal import gallery
        >>> from nonideal.numeric.kernel import parameter_vector
        >>> model = gallery.load("block-on-incline")
        >>> ck = contact_kernel_of(model)
        >>> ck.frictionless(parameter_vector(model))
        frozenset()
        >>> ck.frictionless(parameter_vector(model, {"mu": 0, "mu_s": 0}))
        frozenset({0})
        """
        values = {p: float(v) for p, v in zip(self.params, params)}

        def zero(expr) -> bool:
            value = expr.subs(values)
            return value.is_Number and float(value) == 0.0
        return frozenset(c for c, d in enumerate(self.data)
                         if c not in self.rolling and d.law.exact and zero(d.mu) and zero(d.mu_s))

    def slip(self, out: dict, c: int) -> np.ndarray:
        o = self.offsets[c]
        return out["U"][o:o + self.dims[c]]


def contact_kernel_of(model: Model) -> ContactKernel:
    """The (cached) compiled kernel of *model*'s contacts."""
    return model.cached("contact kernel", lambda: ContactKernel(model))
