"""Domain exceptions of nonideal, in one place.

Two families, two exit codes of the command line:

* :class:`ModelError` (exit code 2) -- the input is wrong: an unknown symbol, a missing
  parameter, an inconsistent initial state, a singular mass matrix, dependent constraints,
  an integration that could not proceed.  The message names the file, the key or the
  constraint, what is wrong, and the fix.  Every problem found is reported, not just the first.
* :class:`MechanicsError` (exit code 3) -- the input is well formed but the mechanics has no
  consistent or no unique answer: Painleve's paradox, an indeterminate or impossible servo
  system.  The message explains why and gives the state where it happened.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from difflib import get_close_matches

__all__ = [
    "NonidealError",
    "ModelError",
    "ExpressionError",
    "InconsistentInitialConditions",
    "SingularSystem",
    "FormNotApplicable",
    "IntegrationFailed",
    "MechanicsError",
    "PainleveParadox",
    "SetValuedFriction",
    "IndeterminateSystem",
    "NotAnEquilibrium",
    "UnitWarning",
    "LinearizationUndefined",
    "did_you_mean",
]


def short_repr(value, width: int = 60) -> str:
    """``repr(value)`` cut to *width* characters for a message; a long number keeps its
    first and last digits and says how many it has (a 1201-digit integer is not printed
    whole).

    Examples
    --------
    >>> short_repr(10**100)
    '100000000000...000000 (101 digits)'
    """
    text = repr(value)
    if len(text) <= width:
        return text
    if text.lstrip("-").isdigit():
        return f"{text[:12]}...{text[-6:]} ({len(text.lstrip('-'))} digits)"
    return text[:width - 3] + "..."


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """Return ``" (did you mean 'x'?)"`` when *name* is close to one of *candidates*."""
    candidates = [str(c) for c in candidates]
    same_case = [c for c in candidates if c.lower() == name.lower() and c != name]
    close = same_case or get_close_matches(name, candidates, n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


class NonidealError(Exception):
    """Base class of every error raised on purpose by nonideal."""

    exit_code = 1


class ModelError(NonidealError):
    """Bad input.  Carries every problem found; ``str()`` prints one per line.

    Parameters
    ----------
    problems : str or list of str
        Each a complete sentence naming the key/constraint and the fix.
    source : str, optional
        The model file (or ``"<api>"``); prefixed to each line.
    """

    exit_code = 2

    def __init__(self, problems: str | Iterable[str], source: str | None = None):
        self.problems = [problems] if isinstance(problems, str) else list(problems)
        self.source = source
        super().__init__(self._format())

    def _format(self) -> str:
        prefix = f"{self.source}: " if self.source else ""
        return "\n".join(prefix + p for p in self.problems)

    def with_source(self, source: str) -> "ModelError":
        """Return a copy of this error attributed to *source* (a file name)."""
        err = type(self).__new__(type(self))
        err.__dict__.update(self.__dict__)
        err.source = source
        Exception.__init__(err, err._format())
        return err


class ExpressionError(ModelError):
    """An expression string could not be parsed or uses something not allowed.

    Attributes
    ----------
    unknown : list of (name, where)
        The unknown names of the expression and where they were used (empty for a syntax
        error); the model collects them into one "missing parameters" summary.
    """

    def __init__(self, problems: str | Iterable[str], source: str | None = None,
                 unknown: Iterable[tuple[str, str]] = ()):
        self.unknown = list(unknown)
        super().__init__(problems, source)


class InconsistentInitialConditions(ModelError):
    """The initial state violates a constraint, or cannot be completed."""


class SingularSystem(ModelError):
    """Singular mass matrix, dependent/redundant constraints, or an unsolvable reduction."""


class FormNotApplicable(ModelError):
    """The requested formalism does not apply to this model (the message says which does)."""


class IntegrationFailed(ModelError):
    """The numerical integration could not proceed.

    Attributes
    ----------
    t : float
        Time where it stopped.
    mode : str
        The active mode (constraints / contacts) at that time.
    reason : str
        What the integrator reported.
    """

    def __init__(self, t: float, mode: str, reason: str, source: str | None = None):
        self.t, self.mode, self.reason = float(t), mode, reason
        super().__init__(
            f"integration failed at t = {t:.10g} in mode [{mode}]: {_explain_reason(reason)}. "
            f"Fix: {_advice(reason, t)}",
            source,
        )


def _advice(reason: str, t: float) -> str:
    """What to try, given the integrator's reason."""
    earlier = f"simulate to an earlier end time (--t-end below {t:.6g} or [simulation] t_end)"
    text = (reason or "").lower()
    if "mode switches" in text or "zeno" in text:
        return (f"{earlier}; impacts that repeat without end (Zeno) stop with restitution = 0 "
                "(plastic), chattering contacts with a regularized friction law "
                "(friction = \"regularized\", eps)")
    if "chart of lagrange ii" in text:
        return ("use --form lagrange1 or --form maggi, which keep the redundant coordinates and "
                f"need no chart, or {earlier}")
    if "not smooth" in text or "collapsed" in text:
        return f"{earlier}, or make the right-hand side smooth there (see the reason)"
    return (f"{earlier}, use method = \"Radau\" in [simulation] if the problem is stiff, or "
            "change rtol/atol in [simulation]")


def _explain_reason(reason: str) -> str:
    """The integrator's reason, with what it usually means."""
    text = (reason or "step failed").strip().rstrip(".")
    if "step size" in text.lower() and "spacing" in text.lower():
        return (f"the step size fell below the floating-point resolution of t ({text!r}); "
                "the solution probably blows up (grows without bound) near this time, or the "
                "problem is very stiff there")
    return text


class MechanicsError(NonidealError):
    """The mechanics has no consistent or no unique answer.

    Parameters
    ----------
    explanation : str
        Why: which contact/constraint, which condition fails.
    t : float, optional
        Time of the state.
    state : mapping, optional
        ``{name: value}`` of coordinates and velocities at that time.
    details : mapping, optional
        Further numbers (e.g. the critical friction coefficient) for machine output.
    """

    exit_code = 3

    def __init__(
        self,
        explanation: str,
        t: float | None = None,
        state: Mapping[str, float] | None = None,
        details: Mapping[str, object] | None = None,
    ):
        self.explanation = explanation
        self.t = t
        self.state = dict(state or {})
        self.details = dict(details or {})
        super().__init__(self._format())

    def _format(self) -> str:
        lines = [self.explanation]
        if self.t is not None:
            lines.append(f"  at t = {self.t:.10g}")
        if self.state:
            lines.append("  state: " + ", ".join(f"{k} = {v:.10g}" for k, v in self.state.items()))
        for key, value in self.details.items():
            lines.append(f"  {key}: {value}")
        return "\n".join(lines)


class SetValuedFriction(MechanicsError):
    """A friction law without a sticking mode (Coulomb-Contensou over a patch) reached the state
    where it is set-valued: the slip and the pivoting vanished together."""


class PainleveParadox(MechanicsError):
    """Sliding has no consistent continuation, or more than one (Painleve's paradox)."""


class IndeterminateSystem(MechanicsError):
    """A servo system with fewer/more program constraints than control unknowns."""


class SingularMotion(MechanicsError):
    """Along the motion the active constraints became dependent, or one lost its gradient:
    the multipliers pass through a pole and the continuation is not determined."""


class NotAnEquilibrium(ModelError):
    """The state given for a stability analysis is not an equilibrium / steady motion and none
    was found near it (the message gives the residual rates and the fix)."""


class LinearizationUndefined(MechanicsError):
    """The first approximation does not exist at the state: dependent (singular) constraint
    rows, or accelerations the constraints leave undetermined."""

    def __init__(self, explanation: str, **kw):
        super().__init__("the linearization is undefined: " + explanation, **kw)


class UnitWarning(UserWarning):
    """A number that looks written in other units than the model's: an angle above 2 pi in
    radians where degrees were probably meant, when it decides whether a contact touches."""
