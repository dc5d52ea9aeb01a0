"""No module of asperity, bem or validation imports another that imports it back.

The import graph is read from the sources with :mod:`ast`: every ``import`` and ``from ...
import`` statement counts, at module level, inside functions and under ``TYPE_CHECKING`` alike.
An edge goes to the module named, or to ``package.name`` when that is a module
(``from validation.common import models``); implicit imports of parent packages are not edges.
A cycle is a strongly connected component of more than one module (Tarjan's algorithm).
"""

from __future__ import annotations

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGES = ("asperity", "bem", "validation")


def module_files(root: pathlib.Path, packages=PACKAGES) -> dict[str, pathlib.Path]:
    """Dotted module name -> source file (a package is its ``__init__.py``)."""
    files = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            files[".".join(parts)] = path
    return files


def import_graph(root: pathlib.Path, packages=PACKAGES) -> dict[str, set[str]]:
    """Module -> the project modules it imports, anywhere in its source."""
    files = module_files(root, packages)

    def targets(module: str, node: ast.Import | ast.ImportFrom):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
            return
        base = node.module or ""
        if node.level:  # relative import: resolve against the importing module's package
            package = module if files[module].name == "__init__.py" else module.rpartition(".")[0]
            for _ in range(node.level - 1):
                package = package.rpartition(".")[0]
            base = f"{package}.{base}" if base else package
        for alias in node.names:
            yield f"{base}.{alias.name}" if f"{base}.{alias.name}" in files else base

    graph = {}
    for module, path in files.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        graph[module] = {target for node in ast.walk(tree)
                         if isinstance(node, (ast.Import, ast.ImportFrom))
                         for target in targets(module, node)
                         if target in files and target != module}
    return graph


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module, each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for other in sorted(graph[node]):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(found)


def test_no_module_imports_one_that_imports_it_back():
    graph = import_graph(ROOT)
    assert len(graph) > 60  # the three packages were found
    cycles = import_cycles(graph)
    detail = ["  " + " | ".join(f"{m} -> {sorted(graph[m] & set(c))}" for m in c) for c in cycles]
    assert not cycles, "import cycles:\n" + "\n".join(detail)


def test_cycles_are_found_through_function_level_relative_and_type_checking_imports(tmp_path):
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    sources = {
        "__init__.py": "from pkg.a import f\n",
        "a.py": "def f():\n    from pkg import b\n    return b\n",          # a -> b (in a function)
        "b.py": "import pkg.a\n",                                            # b -> a
        "c.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg.sub import d\n",
        "sub/__init__.py": "",
        "sub/d.py": "from . import e\n",                                     # relative: pkg.sub.e
        "sub/e.py": "from ..c import x\n",                                   # relative: pkg.c
        "free.py": "import pkg.a\nfrom pkg import sub\n",                   # imports, not imported
    }
    for name, text in sources.items():
        (package / name).write_text(text, encoding="utf-8")
    graph = import_graph(tmp_path, ("pkg",))
    assert graph["pkg.sub.d"] == {"pkg.sub.e"} and graph["pkg.sub.e"] == {"pkg.c"}
    assert graph["pkg.free"] == {"pkg.a", "pkg.sub"}
    assert import_cycles(graph) == [["pkg.a", "pkg.b"], ["pkg.c", "pkg.sub.d", "pkg.sub.e"]]


def test_a_chain_without_a_way_back_is_no_cycle():
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": set(), "d": {"a", "c"}}) == []
