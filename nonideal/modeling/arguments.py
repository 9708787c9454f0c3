"""Checks of the arguments of the Python API, with the messages of the command line.

The public functions (:func:`~nonideal.simulate`, :func:`~nonideal.derive`,
:func:`~nonideal.evaluate`, :func:`~nonideal.modeling.modelfile.model_from_dict`) check what
they are given before any work, and answer a wrong argument with a
:class:`~nonideal.errors.ModelError` that names the function, the argument, what it got and
what to pass -- not an ``AttributeError`` from deep inside, and never by accepting a negative
end time or tolerance silently.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from pathlib import PurePath

import numpy as np

from ..errors import ModelError, short_repr

__all__ = ["require_model", "require_mapping", "require_form", "real_number", "sample_times"]


def _got(value) -> str:
    return f"{type(value).__name__} {short_repr(value, 40)}"


def require_model(model, function: str) -> None:
    """*model* must be a :class:`~nonideal.Model`."""
    from .model import Model

    if isinstance(model, Model):
        return
    if isinstance(model, (str, PurePath)):
        raise ModelError(f"{function}: the model must be a Model, got the path {str(model)!r}; read "
                         f"the file first: {function}(load_model({str(model)!r}), ...)")
    raise ModelError(f"{function}: the model must be a Model (from load_model(path), Model(...) "
                     f"or model_from_mechanics(...)), got {_got(model)}")


def require_mapping(value, function: str, name: str, example: str) -> None:
    """*value* must be a mapping (or None)."""
    if value is not None and not isinstance(value, Mapping):
        raise ModelError(f"{function}: {name} must be a mapping, e.g. {example}, got {_got(value)}")


def require_form(form, function: str, forms) -> None:
    """*form* must be the name of a formalism."""
    if not isinstance(form, str):
        raise ModelError(f"{function}: form must be one of {', '.join(forms)}, got {_got(form)}")


def real_number(value, function: str, name: str, positive: bool = False,
                nonnegative: bool = False) -> float | None:
    """*value* as a finite float (None stays None); *positive*: > 0; *nonnegative*: >= 0."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.ndarray)) \
            or np.ndim(value) != 0:
        raise ModelError(f"{function}: {name} must be a number, got {_got(value)}")
    try:
        x = float(value)
    except OverflowError:
        raise ModelError(f"{function}: {name} = {short_repr(value)} is too large") from None
    if not math.isfinite(x):
        raise ModelError(f"{function}: {name} must be a finite number, got {x}")
    if positive and not x > 0:
        raise ModelError(f"{function}: {name} must be positive, got {x:g}")
    if nonnegative and x < 0:
        raise ModelError(f"{function}: {name} must not be negative, got {x:g}")
    return x


def sample_times(times, function: str) -> np.ndarray | None:
    """*times* as a 1-D float array (None stays None): numbers, at least one."""
    if times is None:
        return None
    if isinstance(times, (str, bytes, Mapping)) or np.ndim(times) != 1:
        raise ModelError(f"{function}: times must be a sequence of numbers, e.g. [0, 0.5, 1], got "
                         f"{_got(times)}")
    try:
        out = np.asarray(times, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"{function}: times must be a sequence of numbers, got {_got(times)}") from None
    if out.size == 0:
        raise ModelError(f"{function}: times is empty; give at least one time, or t_end")
    return out
