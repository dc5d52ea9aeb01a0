"""Benchmark of the boundary-element contact solver (bem.solve_contact).

For N = 256, 512, 1024 and periodic / non-periodic half-spaces, prints the time of one FFT pair
of the convolution grid (2N x 2N non-periodic, N x N periodic), the time of one half-space
product, and for a Weierstrass-Mandelbrot surface (D = 2.4, rms slope 0.1, seed 0) at about 2 %,
10 % and 30 % contact area: iterations, products per iteration, time per iteration (also over
the FFT-pair time) and total time at the default tolerance, cold start. The loads giving those
areas are found first (untimed) on N = 256 and refined on each grid up to 512; N = 1024 reuses
the loads of N = 512 (the surface is the same up to resolution), so its area fractions are
approximately the targets and are printed as reached.

When the optional ``tamaas`` package is importable (not a dependency of this project), Tamaas's
PolonskyKeerRey solves the same surface and load, and its time and the relative differences of
area and mean gap are printed (mean gap from Tamaas's own displacement, with the separation
taken as the mean of z - u over its contact set, as bem does).

Times are medians of repeated runs (FFT pairs and products: 15 runs; solves: ``--repeat``,
3 runs at N = 256 and 1 above by default) on whatever else the machine is doing: on a shared
machine they are pessimistic. The full run takes about 5 minutes on 2 cores (``--quick``: 30 s).

Usage: ``python benchmarks/bench_bem.py [--quick] [--sizes N ...] [--repeat R] [--no-tamaas]``
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import statistics
import time

import numpy as np

import bem
from bem.solver import DEFAULT_TOLERANCE
from validation import wm_surface

TARGET_AREAS = (0.02, 0.10, 0.30)


def median_time(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def find_loads(heights, operator, guesses, targets=TARGET_AREAS, steps=4):
    """Loads giving the target area fractions: secant steps in log(load) vs log(area)."""
    n = heights.shape[0]
    loads = []
    for target, guess in zip(targets, guesses):
        points = []
        load = guess
        for _ in range(steps):
            solution = bem.solve_contact(heights, 1.0 / n, load=load, operator=operator,
                                         periodic=operator.periodic, tol=1e-6)
            points.append((np.log(load), np.log(solution.area_fraction)))
            if abs(solution.area_fraction / target - 1) < 0.01:
                break
            if len(points) == 1:
                slope = 1.0  # area roughly proportional to load at small loads
            else:
                (x0, y0), (x1, y1) = points[-2], points[-1]
                slope = (y1 - y0) / (x1 - x0) if x1 != x0 else 1.0
                slope = slope if slope > 0.1 else 0.1
            load = float(np.exp(np.log(load) + (np.log(target) - points[-1][1]) / slope))
        loads.append(load)
    return loads


_TAMAAS_SCRIPT = """
import json, sys, time
import numpy as np
import tamaas as tm
heights = np.load(sys.argv[1]); load = float(sys.argv[2]); periodic = sys.argv[3] == "1"
n = heights.shape[0]
model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], [n, n])
model.E, model.nu = 1.0, 0.0  # E* = E / (1 - nu^2) = 1
solver = tm.PolonskyKeerRey(model, heights, float(sys.argv[4]), tm.PolonskyKeerRey.pressure,
                            tm.PolonskyKeerRey.pressure)
if not periodic:  # Tamaas needs the non-periodic operator registered in both places
    tm.ModelFactory.registerNonPeriodic(model, "dcfft")
    solver.setIntegralOperator("dcfft")
solver.max_iter = 100000
start = time.perf_counter()
solver.solve(load)  # mean pressure = load on the unit square
elapsed = time.perf_counter() - start
pressure = np.array(model.traction).reshape(n, n)
displacement = np.array(model.displacement).reshape(n, n)
contact = pressure > 0
separation = float(np.mean((heights - displacement)[contact]))
print(json.dumps([elapsed, float(np.count_nonzero(contact)) / n**2,
                  float(np.mean(separation - heights + displacement))]))
"""


def tamaas_solve(heights, load, periodic, tolerance):
    """Tamaas's PolonskyKeerRey in a separate process (its threads never meet ours)."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "heights.npy")
        np.save(path, heights)
        result = subprocess.run(
            [sys.executable, "-c", _TAMAAS_SCRIPT, path, repr(load), "1" if periodic else "0",
             repr(tolerance)], capture_output=True, text=True, check=True)
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 128 and 256 only, one run each")
    parser.add_argument("--sizes", type=int, nargs="+", default=None)
    parser.add_argument("--repeat", type=int, default=None,
                        help="timed runs per solve (median); default 3 for N <= 256, else 1")
    parser.add_argument("--no-tamaas", action="store_true")
    parser.add_argument("--tamaas-max", type=int, default=512,
                        help="largest N for the Tamaas comparison (default 512)")
    parser.add_argument("--tamaas-tol", type=float, default=1e-10,
                        help="Tamaas's own tolerance (its error measure differs from bem's)")
    args = parser.parse_args()
    sizes = args.sizes or ((128, 256) if args.quick else (256, 512, 1024))
    try:
        if args.no_tamaas:
            raise ImportError
        import tamaas  # noqa: F401
        have_tamaas = True
    except ImportError:
        have_tamaas = False
    print(f"FFT backend: {'pyfftw' if bem.fft.have_pyfftw() else 'scipy'}, "
          f"CPUs {bem.fft.default_threads()}, load average {os.getloadavg()[0]:.1f}, "
          f"default tol {DEFAULT_TOLERANCE:g}; "
          f"Tamaas comparison: {'yes' if have_tamaas else 'no (tamaas not importable)'}")
    header = ("| N | half-space | threads | FFT pair (ms) | product (ms) | area | iterations | products/it "
              "| ms/iteration | it / FFT pair | total (s) |")
    rule = "|---|---|---|---|---|---|---|---|---|---|---|"
    if have_tamaas:
        header += " Tamaas total (s) | Tamaas / bem | rel. diff area | rel. diff mean gap |"
        rule += "---|---|---|---|"
    print(header)
    print(rule, flush=True)
    guesses = {False: [0.0005, 0.003, 0.012], True: [0.0005, 0.003, 0.012]}
    for n in sizes:
        heights = wm_surface(n, D=2.4, rms_slope=0.1, seed=0)
        repeat = args.repeat or (1 if args.quick or n > 256 else 3)
        for periodic in (False, True):
            operator = bem.HalfSpace((n, n), 1.0 / n, periodic=periodic)
            # the reference: a full real FFT pair of the convolution grid (2N x 2N non-periodic;
            # the operator's own pruned transforms do about 3/4 of that work)
            fft = bem.fft.RealFFT2(operator.convolution_shape, threads=operator.threads,
                                   planner_effort=operator.planner_effort)
            fft.real_buffer[...] = np.random.default_rng(0).uniform(size=fft.shape)

            def fft_pair():
                fft.execute_forward()
                fft.execute_inverse()

            fft_ms = 1e3 * median_time(fft_pair, 15)
            pressure, displacement = np.random.default_rng(1).uniform(size=(2, n, n))
            product_ms = 1e3 * median_time(lambda: operator._apply(pressure, displacement), 15)
            if n <= 512:
                loads = find_loads(heights, operator, guesses[periodic])
                guesses[periodic] = loads
            else:
                loads = guesses[periodic]
            for load in loads:
                products = [0]
                apply, transform = operator._apply, operator._transform_direction

                def counting(source, out, apply=apply, products=products):
                    products[0] += 1
                    apply(source, out)

                def counting_direction(transform=transform, products=products):
                    products[0] += 1
                    transform()

                operator._apply = counting
                operator._transform_direction = counting_direction
                times = []
                for _ in range(repeat):
                    products[0] = 0
                    start = time.perf_counter()
                    solution = bem.solve_contact(heights, 1.0 / n, load=load, operator=operator,
                                                 periodic=periodic)
                    times.append(time.perf_counter() - start)
                operator._apply, operator._transform_direction = apply, transform
                total = statistics.median(times)
                per_iteration = 1e3 * total / solution.iterations
                row = (f"| {n} | {'periodic' if periodic else 'non-periodic'} | {operator.threads} "
                       f"| {fft_ms:.2f} "
                       f"| {product_ms:.2f} | {solution.area_fraction:.3f} | {solution.iterations} "
                       f"| {products[0] / solution.iterations:.2f} | {per_iteration:.2f} "
                       f"| {per_iteration / fft_ms:.2f} | {total:.2f} |")
                if not solution.converged:
                    row += " (not converged)"
                if have_tamaas:
                    if n <= args.tamaas_max:
                        elapsed, area, mean_gap = tamaas_solve(heights, load, periodic,
                                                               args.tamaas_tol)
                        row += (f" {elapsed:.2f} | {elapsed / total:.1f} "
                                f"| {area / solution.area_fraction - 1:.1e} "
                                f"| {mean_gap / solution.mean_gap - 1:.1e} |")
                    else:
                        row += " - | - | - | - |"
                print(row, flush=True)
    if have_tamaas:
        print(f"Tamaas: one cold run per point in a separate process, tolerance "
              f"{args.tamaas_tol:g}, up to N = {args.tamaas_max}.")


if __name__ == "__main__":
    main()
