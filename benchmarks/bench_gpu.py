"""The boundary-element reference on the CPU and on a CUDA GPU: wall time, iterations, the
largest difference between the two, and the GPU's peak memory.

A periodic self-affine surface (H = 0.8, rms slope 0.1, ``validation.self_affine_surface``) at
a mean pressure of 0.005 E* (about 10 % contact), load control, tol 1e-9, with its stiffness:
one solve per size and kind (periodic, non-periodic window, mirror quadrant), then a
16-point load path (``bem.contact_curve``, periodic, with its error estimate), and at 1024^2 the
discrete model with interaction on the surface's summits (its FFT sums on the device). The CPU runs up
to ``--cpu-max`` points per side (its times above that are minutes). Each line prints
``kind size device wall iterations area relative-difference peak-GPU-memory``; the GPU's memory
is CuPy's pool after the solve (its high-water mark), per grid point as well.

Usage::

    python benchmarks/bench_gpu.py [--sizes 1024,2048,4096,8192] [--cpu-max 2048]
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

import bem
from bem.device import array_module
from validation import self_affine_surface

PRESSURE = 0.005


def _pool_peak(xp) -> int:
    return int(xp.get_default_memory_pool().total_bytes()) if xp is not np else 0


def _solve(kind: str, heights: np.ndarray, device: str):
    n = heights.shape[0]
    periodic = kind != "window"
    operator = bem.HalfSpace(heights.shape, 1.0 / n, periodic=periodic,
                             mirror=kind == "mirror", device=device)
    start = time.perf_counter()
    if kind == "mirror":
        kept = []
        bem.contact_curve(heights, 1.0 / n, loads=[PRESSURE], periodic=True, mirror=True,
                          operator=operator, device=device, tol=1e-9,
                          quantities=("area", "load", "separation", "stiffness"),
                          callback=lambda index, solution: kept.append(solution))
        solution = kept[0]
    else:
        solution = bem.solve_contact(heights, 1.0 / n, load=PRESSURE, periodic=periodic,
                                     tol=1e-9, stiffness=True, operator=operator, device=device)
    return solution, time.perf_counter() - start


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="1024,2048,4096,8192")
    parser.add_argument("--cpu-max", type=int, default=2048)
    args = parser.parse_args(argv)
    xp = array_module("gpu")            # a clear error where there is no GPU
    print(f"{'kind':>8} {'size':>6} {'device':>6} {'wall [s]':>9} {'iter':>6} {'area':>9} "
          f"{'vs CPU':>9} {'GPU MB':>8} {'B/point':>8}", flush=True)
    for n in (int(s) for s in args.sizes.split(",")):
        heights = self_affine_surface(n, hurst=0.8, rms_slope=0.1, L=1.0, seed=1)
        for kind in ("periodic", "window", "mirror"):
            cpu = None
            for device in (("cpu", "gpu") if n <= args.cpu_max else ("gpu",)):
                if device == "gpu":
                    xp.get_default_memory_pool().free_all_blocks()
                solution, wall = _solve(kind, heights, device)
                if device == "gpu":
                    solution, wall = _solve(kind, heights, device)   # plans made: time again
                difference = ("" if cpu is None else
                              f"{abs(solution.area / cpu.area - 1):9.1e}")
                peak = _pool_peak(xp) if device == "gpu" else 0
                print(f"{kind:>8} {n:>6} {device:>6} {wall:9.2f} {solution.iterations:>6} "
                      f"{solution.area:9.5f} {difference:>9} {peak / 2**20:8.0f} "
                      f"{peak / n**2 if peak else 0:8.0f}", flush=True)
                cpu = solution if device == "cpu" else cpu
        loads = np.geomspace(1e-4, 2e-2, 16)
        for device in (("cpu", "gpu") if n <= args.cpu_max else ("gpu",)):
            start = time.perf_counter()
            curve = bem.contact_curve(heights, 1.0 / n, loads=loads, periodic=True,
                                      device=device, error_estimate=True,
                                      quantities=("area", "load", "separation", "conductance"))
            print(f"{'path16':>8} {n:>6} {device:>6} {time.perf_counter() - start:9.2f} "
                  f"{int(np.sum(curve.extras['iterations'])):>6} {curve.area[-1]:9.5f}",
                  flush=True)
        if n == 1024:
            import asperity

            summits = asperity.find_summits(heights, 1.0 / n)
            for device in ("cpu", "gpu"):
                model = asperity.DiscreteAsperityModel(summits, method="fft", device=device)
                start = time.perf_counter()
                curve = model.at_load(np.geomspace(1e-4, 2e-2, 12))
                print(f"{'discrete':>8} {n:>6} {device:>6} {time.perf_counter() - start:9.2f} "
                      f"{summits.count:>6} {curve.area[-1]:9.5f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
