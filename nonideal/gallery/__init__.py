"""The gallery: worked examples from the literature and the classics, runnable and tested.

Each example is a model file (``<module>.toml``) and a Python module with

* a docstring: source, equations, closed form, misprints found in the source;
* ``NAME``, ``ORDER``, ``TITLE``, ``FILE``;
* ``build(**parameters)`` -- the same model built with the Python API;
* ``run(verbose=True) -> dict`` -- derives, evaluates and simulates the model, compares with the
  published numbers / closed forms and returns the numbers (``"ok"`` says whether every check
  passed); ``nonideal examples run NAME`` prints its report.

The examples are discovered without importing them: ``NAME``, ``ORDER``, ``TITLE`` and
``FILE`` are read from each module's source (they must be plain string / number literals), so
that ``nonideal examples list`` answers without loading SymPy.
"""

from __future__ import annotations

import ast
import importlib
import re
from dataclasses import dataclass
from pathlib import Path

__all__ = ["names", "module", "model_path", "load", "run", "info", "EXAMPLES", "Example"]

HERE = Path(__file__).parent
_FIELDS = ("NAME", "ORDER", "TITLE", "FILE")


@dataclass(frozen=True)
class Example:
    """What the gallery knows of an example before importing it."""

    name: str
    module: str
    title: str
    file: str
    order: int = 100


_ASSIGNMENT = re.compile(r"^(NAME|ORDER|TITLE|FILE)\s*(?::[^=]*)?=\s*", re.M)


def _literals(path: Path) -> dict:
    """The module-level literal assignments ``NAME = ...`` etc. of a source file (a value in
    parentheses may span lines)."""
    out = {}
    text = path.read_text(encoding="utf-8")
    for m in _ASSIGNMENT.finditer(text):
        start = m.end()
        if text.startswith("(", start):
            depth, end = 0, start
            for end in range(start, len(text)):
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                if depth == 0:
                    break
            source = text[start:end + 1]
        else:
            source = text[start:text.find("\n", start) if "\n" in text[start:] else len(text)]
        try:
            out[m.group(1)] = ast.literal_eval(source.split("  #")[0].strip())
        except (ValueError, SyntaxError):
            pass
    return out


def _discover() -> dict[str, Example]:
    """name -> Example, for every module of this package that defines NAME (sorted by ORDER)."""
    found = []
    for path in sorted(HERE.glob("*.py")):
        if path.stem.startswith("_"):
            continue
        lit = _literals(path)
        if "NAME" in lit:
            found.append(Example(lit["NAME"], path.stem, lit.get("TITLE", ""),
                                 lit.get("FILE", path.stem + ".toml"), lit.get("ORDER", 100)))
    found.sort(key=lambda e: (e.order, e.name, e.module))
    return {e.name: e for e in found}


EXAMPLES: dict[str, Example] = _discover()


def names() -> list[str]:
    return list(EXAMPLES)


def info(name: str) -> Example:
    return EXAMPLES[name]


def module(name: str):
    return importlib.import_module(f"{__name__}.{EXAMPLES[name].module}")


def model_path(name: str) -> Path:
    return HERE / EXAMPLES[name].file


def load(name: str):
    """The example's model, read from its model file."""
    from ..modeling.modelfile import load_model

    return load_model(model_path(name))


def run(name: str, verbose: bool = True) -> dict:
    return module(name).run(verbose=verbose)
