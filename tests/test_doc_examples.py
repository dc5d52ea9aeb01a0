"""Every code block of the README and the user guide runs as written.

Documents: README.md, docs/index.md and docs/guide/*.md. Each fenced block runs by its language:

* ``python``: executed in the repository root, and must print what it shows;
* ``bash``: run by bash (``-e -o pipefail``) in a fresh folder that holds a link to
  ``examples/`` (the commands' relative paths), with this checkout first on ``PYTHONPATH``, its
  interpreter first on ``PATH`` and a cache folder of its own; it must exit with status 0;
* ``toml``: read as a scene by :func:`validation.parse_scene`, in a folder holding the example
  scan (a measured map's ``path`` that names no file there, the reader's own scan, is read as
  the example scan);
* ``text``: program output or a listing, not code.

A block right after a line ``<!-- needs: MODULE -->`` uses an optional package (pandas, or an
extra's): it runs where that imports and is skipped, saying so, where it does not (the
README's test command installs no extra). A block right after a line
``<!-- not run: REASON -->`` is not run; REASON is a key of
:data:`NOT_RUN`, which says why such a block cannot run here, and such blocks stay few. A
``pending`` block (a command or key written up before it is in the program) must lie in a
section marked ``<!-- BEGIN ... -->`` / ``<!-- END ... -->``, to be run once it lands.

The README's results block is checked against the published report it is taken from, and the
command-line reference of the site (generated from the parser, docs/cli_pages.py) is checked to
list every command and option.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tomllib
import warnings

import pytest

import validation

ROOT = pathlib.Path(__file__).resolve().parents[1]
DOCUMENTS = [ROOT / "README.md", ROOT / "docs" / "index.md",
             *sorted((ROOT / "docs" / "guide").glob("*.md"))]
#: Why a block may be left out, by marker. Each is a thing this test cannot or must not do.
NOT_RUN = {
    "installs": "installs packages into the environment the tests run in",
    "test-suite": "runs the whole test suite, this test among them",
    "docs-build": "builds this site, which CI does on every run (.ci/run)",
    "minutes": "minutes of computing on two cores (a paper-scale or default report); the same "
               "command runs on small scenes in these blocks and in tests/test_cli.py",
    "cluster": "needs a dask scheduler and workers on other hosts",
    "user-file": "names the reader's own scene or scan, which no repository holds",
    "gpu": "needs CuPy and a CUDA device; tests/test_device.py runs the same calls on a "
           "stand-in for CuPy, and on CuPy itself where there is a GPU",
    "pending": "a command or scene key written up from its interface before it is in the "
               "program",
}
#: At most this many blocks are not run, over all the documents.
MAX_NOT_RUN = 16
LANGUAGES = ("python", "bash", "toml", "text")

_FENCE = re.compile(r"^(`{3,})([^`\s]*)\s*$")
_NOT_RUN = re.compile(r"^<!-- not run: ([\w-]+) -->$")
_NEEDS = re.compile(r"^<!-- needs: ([\w, ]+) -->$")


@dataclasses.dataclass(frozen=True)
class Block:
    document: str
    line: int
    language: str
    code: str
    not_run: str | None
    marked: bool        # inside a <!-- BEGIN ... --> / <!-- END ... --> section
    needs: tuple[str, ...] = ()   # optional packages it imports

    def __str__(self) -> str:
        return f"{self.document}:{self.line}"


def _blocks(path: pathlib.Path) -> list[Block]:
    lines = path.read_text(encoding="utf-8").splitlines()
    name = path.relative_to(ROOT).as_posix()
    blocks, number, marked = [], 0, False
    while number < len(lines):
        line = lines[number]
        if line.startswith("<!-- BEGIN"):
            marked = True
        elif line.startswith("<!-- END"):
            marked = False
        fence = _FENCE.match(line)
        if not fence:
            number += 1
            continue
        end = next(k for k in range(number + 1, len(lines)) if lines[k].strip() == fence.group(1))
        before = next((lines[k].strip() for k in range(number - 1, -1, -1) if lines[k].strip()), "")
        reason = _NOT_RUN.match(before)
        needs = _NEEDS.match(before)
        language = fence.group(2)
        if not language.startswith("{"):  # a MyST directive (toctree) is not a code block
            blocks.append(Block(name, number + 1, language, "\n".join(lines[number + 1:end]) + "\n",
                                reason.group(1) if reason else None, marked,
                                tuple(m.strip() for m in needs.group(1).split(",")) if needs
                                else ()))
        number = end + 1
    return blocks


BLOCKS = [block for path in DOCUMENTS for block in _blocks(path)]
RUN = [block for block in BLOCKS if block.not_run is None]


def _run(language: str) -> list[Block]:
    return [block for block in RUN if block.language == language]


def test_the_documents_show_examples():
    assert any(b.document == "README.md" and b.language == "python" for b in RUN), (
        "the README must show a library example that runs")
    assert len(DOCUMENTS) >= 8 and len(RUN) >= 10


def test_every_block_has_a_language_this_test_runs():
    unknown = [f"{b} ({b.language or 'no language'})" for b in BLOCKS if b.language not in LANGUAGES]
    assert not unknown, f"blocks this test does not know how to run: {unknown}"


def test_the_blocks_left_out_are_few_and_say_why():
    for path in DOCUMENTS:  # every marker stands right before a block
        markers = len(re.findall(r"^<!-- not run:", path.read_text(encoding="utf-8"), flags=re.M))
        on_blocks = sum(1 for b in BLOCKS if b.document == path.relative_to(ROOT).as_posix()
                        and b.not_run is not None)
        assert markers == on_blocks, f"{path.name}: a 'not run' marker is not right before a block"
    left_out = [b for b in BLOCKS if b.not_run is not None]
    assert all(b.not_run in NOT_RUN for b in left_out), [
        f"{b}: {b.not_run}" for b in left_out if b.not_run not in NOT_RUN]
    assert len(left_out) <= MAX_NOT_RUN, [f"{b}: {b.not_run}" for b in left_out]
    assert all(b.language != "text" for b in left_out), "text blocks are not run anyway"
    pending = [str(b) for b in left_out if b.not_run == "pending" and not b.marked]
    assert not pending, f"pending blocks outside a BEGIN/END section: {pending}"


@pytest.mark.parametrize("block", _run("python"), ids=str)
def test_python_block_runs(block, capsys, monkeypatch):
    for module in block.needs:
        pytest.importorskip(module, reason=f"{block} uses {module}, an optional package that is "
                                           f"not installed")
    monkeypatch.chdir(ROOT)
    namespace: dict = {"__name__": "__doc_example__"}
    exec(compile(block.code, str(block), "exec"), namespace)
    assert capsys.readouterr().out.strip(), f"{block}: an example should print what it shows"


@pytest.mark.parametrize("block", _run("bash"), ids=str)
def test_shell_block_runs(block, tmp_path):
    (tmp_path / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / ".cache"), MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
               PATH=os.pathsep.join([str(pathlib.Path(sys.executable).parent), os.environ["PATH"]]))
    done = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", block.code], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=600,
                          stdin=subprocess.DEVNULL)
    assert done.returncode == 0, f"{block} exited with {done.returncode}:\n{done.stderr[-3000:]}"


@pytest.mark.parametrize("block", _run("toml"), ids=str)
def test_toml_block_is_a_scene(block, tmp_path):
    example = ROOT / "examples" / "example_topography.txt"
    shutil.copy(example, tmp_path / example.name)
    data = tomllib.loads(block.code)
    surface = data.get("surface", {})
    if surface.get("family") == "file" and not (tmp_path / surface.get("path", "")).is_file():
        surface["path"] = example.name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # SceneWarning: valid, says what it lacks
        validation.parse_scene(data, source=str(block), folder=tmp_path)


def _results_block() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    begin, end = text.index("<!-- BEGIN results table"), text.index("<!-- END results table")
    return text[begin:end]


def _docs_script(name: str):
    """A script of docs/ (readme_results, results_page) imported as a module."""
    import importlib

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(ROOT / "docs"))


def _readme_results():
    return _docs_script("readme_results")


def _results_page():
    return _docs_script("results_page")


def test_the_readme_results_are_the_published_ones():
    published = ROOT / "docs" / "results"
    if (published / "headline.csv").is_file():
        # the block is exactly what docs/readme_results.py writes from the published headline
        generated = _readme_results().block(published)
        assert generated in (ROOT / "README.md").read_text(encoding="utf-8"), \
            "README results block differs: run python docs/readme_results.py"
        return
    # a published report of the layout before the headline: every number of the README's
    # results table is one the published report prints
    text = (published / "report.md").read_text(encoding="utf-8")
    rows = [line for line in _results_block().splitlines() if line.startswith("| ")][1:]
    assert len(rows) >= 8
    numbers = {n for row in rows for n in re.findall(r"\d+(?:\.\d+)?", row.split("|", 2)[2])}
    missing = sorted(n for n in numbers if not re.search(rf"(?<![\d.]){re.escape(n)}(?![\d])",
                                                         text))
    assert not missing, f"numbers of the README's results table not in the published report: {missing}"


def test_the_readme_results_block_is_the_headline(tmp_path):
    """docs/readme_results.py on a constructed headline: every cell's numbers and mark, the
    mean gap named for Persson, a missing cell as a dash."""
    import csv

    columns = ["scene", "D", "model", "quantity", "reference_field", "area_fraction",
               "realizations", "mean_error", "low", "high", "tolerance", "verdict"]
    rows = [["paper-wm-d205", "2.05", "gw", "area", "area", "0.01", "25", "-0.27", "-0.33",
             "-0.21", "0.2", "fails"],
            ["paper-wm-d205", "2.05", "gw", "area", "area", "0.01", "25", "-0.27", "-0.33",
             "-0.21", "0.05", "fails"],
            ["paper-wm-d205", "2.05", "persson", "separation", "mean_gap", "0.1", "25", "0.05",
             "0.01", "0.09", "0.2", "holds"]]
    with (tmp_path / "headline.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(columns)
        writer.writerows(rows)
    block = _readme_results().block(tmp_path)
    lines = block.splitlines()
    assert lines[0].startswith("<!-- BEGIN results table") and lines[-1].startswith("<!-- END")
    assert "**D = 2.05**" in block and "D = 2.95" not in block and "over 25 realizations" in block
    gw = next(line for line in lines if line.startswith("| original GW |"))
    assert gw.split(" | ")[1] == "-27 (-33, -21) ✘" and "–" in gw
    persson = next(line for line in lines if line.startswith("| Persson (mean gap ū) |"))
    assert "+0.05 (+0.01, +0.09) ✔" in persson


def test_the_results_page_is_the_published_report():
    """docs/guide/results.md is exactly what docs/results_page.py writes from docs/results."""
    module = _results_page()
    published = ROOT / "docs" / "results"
    generated = module.page(published, module.written_run_time())
    assert generated == module.PAGE_PATH.read_text(encoding="utf-8"), \
        "results page differs: run python docs/results_page.py"
    for link in re.findall(r"\]\((\.\./results/[^)#]+)", generated):
        assert (module.PAGE_PATH.parent / link).resolve().is_file(), link


def test_the_results_page_counts_the_claims(tmp_path):
    """The claims table on constructed findings: one surface's verdict in words, a family's
    verdicts counted, an untested claim said so, the paper-less overview left out."""

    rows = [("paper-wm-d205", "2.05", "", "a", "claim a", "x", "undecided"),
            ("validity-map", "2.05", "", "a", "claim a", "x", "reproduced"),
            ("validity-map", "2.2", "", "a", "claim a", "x", "reproduced"),
            ("validity-map", "2.4", "", "a", "claim a", "x", "contradicted"),
            ("validity-map", "2.05", "", "h", "claim h", "not tested: one sampling", "undecided"),
            ("paper-wm-d205", "2.05", "", "e", "overview", "x", "not in the paper")]
    findings = [dict(zip(("scene", "D", "H", "finding", "claim", "evidence", "verdict"), r))
                for r in rows]
    table = _results_page().findings_table(findings).splitlines()
    assert table[0] == "| claim | paper, D = 2.05 | validity map |"
    assert table[2] == "| (a) claim a | undecided | 2 reproduced, 1 contradicted |"
    assert table[3] == "| (h) claim h | – | not tested |"
    assert len(table) == 4
    verdicts = [dict(scene="s", tolerance=t, verdict=v, verdict_per_surface=p)
                for t, v, p in (("0.2", "holds", "undecided"), ("0.2", "undecided", "holds"),
                                ("0.05", "fails", ""), ("0.05", "fails", ""))]
    assert _results_page().decided_table(verdicts).splitlines()[2] == "| `s` | 50 % / 0 % | 50 % |"


def test_the_readme_stays_a_front_door():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 250, f"README.md has {len(lines)} lines; the guide (docs/guide) has room"


def test_the_command_line_page_lists_every_command_and_option():
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        from cli_pages import MARKER, command_line_markdown
    finally:
        sys.path.remove(str(ROOT / "docs"))
    from validation.cli import build_parser

    assert MARKER in (ROOT / "docs" / "guide" / "command-line.md").read_text(encoding="utf-8")
    parser = build_parser()
    page = command_line_markdown(parser)
    commands = parser._subparsers._group_actions[0].choices
    assert commands
    for name, sub in commands.items():
        assert f"## `{sub.prog}`" in page, name
        for action in sub._actions:
            for option in action.option_strings:
                if option not in ("-h", "--help"):
                    assert f"`{option}" in page, (name, option)
            if not action.option_strings:
                assert f"`{action.metavar or action.dest}`" in page, (name, action.dest)
