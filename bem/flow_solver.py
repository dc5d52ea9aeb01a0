"""The linear solve of the Reynolds flow system (:mod:`bem.flow`): sparse LU for gaps up to
:data:`DIRECT_SOLVE_LIMIT` cells, multigrid-preconditioned conjugate gradients above.
"""

from __future__ import annotations

import warnings

import numpy as np

from bem.warnings import ConvergenceWarning

__all__ = ["DIRECT_SOLVE_LIMIT", "MULTIGRID_MAX_ITERATIONS", "MULTIGRID_TOLERANCE"]


#: Gaps of up to this many cells are solved by sparse LU, larger ones by multigrid-preconditioned
#: conjugate gradients (:func:`_solve_pressure`): the LU factor of a 2048^2 gap took 4.9 GB
#: (84 s per direction), the multigrid 2.7 GB (docs/guide/benchmarks.md, "The leakage reference").
DIRECT_SOLVE_LIMIT = 1024 * 1024
#: Relative residual ``||b - A p|| / ||b||`` of the multigrid solve (on the Jacobi-scaled
#: system). The aperture comes from the dissipation, whose error is of second order in the
#: pressure's: on an elastic contact gap near percolation (512^2, 29 % contact) it agreed with
#: the sparse LU to 1e-12 (75 and 133 iterations, open and periodic); 1e-8 left 3e-6 on a gap
#: whose g^3 spans more decades (tests/test_hydraulic_aperture.py).
MULTIGRID_TOLERANCE = 1e-9
#: Most conjugate-gradient iterations of the multigrid solve.
MULTIGRID_MAX_ITERATIONS = 1000


def _solve_pressure(matrix, rhs: np.ndarray, *, cells: int) -> np.ndarray:
    """``A p = b`` for the symmetric positive-definite flow system of a gap of ``cells`` cells.

    Up to :data:`DIRECT_SOLVE_LIMIT` cells by sparse LU (SuperLU): fill-reducing order by
    minimum degree on the symmetric pattern (``MMD_AT_PLUS_A``, half the fill of the default
    column order on these grids), no pivoting (``diag_pivot_thresh=0``: elimination of a
    symmetric positive definite matrix is stable in any order). Chosen over algebraic multigrid
    there by measurement (benchmarks/bench_leakage.py): exact whatever the contrast of g^3
    (which spans 20 decades in a contact gap), and faster at 256^2 and 512^2 and near
    percolation. Above, the factor outgrows the memory (4.9 GB at 2048^2), and the system is
    solved by conjugate gradients preconditioned with one V-cycle of pyAMG's smoothed
    aggregation, built on the Jacobi-scaled matrix ``D A D`` (``D = diag(A)^-1/2``) with the
    scaled constant ``1/D`` as its near-null space and the evolution strength of connection
    (near percolation, where thin necks carry the flow, the classical symmetric strength needed
    5-7 times the iterations), to :data:`MULTIGRID_TOLERANCE` (``matrix`` is scaled in place). A
    multigrid solve that stops short of it warns (:class:`bem.warnings.ConvergenceWarning`) and
    returns its last iterate.
    """
    import scipy.sparse.linalg   # where used (start-up of a warm report)

    if cells <= DIRECT_SOLVE_LIMIT:
        factor = scipy.sparse.linalg.splu(matrix.tocsc(), permc_spec="MMD_AT_PLUS_A",
                                          diag_pivot_thresh=0.0,
                                          options={"SymmetricMode": True})
        return factor.solve(rhs)
    import pyamg

    # D A D in place (no copies of a matrix of 20 million entries at 2048^2)
    scaled = matrix.tocsr()
    scale = 1.0 / np.sqrt(scaled.diagonal())
    scaled.data *= np.repeat(scale, np.diff(scaled.indptr))
    scaled.data *= scale[scaled.indices]
    hierarchy = pyamg.smoothed_aggregation_solver(scaled, B=(1.0 / scale)[:, None],
                                                  strength="evolution")
    residuals: list[float] = []
    solution = hierarchy.solve(rhs * scale, tol=MULTIGRID_TOLERANCE, accel="cg",
                               maxiter=MULTIGRID_MAX_ITERATIONS, residuals=residuals)
    reached = residuals[-1] / residuals[0] if residuals and residuals[0] > 0 else 0.0
    if not reached <= MULTIGRID_TOLERANCE:
        warnings.warn(f"hydraulic_aperture: the multigrid solve of {cells} cells stopped at a "
                      f"relative residual {reached:.3g} > {MULTIGRID_TOLERANCE:g} after "
                      f"{len(residuals) - 1} iterations", ConvergenceWarning, stacklevel=3)
    return solution * scale
