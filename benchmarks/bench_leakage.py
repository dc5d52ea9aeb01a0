"""Time of the Reynolds leakage reference (bem.hydraulic_aperture) and the solver choice.

Realistic contact gaps: one periodic self-affine surface per grid (H = 0.8, rolloff L/4, short
cutoff 4 h, rms slope 0.1, seed 1, L = 1) pressed by the periodic BEM (tol 1e-9) to nominal
pressures 0.003, 0.008 and 0.015 E* (about 6 %, 14 % and 27 % contact, the last near the
percolation threshold); the gap is the solved gap, zero on the contact set. On each gap the
aperture is solved for flow along x, periodic and not, by

* ``direct``: ``bem.hydraulic_aperture`` (sparse LU by SuperLU, minimum-degree order on the
  symmetric pattern, no pivoting);
* ``amg-cg``: conjugate gradients preconditioned by one V-cycle of pyamg's smoothed aggregation
  (symmetric-strength default), scipy's ``cg`` to a relative residual of 1e-8;
* ``amg-evo``: the best multigrid found: pyamg smoothed aggregation with evolution strength on
  the Jacobi-scaled matrix, a sparse LU on the coarsest level, conjugate gradients stopped when
  the energy-norm error estimate (the sum of the last 4 energy drops, Strakos & Tichy) is below
  1e-8 of the dissipation.

Each row gives the time (matrix assembly included; the multigrid's setup included), the
iterations and the aperture's relative difference from ``direct`` (the multigrid's stopping
error). Solved gaps are cached in ``--cache`` (default bench-out/leakage-cache; not committed).

Measured 2026-11-24 on two cores shared with about four other jobs, OpenBLAS limited to one
thread (``OPENBLAS_NUM_THREADS=1``), flow along x; time [s] (iterations), periodic / non-periodic:

    N     contact  direct        amg-evo                  amg-cg
    256    7 %     0.54 / 0.87   0.62 (16) / 0.68 (22)    0.77 (40) / 0.56 (27)
    256   17 %     0.32 / 0.33   0.54 (17) / 0.68 (18)    1.73 (117) / 0.91 (52)
    256   29 %     0.26 / 0.18   1.07 (56) / 0.60 (38)    2.58 (255) / 0.95 (95)
    512    6 %     2.23 / 2.55   2.55 (14) / 2.86 (17)    7.11 (92) / 2.83 (47)
    512   16 %     1.46 / 1.37   2.97 (37) / 2.43 (30)    14.8 (332) / 9.22 (152)
    512   29 %     1.48 / 1.16   4.61 (61) / 3.02 (49)    24.2 (500, cap) / 9.98 (297)
    1024   6 %     8.04 / 5.64   7.64 (24) / 9.86 (26)    -
    1024  16 %     3.97 / 5.94   11.1 (40) / 13.7 (66)    -
    1024  28 %     5.13 / 6.60   18.5 (63) / 16.1 (51)    -

Every multigrid result agreed with ``direct`` to 1e-8 or better except amg-evo at 1024^2, 28 %,
periodic: 2.7e-3, its energy-norm estimate stopping on a plateau. With OpenBLAS's default two
threads on the loaded machine the multigrid rows took 3-10 times longer (the preconditioner's
vector norms and the CG dot products wait for a busy second core), the direct rows up to 2x.

The direct solve is exact whatever the contrast of g^3 (20 decades between the widest gap and
the narrowest open pixel next to a contact), fastest or equal everywhere but at 1024^2 with
little contact (where the best multigrid is within its scatter), and 2-3 times faster near
percolation, where multigrid needs Jacobi scaling and evolution strength not to fail and then
40-100 iterations. ``bem.hydraulic_aperture`` therefore uses the direct solve up to 1024^2
cells; above, where the factor outgrows the memory (4.9 GB at 2048^2), smoothed-aggregation
multigrid with conjugate gradients (``bem.flow_solver.DIRECT_SOLVE_LIMIT``). 1024^2 takes 4-8 s here, not the
3 s hoped for.

Usage: ``nice python benchmarks/bench_leakage.py [--sizes 256 512 1024] [--solvers direct
amg-evo amg-cg] [--cache DIR]``
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

import bem
from bem.flow import _dissipation, _flow_system, spanning_cells
from validation import self_affine_surface

LOADS = (0.003, 0.008, 0.015)
SOLVERS = ("direct", "amg-evo", "amg-cg")


def contact_gap(n: int, load: float, cache: pathlib.Path) -> np.ndarray:
    """The solved periodic BEM gap (0 on the contact set) of the benchmark surface."""
    path = cache / f"gap_n{n}_W{load}.npy"
    if path.exists():
        return np.load(path)
    heights = self_affine_surface(n, hurst=0.8, rms_slope=0.1, rolloff=0.25,
                                  short_cutoff=4.0 / n, seed=1)
    solution = bem.solve_contact(heights, 1.0 / n, load=load, periodic=True)
    gap = np.where(solution.contact, 0.0, np.maximum(solution.gap, 0.0))
    cache.mkdir(parents=True, exist_ok=True)
    np.save(path, gap)
    return gap


def _energy_cg(matrix, rhs, preconditioner, dissipation, *, tol=1e-8, max_iter=500, delay=4):
    """Preconditioned CG stopped when the sum of the last ``delay`` energy drops
    ``alpha_k r_k.z_k`` is below ``tol`` times the dissipation of the iterate."""
    x, r = np.zeros_like(rhs), rhs.copy()
    z = preconditioner(r)
    p, rz, drops = z.copy(), float(r @ z), []
    for iteration in range(1, max_iter + 1):
        ap = matrix @ p
        alpha = rz / float(p @ ap)
        x += alpha * p
        r -= alpha * ap
        drops.append(alpha * rz)
        if len(drops) >= delay and sum(drops[-delay:]) <= tol * dissipation(x):
            return x, iteration
        z = preconditioner(r)
        rz_next = float(r @ z)
        p = z + (rz_next / rz) * p
        rz = rz_next
    return x, max_iter


def multigrid(gap: np.ndarray, periodic: bool, variant: str) -> tuple[float, int]:
    """h_eff / max(gap) and the iterations by one of the multigrid variants."""
    import pyamg

    k = (gap / gap.max()) ** 3
    matrix, rhs, faces, boundary = _flow_system(k, spanning_cells(k > 0, periodic=periodic),
                                                periodic)
    if variant == "amg-cg":
        solver = pyamg.smoothed_aggregation_solver(matrix)
        count = [0]
        pressure, _ = scipy.sparse.linalg.cg(
            matrix, rhs, rtol=1e-8, maxiter=500, M=solver.aspreconditioner(cycle="V"),
            callback=lambda _: count.__setitem__(0, count[0] + 1))
        iterations = count[0]
    else:
        scale = 1.0 / np.sqrt(matrix.diagonal())
        diagonal = scipy.sparse.dia_array((scale, 0), shape=matrix.shape)
        scaled = (diagonal @ matrix @ diagonal).tocsr()
        solver = pyamg.smoothed_aggregation_solver(scaled, B=(1.0 / scale)[:, None],
                                                   strength="evolution", coarse_solver="splu")
        y, iterations = _energy_cg(scaled, rhs * scale,
                                   solver.aspreconditioner(cycle="V").matvec,
                                   lambda y: _dissipation(y * scale, faces, boundary))
        pressure = y * scale
    rows, columns = k.shape
    return float(np.cbrt(_dissipation(pressure, faces, boundary) * columns / rows)), iterations


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[256, 512, 1024])
    parser.add_argument("--solvers", nargs="*", default=list(SOLVERS), choices=SOLVERS)
    parser.add_argument("--cache", type=pathlib.Path, default=pathlib.Path("bench-out/leakage-cache"))
    args = parser.parse_args()
    print(f"{'size':>6} {'contact':>8} {'periodic':>8} {'solver':>8} {'time [s]':>9} {'its':>5} "
          f"{'h_eff/max g':>12} {'rel. diff':>9}", flush=True)
    for n in args.sizes:
        for load in LOADS:
            gap = contact_gap(n, load, args.cache)
            for periodic in (True, False):
                reference = None
                for solver in args.solvers:
                    start = time.perf_counter()
                    if solver == "direct":
                        h = bem.hydraulic_aperture(gap, 1.0 / n, periodic=periodic) / gap.max()
                        iterations = 0
                    else:
                        h, iterations = multigrid(gap, periodic, solver)
                    elapsed = time.perf_counter() - start
                    reference = h if reference is None else reference
                    print(f"{n:6d} {np.mean(gap == 0):8.3f} {str(periodic):>8} {solver:>8} "
                          f"{elapsed:9.2f} {iterations:5d} {h:12.6g} {h / reference - 1:9.1e}",
                          flush=True)


if __name__ == "__main__":
    main()
