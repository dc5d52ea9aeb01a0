"""The API reference pages, and the check that the built site documents every public object.

``write_pages(folder)`` (called by docs/conf.py) writes one page per module of asperity, bem and
validation: the module docstring, a summary table, then every public function and class defined
in the module (public: no leading underscore; private modules included). Modules are found with
:mod:`pkgutil` and imported by name, so a package attribute that shadows a module (``asperity``
re-exports the function ``dimensionless`` of the module ``asperity.gw.dimensionless``) is no trap.

``python docs/api_pages.py BUILD_DIR`` after ``python -m sphinx -b html docs BUILD_DIR`` reads
the site's ``objects.inv`` and exits 1, listing them, if a public function or class is missing.
"""

from __future__ import annotations

import importlib
import inspect
import pathlib
import pkgutil
import sys
import zlib

PACKAGES = ("asperity", "bem", "validation")
ROOT = pathlib.Path(__file__).resolve().parents[1]


def module_names(package: str) -> list[str]:
    """The package and all its modules (sub-packages first, then their modules), sorted."""
    found = pkgutil.walk_packages(importlib.import_module(package).__path__, f"{package}.")
    return [package] + sorted(info.name for info in found if not info.name.endswith("__main__"))


def public_objects(name: str) -> list[tuple[str, str]]:
    """(name, "class" or "function") of the public objects defined in a module, in source order."""
    module = importlib.import_module(name)
    found = []
    for attribute, value in vars(module).items():
        if attribute.startswith("_") or getattr(value, "__module__", None) != name:
            continue
        if inspect.isclass(value) or inspect.isfunction(value):
            try:
                line = inspect.getsourcelines(value)[1]
            except (OSError, TypeError):
                line = 0
            found.append((line, attribute, "class" if inspect.isclass(value) else "function"))
    return [(attribute, kind) for _, attribute, kind in sorted(found)]


def module_page(name: str, submodules: list[str]) -> str:
    lines = [name, "=" * len(name), "", f".. automodule:: {name}", "   :no-members:", ""]
    if submodules:
        lines += [".. toctree::", "   :maxdepth: 1", ""] + [f"   {sub}" for sub in submodules] + [""]
    members = public_objects(name)
    if members:
        lines += [".. rubric:: Summary", "", ".. autosummary::", "   :nosignatures:", ""]
        lines += [f"   {member}" for member, _ in members] + [""]
        lines += [f".. auto{kind}:: {name}.{member}\n" for member, kind in members]
    return "\n".join(lines) + "\n"


def write_pages(folder: pathlib.Path) -> list[str]:
    """Write ``<module>.rst`` for every module into ``folder`` (only files whose text changed,
    so incremental builds stay incremental) and remove the pages of modules that are gone (a
    moved module's old page would fail to import); returns the top-level package page names."""
    folder.mkdir(parents=True, exist_ok=True)
    pages = set()
    for package in PACKAGES:
        names = module_names(package)
        pages.update(f"{name}.rst" for name in names)
        for name in names:
            depth = name.count(".") + 1
            children = [other for other in names
                        if other.startswith(f"{name}.") and other.count(".") + 1 == depth + 1]
            page = folder / f"{name}.rst"
            text = module_page(name, children)
            if not page.exists() or page.read_text(encoding="utf-8") != text:
                page.write_text(text, encoding="utf-8")
    for page in folder.glob("*.rst"):
        if page.name not in pages:
            page.unlink()
    return list(PACKAGES)


def documented(build: pathlib.Path) -> set[str]:
    """Fully qualified names of the Python objects in a Sphinx inventory (format version 2)."""
    header, _, body = (build / "objects.inv").read_bytes().partition(b"zlib.\n")
    if not header.startswith(b"# Sphinx inventory version 2"):
        raise SystemExit(f"{build / 'objects.inv'}: not a version-2 Sphinx inventory")
    return {line.split(" ", 2)[0] for line in zlib.decompress(body).decode().splitlines()
            if line.split(" ", 2)[1].startswith("py:")}


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__)
        return 2
    expected = {f"{name}.{member}": kind for package in PACKAGES for name in module_names(package)
                for member, kind in public_objects(name)}
    missing = sorted(set(expected) - documented(pathlib.Path(argv[0])))
    for name in missing:
        print(f"not in the API reference: {expected[name]} {name}")
    print(f"API reference: {len(expected) - len(missing)} of {len(expected)} public functions "
          f"and classes documented")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main(sys.argv[1:]))
