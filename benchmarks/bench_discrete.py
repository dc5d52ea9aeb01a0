"""Run time of summit detection and of the discrete asperity model with interaction.

    python benchmarks/bench_discrete.py [--repeats 5] [--quick]

Prints, for the paper's WM surfaces (D = 2.05 and 2.95, n = 512, rms slope 0.1, seed 0,
spacing 1/512, L = 1, E* = 1) and for 10^4 random asperities (on a lattice: exact FFT sums;
at arbitrary positions: blocked direct sums):

* the number of summits (and of rejected non-convex maxima);
* the time of one load step solved cold (at_load of the heaviest load alone) and of a 30-step
  load path, with interaction, stiffness included: W / (E* L^2) = geomspace(1e-6, 1e-3, 30),
  and for the random lattice set also geomspace(1e-5, 1e-2, 30) (thousands of contacts; at
  arbitrary positions that many contacts are slow: see asperity.discrete.interaction);
* contacts, area fraction and Newton iterations at the end of the path;
* the largest relative difference between the lattice FFT and the direct interaction sum.

Times are medians of ``--repeats`` runs (wall clock). The machine may be shared: numbers are
then pessimistic.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
import warnings

import numpy as np
import scipy

import asperity
from asperity import DiscreteAsperityModel, PointForceInteraction, Summits, ValidityWarning
from validation import wm_surface


def median_time(function, repeats):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def random_summits(n, lattice, seed=0, sigma=1e-3):
    """n summits on a unit square, Gaussian heights (std sigma), radii around the typical GW
    value eta R sigma = 0.05 (one decade of spread), on a lattice of 4 n cells or anywhere."""
    rng = np.random.default_rng(seed)
    cells = int(np.ceil(np.sqrt(4 * n)))
    index = rng.choice(cells * cells, n, replace=False)
    row, column = np.divmod(index, cells)
    spacing = 1.0 / cells
    radius = 0.05 / (n * sigma) * 10 ** rng.uniform(-0.5, 0.5, n)
    return Summits.from_points(column * spacing, row * spacing, rng.normal(0, sigma, n), radius,
                               area=1.0, spacing=spacing if lattice else None)


def fft_error(summits):
    """Largest relative difference of the lattice FFT and direct sums over all summits."""
    operator = PointForceInteraction.from_summits(summits)
    forces = np.random.default_rng(1).random(summits.count)
    fft = operator.displacement(forces, method="fft")
    direct = operator.displacement(forces, method="direct")
    return float(np.max(np.abs(fft - direct) / np.abs(direct)))


def bench_case(name, summits, loads, repeats):
    model = DiscreteAsperityModel(summits)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        step, _ = median_time(lambda: model.at_load(loads[-1]), repeats)
        path, curve = median_time(lambda: model.at_load(loads), repeats)
    return dict(case=name, summits=summits.count, rejected=summits.rejected, step=step,
                path=path, contacts=int(curve.contacts[-1]),
                area=float(curve.area_fraction[-1]),
                iterations=int(curve.extras["iterations"].sum()),
                converged=bool(curve.extras["converged"].all()),
                stable=int(curve.extras["stable"].sum()),
                overlap=int(curve.extras["overlapping_spots"][-1]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="n = 128 and 10^3 asperities")
    args = parser.parse_args(argv)
    n = 128 if args.quick else 512
    many = 1000 if args.quick else 10_000
    loads = np.geomspace(1e-6, 1e-3, 30)
    heavy = np.geomspace(1e-5, 1e-2, 30)

    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__},"
          f" {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} "
          f"({platform.machine()}, {platform.system()})")
    print(f"median of {args.repeats} runs; load path: 30 loads W/(E* L^2) log-spaced in "
          "[1e-6, 1e-3] or [1e-5, 1e-2]; one step: the heaviest load solved cold\n")

    rows = []
    for D in (2.05, 2.95):
        heights = wm_surface(n, D=D, rms_slope=0.1, seed=0)
        detect, summits = median_time(lambda: asperity.find_summits(heights, 1.0 / n),
                                      args.repeats)
        row = bench_case(f"WM D={D} n={n}", summits, loads, args.repeats)
        row["detect"] = detect
        rows.append(row)
    for lattice, path, label in ((True, loads, "W <= 1e-3"), (False, loads, "W <= 1e-3"),
                                 (True, heavy, "W <= 1e-2")):
        summits = random_summits(many, lattice)
        where = "lattice (FFT)" if lattice else "anywhere (direct)"
        rows.append(bench_case(f"{many} random, {where}, {label}", summits, path,
                               args.repeats))

    header = ("case", "summits", "rejected", "detect [s]", "one step [s]", "30-step path [s]",
              "Newton its", "contacts", "area frac", "converged", "stable pts", "overlap")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        detect = f"{r['detect']:.4f}" if "detect" in r else "-"
        print(f"| {r['case']} | {r['summits']} | {r['rejected']} | {detect} | {r['step']:.3f} | "
              f"{r['path']:.3f} | {r['iterations']} | {r['contacts']} | {r['area']:.4f} | "
              f"{r['converged']} | {r['stable']}/30 | {r['overlap']} |")

    lattice = random_summits(many, True)
    wm = asperity.find_summits(wm_surface(n, D=2.95, rms_slope=0.1, seed=0), 1.0 / n)
    print(f"\nlattice FFT vs direct interaction sum, max relative difference: "
          f"{fft_error(lattice):.2e} ({many} random lattice summits), "
          f"{fft_error(wm):.2e} (WM D=2.95 summits)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
