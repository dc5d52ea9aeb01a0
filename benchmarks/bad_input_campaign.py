"""Bad-input campaign over every public entry point: counts per outcome class.

    python benchmarks/bad_input_campaign.py [--details]

Outcome classes and the table of entry points: :mod:`validation.campaigns.bad_input`. A clean run has
only ``clear error`` and ``plausible result``; the script exits 1 otherwise.
"""

from __future__ import annotations

import collections
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from validation.campaigns.bad_input import GOOD, OUTCOMES, run_campaign  # noqa: E402


def main(argv: list[str]) -> int:
    start = time.perf_counter()
    rows = run_campaign()
    counts = collections.Counter(outcome for *_, outcome, _ in rows)
    entries = len({row[0] for row in rows})
    print(f"{len(rows)} cases on {entries} entry points in {time.perf_counter() - start:.1f} s")
    for outcome in OUTCOMES:
        print(f"  {outcome:22s} {counts.get(outcome, 0):5d}")
    bad = [row for row in rows if row[3] not in GOOD]
    if "--details" in argv:
        for entry, parameter, label, outcome, detail in bad:
            print(f"{outcome:22s} {entry}({parameter}={label}): {detail[:150]}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
