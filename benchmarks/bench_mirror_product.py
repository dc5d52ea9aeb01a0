"""Benchmark of the mirror (interface) half-space product: one real FFT pair of the folded
quadrant (:class:`bem.elastic.mirror_product.MirrorProduct`, what :class:`bem.HalfSpace` uses with
``mirror=True`` on even grids) against type-II/III cosine transforms of the quadrant
(:class:`bem.elastic.fft.CosineTransform2`, FFTW's REDFT10/01 where pyFFTW is installed, scipy's
otherwise, times the same multiplier).

Per grid N and FFT thread count it prints the median time of one product (of 15, after one
untimed) each way, their ratio, and the largest difference of the two products relative to
the largest displacement. Plans are made with FFTW_MEASURE (kept in the wisdom file). Times
are of whatever else the machine does: run it on a quiet machine, or alternate.

Usage: ``python benchmarks/bench_mirror_product.py [--sizes 512 1024 2048] [--threads 1 2]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bem import HalfSpace
from bem.elastic.fft import CosineTransform2


def median_ms(function, repeat: int = 15) -> float:
    function()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[256, 512, 1024, 2048])
    parser.add_argument("--threads", type=int, nargs="*", default=[1, 2])
    args = parser.parse_args()
    print(f"{'N':>6} {'threads':>7} {'folded ms':>10} {'cosine ms':>10} {'ratio':>6} "
          f"{'rel. diff':>10}")
    rng = np.random.default_rng(11)
    for n in args.sizes:
        pressure = rng.random((n, n))
        for threads in args.threads:
            operator = HalfSpace((n, n), 1.0 / n, periodic=True, mirror=True, threads=threads,
                                 planner_effort="FFTW_MEASURE")
            cosine = CosineTransform2((n, n), threads=threads, planner_effort="FFTW_MEASURE")
            multiplier = operator.kernel_spectrum / cosine.size
            folded_out = np.empty((n, n))

            def folded():
                operator._apply(pressure, folded_out)

            def by_cosines():
                cosine.real_buffer[...] = pressure
                cosine.execute_forward()
                cosine.spectrum_buffer *= multiplier
                cosine.execute_inverse()

            folded_ms, cosine_ms = median_ms(folded), median_ms(by_cosines)
            difference = (np.abs(folded_out - cosine.output_buffer).max()
                          / np.abs(cosine.output_buffer).max())
            print(f"{n:>6} {threads:>7} {folded_ms:>10.2f} {cosine_ms:>10.2f} "
                  f"{cosine_ms / folded_ms:>6.2f} {difference:>10.1e}", flush=True)


if __name__ == "__main__":
    main()
