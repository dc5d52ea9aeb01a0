"""Benchmark of the boundary-element contact solver (bem.solve_contact) across grids.

One Weierstrass-Mandelbrot surface (D = 2.5, rms slope 0.1, seed 9173, ``slope_grid=1024``, so
every grid samples the same continuous surface; L = 1, E* = 1) at the loads 2e-3, 1e-2 and 3e-2
(about 4, 18 and 44 % contact area; above N = 1024 only 1e-2), tol 1e-9, cold start,
non-periodic and periodic. Per grid
N and load it prints: iterations on the N x N grid (the nested coarse solves are counted in the
time, not in this column), the solve time, the time of one real FFT pair of the convolution grid
(2N x 2N non-periodic, N x N periodic) and the solve time over iterations in those FFT pairs,
and the peak of numpy allocations (``tracemalloc``) of one solve with the stiffness, operator
built inside, in bytes per grid point (a separate, untimed run, at the first load, as
validation/campaigns/bench.py measures it). The operator, with its coarse levels, is built before the
timed solves, and its build time is printed once per grid.

``--plain`` solves with the plain Polonsky-Keer iteration (``preconditioned=False``), the
solver before preconditioning. ``--path N`` also times a 12-point load path (``contact_curve``,
loads 1e-3 to 3e-2 geometric; each point starts from its coarse-grid
solve, warm-started from the previous point's) on N x N. When the optional ``tamaas`` package is
importable, Tamaas's PolonskyKeerRey solves the same problems (N <= ``--tamaas-max``) in a
separate process: its time, the ratio to ours and the relative differences of area and mean gap
(Tamaas's tolerance is its own error measure, 1e-10 by default).

Times are of single runs on whatever else the machine does: on a shared machine they are upper
bounds (the load average is printed).

Usage: ``python benchmarks/bench_bem.py [--sizes N ...] [--periodic {no,yes,both}] [--plain]
[--path N] [--no-memory] [--no-tamaas]``
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc

import numpy as np

import bem
import bem.elastic.fft_threads
from bem.contact.solver import DEFAULT_TOLERANCE
from validation import wm_surface

LOADS = (2e-3, 1e-2, 3e-2)
PATH_LOADS = tuple(np.geomspace(1e-3, 3e-2, 12))


def surface(n: int) -> np.ndarray:
    return wm_surface(n, D=2.5, rms_slope=0.1, seed=9173, slope_grid=1024)


def median_time(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def fft_pair_ms(operator: bem.HalfSpace) -> float:
    """One real FFT pair of the operator's convolution grid [ms], median of 7."""
    fft = bem.elastic.fft.RealFFT2(operator.convolution_shape, threads=operator.threads,
                           planner_effort=operator.planner_effort)
    fft.real_buffer[...] = np.random.default_rng(0).uniform(size=fft.shape)

    def pair():
        fft.execute_forward()
        fft.execute_inverse()

    return 1e3 * median_time(pair, 7)


def peak_bytes_per_point(heights, load, periodic, preconditioned) -> float:
    n = heights.shape[0]
    tracemalloc.start()
    bem.solve_contact(heights, 1.0 / n, load=load, periodic=periodic, stiffness=True,
                      preconditioned=preconditioned)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / n**2


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


def load_path(n: int, preconditioned: bool) -> None:
    heights = surface(n)
    start = time.perf_counter()
    operator = bem.HalfSpace((n, n), 1.0 / n)
    built = time.perf_counter() - start
    start = time.perf_counter()
    curve = bem.contact_curve(heights, 1.0 / n, loads=PATH_LOADS, operator=operator,
                              preconditioned=preconditioned)
    elapsed = time.perf_counter() - start
    iterations = curve.extras["iterations"]
    print(f"12-point load path, {n} x {n} non-periodic, loads 1e-3..3e-2 (area "
          f"{curve.area[0]:.3f}..{curve.area[-1]:.3f}): {elapsed:.1f} s after a {built:.1f} s "
          f"operator build; iterations {int(iterations.sum())} "
          f"({', '.join(str(int(i)) for i in iterations)}); "
          f"all converged: {bool(np.all(curve.extras['converged']))}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[128, 256, 512, 1024, 2048])
    parser.add_argument("--all-loads-max", type=int, default=1024,
                        help="above this N only the middle load (about 18 %% area) is solved")
    parser.add_argument("--periodic", choices=("no", "yes", "both"), default="both")
    parser.add_argument("--plain", action="store_true",
                        help="the plain Polonsky-Keer iteration (preconditioned=False)")
    parser.add_argument("--path", type=int, default=None, help="time a 12-point load path on N")
    parser.add_argument("--no-memory", action="store_true")
    parser.add_argument("--memory-max", type=int, default=1024)
    parser.add_argument("--no-tamaas", action="store_true")
    parser.add_argument("--tamaas-max", type=int, default=512)
    parser.add_argument("--tamaas-tol", type=float, default=1e-10)
    args = parser.parse_args()
    preconditioned = not args.plain
    try:
        if args.no_tamaas:
            raise ImportError
        import tamaas
        tamaas_version = tamaas.__version__
    except ImportError:
        tamaas_version = None
    print(f"FFT backend: {'pyfftw' if bem.elastic.fft.have_pyfftw() else 'scipy'}, "
          f"CPUs {bem.elastic.fft_threads.default_threads()}, load average {os.getloadavg()[0]:.1f}, "
          f"tol {DEFAULT_TOLERANCE:g}, {'plain' if args.plain else 'preconditioned, nested'}; "
          f"Tamaas: {tamaas_version or 'not importable'}")
    header = ("| N | half-space | load | area | iterations | time (s) | FFT pair (ms) "
              "| FFT pairs/iteration | peak (B/point) |")
    if tamaas_version:
        header += " Tamaas (s) | Tamaas / bem | d area | d mean gap |"
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    periodicities = {"no": (False,), "yes": (True,), "both": (False, True)}[args.periodic]
    for n in args.sizes:
        heights = surface(n)
        for periodic in periodicities:
            start = time.perf_counter()
            operator = bem.HalfSpace((n, n), 1.0 / n, periodic=periodic)
            bem.solve_contact(heights, 1.0 / n, load=LOADS[0], operator=operator,
                              periodic=periodic, tol=1e-3, preconditioned=preconditioned)
            setup = time.perf_counter() - start
            pair = fft_pair_ms(operator)
            memory = None
            if not args.no_memory and n <= args.memory_max:
                memory = peak_bytes_per_point(heights, LOADS[0], periodic, preconditioned)
            for load in LOADS if n <= args.all_loads_max else LOADS[1:2]:
                start = time.perf_counter()
                solution = bem.solve_contact(heights, 1.0 / n, load=load, operator=operator,
                                             periodic=periodic, preconditioned=preconditioned)
                elapsed = time.perf_counter() - start
                per_iteration = 1e3 * elapsed / solution.iterations / pair
                row = (f"| {n} | {'periodic' if periodic else 'non-periodic'} | {load:g} "
                       f"| {solution.area_fraction:.3f} | {solution.iterations} | {elapsed:.2f} "
                       f"| {pair:.2f} | {per_iteration:.1f} "
                       f"| {'-' if memory is None else f'{memory:.0f}'} |")
                if not solution.converged:
                    row += " (not converged)"
                if tamaas_version:
                    if n <= args.tamaas_max:
                        spent, area, mean_gap = tamaas_solve(heights, load, periodic,
                                                             args.tamaas_tol)
                        row += (f" {spent:.2f} | {spent / elapsed:.1f} "
                                f"| {area / solution.area_fraction - 1:.1e} "
                                f"| {mean_gap / solution.mean_gap - 1:.1e} |")
                    else:
                        row += " - | - | - | - |"
                print(row, flush=True)
            print(f"(N = {n}, {'periodic' if periodic else 'non-periodic'}: operator and coarse "
                  f"levels built in {setup:.1f} s, FFT threads {operator.threads})", flush=True)
    if args.path:
        load_path(args.path, preconditioned)


if __name__ == "__main__":
    main()
