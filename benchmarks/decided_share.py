"""How decisive a report is: per scene and frame, the share of verdicts on the mean that are
undecided at one tolerance, and why (the reference band, too few realizations, ...).

Reads a report folder's ``verdicts.csv`` (every model, quantity and load point, on the mean over
realizations) and prints one row per scene and frame: the cells, the undecided share and the
share undecided for each reason, all in % of the cells; and the median half-width of the
headline's intervals per scene (``headline.csv``).

    python benchmarks/decided_share.py [docs/results] [--tolerance 0.2]
"""

from __future__ import annotations

import argparse
import csv
import pathlib
from collections import Counter, defaultdict

import numpy as np


def read(path: pathlib.Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def decided_table(rows: list[dict], tolerance: float) -> dict:
    """Per (scene, frame): cells, undecided count and a Counter of the reasons."""
    table = defaultdict(lambda: [0, 0, Counter()])
    for row in rows:
        if not row["tolerance"] or abs(float(row["tolerance"]) - tolerance) > 1e-9:
            continue
        cell = table[(row["scene"], row["frame"])]
        cell[0] += 1
        if row["verdict"] == "undecided":
            cell[1] += 1
            cell[2][row["undecided_reason"] or "unstated"] += 1
    return table


def half_widths(rows: list[dict], tolerance: float) -> dict[tuple[str, str], float]:
    """Median half-width of the headline's 95 % intervals per scene and frame, over every
    quantity in its own measure (relative, σ, ln h_eff: the tolerance's), as the report's
    precision section gives it."""
    widths = defaultdict(list)
    for row in rows:
        if row["half_width"] not in ("", "nan") and abs(float(row["tolerance"]) - tolerance) < 1e-9:
            widths[row["scene"], row["frame"]].append(float(row["half_width"]))
    return {key: float(np.median(w)) for key, w in widths.items()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", nargs="?", default="docs/results")
    parser.add_argument("--tolerance", type=float, default=0.2)
    args = parser.parse_args(argv)
    folder = pathlib.Path(args.folder)
    table = decided_table(read(folder / "verdicts.csv"), args.tolerance)
    widths = half_widths(read(folder / "headline.csv"), args.tolerance) if (folder / "headline.csv").is_file() \
        else {}
    print(f"verdicts on the mean at tolerance {args.tolerance:g}, {folder}")
    print("| scene | frame | cells | undecided | of which: reasons (% of cells) | headline "
          "median half-width |\n|---|---|---|---|---|---|")
    for (scene, frame), (cells, undecided, reasons) in sorted(table.items()):
        why = ", ".join(f"{reason} {100 * n / cells:.0f} %" for reason, n in reasons.most_common())
        print(f"| {scene} | {frame} | {cells} | {100 * undecided / cells:.0f} % | {why} | "
              f"{widths.get((scene, frame), float('nan')):.3f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
