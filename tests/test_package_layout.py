"""The packages' layout: every module ships, no module is long, imports between the packages go
one way (validation -> asperity -> bem), bem and asperity keep their modules in sub-packages by
role, and every public name stays where users import it from.

Imports inside each package are checked by ``tests/test_import_layers.py``.
"""

from __future__ import annotations

import ast
import importlib
import pathlib
import tomllib

import pytest
import setuptools

from test_import_cycles import ROOT, import_graph

PACKAGES = ("asperity", "bem", "validation")
#: Most lines of one module.
MAX_LINES = 400
#: (most modules beside ``__init__.py`` at the package's top, fewest sub-packages)
SHAPE = {"bem": (6, 3), "asperity": (6, 2)}
#: What each package may import of the others.
MAY_IMPORT = {"bem": set(), "asperity": {"bem"}, "validation": {"asperity", "bem"}}
#: The public names of bem and asperity (each package's ``__all__``): users import them from the
#: package, whatever module defines them.
PUBLIC = {
    "bem": {"ContactCurve", "CURVE_QUANTITIES", "HalfSpace", "solve_contact", "ContactSolution",
            "contact_curve", "count_contacts", "ConvergenceWarning", "ContactModel",
            "BoundaryElementModel", "InterfaceModel", "NominalContactModel", "hydraulic_aperture"},
    "asperity": {"ContactCurve", "gw_integral", "log_gw_integral", "GW_ORDERS", "DISTRIBUTIONS",
                 "GreenwoodWilliamson", "ImprovedGreenwoodWilliamson", "holm_greenwood",
                 "dimensionless", "DimensionlessCurve", "dimensionless_pressure",
                 "interaction_parameter", "interaction_curves", "InteractionCurves", "Summits",
                 "find_summits", "summits_to_arrays", "summits_from_arrays",
                 "DiscreteAsperityModel", "ValidityWarning", "DISCRETE_QUANTITIES",
                 "PointForceInteraction", "Persson", "PERSSON_QUANTITIES", "separation_kernel",
                 "IsotropicSpectrum", "radial_power_spectrum", "SpectralMoments",
                 "SpectralSummits", "spectral_moments", "spectral_summits",
                 "hertz_elliptic_factors", "BushGibsonThomas"},
}


def source_folders(root: pathlib.Path) -> set[str]:
    """Dotted names of the folders under the packages that hold Python sources."""
    return {".".join(path.parent.relative_to(root).parts)
            for package in PACKAGES for path in (root / package).rglob("*.py")}


def shipped(root: pathlib.Path) -> set[str]:
    """The packages the build finds: setuptools with pyproject's ``packages.find`` options."""
    options = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))
    find = options["tool"]["setuptools"]["packages"]["find"]
    return set(setuptools.find_packages(str(root), include=find["include"],
                                        exclude=find.get("exclude", ())))


def unshipped(root: pathlib.Path) -> set[str]:
    return source_folders(root) - shipped(root)


def long_modules(root: pathlib.Path) -> dict[str, int]:
    lengths = {path.relative_to(root).as_posix(): len(path.read_text(encoding="utf-8").splitlines())
               for package in PACKAGES for path in (root / package).rglob("*.py")}
    return {name: lines for name, lines in lengths.items() if lines > MAX_LINES}


def foreign_imports(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Imports ``(importer, imported)`` of a package the importer's package may not import."""
    return sorted((module, target) for module, targets in graph.items() for target in targets
                  if target.split(".")[0] != module.split(".")[0]
                  and target.split(".")[0] not in MAY_IMPORT[module.split(".")[0]])


def shape(root: pathlib.Path, package: str) -> tuple[list[str], list[str]]:
    """(modules at the package's top but ``__init__.py``, sub-packages)."""
    folder = root / package
    modules = sorted(path.name for path in folder.glob("*.py") if path.name != "__init__.py")
    subs = sorted(path.name for path in folder.iterdir() if (path / "__init__.py").is_file())
    return modules, subs


def test_every_folder_of_sources_ships_in_the_wheel():
    assert {"bem.contact", "asperity.gw", "validation.judge"} <= source_folders(ROOT)
    missing = unshipped(ROOT)
    assert not missing, f"packages.find in pyproject.toml leaves out {sorted(missing)}"


def test_a_folder_left_out_of_the_build_is_found(tmp_path):
    for name in ("bem/__init__.py", "bem/contact/__init__.py", "bem/contact/path.py",
                 "bem/loose/tool.py", "asperity/__init__.py", "asperity/gw/__init__.py",
                 "validation/__init__.py"):
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("", encoding="utf-8")
    (tmp_path / "pyproject.toml").write_text(
        '[tool.setuptools.packages.find]\ninclude = ["asperity", "bem", "bem.*", "validation"]\n',
        encoding="utf-8")
    # bem/loose has no __init__.py; asperity.gw is not matched by the include
    assert unshipped(tmp_path) == {"bem.loose", "asperity.gw"}


def test_no_module_is_longer_than_the_limit():
    assert not long_modules(ROOT), f"split by role, at most {MAX_LINES} lines each"


def test_a_long_module_is_found(tmp_path):
    (tmp_path / "bem").mkdir()
    (tmp_path / "bem" / "long.py").write_text("x = 1\n" * (MAX_LINES + 1), encoding="utf-8")
    (tmp_path / "bem" / "short.py").write_text("x = 1\n" * MAX_LINES, encoding="utf-8")
    for package in ("asperity", "validation"):
        (tmp_path / package).mkdir()
    assert long_modules(tmp_path) == {"bem/long.py": MAX_LINES + 1}


def test_imports_between_the_packages_go_one_way():
    graph = import_graph(ROOT)
    assert any(target.startswith("bem.") for target in graph["asperity.discrete.model"])
    assert not foreign_imports(graph)


def test_a_foreign_import_is_found_in_a_function():
    sources = {
        "bem/contact/path.py": "def f():\n    import asperity.gw.summits\n",
        "asperity/gw/summits.py": "from bem.common import checks\n",
        "asperity/gw/base.py": "from validation.common import models\n",
    }
    graph = {}
    for name, text in sources.items():
        module = name[:-3].replace("/", ".")
        graph[module] = {node.module if isinstance(node, ast.ImportFrom) else node.names[0].name
                         for node in ast.walk(ast.parse(text))
                         if isinstance(node, (ast.Import, ast.ImportFrom))}
    assert foreign_imports(graph) == [("asperity.gw.base", "validation.common"),
                                      ("bem.contact.path", "asperity.gw.summits")]


@pytest.mark.parametrize("package", sorted(SHAPE))
def test_bem_and_asperity_keep_their_modules_in_sub_packages(package):
    most, fewest = SHAPE[package]
    modules, subs = shape(ROOT, package)
    assert len(modules) <= most, f"{package} has {len(modules)} modules at its top: {modules}"
    assert len(subs) >= fewest, f"{package} has {len(subs)} sub-packages: {subs}"
    for sub in subs:   # each says what it holds
        docstring = ast.get_docstring(ast.parse((ROOT / package / sub / "__init__.py").read_text()))
        assert docstring, f"{package}/{sub}/__init__.py says nothing of its role"


@pytest.mark.parametrize("package", sorted(PUBLIC))
def test_every_public_name_is_importable_from_its_package(package):
    module = importlib.import_module(package)
    assert PUBLIC[package] <= set(module.__all__), "a public name left __all__"
    missing = [name for name in module.__all__ if not hasattr(module, name)]
    assert not missing, f"in {package}.__all__ but not importable: {missing}"
    for name in module.__all__:   # defined in a module of the package (or bem's, for asperity)
        value = getattr(module, name)
        origin = getattr(value, "__module__", None)
        if origin is not None and callable(value):
            assert origin.split(".")[0] in {package, "bem"}, (name, origin)


def test_the_api_reference_drops_the_pages_of_moved_modules(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / "docs"))
    from api_pages import write_pages

    (tmp_path / "bem.path.rst").write_text("bem.path\n========\n", encoding="utf-8")
    write_pages(tmp_path)
    assert not (tmp_path / "bem.path.rst").exists()
    assert (tmp_path / "bem.contact.path.rst").is_file() and (tmp_path / "bem.rst").is_file()
