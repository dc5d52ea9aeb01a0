"""Two reports' headline numbers side by side: what a change of the surfaces or the reference
moved. For every scene, model, frame, quantity and area fraction both reports hold, the mean
error and its 95 % interval in each, and the largest and median absolute change per scene and
frame (in the headline's units: fractions, σ, or ln h_eff).

    python benchmarks/compare_headlines.py OLD_FOLDER NEW_FOLDER [--frame finite] [--rows]

A published report's earlier state: ``git show <commit>:docs/results/headline.csv > old.csv``
and pass the CSV's path instead of a folder.
"""

from __future__ import annotations

import argparse
import csv
import pathlib
from collections import defaultdict

import numpy as np


def headline(path: str) -> dict:
    """(scene, D, H, L, model, frame, quantity, area_fraction) -> (mean, low, high), at the
    largest tolerance."""
    path = pathlib.Path(path)
    path = path / "headline.csv" if path.is_dir() else path
    with path.open(newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    tolerance = max(float(r["tolerance"]) for r in rows)
    out = {}
    for r in rows:
        if float(r["tolerance"]) == tolerance and r["mean_error"] not in ("", "nan"):
            key = (r["scene"], r["D"], r["H"], r["L"], r["model"], r["frame"], r["quantity"],
                   r["area_fraction"])
            out[key] = tuple(float(r[k]) if r[k] not in ("", "nan") else np.nan
                             for k in ("mean_error", "low", "high"))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--frame", default=None, help="only this frame (interface, finite)")
    parser.add_argument("--rows", action="store_true", help="print every cell, not only the "
                                                            "summary")
    args = parser.parse_args(argv)
    old, new = headline(args.old), headline(args.new)
    common = sorted(k for k in old.keys() & new.keys() if args.frame in (None, k[5]))
    changes = defaultdict(list)
    if args.rows:
        print("| scene | D | H | L | model | frame | quantity | fraction | old | new |\n"
              "|---|---|---|---|---|---|---|---|---|---|")
    for key in common:
        (a, a_low, a_high), (b, b_low, b_high) = old[key], new[key]
        changes[key[0], key[5]].append(abs(b - a))
        if args.rows:
            print(f"| {' | '.join(key)} | {a:+.3f} ({a_low:+.3f}, {a_high:+.3f}) | "
                  f"{b:+.3f} ({b_low:+.3f}, {b_high:+.3f}) |")
    print(f"\ncells in both: {len(common)}; |new - old| mean error per scene and frame:")
    print("| scene | frame | cells | median change | largest change |\n|---|---|---|---|---|")
    for (scene, frame), values in sorted(changes.items()):
        print(f"| {scene} | {frame} | {len(values)} | {np.median(values):.3f} | "
              f"{np.max(values):.3f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
