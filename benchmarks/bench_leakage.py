"""Time of the Reynolds leakage reference (bem.hydraulic_aperture) and the solver choice.

Realistic contact gaps: one periodic self-affine surface per grid (H = 0.8, rolloff L/4, short
cutoff 4 h, rms slope 0.1, seed 1, L = 1) pressed by the periodic BEM (tol 1e-9) to nominal
pressures 0.003, 0.008 and 0.015 E* (about 6 %, 14 % and 27 % contact, the last near the
percolation threshold); the gap is the solved gap, zero on the contact set. On each gap the
aperture is solved for flow along x, periodic and not, by

* ``direct``: ``bem.hydraulic_aperture`` with every gap solved by sparse LU (SuperLU,
  minimum-degree order on the symmetric pattern, no pivoting);
* ``multigrid``: ``bem.hydraulic_aperture`` with every gap solved by conjugate gradients
  preconditioned by the multigrid of ``bem.leakage.flow_solver`` (2 x 2 blocks of pixels, split where
  their connections are weak, as aggregates, piecewise-constant interpolation, Gauss-Seidel,
  sparse LU on the coarsest grid; periodic or not; stopped when the dissipation is known);
* ``amg-evo``: algebraic coarsening for comparison: pyamg smoothed aggregation with evolution
  strength on the Jacobi-scaled matrix, a sparse LU on the coarsest level, conjugate gradients
  to a relative residual of 1e-7.

Each row gives the time (matrix assembly and the multigrid's setup included), the iterations
where known and the aperture's relative difference from ``direct``. Solved gaps are cached in
``--cache`` (default bench-out/leakage-cache; not committed). ``bem.hydraulic_aperture`` solves
gaps up to ``bem.leakage.flow_solver.DIRECT_SOLVE_LIMIT`` cells (128^2, periodic or not)
directly and larger ones by ``multigrid``; the measured rows are in docs/guide/benchmarks.md,
"The leakage reference".

Usage: ``python benchmarks/bench_leakage.py [--sizes 256 512 1024] [--solvers direct
multigrid amg-evo] [--cache DIR]``
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

import bem
from bem.leakage.flow import _dissipation, _flow_system, spanning_cells
from validation import self_affine_surface

LOADS = (0.003, 0.008, 0.015)
SOLVERS = ("direct", "multigrid", "amg-evo")


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


def project_solver(gap: np.ndarray, periodic: bool, direct: bool) -> float:
    """h_eff / max(gap) by ``bem.hydraulic_aperture`` with every gap solved by sparse LU
    (``direct``) or by its multigrid."""
    import bem.leakage.flow_solver

    names = ("DIRECT_SOLVE_LIMIT",)
    limits = [getattr(bem.leakage.flow_solver, name) for name in names]
    for name in names:
        setattr(bem.leakage.flow_solver, name, gap.size if direct else 0)
    try:
        return bem.hydraulic_aperture(gap, 1.0, periodic=periodic) / gap.max()
    finally:
        for name, limit in zip(names, limits):
            setattr(bem.leakage.flow_solver, name, limit)


def algebraic_multigrid(gap: np.ndarray, periodic: bool) -> tuple[float, int]:
    """h_eff / max(gap) and the iterations by smoothed aggregation with evolution strength."""
    import pyamg

    k = (gap / gap.max()) ** 3
    matrix, rhs, faces, boundary = _flow_system(k, spanning_cells(k > 0, periodic=periodic),
                                                periodic)
    scale = 1.0 / np.sqrt(matrix.diagonal())
    matrix.scale(scale)   # (the system held by its faces, bem.leakage.face_matrix)
    scaled = matrix.tocsr()
    solver = pyamg.smoothed_aggregation_solver(scaled, B=(1.0 / scale)[:, None],
                                               strength="evolution", coarse_solver="splu")
    residuals: list[float] = []
    y = solver.solve(rhs * scale, tol=1e-7, accel="cg", maxiter=1000, residuals=residuals)
    pressure = y * scale
    rows, columns = k.shape
    return (float(np.cbrt(_dissipation(pressure, faces, boundary) * columns / rows)),
            len(residuals) - 1)


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
                    if solver == "amg-evo":
                        h, iterations = algebraic_multigrid(gap, periodic)
                    else:
                        h = project_solver(gap, periodic, direct=solver == "direct")
                        iterations = 0
                    elapsed = time.perf_counter() - start
                    reference = h if reference is None else reference
                    print(f"{n:6d} {np.mean(gap == 0):8.3f} {str(periodic):>8} {solver:>8} "
                          f"{elapsed:9.2f} {iterations:5d} {h:12.6g} {h / reference - 1:9.1e}",
                          flush=True)


if __name__ == "__main__":
    main()
