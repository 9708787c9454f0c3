"""The gallery: every worked example of the seeds and the classics, runnable and tested.

Each example is a model file (``<module>.toml``) and a Python module with

* a docstring: source, equations, closed form, misprints found in the source;
* ``NAME``, ``TITLE``, ``FILE``;
* ``build(**parameters)`` -- the same model built with the Python API;
* ``run(verbose=True) -> dict`` -- derives, evaluates and simulates the model, compares with the
  published numbers / closed forms and returns the numbers (``"ok"`` says whether every check
  passed); ``nonideal examples run NAME`` prints its report.
"""

from __future__ import annotations

import importlib
from pathlib import Path

from ..modeling.modelfile import load_model

__all__ = ["names", "module", "model_path", "load", "run", "EXAMPLES"]

HERE = Path(__file__).parent


def _discover() -> dict[str, str]:
    """name -> module, for every module of this package that defines NAME (sorted by ORDER)."""
    found = []
    for path in sorted(HERE.glob("*.py")):
        if path.stem.startswith("_"):
            continue
        mod = importlib.import_module(f"{__name__}.{path.stem}")
        if hasattr(mod, "NAME"):
            found.append((getattr(mod, "ORDER", 100), mod.NAME, path.stem))
    return {name: stem for _, name, stem in sorted(found)}


EXAMPLES: dict[str, str] = _discover()


def names() -> list[str]:
    return list(EXAMPLES)


def module(name: str):
    return importlib.import_module(f"{__name__}.{EXAMPLES[name]}")


def model_path(name: str) -> Path:
    return HERE / module(name).FILE


def load(name: str):
    """The example's model, read from its model file."""
    return load_model(model_path(name))


def run(name: str, verbose: bool = True) -> dict:
    return module(name).run(verbose=verbose)
