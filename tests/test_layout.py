"""The layout rule (docs/ARCHITECTURE.md): the package is a pipeline of stages, one folder each,
and a stage imports only earlier stages -- no import cycles, no arrows back up, no private
names taken from another module, and no module too long to read in one sitting."""

import ast
from collections import defaultdict
from pathlib import Path

import nonideal

ROOT = Path(nonideal.__file__).parent

#: the stages in pipeline order; a module may import modules of its own or earlier stages
STAGES = ["errors", "modeling", "equations", "numeric", "modes", "simulation", "analysis",
          "plotting", "gallery", "cli"]
MAX_LINES = 600


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _stage(module: str) -> int | None:
    parts = module.split(".")
    if len(parts) < 2:
        return None                    # the package itself: the public API imports everything
    return STAGES.index(parts[1]) if parts[1] in STAGES else None


def _imports():
    """(module, imported module, imported names, line) for every import of the package's
    modules, inside functions too."""
    modules = {_module_name(p): p for p in ROOT.rglob("*.py")}
    found = []
    for mod, path in modules.items():
        package = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if target.split(".")[0] != "nonideal":
                    continue
                for alias in node.names:
                    sub = f"{target}.{alias.name}"
                    if sub in modules:         # "from . import module"
                        found.append((mod, sub, [], node.lineno))
                    else:
                        found.append((mod, target, [alias.name], node.lineno))
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == "nonideal":
                        found.append((mod, alias.name, [], node.lineno))
    return modules, found


def test_no_import_back_up_a_stage():
    _, found = _imports()
    bad = []
    for mod, target, _, line in found:
        a, b = _stage(mod), _stage(target)
        if a is not None and b is not None and b > a:
            bad.append(f"{mod}:{line} imports {target} ({STAGES[b]} comes after {STAGES[a]})")
    assert not bad, "\n".join(bad)


def test_no_import_cycles():
    modules, found = _imports()
    graph = defaultdict(set)
    for mod, target, _, _ in found:
        if target in modules and target != mod and mod != "nonideal":
            # importing a package runs its __init__: an edge to it, not to its modules
            graph[mod].add(target)
    index, low, stack, on_stack, cycles = {}, {}, [], set(), []

    def connect(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in list(graph):
        if v not in index:
            connect(v)
    assert not cycles, cycles


def test_no_private_names_across_modules():
    _, found = _imports()
    bad = [f"{mod}:{line} takes {target}.{name}" for mod, target, names, line in found
           for name in names if name.startswith("_") and not name.startswith("__")]
    assert not bad, "\n".join(bad)


def test_modules_short_enough_to_read():
    long = [f"{p.relative_to(ROOT.parent)}: {n} lines" for p in ROOT.rglob("*.py")
            if "gallery" not in p.parts and (n := len(p.read_text().splitlines())) > MAX_LINES]
    assert not long, "\n".join(long)


def test_every_module_belongs_to_a_stage():
    modules, _ = _imports()
    loose = [m for m in modules if m not in ("nonideal", "nonideal.__main__") and _stage(m) is None]
    assert not loose, loose
