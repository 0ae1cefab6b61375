"""The layers of ``coincli`` (docs/architecture.md), enforced: every import of every module,
those inside functions included, read from the source (AST), against the table of allowed
imports; and no circle of imports anywhere in the package."""

from __future__ import annotations

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1] / "coincli"

#: each layer, and the layers it may import (besides itself): docs/architecture.md's table
ALLOWED = {
    "cli": {"requests", "reports", "render", "io", "errors", "limits", "signals"},
    "api": {"requests", "reports", "io", "errors"},
    "reports": {"requests", "render", "io", "core", "errors", "limits"},
    "requests": {"io", "core", "errors", "limits"},
    "render": {"io", "core", "errors", "limits"},
    "io": {"core", "errors", "limits"},
    "core": {"errors", "limits"},
    "errors": set(),
    "limits": set(),
    "signals": set(),
    "_entry": {"signals", "cli"},
    "__main__": {"_entry"},
}


def _module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: pathlib.Path):
    """``(line, module imported)`` for every import of coincli in ``path``, at any depth."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("coincli"):
                    yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.split(".")
                parent = parent[: len(parent) - node.level + 1]
                base = ".".join(parent + ([base] if base else []))
            if not base.startswith("coincli"):
                continue
            for alias in node.names:  # `from coincli.io import notes` imports a module
                sub = f"{base}.{alias.name}"
                yield node.lineno, sub if _is_module(sub) else base


def _is_module(name: str) -> bool:
    path = ROOT.parent.joinpath(*name.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def _layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


MODULES = sorted(p for p in ROOT.rglob("*.py"))


def test_every_layer_is_in_the_table():
    layers = {_layer(_module_name(p)) for p in MODULES} - {"__init__"}
    assert layers <= set(ALLOWED), layers - set(ALLOWED)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT.parent)))
def test_imports_go_down_the_layers(path):
    me = _layer(_module_name(path))
    if me == "__init__":  # coincli/__init__.py: the closed forms of the core, re-exported
        allowed = {"core"}
    else:
        allowed = ALLOWED[me] | {me}
    wrong = [f"line {line}: {module}" for line, module in _imports(path)
             if _layer(module) not in allowed and module != "coincli"]
    assert not wrong, f"{_module_name(path)} ({me}) may import only {sorted(allowed)}: {wrong}"


def test_no_circle_of_imports():
    """Tarjan's strongly connected components of the import graph of every module (imports
    inside functions too): each must be a single module."""
    graph = {}
    for path in MODULES:
        name = _module_name(path)
        graph[name] = {m for _, m in _imports(path) if m != name and m in
                       {_module_name(p) for p in MODULES}}
    index, low, stack, on, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    assert not circles, circles
