"""How large is the solver's own error at a given tolerance, against the reference band?

One WM surface per D (D = 2.05, 2.95; rms slope 0.1, seed 5, L = 1, non-periodic, 256 x 256 by
default) is solved along Load = W/(E* L^2) = 1e-5 ... 1e-2 (8 points) at solver tolerances
(T25) 1e-3 ... 1e-8 and at 1e-12, twice: with the stiffness (whose solve waits for a contact
set that no longer changes, ``bem.contact.constrained_cg``) and without it (Polonsky-Keer's rule alone,
the pixels that still join or leave counted in the pressure change). The table gives, per
tolerance, the largest solver error over the points, relative for area and conductance and in
units of sigma (the rms height here, a stand-in for the summits' one) for separation and mean
gap, and that error divided by the tolerance: the constant
``validation.run.refine.SOLVER_ERROR`` bounds it for the separation, mean gap and conductance,
so that a refined solve at tolerance ``0.01 band / SOLVER_ERROR`` spends at most 1 % of its band
on the solver (docs/theory.md, eq. T40); the area's error is a few pixels at the contact edge
instead, not proportional to the tolerance, and T40 says how large (the ``px`` column: the
largest number of pixels). The last column is the wall time of the path against that at the
scene default 1e-8 (shared cores: read it as indicative).

Usage: ``nice python benchmarks/bench_solver_tolerance.py [--n 256]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import bem
from validation import wm_surface

TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
LOADS = np.geomspace(1e-5, 1e-2, 8)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=256)
    args = parser.parse_args()
    print(f"{'D':>5} {'stiffness':>9} {'tol':>7} {'area':>9} {'px':>3} {'sep/σ':>9} {'gap/σ':>9} "
          f"{'cond':>9} {'max/tol':>8} {'time':>6}")
    for D in (2.05, 2.95):
        z = wm_surface(args.n, D=D, rms_slope=0.1, seed=5)
        sigma = float(np.std(z))
        h = 1.0 / args.n
        for stiffness in (True, False):
            quantities = ("area", "load", "separation") + (("conductance",) if stiffness else ())

            def solve(tol):
                return bem.contact_curve(z, h, loads=LOADS, quantities=quantities, tol=tol,
                                         max_iter=20000)
            exact = solve(1e-12)
            seconds = {}
            for tol in TOLERANCES[::-1]:
                start = time.perf_counter()
                solve(tol)
                seconds[tol] = time.perf_counter() - start
            for tol in TOLERANCES:
                curve = solve(tol)
                pixels = int(np.max(np.abs(curve.area - exact.area)) / h**2 + 0.5)
                errors = [np.max(np.abs(curve.area / exact.area - 1)),
                          np.max(np.abs(curve.separation - exact.separation)) / sigma,
                          np.max(np.abs(curve.extras["mean_gap"] - exact.extras["mean_gap"]))
                          / sigma,
                          (np.max(np.abs(curve.conductance / exact.conductance - 1))
                           if stiffness else np.nan)]
                bounded = np.nanmax(errors[1:])
                print(f"{D:5.2f} {'yes' if stiffness else 'no':>9} {tol:7.0e} {errors[0]:9.2e} "
                      f"{pixels:3d} " + " ".join(f"{e:9.2e}" for e in errors[1:])
                      + f" {bounded / tol:8.3f} {seconds[tol] / seconds[1e-8]:6.2f}")


if __name__ == "__main__":
    main()
