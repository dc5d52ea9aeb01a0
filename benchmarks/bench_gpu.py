"""The boundary-element reference on the CPU and on a CUDA GPU: wall time, iterations, the
largest difference between the two, and the GPU's peak memory.

A periodic self-affine surface (H = 0.8, rms slope 0.1, ``validation.self_affine_surface``) at
a mean pressure of 0.005 E* (about 8 % contact), load control, tol 1e-9, with its stiffness:
one solve per size and kind (periodic; a non-periodic window and a mirror quadrant up to
``--window-max``), then a 16-point load path (``bem.contact_curve``, periodic, with its error
estimate, up to ``--path-max``), at ``--discrete-size`` the discrete model with interaction on
the surface's summits (its FFT sums on the device), and last the check of the synthetic scans of
``benchmarks/bench_check.py`` with ``--device gpu`` (``--check-sizes``). The CPU runs up to
``--cpu-max`` points per side (its times above that are minutes). Each solve's line prints
``kind size device wall iterations area relative-difference peak-GPU-memory``; the GPU's memory
is CuPy's pool after the solve (its high-water mark), per grid point as well. A GPU solve runs
twice and the second is timed (the first makes cuFFT's plans and compiles the kernels).

Usage::

    python benchmarks/bench_gpu.py [--sizes 1024,2048,4096,8192] [--cpu-max 2048]
                                   [--window-max 4096] [--path-max 4096]
                                   [--discrete-size 1024] [--check-sizes 1024,2048]
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

import bem
from bem.elastic.device import array_module
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


def _devices(n: int, cpu_max: int) -> tuple[str, ...]:
    return ("cpu", "gpu") if n <= cpu_max else ("gpu",)


def _solves(n: int, heights: np.ndarray, kinds, cpu_max: int, xp) -> None:
    for kind in kinds:
        cpu = None
        for device in _devices(n, cpu_max):
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


def _path(n: int, heights: np.ndarray, cpu_max: int) -> None:
    loads = np.geomspace(1e-4, 2e-2, 16)
    for device in _devices(n, cpu_max):
        start = time.perf_counter()
        curve = bem.contact_curve(heights, 1.0 / n, loads=loads, periodic=True,
                                  device=device, error_estimate=True,
                                  quantities=("area", "load", "separation", "conductance"))
        print(f"{'path16':>8} {n:>6} {device:>6} {time.perf_counter() - start:9.2f} "
              f"{int(np.sum(curve.extras['iterations'])):>6} {curve.area[-1]:9.5f}",
              flush=True)


def _discrete(n: int, heights: np.ndarray) -> None:
    import asperity

    summits = asperity.find_summits(heights, 1.0 / n)
    for device in ("cpu", "gpu"):
        model = asperity.DiscreteAsperityModel(summits, method="fft", device=device)
        start = time.perf_counter()
        curve = model.at_load(np.geomspace(1e-4, 2e-2, 12))
        print(f"{'discrete':>8} {n:>6} {device:>6} {time.perf_counter() - start:9.2f} "
              f"{summits.count:>6} {curve.area[-1]:9.5f}", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="1024,2048,4096,8192")
    parser.add_argument("--cpu-max", type=int, default=2048)
    parser.add_argument("--window-max", type=int, default=4096,
                        help="largest side of the window and mirror solves (they pad to 2n)")
    parser.add_argument("--path-max", type=int, default=4096)
    parser.add_argument("--discrete-size", type=int, default=1024)
    parser.add_argument("--check-sizes", default="1024,2048",
                        help="scans checked with --device gpu ('' for none)")
    args = parser.parse_args(argv)
    xp = array_module("gpu")            # a clear error where there is no GPU
    print(f"{'kind':>8} {'size':>6} {'device':>6} {'wall [s]':>9} {'iter':>6} {'area':>9} "
          f"{'vs CPU':>9} {'GPU MB':>8} {'B/point':>8}", flush=True)
    for n in (int(s) for s in args.sizes.split(",")):
        heights = self_affine_surface(n, hurst=0.8, rms_slope=0.1, L=1.0, seed=1)
        kinds = ("periodic", "window", "mirror") if n <= args.window_max else ("periodic",)
        _solves(n, heights, kinds, args.cpu_max, xp)
        if n <= args.path_max:
            _path(n, heights, args.cpu_max)
        if n == args.discrete_size:
            _discrete(n, heights)
    if args.check_sizes:
        import bench_check

        return bench_check.main(["--sizes", args.check_sizes, "--device", "gpu"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
