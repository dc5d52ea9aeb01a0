"""Imports in each package follow its layers one way, bottom to top:

    validation: common (and _version) -> surfaces -> scenes -> run -> judge -> report -> check
                -> atlas -> cli, campaigns
    bem:        common -> elastic -> leakage -> contact -> model, interface, reference
    asperity:   common -> gw -> spectral | discrete

A sub-package imports only itself and the layers below it (two sub-packages of one layer, such as
asperity's spectral and discrete, not each other); the top (validation's ``cli.py``,
``__main__.py`` and ``campaigns/``, bem's model, interface and reference modules, and each
package's ``__init__.py``, the public names) may import anything, and nothing below imports it.
Every import counts: at module level, inside functions, under ``TYPE_CHECKING``, relative, and
``from bem import x`` (an edge to the package's ``__init__``, the top). The import graph is read
from the sources with :mod:`ast` by ``tests/test_import_cycles.py``; imports between the packages
are checked by ``tests/test_package_layout.py``.
"""

from __future__ import annotations

import pytest

from test_import_cycles import ROOT, import_graph

#: The layers of each package, bottom first: each entry names the sub-packages (or top-level
#: modules) of one layer. Only the top layer's members may import each other.
LAYERS = {
    "validation": (
        ("_version",),
        ("common",),
        ("surfaces",),
        ("scenes",),
        ("run",),
        ("judge",),
        ("report",),
        ("check",),
        ("atlas",),
        ("cli", "campaigns", "__main__", "__init__"),
    ),
    "bem": (
        ("common",),
        ("elastic",),
        ("leakage",),
        ("contact",),
        ("model", "interface", "reference", "__init__"),
    ),
    "asperity": (
        ("common",),
        ("gw",),
        ("spectral", "discrete"),
        ("__init__",),
    ),
}


def ranks(package: str) -> dict[str, int]:
    return {unit: rank for rank, units in enumerate(LAYERS[package]) for unit in units}


def unit(module: str, package: str = "validation") -> str:
    """The sub-package or top-level module a module belongs to (``__init__`` for the package)."""
    parts = module.split(".")
    if parts[0] != package:
        raise ValueError(f"{module} is not in {package}")
    return parts[1] if len(parts) > 1 else "__init__"


def unplaced(graph: dict[str, set[str]], package: str = "validation") -> set[str]:
    """Sub-packages and top-level modules of ``package`` that have no place in :data:`LAYERS`."""
    return {unit(module, package) for module in graph} - set(ranks(package))


def back_edges(graph: dict[str, set[str]], package: str = "validation") -> list[tuple[str, str]]:
    """The imports ``(importer, imported)`` that go up or sideways between layers, sorted."""
    rank, top = ranks(package), len(LAYERS[package]) - 1
    found = []
    for module, targets in graph.items():
        source = unit(module, package)
        for target in targets:
            destination = unit(target, package)
            if source == destination:
                continue
            if rank[destination] < rank[source] or rank[destination] == rank[source] == top:
                continue
            found.append((module, target))
    return sorted(found)


@pytest.mark.parametrize("package", sorted(LAYERS))
def test_every_part_of_a_package_has_a_layer(package):
    graph = import_graph(ROOT, (package,))
    assert not unplaced(graph, package), "place these in LAYERS (and the map of the code)"
    assert not set(ranks(package)) - {unit(module, package) for module in graph}, \
        "LAYERS names parts that are gone"


@pytest.mark.parametrize("package, least", [("validation", 50), ("bem", 30), ("asperity", 15)])
def test_imports_follow_the_layers(package, least):
    graph = import_graph(ROOT, (package,))
    crossing = [(a, b) for a, targets in graph.items() for b in targets
                if unit(a, package) != unit(b, package)]
    assert len(crossing) > least  # the graph was read (every layer imports the ones below)
    edges = back_edges(graph, package)
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


def test_sideways_and_upward_imports_in_bem_and_asperity_are_found(tmp_path):
    sources = {
        "bem/__init__.py": "from bem.contact.path import contact_curve\n",       # top: allowed
        "bem/model.py": "from bem.contact import path\n",                        # top: allowed
        "bem/common/__init__.py": "",
        "bem/common/checks.py": "",
        "bem/elastic/__init__.py": "",
        "bem/elastic/halfspace.py": "from bem.model import x\n",                 # up to the top
        "bem/leakage/__init__.py": "",
        "bem/leakage/flow.py": "def f():\n    from bem.contact import path\n",  # up, in a function
        "bem/contact/__init__.py": "",
        "bem/contact/path.py": "from bem.leakage import flow\nfrom bem import checks\n",
        "asperity/__init__.py": "",
        "asperity/gw/__init__.py": "",
        "asperity/gw/summits.py": "",
        "asperity/spectral/__init__.py": "",
        "asperity/spectral/persson.py": "from asperity.gw import summits\n",    # down: allowed
        "asperity/discrete/__init__.py": "",
        "asperity/discrete/model.py": "from asperity.spectral import persson\n",  # sideways
    }
    for name, text in sources.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    assert back_edges(import_graph(tmp_path, ("bem",)), "bem") == [
        ("bem.contact.path", "bem"), ("bem.elastic.halfspace", "bem.model"),
        ("bem.leakage.flow", "bem.contact.path")]
    assert back_edges(import_graph(tmp_path, ("asperity",)), "asperity") == [
        ("asperity.discrete.model", "asperity.spectral.persson")]
