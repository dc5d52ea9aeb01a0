"""A report's folder: which files a report owns, and so replaces when it is written again
(:func:`previous_report`), and which folders it refuses to write into."""

from __future__ import annotations

import pathlib
import re

__all__ = ["REPORT_FILES", "previous_report"]

#: What a report writes into its folder, and so what it replaces there: its Markdown, figures
#: and tables (and the scene pages its ``report.md`` links).
REPORT_FILES = ("report.md", "*.png", "*.csv")


def previous_report(folder: str | pathlib.Path) -> list[pathlib.Path]:
    """The files of the previous report in ``folder``, which a new report replaces.

    A report owns the files it writes (:data:`REPORT_FILES`, and the pages its ``report.md``
    links), so that no figure, table or page of an earlier run survives beside a new one. It
    writes into a new or empty folder (hidden files aside), or one holding a previous report (a
    ``report.md``): that report's Markdown, PNG and CSV files and pages are replaced, anything
    else there is left alone. Any other folder is refused,
    so that a report never deletes or mixes with files it did not write.

    Raises
    ------
    ValueError
        When ``folder`` is a file, or holds files but no previous report.
    """
    folder = pathlib.Path(folder)
    if not folder.exists():
        return []
    if not folder.is_dir():
        raise ValueError(f"{str(folder)!r} is a file, not a folder for a report")
    entries = sorted(p.name for p in folder.iterdir() if not p.name.startswith("."))
    if entries and not (folder / "report.md").is_file():
        shown = ", ".join(entries[:4]) + (f" and {len(entries) - 4} more" if len(entries) > 4
                                          else "")
        raise ValueError(f"{str(folder)!r} holds files that are not a report ({shown}); a "
                         f"report replaces the files of a previous report in its folder, so it "
                         f"needs a new or empty folder, or one holding only an earlier report")
    owned = {path for pattern in REPORT_FILES for path in folder.glob(pattern) if path.is_file()}
    return sorted(owned | set(_pages_of(folder)))


def _pages_of(folder: pathlib.Path) -> list[pathlib.Path]:
    """The scene pages the ``report.md`` in ``folder`` links (Markdown files beside it)."""
    report = folder / "report.md"
    if not report.is_file():
        return []
    names = re.findall(r"\]\(([^()/\s]+\.md)\)", report.read_text(encoding="utf-8",
                                                                  errors="replace"))
    return [folder / name for name in set(names) if (folder / name).is_file()]
