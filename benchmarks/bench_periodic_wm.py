"""What the periodic WM surface changes: its statistics and finite-frame contact against eq. (11).

``validation.wm_surface(..., periodic=True)`` moves every wave vector of eq. (11) onto the
nearest point of the period's lattice (docs/theory.md, "A periodic WM surface", eq. T52). For
each D, the same seeds (the same phases) are drawn both ways, at the scenes' rms slope on the
same grid, and compared:

* statistics, over ``--seeds`` seeds: the standard deviation sigma of the summit heights (8
  neighbours, as ``validation.run.realization`` computes it per realization: ``np.std`` of
  ``asperity.find_summits(...).height``), the rms height and rms slope (non-periodic central
  differences on the interior points, ``validation.surface_statistics``: the same estimator
  for both; the periodic map's amplitude is set by its wrap-around slope), the summit density
  (summits per L^2), Nayak's alpha, and the slope of the radially averaged power spectrum
  (``validation.radial_power_spectrum`` in logarithmic bins a factor of about gamma = 1.5 wide,
  so that each bin holds about one ring of WM terms; a straight-line fit of log C(q) against
  log q over the bins with power from 1.2 to 30 lattice units 2 pi / L, which hold every
  term: gamma^8 = 25.6). The terms' amplitudes gamma^{(D-3) n} on rings of radius gamma^n
  give a slope 2D - 8 (-3.9, -3, -2.1); the FFT of the non-periodic map adds its edges'
  leakage, which flattens it;
* the finite frame (``bem.BoundaryElementModel``, non-periodic: the map pressed as a whole,
  what the scenes' ``bem`` reference solves), on ``--contact-seeds`` seeds at D = 2.05 and
  2.95: the area fraction and the separation d (in units of each map's rms height) at mean
  pressures 1e-4, 1e-3, 1e-2 E*.

Each cell is the mean over the seeds and, after ``±``, their standard deviation.

    nice python benchmarks/bench_periodic_wm.py [--n 256] [--seeds 8] [--contact-seeds 2]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from asperity import find_summits
from bem import BoundaryElementModel
from validation import radial_power_spectrum, surface_statistics, wm_surface

DIMENSIONS = (2.05, 2.5, 2.95)
CONTACT_DIMENSIONS = (2.05, 2.95)
PRESSURES = (1e-4, 1e-3, 1e-2)       # mean pressure / E*
RMS_SLOPE = 0.1
GAMMA = 1.5                           # wm_surface's default, the paper's


def statistics(heights: np.ndarray, spacing: float) -> dict[str, float]:
    """The statistics of one map (module docstring)."""
    summits = find_summits(heights, spacing)
    moments = surface_statistics(heights, spacing)
    n = heights.shape[0]
    side = n * spacing
    bins = math.ceil(math.log(n / 2) / math.log(GAMMA))
    q, spectrum = radial_power_spectrum(heights, spacing, bins=bins)
    lattice = q * side / (2 * np.pi)
    band = (lattice >= 1.2) & (lattice <= 30.0) & (spectrum > 1e-20 * spectrum.max())
    slope = np.polyfit(np.log(q[band]), np.log(spectrum[band]), 1)[0]
    return {"sigma": float(np.std(summits.height)), "rms height": moments.rms_height,
            "rms slope": moments.rms_gradient,
            "summits / L^2": summits.count / side**2, "alpha": moments.nayak,
            "PSD slope": float(slope)}


def contact(heights: np.ndarray, spacing: float) -> dict[str, np.ndarray]:
    """Area fraction and d / h_rms of the finite frame at :data:`PRESSURES`."""
    side = heights.shape[0] * spacing
    model = BoundaryElementModel(heights, spacing, e_star=1.0, periodic=False, tol=1e-8)
    curve = model.at_load(np.array(PRESSURES) * side**2, quantities=("area",))
    return {"area fraction": np.asarray(curve.area_fraction),
            "d / h_rms": np.asarray(curve.separation) / float(np.std(heights))}


def cell(values) -> str:
    values = np.asarray(values, dtype=float)
    return f"{values.mean():.4g} ± {values.std():.2g}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=256)
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--contact-seeds", type=int, default=2)
    args = parser.parse_args()
    spacing = 1.0 / args.n
    start = time.perf_counter()

    print(f"Statistics: n = {args.n}, rms slope {RMS_SLOPE}, {args.seeds} seeds "
          f"(mean ± standard deviation over the seeds)\n")
    print("| D | quantity | eq. (11) | periodic (T52) | periodic / eq. (11) |")
    print("|---|---|---|---|---|")
    for D in DIMENSIONS:
        rows = {False: [], True: []}
        for periodic in (False, True):
            for seed in range(args.seeds):
                heights = wm_surface(args.n, D=D, rms_slope=RMS_SLOPE, seed=seed,
                                     periodic=periodic)
                rows[periodic].append(statistics(heights, spacing))
        for key in rows[False][0]:
            plain = np.array([r[key] for r in rows[False]])
            lattice = np.array([r[key] for r in rows[True]])
            print(f"| {D:g} | {key} | {cell(plain)} | {cell(lattice)} | "
                  f"{lattice.mean() / plain.mean():.3f} |")

    print(f"\nFinite frame (non-periodic BEM of the map), {args.contact_seeds} seeds: area "
          f"fraction and d / h_rms at mean pressure p / E*\n")
    print("| D | p / E* | quantity | eq. (11) | periodic (T52) | periodic / eq. (11) |")
    print("|---|---|---|---|---|---|")
    for D in CONTACT_DIMENSIONS:
        curves = {False: [], True: []}
        for periodic in (False, True):
            for seed in range(args.contact_seeds):
                heights = wm_surface(args.n, D=D, rms_slope=RMS_SLOPE, seed=seed,
                                     periodic=periodic)
                curves[periodic].append(contact(heights, spacing))
        for index, pressure in enumerate(PRESSURES):
            for key in curves[False][0]:
                plain = np.array([c[key][index] for c in curves[False]])
                lattice = np.array([c[key][index] for c in curves[True]])
                print(f"| {D:g} | {pressure:g} | {key} | {cell(plain)} | {cell(lattice)} | "
                      f"{lattice.mean() / plain.mean():.3f} |")
    print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
