"""The report's summary: at most ten sentences, each generated from the rows of this run's
tables (``headline.csv`` and ``findings.csv``, as :func:`validation.report.tables.records`
gives them), none written by hand.

Per quantity (area, separation, conductance, leakage) two sentences: which theory to use at
light, intermediate and heavy contact (:data:`validation.judge.headline.REGIMES`), and how
wrong the others are; then what the paper's claims came to, and how precise the headline is.

**The theory to use** for a quantity in a regime is the one that beats the most others head to
head: on the headline cells both are compared at (surface families and fractions of the run
that reach the regime), its largest ``|mean error|`` is the smaller (ties: the smaller largest
``|mean error|`` over all its cells, then the one that holds at more of them). So a model that
a scene leaves out is neither favoured nor penalised. It is called the one to *use* only where
it holds at every cell it is compared at in the regime; otherwise it is the *closest* (with
the share of its cells that hold), and where it fails at every cell, "none holds". Its
sentence gives the range of its mean errors there and the range its intervals span (the 95 % intervals over realizations, or ± the
reference band for one surface). **How wrong the others are**: the largest mean error of each
other model in the regime, from the smallest of them to the largest (marked where a model is
not compared on every surface family). Every cell is read at its scene's largest tolerance.
"""

from __future__ import annotations

import math
from collections import defaultdict

from validation.judge.errors import ABSOLUTE_QUANTITIES, RELATIVE_QUANTITIES
from validation.judge.findings import NEW
from validation.judge.headline import REGIMES
from validation.judge.verdicts import FAILS, HOLDS
from validation.common.labels import compared_label, model_label
from validation.common.models import FRAME_LABELS

__all__ = ["MAX_SENTENCES", "SUMMARY_QUANTITIES", "RULE", "error_text", "number_text",
           "summary_sentences"]

#: The summary's length limit.
MAX_SENTENCES = 10
#: Quantities the summary speaks of, in its order.
SUMMARY_QUANTITIES = ("area", "separation", "conductance", "leakage")
#: How the summary chooses (Markdown, printed under it).
RULE = ("*Light, intermediate and heavy contact: the contact-area fractions 0.1–1 %, 10 % "
        "and 30 % of the headline, each of the reference of the model's frame ([interface]: "
        "the unbounded interface, periodic BEM; [finite contact]: the window, or a given "
        "nominal contact, pressed as a whole). Each model is judged in its own frame. The "
        "theory to use is the one that beats the most others "
        "head to head: on the headline cells both are compared at, its largest |mean error| "
        "is the smaller; it is to *use* where it holds at every cell, and only the *closest* "
        "where it does not (none holds: it fails at every cell). Errors relative for area and "
        "conductance, in σ for separation (Persson: its mean gap ū against the BEM's), "
        "ln(h_eff/h_eff,BEM) for leakage; every "
        "number is in `headline.csv` and `findings.csv`.*")
_NAMES = {"area": "Area", "separation": "Separation", "conductance": "Conductance",
          "leakage": "Leakage"}
_PHRASES = {"light": "light contact", "intermediate": "intermediate contact",
            "heavy": "heavy contact"}


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


def _fraction_text(fractions) -> str:
    values = sorted({100.0 * float(f) for f in fractions})
    texts = [f"{v:g}" for v in values]
    return f"{texts[0]}–{texts[-1]} %" if len(texts) > 1 else f"{texts[0]} %"


def _largest_tolerance_rows(rows: list[dict]) -> list[dict]:
    """Each cell once: its rows at the largest tolerance of its scene."""
    largest: dict[str, float] = {}
    for row in rows:
        largest[row["scene"]] = max(largest.get(row["scene"], -math.inf), float(row["tolerance"]))
    return [row for row in rows if float(row["tolerance"]) == largest[row["scene"]]]


def _label(row: dict) -> str:
    label = model_label(row["model"])
    field = row.get("reference_field") or row["quantity"]
    label = label if field == row["quantity"] else \
        f"{label} ({compared_label(row['quantity'], field)})"
    frame = row.get("frame") or ""
    return f"{label} [{FRAME_LABELS[frame]}]" if frame in FRAME_LABELS else label


def _slot(row: dict) -> tuple:
    return (row["scene"], row["D"], row["H"], row["L"], float(row["area_fraction"]))


def _largest(rows: list[dict], slots: set | None = None) -> float:
    """The largest |mean error| of ``rows`` (at ``slots`` only, when given); inf where none is
    finite."""
    sizes = [abs(float(r["mean_error"])) for r in rows if slots is None or _slot(r) in slots]
    sizes = [size for size in sizes if math.isfinite(size)]
    return max(sizes) if sizes else math.inf


def _choose(cells: list[dict]) -> tuple[str, dict[str, list[dict]], set[str]]:
    """The model to use (module docstring: the most wins head to head), every model's cells,
    and the models compared at every slot of ``cells``."""
    by_model: dict[str, list[dict]] = defaultdict(list)
    for row in cells:
        by_model[row["model"]].append(row)
    slots = {model: {_slot(r) for r in rows} for model, rows in by_model.items()}
    everywhere = {m for m in by_model if slots[m] == {_slot(r) for r in cells}}

    def wins(model: str) -> int:
        count = 0
        for other in by_model:
            common = slots[model] & slots[other]
            if other != model and common and \
                    _largest(by_model[model], common) < _largest(by_model[other], common):
                count += 1
        return count

    best = min(by_model, key=lambda m: (-wins(m), _largest(by_model[m]),
                                        -sum(r["verdict"] == HOLDS for r in by_model[m]), m))
    return best, by_model, everywhere


def _worst(rows: list[dict]) -> dict:
    """The row of the largest finite ``|mean error|`` (the first row where none is finite)."""
    finite = [r for r in rows if math.isfinite(float(r["mean_error"]))]
    return max(finite, key=lambda r: abs(float(r["mean_error"]))) if finite else rows[0]


def _use_part(regime: str, fractions, quantity: str, rows: list[dict]) -> str:
    """The chosen model's part of the sentence: "use" it only where it holds at every cell it
    is compared at; otherwise it is only the closest, and the sentence says how often it holds."""
    held = sum(r["verdict"] == HOLDS for r in rows)
    failed = sum(r["verdict"] == FAILS for r in rows)
    verb = ("use" if held == len(rows) else "none holds, closest" if failed == len(rows)
            else "closest")
    where = f"at {_PHRASES[regime]} ({_fraction_text(fractions)}) {verb}"
    means = [float(r["mean_error"]) for r in rows if math.isfinite(float(r["mean_error"]))]
    if not means:
        return f"{where} {_label(rows[0])}, whose error is not known there"
    low, high = error_text(min(means), quantity), error_text(max(means), quantity)
    text = f"{where} {_label(rows[0])} (mean error {low}" + (f" to {high}" if high != low else "")
    lows = [float(r["low"]) for r in rows]
    highs = [float(r["high"]) for r in rows]
    if all(map(math.isfinite, lows + highs)):
        text += (f", intervals within {error_text(min(lows), quantity)} to "
                 f"{error_text(max(highs), quantity)}")
    if verb == "closest":
        text += f"; holds at {held} of {len(rows)} cells"
    return text + ")"


def _other_text(row: dict, quantity: str, everywhere: set[str]) -> str:
    where = "" if row["model"] in everywhere else ", not compared everywhere"
    return f"{error_text(float(row['mean_error']), quantity)} ({_label(row)}{where})"


def _quantity_sentences(quantity: str, rows: list[dict]) -> list[str]:
    name = _NAMES[quantity]
    cells = [r for r in rows if r["quantity"] == quantity]
    if not cells:
        return [f"{name}: not compared in this run."]
    uses, others, missing = [], [], []
    for regime, fractions in REGIMES:
        held = [r for r in cells if r["regime"] == regime]
        if not held:
            missing.append(f"{_PHRASES[regime]} ({_fraction_text(fractions)})")
            continue
        best, by_model, everywhere = _choose(held)
        reached = sorted({float(r["area_fraction"]) for r in held})
        uses.append(_use_part(regime, reached, quantity, by_model[best]))
        rest = sorted((w for w in (_worst(by_model[m]) for m in by_model if m != best)
                       if math.isfinite(float(w["mean_error"]))),
                      key=lambda r: abs(float(r["mean_error"])))
        if rest:
            span = _other_text(rest[0], quantity, everywhere)
            if len(rest) > 1:
                span += " to " + _other_text(rest[-1], quantity, everywhere)
            others.append(f"at {_PHRASES[regime]} {span}")
    use = f"{name}: " + "; ".join(uses)
    if missing:
        use += "; " + " and ".join(missing) + " not reached by this run's load paths"
    sentences = [use + "."]
    if others:
        sentences.append(f"{name}, the others' largest mean errors: " + "; ".join(others) + ".")
    return sentences


def _findings_sentence(findings: list[dict]) -> str | None:
    """What the paper's claims came to: per claim, its verdicts over the surfaces checked."""
    by_key: dict[str, list[dict]] = defaultdict(list)
    for row in findings:
        if row["verdict"] != NEW:
            by_key[row["finding"]].append(row)
    if not by_key:
        return None
    parts = []
    for key in sorted(by_key):
        rows = by_key[key]
        counts: dict[str, int] = defaultdict(int)
        for row in rows:   # a claim the run could not test is said so, not "undecided"
            counts["not tested" if str(row.get("evidence", "")).startswith("not tested")
                   else row["verdict"]] += 1
        if len(rows) == 1:   # one surface family (one scan): the verdict alone
            parts.append(f"({key}) {rows[0]['claim']}: {next(iter(counts))}")
            continue
        tally = ", ".join(f"{verdict} on {count}" for verdict, count in
                          sorted(counts.items(), key=lambda item: (-item[1], item[0])))
        parts.append(f"({key}) {rows[0]['claim']}: {tally} of {len(rows)}")
    return "The paper's claims, per surface family checked: " + "; ".join(parts) + "."


def _precision_sentence(rows: list[dict]) -> str | None:
    cells = [r for r in rows if math.isfinite(float(r["half_width"]))]
    if not cells:
        return None
    widths = sorted(float(r["half_width"]) for r in cells)
    middle = len(widths) // 2
    median = widths[middle] if len(widths) % 2 else 0.5 * (widths[middle - 1] + widths[middle])
    worst = max(cells, key=lambda r: float(r["half_width"]))
    member = ", ".join(f"{k} = {worst[k]}" for k in ("D", "H") if worst[k] != "")
    where = (f"{_label(worst)}, {worst['quantity']} at {_fraction_text([worst['area_fraction']])}"
             f" on {worst['scene']}" + (f", {member}" if member else ""))
    return (f"The headline's intervals (relative, in σ, or ln for leakage) have a median "
            f"half-width of {number_text(median, False)} and at worst "
            f"{number_text(float(worst['half_width']), False)} ({where}).")


def summary_sentences(headline: list[dict], findings: list[dict]) -> list[str]:
    """The summary, at most :data:`MAX_SENTENCES` sentences (module docstring).

    Parameters
    ----------
    headline, findings : list of dict
        The rows of ``headline.csv`` and ``findings.csv`` by column
        (:func:`validation.report.tables.records`).
    """
    rows = _largest_tolerance_rows(headline)
    if not rows:
        return []
    sentences = [s for q in SUMMARY_QUANTITIES for s in _quantity_sentences(q, rows)]
    sentences += [s for s in (_findings_sentence(findings), _precision_sentence(rows)) if s]
    return sentences[:MAX_SENTENCES]
