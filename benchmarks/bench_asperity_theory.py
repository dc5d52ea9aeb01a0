"""Timing of the asperity theory kernels: F_n(h), GW / improved GW curves, Holm-Greenwood.

Run: ``python benchmarks/bench_asperity_theory.py [--repeats 7]``. Prints the median (and the
fastest) of repeated runs in seconds; nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from asperity import (GreenwoodWilliamson, ImprovedGreenwoodWilliamson, gw_integral,
                      holm_greenwood)
from asperity.common.gw_functions import gw_integrals


def timed(function, repeats: int) -> tuple[float, float]:
    function()                                            # warm-up (imports, caches)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times)


def report(label: str, function, repeats: int) -> None:
    median, best = timed(function, repeats)
    print(f"{label:<58s} median {median * 1e3:9.2f} ms   best {best * 1e3:9.2f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=7)
    repeats = parser.parse_args().repeats

    h = np.linspace(-10.0, 37.0, 10**6)
    print(f"F_n(h) over 10^6 points, h uniform on [-10, 37] (median of {repeats})")
    for n in (0.0, 0.5, 1.0, 1.5):
        report(f"  gw_integral({n}, h)", lambda n=n: gw_integral(n, h), repeats)
    report("  F_0, F_1/2, F_1, F_3/2 together (what a GW curve needs)",
           lambda: gw_integrals((0.0, 0.5, 1.0, 1.5), h), repeats)
    central = np.random.default_rng(0).uniform(-10.0, 12.0, 10**6)
    report("  gw_integral(1.5, h), h on [-10, 12] (trapezoid region)",
           lambda: gw_integral(1.5, central), repeats)

    gw = GreenwoodWilliamson(500.0, 1e-4, 1e-3)
    improved = ImprovedGreenwoodWilliamson(5e4, 1e-6, 1e-3, area=1.0)   # C = 50
    separations = 1e-3 * np.linspace(-5.0, 30.0, 10**4)
    loads = improved.reference_load * np.logspace(-12, 3, 10**4)
    print("\nContact curves, 10^4 points")
    report("  GreenwoodWilliamson.at_separation", lambda: gw.at_separation(separations), repeats)
    report("  GreenwoodWilliamson.at_load (15 decades)", lambda: gw.at_load(loads), repeats)
    report("  ImprovedGreenwoodWilliamson.at_separation (C = 50, exact)",
           lambda: improved.at_separation(separations), repeats)
    report("  ImprovedGreenwoodWilliamson.at_load (C = 50)", lambda: improved.at_load(loads),
           repeats)

    print("\nholm_greenwood (exact eq. 6), random spots in a unit square")
    rng = np.random.default_rng(1)
    for count in (500, 10**4):
        x, y = rng.uniform(0.0, 1.0, count), rng.uniform(0.0, 1.0, count)
        radii = rng.uniform(1e-4, 1e-3, count)
        report(f"  {count} spots", lambda x=x, y=y, r=radii: holm_greenwood(x, y, r), repeats)


if __name__ == "__main__":
    main()
