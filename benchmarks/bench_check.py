"""How long ``python -m validation check`` takes on one scan, and how much memory.

A synthetic instrument scan per size (a self-affine surface, H = 0.8, rms slope 0.3, cut as a
non-periodic window, with 1 % white noise at the pixel scale as an AFM adds), written as a
Gwyddion ASCII matrix with its size (1 nm pixels), then the check with twelve pressures from
light to heavy contact, every model and the leakage, with the command's defaults (the scan
in-process, the models beside the reference in a second thread), in a fresh process with an
empty cache (so FFTW plans too, as on a machine's first check). Prints per size: wall time,
process time (the command and its workers), the peak resident memory of the largest process,
and the share of verdict cells decided by the band alone, at both tolerances (from
verdicts.csv); first the machine it ran on (CPU model and count, library versions).

Usage::

    python benchmarks/bench_check.py [--sizes 512,1024,2048] [--short-cutoff 8px] [--keep DIR]
                                     [--device gpu]
"""

from __future__ import annotations

import argparse
import csv
import os
import pathlib
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

from validation import self_affine_surface
from validation.campaigns.bench import machine_description
from validation.surfaces.topography import write_gwyddion_ascii


def make_scan(path: pathlib.Path, n: int, seed: int = 1) -> pathlib.Path:
    """The benchmark scan: n x n pixels of 1 nm, heights in nm."""
    heights = self_affine_surface(n, hurst=0.8, rms_slope=0.3, L=float(n), window=2 * n,
                                  seed=seed)
    rng = np.random.default_rng(seed)
    heights = heights + 0.01 * np.std(heights) * rng.standard_normal(heights.shape)
    write_gwyddion_ascii(path, heights, spacing=1.0, unit="nm")
    return path


def decided(verdicts: pathlib.Path) -> str:
    with verdicts.open(newline="") as stream:
        table = list(csv.DictReader(stream))
    out = []
    for tolerance in sorted({row["tolerance"] for row in table}, key=float):
        cells = [row["verdict"] for row in table if row["tolerance"] == tolerance]
        share = sum(v != "undecided" for v in cells) / max(len(cells), 1)
        out.append(f"{100 * share:.0f} % at {tolerance}")
    return ", ".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="512,1024,2048")
    parser.add_argument("--short-cutoff", default=None)
    parser.add_argument("--keep", default=None, help="keep the scans and reports in DIR")
    parser.add_argument("--device", default=None, choices=("cpu", "gpu"),
                        help="where the reference's contact problems are solved (default: cpu)")
    args = parser.parse_args(argv)
    folder = pathlib.Path(args.keep or tempfile.mkdtemp(prefix="bench-check-"))
    folder.mkdir(parents=True, exist_ok=True)
    print(f"machine: {machine_description()}")
    print(f"{'size':>6} {'wall [s]':>9} {'process [s]':>12} {'peak RSS [MB]':>14}  decided")
    for n in (int(s) for s in args.sizes.split(",")):
        scan = make_scan(folder / f"scan-{n}.txt", n)
        out, cache = folder / f"check-{n}", folder / f"cache-{n}"
        command = [sys.executable, "-m", "validation", "check", str(scan), "--e-star", "115GPa",
                   "--out", str(out), "--cache", str(cache), "--quiet"]
        if args.short_cutoff:
            command += ["--short-cutoff", args.short_cutoff]
        if args.device:
            command += ["--device", args.device]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(command, check=True, env=dict(os.environ))
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        peak = after.ru_maxrss / 1024   # kB on Linux: the largest child process so far
        print(f"{n:>6} {wall:>9.1f} {cpu:>12.1f} {peak:>14.0f}  {decided(out / 'verdicts.csv')}",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
