"""The interface reference's own error: the mirror method against the periodic solution.

On periodic self-affine surfaces (``validation.self_affine_surface`` without a window: rms slope
0.1, rolloff L/4 or ``--rolloff``, L = 1), and with ``--wm`` on periodic WM surfaces (eq. T52), the exact
interface is the periodic BEM of the surface itself. The
mirror method (:class:`bem.InterfaceModel` with ``extension="mirror"``, what a measured scan or
any non-periodic window gets) is solved on the same map at the same mean pressures and compared
with the periodic solution: area (relative), mean gap (in units of the rms height; d = u-bar)
and stiffness per unit area (relative). With ``--window`` the finite window
(:class:`bem.BoundaryElementModel`, ``periodic=False``) is compared as well.

The calibration of the method error (docs/theory.md, eq. T50): the points are binned by the
periodic solution's contact-area fraction (:data:`BIN_EDGES`); per quantity and bin

* the **bias**: the mean over surfaces of each surface's mean signed error in the bin, and its
  95 % confidence bound ``|mean| + t_{0.975, n-1} s / sqrt(n)`` (what a verdict on the mean over
  realizations must allow: the scatter is in each realization's error already);
* the **bound**: the largest |error| of one surface at one point (the empirical maximum), and
  the bound stated, the larger of 1.25 times it and the one-sided 95 %/95 % normal tolerance
  limit ``mean + k s`` of the surfaces' largest |error| in the bin (what one surface carries).

Prints both tables per H and pooled, and their envelope, the tables of ``bem.interface``
(``MIRROR_BIAS``, ``MIRROR_BOUND``): per bin the largest over the H and the pooled ensemble (a
scene's realizations share one H, and the bias depends on it). ``--save`` keeps the errors,
``--load`` prints the tables from them without solving. ``--cover`` checks the tables instead
on surfaces they were not measured on (other seeds): the share of one surface's points within
the bound, and the mean signed error per bin against the bias.

    python benchmarks/bench_interface.py [--n 256] [--seeds 24] [--hurst 0.3,0.5,0.8]
        [--rolloff 0.25] [--wm 2.05,2.95] [--window] [--save errors.npz] [--load errors.npz]
        [--first-seed 0] [--cover]
"""

from __future__ import annotations

import argparse
import time
from functools import partial

import numpy as np
from scipy import stats

from bem import BoundaryElementModel, InterfaceModel
from bem.interface import mirror_error
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.wm import wm_surface

PRESSURES = np.geomspace(1.5e-4, 2.5e-2, 14)   # mean pressure / E*: about 0.25-32 % contact
QUANTITIES = ("area", "stiffness")
NAMES = ("area", "mean_gap", "stiffness")
#: Contact-area fraction bins of the calibration (the periodic solution's fraction).
BIN_EDGES = np.array([0.003, 0.01, 0.03, 0.10, 0.30])
#: Inflation of the largest one-surface |error| measured, and the tolerance coverage.
INFLATION, COVERAGE, CONFIDENCE = 1.25, 0.95, 0.95


def errors(curve, exact, rms_height: float) -> np.ndarray:
    """Rows area, mean gap, stiffness: the signed errors of ``curve`` against ``exact``."""
    return np.vstack([curve.area_fraction / exact.area_fraction - 1.0,
                      (np.asarray(curve.extras["mean_gap"]) - exact.extras["mean_gap"]) / rms_height,
                      (curve.stiffness / curve.nominal_area) / (exact.stiffness / exact.nominal_area)
                      - 1.0])


def tolerance_factor(n: int, coverage: float = COVERAGE, confidence: float = CONFIDENCE) -> float:
    """One-sided normal tolerance factor k: ``mean + k s`` of n samples exceeds the
    ``coverage`` quantile with probability ``confidence`` (noncentral t)."""
    z = stats.norm.ppf(coverage)
    return float(stats.nct.ppf(confidence, n - 1, z * np.sqrt(n)) / np.sqrt(n))


def bin_statistics(records: list[tuple[np.ndarray, np.ndarray]]) -> dict:
    """Per bin and quantity: bias (mean, its 95 % confidence bound), bound (max, stated).

    ``records``: per surface (periodic area fractions, errors of shape (3, points)).
    """
    table = {}
    for b in range(len(BIN_EDGES) - 1):
        means, largest = [], []
        for fraction, err in records:
            inside = (fraction >= BIN_EDGES[b]) & (fraction < BIN_EDGES[b + 1])
            if inside.any():
                means.append(err[:, inside].mean(axis=1))
                largest.append(np.abs(err[:, inside]).max(axis=1))
        means, largest = np.array(means), np.array(largest)
        n = len(means)
        if n < 3:
            continue
        mean, spread = means.mean(axis=0), means.std(axis=0, ddof=1)
        bias = np.abs(mean) + stats.t.ppf(0.975, n - 1) * spread / np.sqrt(n)
        tolerance = largest.mean(axis=0) + tolerance_factor(n) * largest.std(axis=0, ddof=1)
        bound = np.maximum(INFLATION * largest.max(axis=0), tolerance)
        table[b] = dict(n=n, mean=mean, bias=bias, max=largest.max(axis=0),
                        tolerance=tolerance, bound=bound)
    return table


def print_tables(label: str, records) -> None:
    """Print the bias and bound tables of ``records`` (see :func:`bin_statistics`)."""
    table = bin_statistics(records)
    print(f"\n{label}: {len(records)} surfaces")
    print("  bin [%]        n  | mean signed error (area, gap/h_rms, stiffness) | 95 % bias bound"
          " | largest |error| | 95/95 tolerance | bound")
    for b, row in table.items():
        edges = f"{100 * BIN_EDGES[b]:g}-{100 * BIN_EDGES[b + 1]:g}"
        cells = [" ".join(f"{v:+.4f}" for v in row["mean"])]
        cells += [" ".join(f"{v:.4f}" for v in row[key])
                  for key in ("bias", "max", "tolerance", "bound")]
        print(f"  {edges:12s} {row['n']:3d}  | " + " | ".join(cells), flush=True)


def print_envelope(tables: list[dict]) -> None:
    """The tables of ``bem.interface``: per bin, the largest bias bound and bound over the
    tables given (each H's and the pooled one). A scene's realizations share one H, and the
    bias depends on it (the stiffness's changes sign with H): the pooled mean would hide it."""
    print("\nenvelope over H and pooled (bem.interface.MIRROR_BIAS, MIRROR_BOUND): area, "
          "mean gap/h_rms, stiffness")
    for b in tables[0]:
        bias = np.max([t[b]["bias"] for t in tables if b in t], axis=0)
        bound = np.max([t[b]["bound"] for t in tables if b in t], axis=0)
        centre = 100 * np.sqrt(BIN_EDGES[b] * BIN_EDGES[b + 1])
        print(f"  {centre:6.3g} %  bias " + " ".join(f"{v:.4f}" for v in bias)
              + " | bound " + " ".join(f"{v:.4f}" for v in bound), flush=True)


def print_coverage(label: str, records) -> None:
    """How the tables of ``bem.interface`` hold on ``records`` (surfaces they were not measured
    on): per quantity and bin, the share of one surface's points whose |error| is within the
    bound at the point's fraction, and whether the mean signed error over the surfaces lies
    within the bias (its 95 % interval reaching the bias)."""
    print(f"\n{label}: {len(records)} surfaces against bem.interface's tables")
    for q, name in enumerate(NAMES):
        inside = total = 0
        for fraction, err in records:
            points = (fraction >= BIN_EDGES[0]) & (fraction < BIN_EDGES[-1])
            bound = mirror_error(name, np.clip(fraction[points], 0.0, 1.0), "bound")
            inside += int(np.count_nonzero(np.abs(err[q, points]) <= bound))
            total += int(np.count_nonzero(points))
        means = []
        for b in range(len(BIN_EDGES) - 1):
            values = [err[q, (f >= BIN_EDGES[b]) & (f < BIN_EDGES[b + 1])].mean()
                      for f, err in records
                      if np.any((f >= BIN_EDGES[b]) & (f < BIN_EDGES[b + 1]))]
            centre = np.sqrt(BIN_EDGES[b] * BIN_EDGES[b + 1])
            bias = float(mirror_error(name, centre, "bias"))
            # the sample mean's own 95 % interval: the table is contradicted only where the
            # whole interval lies beyond the bias
            half = (stats.t.ppf(0.975, len(values) - 1) * np.std(values, ddof=1)
                    / np.sqrt(len(values))) if len(values) > 1 else np.inf
            means.append(f"{np.mean(values):+.4f} +- {half:.4f} (bias {bias:.4f}"
                         f"{', BEYOND' if abs(np.mean(values)) - half > bias else ''})")
        print(f"  {name:9s} within the bound: {inside} of {total} points "
              f"({100 * inside / max(total, 1):.1f} %); mean signed error per bin: "
              + ", ".join(means), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=256)
    parser.add_argument("--seeds", type=int, default=24)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--hurst", default="0.3,0.5,0.8",
                        help="Hurst exponents of periodic self-affine surfaces ('' for none)")
    parser.add_argument("--rolloff", type=float, default=0.25,
                        help="rolloff wavelength of the self-affine surfaces over L (1: none, "
                             "the longest waves span the map as in a scan that does not show "
                             "its rolloff)")
    parser.add_argument("--wm", default="",
                        help="fractal dimensions D of periodic WM surfaces (eq. T52), e.g. "
                             "2.05,2.5,2.95: the second family of the tables' envelope")
    parser.add_argument("--tol", type=float, default=1e-8)
    parser.add_argument("--window", action="store_true", help="compare the finite window too")
    parser.add_argument("--save", default="", help="write the mirror's errors to this .npz")
    parser.add_argument("--load", default="", help="tables from the errors saved in this .npz")
    parser.add_argument("--cover", action="store_true",
                        help="instead of new tables, how bem.interface's tables hold on these "
                             "surfaces (use seeds the tables were not measured on)")
    args = parser.parse_args()
    n, spacing = args.n, 1.0 / args.n
    print(f"grid {n}^2, pressures {PRESSURES[0]:.1e}-{PRESSURES[-1]:.1e} E*, tol {args.tol:g}; "
          f"bins {', '.join(f'{100 * e:g}' for e in BIN_EDGES)} % (periodic solution's "
          "fraction); per surface: largest |error| in 0.3-30 %: area (rel), mean gap (h_rms), "
          "stiffness (rel)")
    pooled, saved, tables = [], {}, []
    if args.load:
        with np.load(args.load) as data:
            for hurst, stack in data.items():
                records = [(row[0], row[1:]) for row in stack]
                print_tables(f"H {hurst}", records)
                tables.append(bin_statistics(records))
                pooled += records
        print_tables("pooled", pooled)
        print_envelope(tables + [bin_statistics(pooled)])
        return
    families = [(f"H {float(h):g}", partial(self_affine_surface, hurst=float(h),
                                            rolloff=args.rolloff))
                for h in args.hurst.split(",") if h.strip()]
    families += [(f"WM D {float(d):g}", partial(wm_surface, D=float(d), periodic=True))
                 for d in args.wm.split(",") if d.strip()]
    for label, surface in families:
        records = []
        seconds = {"periodic": 0.0, "mirror": 0.0, "window": 0.0}
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            z = surface(n, rms_slope=0.1, seed=seed)
            loads = PRESSURES * n * n * spacing**2
            models = [("periodic", InterfaceModel(z, spacing, extension="periodic", tol=args.tol)),
                      ("mirror", InterfaceModel(z, spacing, extension="mirror", tol=args.tol))]
            if args.window:
                models.append(("window", BoundaryElementModel(z, spacing, periodic=False,
                                                              tol=args.tol)))
            solved = {}
            for name, model in models:
                start = time.perf_counter()
                solved[name] = model.at_load(loads, quantities=QUANTITIES)
                seconds[name] += time.perf_counter() - start
            exact = solved["periodic"]
            fraction = np.asarray(exact.area_fraction)
            inside = (fraction >= BIN_EDGES[0]) & (fraction < BIN_EDGES[-1])
            row = []
            for name in solved.keys() - {"periodic"}:
                err = errors(solved[name], exact, float(np.std(z)))
                if name == "mirror":
                    records.append((fraction, err))
                largest = np.max(np.abs(err[:, inside]), axis=1)
                row.append(f"{name} " + " ".join(f"{v:.3f}" for v in largest))
            print(f"{label} seed {seed}: " + " | ".join(sorted(row)), flush=True)
        print(f"{label} time per seed: " + ", ".join(
            f"{k} {v / args.seeds:.1f} s" for k, v in seconds.items() if v), flush=True)
        if args.cover:
            print_coverage(label, records)
            pooled += records
            continue
        print_tables(label, records)
        tables.append(bin_statistics(records))
        pooled += records
        if args.save:
            saved[label.removeprefix("H ")] = np.stack([np.vstack([f, e]) for f, e in records])
            np.savez(args.save, **saved)
    if args.cover:
        print_coverage("pooled", pooled)
        return
    print_tables("pooled", pooled)
    print_envelope(tables + [bin_statistics(pooled)])


if __name__ == "__main__":
    main()
