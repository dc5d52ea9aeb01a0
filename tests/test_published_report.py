"""The published report is complete in the repository: every image and file that
docs/results/report.md, its scene pages (and the README, the user guide and the theory page) link
exists and is tracked by git, and nothing ``python -m validation report --publish`` writes is
ignored by the repository.

Outside a git checkout (an unpacked source archive) only existence is checked.
"""

from __future__ import annotations

import pathlib
import re
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PUBLISHED = ROOT / "docs" / "results"
DOCUMENTS = ("docs/results/report.md", "README.md", "docs/theory.md", "docs/index.md",
             *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs" / "guide").glob("*.md")))

# [text](target) and ![alt](target "title"); the target ends at whitespace or ")".
_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")


def local_links(text: str) -> list[str]:
    """Targets of the Markdown links and images in ``text`` that are files of the repository:
    no URL scheme, no pure #anchor; a #fragment is dropped. Links inside code are skipped."""
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    text = re.sub(r"`[^`\n]*`", "", text)
    targets = []
    for target in _LINK.findall(text):
        if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
            continue
        targets.append(target.split("#", 1)[0])
    return targets


def _git(*args: str) -> subprocess.CompletedProcess | None:
    if shutil.which("git") is None:
        return None
    try:
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True,
                              timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None


def _in_checkout() -> bool:
    top = _git("rev-parse", "--show-toplevel")
    return (top is not None and top.returncode == 0
            and pathlib.Path(top.stdout.strip()).resolve() == ROOT)


def _tracked() -> set[str]:
    listing = _git("ls-files", "-z")
    assert listing is not None and listing.returncode == 0, listing
    return set(listing.stdout.split("\0")) - {""}


def test_local_links_are_parsed():
    text = ("![a figure](fig-1.png) and [a table](t.csv \"title\"), [theory](docs/theory.md#eq-t4),"
            " [web](https://example.org/x.png), [anchor](#top), [a [nested] label](sub/b.png),"
            " `[code](not-a-link.png)`\n```\n![block](not-either.png)\n```\n")
    assert local_links(text) == ["fig-1.png", "t.csv", "docs/theory.md", "sub/b.png"]


@pytest.mark.parametrize("document", DOCUMENTS)
def test_every_linked_file_is_in_the_repository(document):
    path = ROOT / document
    links = local_links(path.read_text(encoding="utf-8"))
    targets = {(path.parent / link).resolve() for link in links}
    missing = sorted(str(t.relative_to(ROOT)) for t in targets if not t.is_file())
    assert not missing, f"{document} links files that do not exist: {missing}"
    if _in_checkout():
        tracked = _tracked()
        untracked = sorted(name for name in (t.relative_to(ROOT).as_posix() for t in targets)
                           if name not in tracked)
        assert not untracked, f"{document} links files git does not track: {untracked}"


def report_pages() -> list[pathlib.Path]:
    """The published report.md and the scene pages it links (in docs/results)."""
    front = PUBLISHED / "report.md"
    links = local_links(front.read_text(encoding="utf-8"))
    return [front] + sorted({PUBLISHED / link for link in links
                             if link.endswith(".md") and "/" not in link})


def test_every_file_a_scene_page_links_is_in_the_repository():
    tracked = _tracked() if _in_checkout() else None
    for page in [p for p in report_pages() if p.name != "report.md"]:
        targets = {(page.parent / link).resolve()
                   for link in local_links(page.read_text(encoding="utf-8"))}
        missing = sorted(str(t.relative_to(ROOT)) for t in targets if not t.is_file())
        assert not missing, f"{page.name} links files that do not exist: {missing}"
        if tracked is not None:
            untracked = sorted(name for name in (t.relative_to(ROOT).as_posix() for t in targets)
                               if name not in tracked)
            assert not untracked, f"{page.name} links files git does not track: {untracked}"


def test_the_published_report_links_its_figures():
    links = [link for page in report_pages()
             for link in local_links(page.read_text(encoding="utf-8"))]
    assert sum(link.endswith(".png") for link in links) >= 10
    assert {"curves.csv", "errors.csv", "verdicts.csv"} <= set(links)


def test_nothing_publish_writes_is_ignored():
    # --publish writes report.md, CSV tables and PNG figures into docs/results (validation.cli,
    # validation.report.write and .tables); none of them, present or future, may be ignored.
    if not _in_checkout():
        pytest.skip("not a git checkout")
    names = {"report.md", "a-new-figure.png", "a-new-table.csv", "a-new-scene.md"}
    for page in report_pages():
        names |= {page.name} | set(local_links(page.read_text(encoding="utf-8")))
    paths = sorted((PUBLISHED / name).relative_to(ROOT).as_posix() for name in names)
    check = subprocess.run(["git", "-C", str(ROOT), "check-ignore", "--no-index", "--stdin", "-z"],
                           input="\0".join(paths) + "\0", capture_output=True, text=True,
                           timeout=30)
    assert check.returncode in (0, 1), check.stderr
    ignored = sorted(set(check.stdout.split("\0")) - {""})
    assert not ignored, f"the repository ignores files that --publish writes: {ignored}"
