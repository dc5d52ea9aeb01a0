"""Every citation of docs/theory.md in the code names a section or an equation that exists."""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[1]
THEORY = (ROOT / "docs" / "theory.md").read_text(encoding="utf-8")
HEADINGS = [line.lstrip("#").strip() for line in THEORY.splitlines() if line.startswith("#")]
# An equation label is written at the end of its display line: "(T12)", "(P5)", "(L2)", "(S3)" or "(4)".
LABELS = set(re.findall(r"\(([TPLS]?\d+)\)\s*$", THEORY, flags=re.MULTILINE))
SOURCES = [path for package in ("asperity", "bem", "validation", "tests")
           for path in sorted((ROOT / package).rglob("*.py"))
           if path.name != pathlib.Path(__file__).name]
# A citation: "docs/theory.md" and the rest of its line, joined with the next line (a quoted
# section name may wrap).
CITATION = re.compile(r"docs/theory\.md(.*\n?.*)")


def citations():
    for path in SOURCES:
        for match in CITATION.finditer(path.read_text(encoding="utf-8")):
            yield path.relative_to(ROOT), " ".join(match.group(1).split())


def cited_part(text: str) -> str:
    """The citation itself: up to the first ``)``, ``:``, ``;`` or ``.`` outside quotes, after
    unwrapping equation labels such as ``(11)``."""
    text = re.sub(r"\(([TPLS]?\d+)\)", r"\1", text)
    quoted = False
    for index, char in enumerate(text):
        if char == '"':
            quoted = not quoted
        elif not quoted and (char in "):;" or char == "."
                             and not text[:index].endswith(("eq", "eqs"))):
            return text[:index]
    return text


def cited_names(text: str) -> list[str]:
    return re.findall(r'"([^"]+)"', cited_part(text))


def cited_equations(text: str) -> list[str]:
    found = re.findall(r"eqs?\.\s*([TPLS]?\d+)(?:\s*-\s*([TPLS]?\d+))?", cited_part(text))
    return [label for pair in found for label in pair if label]


def test_the_theory_page_numbers_the_papers_equations_and_its_own():
    assert {str(n) for n in range(1, 13)} <= LABELS
    assert {f"T{n}" for n in range(1, 31)} <= LABELS
    assert {f"P{n}" for n in range(1, 10)} <= LABELS           # Persson's theory, section 7
    assert {f"L{n}" for n in range(1, 8)} <= LABELS            # leakage, section 10


def test_spectral_citations_are_checked():
    assert cited_equations(", eqs. S8-S12.") == ["S8", "S12"]
    assert any("eq. S9" in text for path, text in citations() if path.name == "hertz_elliptic.py")


def test_persson_citations_are_checked():
    # the Persson code cites its equations as P-labels; they are parsed like the others
    assert cited_equations(", eq. P1), used throughout") == ["P1"]
    assert cited_equations(" eqs. (P3)-(P9).") == ["P3", "P9"]
    assert any("eq. P1" in text for path, text in citations() if path.name == "spectrum.py")


def test_the_code_cites_the_theory_page():
    assert sum(1 for _ in citations()) >= 30
    assert not [p for p in SOURCES if "THEORY.md" in p.read_text(encoding="utf-8")]


def test_every_cited_section_and_equation_exists():
    missing = []
    for path, text in citations():
        for name in cited_names(text):
            if not any(name in heading for heading in HEADINGS):
                missing.append((str(path), name))
        for label in cited_equations(text):
            if label not in LABELS:
                missing.append((str(path), label))
    assert not missing, missing
