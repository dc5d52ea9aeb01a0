"""The check's answer at a glance: every theory's verdicts across the user's pressures, one
strip of symbols per theory and field, and per field one sentence naming the theory that holds
over most of the range.

A strip reads left to right from the lowest to the highest pressure, one symbol per pressure
(✔ holds, ✘ fails, ? undecided: :func:`validation.judge.verdicts.verdict_strip`), at the tolerance of
the field's table (the scene's largest). The theory named for a field is the one that holds at
the most pressures (ties: the fewer failures, then the order of the tables); a field the
reference cannot judge at the scan's resolution gets no strip and no theory; a theory is said
to hold "everywhere" only when it holds at every pressure, and where the reference's contact
is closed (its real contact area at least :data:`CLOSED` of the nominal area) the glance says
at which pressures: a theory that holds there holds for a flat, closed interface, not for
rough contact.
"""

from __future__ import annotations

import numpy as np

from validation.check.units import format_pressure
from validation.common.labels import model_label
from validation.judge.verdicts import FAILS, HOLDS, true_runs, verdict_strip

__all__ = ["CLOSED", "closed_pressures", "glance_lines"]

#: Real contact-area fraction of the reference from which the interface counts as closed.
CLOSED = 0.99

_COLUMNS = {"area": "area A/A0", "separation": "separation d", "mean_gap": "mean gap ū",
            "stiffness": "stiffness K", "conductance": "stiffness K",
            "leakage": "leakage h_eff"}


def _pressure(table, k: int) -> str:
    return (format_pressure(table.pressure[k]) if table.pressure is not None
            else f"{table.load[k]:.3g} E*")


def _spans(table, held: np.ndarray) -> str:
    """The pressures where ``held`` is true, as ranges of consecutive points."""
    return ", ".join(_pressure(table, a) if a == b
                     else f"{_pressure(table, a)} to {_pressure(table, b)}"
                     for a, b in true_runs(held))


def _column(table, framed: bool) -> str:
    """A field's name, with its frame where the check answers in both."""
    from validation.common.models import FRAME_LABELS

    return _COLUMNS[table.field] + (f" ({FRAME_LABELS[table.frame]})" if framed else "")


def closed_pressures(tables) -> np.ndarray:
    """Per pressure (in the tables' order), whether the reference's real contact-area fraction
    is at least :data:`CLOSED` (the first area table's reference; none closed without one)."""
    area = next((t for t in tables if t.field == "area"), None)
    if area is None:
        return np.zeros(tables[0].load.size if tables else 0, dtype=bool)
    return np.asarray(area.reference) >= CLOSED


def _sentence(table, framed: bool = False, unjudged: str | None = None,
              closed: np.ndarray | None = None) -> str:
    column = _column(table, framed)
    name = column[0].upper() + column[1:]
    if unjudged:
        return f"{name}: {unjudged}."
    if not table.verdicts:
        return f"{name}: no theory is compared."
    order = np.argsort(table.load, kind="stable")
    counts = {m: (int(np.sum(np.asarray(v)[order] == HOLDS)),
                  int(np.sum(np.asarray(v)[order] == FAILS))) for m, v in table.verdicts.items()}
    best = min(counts, key=lambda m: (-counts[m][0], counts[m][1]))
    held, failed = counts[best]
    total = table.load.size
    if held == 0:
        return (f"{name}: no theory holds at any pressure"
                + ("" if failed == total else " (some are undecided)") + ".")
    where = _spans(table, np.asarray(table.verdicts[best])[order] == HOLDS)
    closed_held = (np.zeros(total, dtype=bool) if closed is None
                   else closed[order] & (np.asarray(table.verdicts[best])[order] == HOLDS))
    at_closed = ("" if not closed_held.any() else
                 f", {int(closed_held.sum())} of them in full contact ({_spans(table, closed_held)})")
    if held == total:
        return (f"{name}: {model_label(best)} holds everywhere." if not at_closed else
                f"{name}: {model_label(best)} holds at every pressure{at_closed}.")
    return f"{name}: {model_label(best)} holds at {held} of {total} pressures ({where}){at_closed}."


def glance_lines(tables, unjudged: dict[str, str] | None = None) -> list[str]:
    """The check's first table: each theory's verdict strip per field, and one sentence per
    field (module docstring). ``tables`` are :class:`validation.check.physical.PhysicalTable` s
    of one surface (same pressures); ``unjudged`` maps the fields the reference cannot judge
    at the scan's resolution to what to do (:func:`validation.check.resolution.unjudged`):
    their sentence says so and names no theory."""
    unjudged = unjudged or {}
    if not tables:
        return []
    first = tables[0]
    order = np.argsort(first.load, kind="stable")
    low, high = _pressure(first, int(order[0])), _pressure(first, int(order[-1]))
    models = list(dict.fromkeys(m for t in tables for m in t.verdicts))
    framed = len({t.frame for t in tables}) > 1
    header = ["theory"] + [f"{_column(t, framed)} (±{t.tolerance_text or t.tolerance})"
                           for t in tables]
    lines = [f"**At a glance**: each theory at the {first.load.size} pressures from {low} to "
             f"{high}, left to right (✔ holds, ✘ fails, ? undecided: the reference's band "
             f"straddles the tolerance):\n",
             "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for model in models:
        cells = ["not judged" if t.field in unjudged else
                 verdict_strip(np.asarray(t.verdicts[model])[order]) if model in t.verdicts
                 else "–" for t in tables]
        lines.append(f"| {model_label(model)} | " + " | ".join(cells) + " |")
    lines.append("")
    closed = closed_pressures(tables)
    if closed.any():
        lines += [f"**Full contact** at {_spans(first, closed[order])}: the reference's real "
                  f"contact area is at least {100 * CLOSED:g} % of the nominal area there, the "
                  f"interface is closed; a theory that holds there holds for a flat, closed "
                  f"interface, not for rough contact (if you did not mean to press this hard, check the unit of E*)."
                  "\n"]
    lines += [f"- {_sentence(t, framed, unjudged.get(t.field), closed)}" for t in tables]
    return lines + [""]
