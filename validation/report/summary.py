"""The report's summary: two small decision tables, one per frame (an unbounded interface; a
finite nominal contact), and at most five sentences, all generated from the rows of this run's
tables (``headline.csv`` and ``findings.csv``, as :func:`validation.report.tables.records`
gives them), none written by hand.

Each table has a row per quantity (area, separation, conductance, leakage where computed) and a
column per contact regime, each one headline fraction of its frame's reference
(:data:`COLUMNS`: light 1 %, intermediate 10 %, heavy 30 %; a column no load path reaches is
left out and said so). A cell names **the theory to use** there among the theories of the
frame (:func:`choose`): every theory is read on each surface family whose reference reaches
the fraction, at its scene's largest tolerance; it *holds* (✔) where it holds on every family,
*fails* (✘) where it fails on one or more, and is *undecided* (?) otherwise. The theory shown
is, of those that hold, the one whose largest ``|mean error|`` over the families is the
smallest; where none holds, the one with the smallest largest ``|mean error|``, with its mark.
Its numbers are those of its worst family (largest ``|mean error|``): the mean error with its
95 % interval over realizations (± the reference band for one surface), the family named, and
on how many families it holds. The sentences: what the paper's claims came to
(``findings.csv``) and how precise the headline is.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass

from validation.judge.claims import RANGED, fraction_text
from validation.judge.errors import ABSOLUTE_QUANTITIES, RELATIVE_QUANTITIES
from validation.judge.findings import NEW
from validation.judge.verdicts import FAILS, HOLDS, SYMBOLS, UNDECIDED
from validation.common.labels import compared_label, model_label
from validation.common.models import FRAME_LABELS, FRAMES

__all__ = ["COLUMNS", "FRAME_TITLES", "MAX_SENTENCES", "SUMMARY_QUANTITIES", "RULE", "Choice",
           "choose", "decision_table", "error_text", "number_text", "summary_lines",
           "summary_sentences"]

#: The sentences' length limit (after the tables).
MAX_SENTENCES = 5
#: Quantities the tables speak of, in their order, with the rows' names.
SUMMARY_QUANTITIES = ("area", "separation", "conductance", "leakage")
_NAMES = {"area": "area", "separation": "separation (Persson: mean gap ū)",
          "conductance": "conductance (stiffness)", "leakage": "leakage"}
#: The tables' columns: contact regime and the headline fraction that stands for it.
COLUMNS = (("light", 0.01), ("intermediate", 0.1), ("heavy", 0.3))
#: The tables' titles, per frame, and the theories each judges.
FRAME_TITLES = {
    "interface": "An unbounded interface (original GW, GW and Bush-Gibson-Thomas from the "
                 "spectrum, Persson, the discrete model without interaction; against the "
                 "surface solved as a periodic interface)",
    "finite": "A finite nominal contact (improved GW, improved GW from the spectrum, the "
              "discrete model with interaction; against the window pressed as a whole)",
}
#: How the tables choose (Markdown, one line printed under them).
RULE = ("*Rule: in each cell every theory of the frame is read on each surface family whose "
        "reference reaches the fraction, at the scene's largest tolerance, ✔ where it holds on "
        "every family, ✘ where it fails on one or more, ? otherwise; shown is the theory that "
        "holds with the smallest largest |mean error|, or where none holds the one with the "
        "smallest, with the numbers of its worst family (mean error, 95 % interval over "
        "realizations or ± reference band for one surface) and on how many families it holds. "
        "Errors relative for area and conductance, in σ for separation (Persson: its mean gap ū "
        "against the BEM's), ln(h_eff/h_eff,BEM) for leakage; every number is in "
        "`headline.csv`.*")


def number_text(value: float, signed: bool = True) -> str:
    """A number as the summary and the headline tables print it: no decimals from 10 on, one
    from 1, two below (``+27``, ``-3.4``, ``+0.12``); ``inf`` where it is not finite."""
    if not math.isfinite(value):
        return "inf" if value > 0 else "-inf" if value < 0 else "nan"
    size = abs(value)
    digits = 0 if size >= 9.5 else 1 if size >= 0.995 else 2
    value = value if round(value, digits) != 0 else 0.0     # no "-0.00"
    return f"{value:{'+' if signed else ''}.{digits}f}"


def error_text(value: float, quantity: str, signed: bool = True, unit: bool = True) -> str:
    """An error in its quantity's measure: percent for relative errors, σ for separations,
    the bare log ratio for the leakage."""
    if quantity in RELATIVE_QUANTITIES:
        return number_text(100.0 * value, signed) + (" %" if unit else "")
    if quantity in ABSOLUTE_QUANTITIES:
        return number_text(value, signed) + (" σ" if unit else "")
    return number_text(value, signed)


def _largest_tolerance_rows(rows: list[dict]) -> list[dict]:
    """Each cell once: its rows at the largest tolerance of its scene."""
    largest: dict[str, float] = {}
    for row in rows:
        largest[row["scene"]] = max(largest.get(row["scene"], -math.inf), float(row["tolerance"]))
    return [row for row in rows if float(row["tolerance"]) == largest[row["scene"]]]


def _label(row: dict) -> str:
    """The theory's name, with what it is compared by where that is not the quantity
    (Persson's mean gap)."""
    label = model_label(row["model"])
    field = row.get("reference_field") or row["quantity"]
    return label if field == row["quantity"] else \
        f"{label} ({compared_label(row['quantity'], field)})"


def _value(value) -> str:
    try:
        return f"{float(value):g}"
    except (TypeError, ValueError):
        return str(value)


def family_text(row: dict) -> str:
    """A surface family as the tables name it: its scene and swept value ("validity-map,
    D = 2.2"; the side L only where it is not 1)."""
    parts = [f"{key} = {_value(row[key])}" for key in ("D", "H") if row.get(key, "") != ""]
    if row.get("L", "") != "" and float(row["L"]) != 1.0:
        parts.append(f"L = {_value(row['L'])}")
    return ", ".join([row["scene"]] + parts)


def _size(row: dict) -> float:
    size = abs(float(row["mean_error"]))
    return size if math.isfinite(size) else math.inf


@dataclass(frozen=True)
class Choice:
    """The theory a cell names: its worst family's row (the largest known ``|mean error|``; any
    row where none is known), its mark over the families (holds / fails / undecided), and on
    how many of its families it holds."""

    row: dict
    verdict: str
    held: int
    families: int

    @property
    def largest(self) -> float:
        """Its largest ``|mean error|`` over the families (inf where none is known)."""
        return _size(self.row)


def _judged(rows: list[dict]) -> Choice:
    """One theory's rows (one per surface family) read together (module docstring)."""
    held = sum(r["verdict"] == HOLDS for r in rows)
    verdict = HOLDS if held == len(rows) else \
        FAILS if any(r["verdict"] == FAILS for r in rows) else UNDECIDED
    known = [r for r in rows if math.isfinite(_size(r))]
    worst = max(known, key=_size) if known else rows[0]
    return Choice(worst, verdict, held, len(rows))


def choose(cells: list[dict]) -> Choice | None:
    """The theory to use among the headline rows of one frame, quantity and fraction (one row
    per theory and surface family): of those that hold on every family, the smallest largest
    ``|mean error|``; where none holds, the smallest largest ``|mean error|`` (``None``: no rows)."""
    by_model: dict[str, list[dict]] = defaultdict(list)
    for row in cells:
        by_model[row["model"]].append(row)
    if not by_model:
        return None
    judged = [_judged(rows) for rows in by_model.values()]
    return min(judged, key=lambda c: (c.verdict != HOLDS, c.largest, c.row["model"]))


def _cell_text(choice: Choice | None, quantity: str) -> str:
    if choice is None:
        return "not reached"
    row, mark = choice.row, SYMBOLS[choice.verdict]
    mean, low, high = (float(row[k]) for k in ("mean_error", "low", "high"))
    where = (f"holds on {choice.held} of {choice.families} families, worst "
             f"{family_text(row)}" if choice.families > 1 else family_text(row))
    if not math.isfinite(mean):
        return f"{_label(row)}: error not known {mark} ({where})"
    interval = (f" ({error_text(low, quantity, unit=False)}, {error_text(high, quantity, unit=False)})"
                if math.isfinite(low) and math.isfinite(high) else "")
    return f"**{_label(row)}** {error_text(mean, quantity)}{interval} {mark} ({where})"


def _at(row: dict, fraction: float) -> bool:
    return math.isclose(float(row["area_fraction"]), fraction, rel_tol=1e-9)


def decision_table(rows: list[dict], frame: str) -> list[str]:
    """One frame's decision table (Markdown lines, empty where the frame has no headline row):
    its title and columns, a row per quantity, a column per regime of :data:`COLUMNS` that
    some load path reaches. ``rows``: headline rows at each scene's largest tolerance."""
    rows = [r for r in rows if (r.get("frame") or "finite") == frame]
    quantities = [q for q in SUMMARY_QUANTITIES if any(r["quantity"] == q for r in rows)]
    columns = [(regime, f) for regime, f in COLUMNS if any(_at(r, f) for r in rows)]
    if not quantities or not columns:
        return []
    missing = [f"{regime} ({fraction_text(f)})" for regime, f in COLUMNS
               if (regime, f) not in columns]
    named = ", ".join(f"{regime} contact = {fraction_text(f)}" for regime, f in columns)
    caption = (f"**{FRAME_TITLES[frame]}.** The theory to use; columns: {named} of the nominal "
               f"area in contact (the {FRAME_LABELS[frame]} reference's contact-area fraction)"
               + (f"; {' and '.join(missing)} not reached by this run's load paths"
                  if missing else "") + ".\n")
    header = ["quantity"] + [f"{regime}: {fraction_text(f)}" for regime, f in columns]
    lines = [caption, "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for quantity in quantities:
        cells = [_cell_text(choose([r for r in rows if r["quantity"] == quantity and _at(r, f)]),
                            quantity) for _, f in columns]
        lines.append("| " + " | ".join([_NAMES[quantity]] + cells) + " |")
    return lines + [""]


def _claim_tally(rows: list[dict]) -> str:
    """A claim's verdicts over its surface families, counted; the ranges of those reproduced
    over a range."""
    counts: dict[str, int] = defaultdict(int)
    for row in rows:   # a claim the run could not test is said so, not "undecided"
        counts["not tested" if str(row.get("evidence", "")).startswith("not tested")
               else row["verdict"]] += 1
    ranged = [r for r in rows if r["verdict"] == RANGED and r.get("reproduced_from", "") != ""]

    def span(column: str) -> str:
        values = sorted(float(r[column]) for r in ranged)
        low, high = fraction_text(values[0]), fraction_text(values[-1])
        return low if low == high else f"{low.removesuffix(' %')}–{high}"

    parts = []
    for verdict, count in sorted(counts.items(), key=lambda item: (-item[1], item[0])):
        text = f"{verdict} on {count}" if len(rows) > 1 else verdict
        if verdict == RANGED and ranged:
            text += (f" (its lower end at {span('reproduced_from')}, its upper end at "
                     f"{span('reproduced_to')} contact)")
        parts.append(text)
    return ", ".join(parts) + (f" of {len(rows)}" if len(rows) > 1 else "")


def _findings_sentence(findings: list[dict]) -> str | None:
    """What the paper's claims came to: per claim, its verdicts over the surfaces checked."""
    by_key: dict[str, list[dict]] = defaultdict(list)
    for row in findings:
        if row["verdict"] != NEW:
            by_key[row["finding"]].append(row)
    if not by_key:
        return None
    parts = [f"({key}) {by_key[key][0]['claim']}: {_claim_tally(by_key[key])}"
             for key in sorted(by_key)]
    return "The paper's claims, per surface family checked: " + "; ".join(parts) + "."


def _precision_sentence(rows: list[dict]) -> str | None:
    cells = [r for r in rows if math.isfinite(float(r["half_width"]))]
    if not cells:
        return None
    widths = sorted(float(r["half_width"]) for r in cells)
    middle = len(widths) // 2
    median = widths[middle] if len(widths) % 2 else 0.5 * (widths[middle - 1] + widths[middle])
    worst = max(cells, key=lambda r: float(r["half_width"]))
    frame = FRAME_LABELS.get(worst.get("frame") or "", "")
    where = (f"{_label(worst)}{f' [{frame}]' if frame else ''}, {worst['quantity']} at "
             f"{fraction_text(float(worst['area_fraction']))} on {family_text(worst)}")
    return (f"The headline's intervals (relative, in σ, or ln for leakage) have a median "
            f"half-width of {number_text(median, False)} and at worst "
            f"{number_text(float(worst['half_width']), False)} ({where}).")


def summary_sentences(headline: list[dict], findings: list[dict]) -> list[str]:
    """The sentences under the tables, at most :data:`MAX_SENTENCES`: the paper's claims and
    the headline's precision.

    Parameters
    ----------
    headline, findings : list of dict
        The rows of ``headline.csv`` and ``findings.csv`` by column
        (:func:`validation.report.tables.records`).
    """
    rows = _largest_tolerance_rows(headline)
    sentences = [_findings_sentence(findings), _precision_sentence(rows) if rows else None]
    return [s for s in sentences if s][:MAX_SENTENCES]


def summary_lines(headline: list[dict], findings: list[dict]) -> list[str]:
    """The summary's Markdown lines after its heading (empty where the run has no headline):
    a decision table per frame (:func:`decision_table`), :data:`RULE`, then the sentences."""
    rows = _largest_tolerance_rows(headline)
    tables = [line for frame in FRAMES for line in decision_table(rows, frame)]
    if not tables:
        return []
    return (tables + [RULE + "\n"]
            + [f"- {sentence}" for sentence in summary_sentences(headline, findings)] + [""])
