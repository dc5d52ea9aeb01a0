"""The README's Performance table quotes the benchmarks page, number for number.

The table is the README's compact summary of docs/guide/benchmarks.md, where every measurement
stands once with the command that measures it. Every measured number of its "measured" column
(a number or a range with its unit: s, ms, min, GB, %, bytes, ...) must appear on that page as
written: with its unit, or in a table of the page whose heading gives the unit ("time (s)").
A list whose members share one unit (``0.60 / 1.04 / 1.58 s``) must appear as the same list.
So a number measured again is changed in one place, and this test names the README rows left
behind.
"""

from __future__ import annotations

import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
BENCHMARKS = ROOT / "docs" / "guide" / "benchmarks.md"

_NUMBER = r"\d+(?:\.\d+)?(?:\s*[–-]\s*\d+(?:\.\d+)?)?"
_UNIT = r"ms|s|min|h|GB|MB|GiB|MiB|kB|%|bytes|B/point"
# a number or range with its unit, or a list "a / b / c unit" whose members share the unit
_QUANTITY = re.compile(
    rf"(?<![\w.²³⁰-⁹])({_NUMBER}(?:\s*/\s*{_NUMBER})*)\s*({_UNIT})(?![\w/])")


def performance_rows(readme: str) -> list[tuple[str, str]]:
    """(what, measured) of each row of the README's table under '## Performance'."""
    section = readme.split("\n## Performance", 1)[1].split("\n## ", 1)[0]
    lines = [line for line in section.splitlines() if line.startswith("|")]
    header = [cell.strip() for cell in lines[0].strip("|").split("|")]
    column = header.index("measured")
    rows = []
    for line in lines[2:]:
        cells = [cell.strip() for cell in line.strip("|").split("|")]
        rows.append((cells[0], cells[column]))
    return rows


def measured_numbers(cell: str) -> list[tuple[str, str]]:
    """(number or list of numbers, unit) of every quantity in one cell, each as written."""
    return [(re.sub(r"\s*/\s*", " / ", m.group(1)), m.group(2))
            for m in _QUANTITY.finditer(cell)]


def _standing(text: str) -> str:
    """A pattern for ``text`` not part of a longer number."""
    return rf"(?<![\d.]){re.escape(text)}(?!\d|\.\d)"


def _tables(page: str) -> list[tuple[str, list[str]]]:
    """(heading line, rows) of every Markdown table of the page."""
    tables, block = [], []
    for line in page.splitlines() + [""]:
        if line.startswith("|"):
            block.append(line)
        elif block:
            tables.append((block[0], block[2:]))
            block = []
    return tables


def on_page(numbers: str, unit: str, page: str) -> bool:
    """Whether ``numbers`` stand on the page as written: followed by ``unit``, or in a table
    whose heading gives ``unit`` in parentheses."""
    if re.search(_standing(numbers) + rf"\s?{re.escape(unit)}(?![\w/])", page):
        return True
    return any(f"({unit})" in heading and any(re.search(_standing(numbers), row) for row in rows)
               for heading, rows in _tables(page))


def missing_numbers(readme: str, page: str) -> list[str]:
    return [f"{numbers} {unit}  (row: {what})" for what, cell in performance_rows(readme)
            for numbers, unit in measured_numbers(cell) if not on_page(numbers, unit, page)]


def test_the_performance_table_is_found_and_has_numbers():
    rows = performance_rows(README.read_text(encoding="utf-8"))
    assert len(rows) >= 10, f"the README's Performance table has {len(rows)} rows"
    numbers = [n for _, cell in rows for n in measured_numbers(cell)]
    assert len(numbers) >= 3 * len(rows) // 2, (
        f"too few measured numbers read from the README's Performance table: {numbers}")
    for expected in [("0.60 / 1.04 / 1.58", "s"), ("32.4", "s"), ("73", "%"),
                     ("210", "bytes"), ("18.5–24.4", "ms")]:
        assert expected in numbers, (expected, numbers)


def test_every_readme_performance_number_is_on_the_benchmarks_page():
    missing = missing_numbers(README.read_text(encoding="utf-8"),
                              BENCHMARKS.read_text(encoding="utf-8"))
    assert not missing, (
        "numbers of the README's Performance table ('measured' column) that "
        "docs/guide/benchmarks.md does not state as written; copy the page's figure into the "
        "README (or add the measurement, with its command, to the page):\n  "
        + "\n  ".join(missing))


@pytest.mark.parametrize("before, after", [
    ("0.60 / 1.04 / 1.58 s", "0.60 / 1.04 / 1.6 s"),   # rounded
    ("43.2–44.5 s", "43–45 s"),                          # a range rounded
    ("350.4 s", "5.8 min"),                              # another unit
    ("18.5–24.4 ms", "18–24 ms"),                        # a number of a table in ms
    ("1.92 GB", "1.9 GB"),
    ("58 %", "59 %"),
])
def test_a_number_that_differs_from_the_page_is_named(before, after):
    readme = README.read_text(encoding="utf-8")
    assert before in readme, f"the README no longer says {before!r}: update this test"
    missing = missing_numbers(readme.replace(before, after, 1),
                              BENCHMARKS.read_text(encoding="utf-8"))
    assert len(missing) == 1 and missing[0].startswith(after), missing
