"""Imports in validation/ follow the data flow one way, bottom to top:

    common (and _version) -> surfaces -> scenes -> run -> judge -> report -> check -> cli, campaigns

A sub-package imports only itself and the layers below it; the top (``cli.py``,
``__main__.py``, ``campaigns/`` and the package's ``__init__.py``, the public names) may import
anything, and nothing below imports it. Every import counts: at module level, inside functions,
under ``TYPE_CHECKING``, relative, and ``from validation import x`` (an edge to the package's
``__init__``, the top). The import graph is read from the sources with :mod:`ast` by
``tests/test_import_cycles.py``.
"""

from __future__ import annotations

from test_import_cycles import ROOT, import_graph

#: The layers of validation/, bottom first: each entry names the sub-packages (or top-level
#: modules) of one layer. Only the top layer's members may import each other.
LAYERS = (
    ("_version",),
    ("common",),
    ("surfaces",),
    ("scenes",),
    ("run",),
    ("judge",),
    ("report",),
    ("check",),
    ("cli", "campaigns", "__main__", "__init__"),
)
RANK = {unit: rank for rank, units in enumerate(LAYERS) for unit in units}
TOP = len(LAYERS) - 1


def unit(module: str, package: str = "validation") -> str:
    """The sub-package or top-level module a module belongs to (``__init__`` for the package)."""
    parts = module.split(".")
    if parts[0] != package:
        raise ValueError(f"{module} is not in {package}")
    return parts[1] if len(parts) > 1 else "__init__"


def unplaced(graph: dict[str, set[str]], package: str = "validation") -> set[str]:
    """Sub-packages and top-level modules of ``package`` that have no place in :data:`LAYERS`."""
    return {unit(module, package) for module in graph} - set(RANK)


def back_edges(graph: dict[str, set[str]], package: str = "validation") -> list[tuple[str, str]]:
    """The imports ``(importer, imported)`` that go up or sideways between layers, sorted."""
    found = []
    for module, targets in graph.items():
        source = unit(module, package)
        for target in targets:
            destination = unit(target, package)
            if source == destination:
                continue
            if RANK[destination] < RANK[source] or RANK[destination] == RANK[source] == TOP:
                continue
            found.append((module, target))
    return sorted(found)


def test_every_part_of_validation_has_a_layer():
    graph = import_graph(ROOT, ("validation",))
    assert not unplaced(graph), "place these in LAYERS (and the README's map of the code)"
    assert not set(RANK) - {unit(module) for module in graph}, "LAYERS names parts that are gone"


def test_imports_follow_the_layers():
    graph = import_graph(ROOT, ("validation",))
    crossing = [(a, b) for a, targets in graph.items() for b in targets if unit(a) != unit(b)]
    assert len(crossing) > 50  # the graph was read (every layer imports the ones below)
    edges = back_edges(graph)
    assert not edges, "imports against the layers:\n" + "\n".join(f"  {a} -> {b}" for a, b in edges)


def test_a_back_edge_is_found_in_every_import_form(tmp_path):
    # A small validation/ tree: the allowed imports and one back door of each form.
    sources = {
        "__init__.py": "from validation.judge.compare import f\n",              # top: allowed
        "_version.py": "",
        "cli.py": "def main():\n    from validation.campaigns import bench\n",  # top beside top
        "common/__init__.py": "",
        "common/names.py": "",
        "surfaces/__init__.py": "",
        "surfaces/spec.py": "from validation.common import names\n",            # down: allowed
        "scenes/__init__.py": "",
        "scenes/scene.py": "def check():\n    from validation.run import models\n",  # in a function
        "run/__init__.py": "",
        "run/models.py": "from . import plan\n",                                 # same layer
        "run/plan.py": "from typing import TYPE_CHECKING\n"
                       "if TYPE_CHECKING:\n    from ..judge import compare\n",   # relative, typing
        "judge/__init__.py": "",
        "judge/compare.py": "import validation.run.plan\nfrom validation import cli\n",
        "report/__init__.py": "",
        "report/write.py": "from validation import judge\nimport validation\n",   # the top itself
        "campaigns/__init__.py": "",
        "campaigns/bench.py": "import validation\n",                             # top: allowed
    }
    for name, text in sources.items():
        path = tmp_path / "validation" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    edges = back_edges(import_graph(tmp_path, ("validation",)))
    assert edges == [("validation.judge.compare", "validation.cli"),
                     ("validation.report.write", "validation"),
                     ("validation.run.plan", "validation.judge.compare"),
                     ("validation.scenes.scene", "validation.run.models")]


def test_a_sub_package_without_a_layer_is_found(tmp_path):
    for name in ("__init__.py", "run/__init__.py", "extra/__init__.py", "extra/tool.py"):
        path = tmp_path / "validation" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("", encoding="utf-8")
    assert unplaced(import_graph(tmp_path, ("validation",))) == {"extra"}
