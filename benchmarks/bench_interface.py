"""The interface reference's own error: the mirror method against the periodic solution.

On periodic self-affine surfaces (``validation.self_affine_surface`` without a window: rms slope
0.1, rolloff L/4, L = 1) the exact interface is the periodic BEM of the surface itself. The
mirror method (:class:`bem.InterfaceModel` with ``extension="mirror"``, what a measured scan or
any non-periodic window gets) and the finite window (:class:`bem.BoundaryElementModel`,
``periodic=False``, the finite-nominal-contact reference) are solved on the same map at the same
mean pressures, and each is compared with the periodic solution: area (relative), mean gap (in
units of the rms height; for the window its mean gap, for the interface d = u-bar) and stiffness
per unit area (relative), at the points with 0.5-30 % contact in the periodic solution.

Prints one row per (H, seed) with the largest |error| of each method and a summary per H;
``bem.interface.MIRROR_ERROR`` is set from the summary (docs/theory.md, eq. T50).

    python benchmarks/bench_interface.py [--n 256] [--seeds 8] [--hurst 0.3,0.5,0.8]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bem import BoundaryElementModel, InterfaceModel
from validation.surfaces.self_affine import self_affine_surface

PRESSURES = np.geomspace(2e-4, 3e-2, 9)   # mean pressure / E*
QUANTITIES = ("area", "stiffness")


def errors(curve, exact, rms_height: float) -> np.ndarray:
    """Rows area, mean gap, stiffness: the errors of ``curve`` against ``exact``."""
    return np.vstack([curve.area_fraction / exact.area_fraction - 1.0,
                      (np.asarray(curve.extras["mean_gap"]) - exact.extras["mean_gap"]) / rms_height,
                      (curve.stiffness / curve.nominal_area) / (exact.stiffness / exact.nominal_area)
                      - 1.0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=256)
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--hurst", default="0.3,0.5,0.8")
    parser.add_argument("--tol", type=float, default=1e-8)
    args = parser.parse_args()
    n, spacing = args.n, 1.0 / args.n
    print(f"grid {n}^2, pressures {PRESSURES[0]:.1e}-{PRESSURES[-1]:.1e} E*, tol {args.tol:g}; "
          "largest |error| over the points with 0.5-30 % contact: area (rel), mean gap (h_rms), "
          "stiffness (rel)")
    for hurst in (float(h) for h in args.hurst.split(",")):
        worst = {"mirror": np.zeros(3), "window": np.zeros(3)}
        seconds = {"periodic": 0.0, "mirror": 0.0, "window": 0.0}
        for seed in range(args.seeds):
            z = self_affine_surface(n, hurst=hurst, rms_slope=0.1, rolloff=0.25, seed=seed)
            loads = PRESSURES * n * n * spacing**2
            solved = {}
            for name, model in (
                    ("periodic", InterfaceModel(z, spacing, extension="periodic", tol=args.tol)),
                    ("mirror", InterfaceModel(z, spacing, extension="mirror", tol=args.tol)),
                    ("window", BoundaryElementModel(z, spacing, periodic=False, tol=args.tol))):
                start = time.perf_counter()
                solved[name] = model.at_load(loads, quantities=QUANTITIES)
                seconds[name] += time.perf_counter() - start
            exact = solved["periodic"]
            inside = (exact.area_fraction >= 0.005) & (exact.area_fraction <= 0.30)
            row = []
            for name in ("mirror", "window"):
                largest = np.max(np.abs(errors(solved[name], exact, float(np.std(z)))[:, inside]),
                                 axis=1)
                worst[name] = np.maximum(worst[name], largest)
                row.append(f"{name} {largest[0]:.3f} {largest[1]:.3f} {largest[2]:.3f}")
            print(f"H {hurst:g} seed {seed}: " + " | ".join(row), flush=True)
        print(f"H {hurst:g} largest over {args.seeds} seeds: "
              + " | ".join(f"{k} area {v[0]:.3f} gap {v[1]:.3f} stiffness {v[2]:.3f}"
                           for k, v in worst.items())
              + "; time per seed: " + ", ".join(f"{k} {v / args.seeds:.1f} s"
                                                 for k, v in seconds.items()), flush=True)


if __name__ == "__main__":
    main()
