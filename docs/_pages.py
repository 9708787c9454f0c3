"""Pages generated when the documentation is built (into ``docs/generated/``, never edited by
hand): one executed page per gallery example, found the way ``nonideal examples`` finds them,
and the command reference read from the command line's own parser -- so a new example or a
new option appears without editing the documentation."""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

PAGE = '''---
file_format: mystnb
kernelspec:
  name: python3
  display_name: Python 3
  language: python
---

# {title}

`nonideal examples run {name}` runs this example; `nonideal examples show {name}` prints its
model file, `nonideal/gallery/{file}` in the package.  The page below is executed when the documentation is built: the equations, the plot and the
numbers are those of this version of nonideal.

```{{eval-rst}}
.. automodule:: nonideal.gallery.{module}
   :no-index:
   :no-members:
```

## The model file

```{{literalinclude}} ../../../nonideal/gallery/{file}
:language: toml
```

## The equations of motion

Lagrange's equations of the first kind (`nonideal derive {name}`), contacts in their state at
t0:

```{{code-cell}} ipython3
:tags: [hide-input]
import contextlib, io
from IPython.display import Image, Latex, Markdown
import nonideal
from nonideal import gallery
from nonideal.plotting import plot_trajectory

model = gallery.load("{name}")
eom = nonideal.derive(model)
Latex(eom._repr_latex_())
```

## The motion

```{{code-cell}} ipython3
:tags: [hide-input]
if model.simulation.t_end is None:
    display(Markdown("The model file sets no `[simulation] t_end`: the example studies the "
                     "equations (see the numbers below)."))
else:
    traj = nonideal.simulate(model)
    plot_trajectory(traj, "{name}.png", title=model.name, model=model)
    display(traj)
    display(Image(filename="{name}.png"))
```

## The checked numbers

What `nonideal examples run {name}` compares with the closed forms and the literature; the
build fails if a check fails.

```{{code-cell}} ipython3
:tags: [hide-input]
with contextlib.redirect_stdout(io.StringIO()) as report:
    result = gallery.run("{name}", verbose=True)
print(report.getvalue().strip())
assert result["ok"], "a check of the example failed"
```
'''


def write_all(docs: Path, only: str | None = None) -> None:
    out = docs / "generated"
    if out.exists():
        shutil.rmtree(out)
    (out / "gallery").mkdir(parents=True)
    write_gallery(out / "gallery", [n.strip() for n in only.split(",")] if only else None)
    write_commands(out / "commands.md")


def write_gallery(folder: Path, only: list[str] | None) -> None:
    from nonideal import gallery

    names = gallery.names()
    if only:
        unknown = [n for n in only if n not in names]
        if unknown:
            raise SystemExit(f"NONIDEAL_DOCS_GALLERY: no example {', '.join(unknown)}")
        names = [n for n in names if n in only]
    for k, name in enumerate(names):
        ex = gallery.info(name)
        text = PAGE.format(name=name, title=ex.title.replace("\n", " "), file=ex.file, module=ex.module)
        (folder / f"{k:03d}_{ex.module}.md").write_text(text, encoding="utf-8")


def write_commands(path: Path) -> None:
    """Every command's ``--help``, as the terminal shows it, in a page."""
    from nonideal.cli import COMMANDS, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    lines = ["# Command reference", "",
             "Every command of `nonideal` with its options, as `nonideal COMMAND --help` prints "
             "them (generated from the command line itself).  Exit codes: 0 success, 2 bad "
             "input (the message names the file, the key and the fix), 3 the mechanics has no "
             "consistent or no unique answer, 130/143 interrupted.", ""]
    for name in COMMANDS:
        command = name.replace("_", "-")
        p = sub.choices.get(command) or sub.choices[name]
        lines += [f"## `nonideal {command}`", "", "```text", p.format_help().rstrip(), "```", ""]
    path.write_text("\n".join(lines), encoding="utf-8")
