"""Sphinx configuration: the user guide (guide/), the published report (results/), the theory
page and the API reference of asperity, bem and validation.
Build: ``python -m sphinx -W --keep-going -b html docs docs/_build/html``."""

import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # document this source tree, not another installed copy
sys.path.insert(0, str(ROOT / "docs"))

import validation  # noqa: E402
from api_pages import write_pages  # noqa: E402
from cli_pages import MARKER, command_line_markdown  # noqa: E402

project = "asperity-validation"
author = "asperity-validation contributors"
copyright = "asperity-validation contributors"
release = version = validation.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
# results/report.md (the published report, with its figures and CSVs) is a page of the site too.
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]

# API pages: one per module (docs/api_pages.py writes them into api/ at every build).
write_pages(ROOT / "docs" / "api")
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"           # numpydoc's Parameters sections carry the types and units
autodoc_preserve_defaults = True
numpydoc_show_class_members = False  # members are documented by autodoc on the class itself
numpydoc_class_members_toctree = False

myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

html_theme = "pydata_sphinx_theme"
html_title = "asperity-validation"
html_theme_options = {"navigation_depth": 3, "show_toc_level": 2}


def _command_line(app, docname, source):
    """The page ``guide/command-line`` gets the reference of every command and option in place
    of its marker line, rendered from the program's parser (docs/cli_pages.py)."""
    if docname == "guide/command-line":
        if MARKER not in source[0]:
            raise RuntimeError(f"guide/command-line.md lost its marker line {MARKER!r}")
        source[0] = source[0].replace(MARKER, command_line_markdown())


def setup(app):
    app.connect("source-read", _command_line)
