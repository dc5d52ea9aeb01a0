"""How long a prediction without a solve takes (``validation.predict_errors``), per scan size.

A periodic self-affine scan (H = 0.7, rms slope 0.1, rolloff at an eighth of its side, 1 nm
pixels) as a height array, predicted at the check's default pressures with E* = 115 GPa, in a
process of its own. Prints per size: the call's wall time, the whole process's wall time (the
scan's generation and the imports included), its peak resident memory, and whether the scan lies
inside the atlas (a magnification above the atlas' makes a large scan fall outside: its
descriptors are computed all the same).

Usage::

    python benchmarks/bench_predict.py [--sizes 2048,8192]
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time

_ONE = """
import sys, time, validation
n = int(sys.argv[1])
heights = validation.self_affine_surface(n, hurst=0.7, rms_slope=0.1, L=float(n), rolloff=n / 8,
                                         seed=1) * 1e-9
start = time.perf_counter()
prediction = validation.predict_errors(heights, spacing="1nm", e_star="115GPa", cache=sys.argv[2])
print(f"{time.perf_counter() - start:.1f} {'inside' if not prediction.outside else 'outside'}")
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="2048,8192")
    args = parser.parse_args()
    print("  size  call [s]  process [s]  peak RSS [MB]  atlas")
    for n in (int(s) for s in args.sizes.split(",")):
        with tempfile.TemporaryDirectory() as cache:
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-c", _ONE, str(n), cache], check=True,
                                  capture_output=True, text=True)
            wall = time.perf_counter() - start
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
        call, where = done.stdout.split()[-2:]
        print(f"{n:6d}  {float(call):8.1f}  {wall:11.1f}  {peak:13.0f}  {where}", flush=True)


if __name__ == "__main__":
    main()
