"""One V-cycle of a pyAMG multigrid hierarchy as a preconditioner, smoothed by the compiled
Gauss-Seidel sweeps of :mod:`bem.leakage.gauss_seidel`, with the coarsest level's exact solve held as
a symmetric factor (the Reynolds solves' multigrid, :mod:`bem.leakage.flow_solver`)."""

from __future__ import annotations

import numba
import numpy as np

from bem.leakage.gauss_seidel import backward_sweep, forward_sweep

__all__ = ["CoarseFactor", "VCycle"]


class VCycle:
    """One V-cycle of a pyAMG hierarchy from a zero guess, as ``cycle @ residual``: its levels'
    interpolations and coarse solver, in pyAMG's order, and its Gauss-Seidel smoothing by the
    compiled sweeps of :mod:`bem.leakage.gauss_seidel`, which release the GIL (pyAMG's hold it, and
    the contact path beside the leakage waits on every sweep): one forward sweep before the
    coarse correction and one backward after it, or with ``symmetric`` a forward and a
    backward sweep on either side (pyAMG's smoothed-aggregation default). Without the residual
    norms that pyAMG's own preconditioner computes around each cycle for its stopping test
    (two products with the finest matrix and three norms per application, a tenth of a 1024^2
    solve, and BLAS calls whose threads then spin on the path's cores). With ``factor_options``
    (SuperLU's, for :class:`CoarseFactor`) the coarsest level is factored at once and solved
    by its symmetric factor instead of the hierarchy's own coarse solver."""

    def __init__(self, hierarchy, *, symmetric: bool = False,
                 factor_options: dict | None = None) -> None:
        self.levels, self.coarse_solver = hierarchy.levels, hierarchy.coarse_solver
        if factor_options is not None:
            factor = CoarseFactor(self.levels[-1].A, factor_options)
            self.coarse_solver = lambda matrix, right: factor.solve(right)
        self.before = (forward_sweep, backward_sweep) if symmetric else (forward_sweep,)
        self.after = (forward_sweep, backward_sweep) if symmetric else (backward_sweep,)

    def __matmul__(self, residual: np.ndarray) -> np.ndarray:
        return self._cycle(0, residual)

    def _cycle(self, index: int, right: np.ndarray) -> np.ndarray:
        level = self.levels[index]
        x = np.zeros_like(right)
        for sweep in self.before:
            sweep(level.A, x, right)
        coarse = level.R @ (right - level.A @ x)
        if index == len(self.levels) - 2:
            correction = self.coarse_solver(self.levels[-1].A, coarse)
        else:
            correction = self._cycle(index + 1, coarse)
        x += level.P @ correction
        for sweep in self.after:
            sweep(level.A, x, right)
        return x


class CoarseFactor:
    """The exact solve of a symmetric positive-definite sparse matrix by SuperLU's factor,
    held as ``P A P^T = L D L^T``: the unit lower factor L (compressed columns) and the
    diagonal D of ``U = D L^T``, solved by compiled substitutions.

    SuperLU keeps the room it reserved for the fill with its factor: 285 MB for the 3.2
    million entries of L and U (38 MB in compressed columns) on the 256^2 coarsest level of a
    2048^2 gap, for the whole solve; L alone takes 19 MB, and a substitution pair about the
    time of SuperLU's solve (11 against 10 ms there). With ``options`` that keep the
    elimination symmetric (one symmetric order, ``diag_pivot_thresh=0``, no pivoting, as the
    Reynolds solves' :data:`bem.leakage.flow_solver._LU_OPTIONS`) U is ``D L^T`` to rounding; should
    the rows still be permuted otherwise, SuperLU's own factor is kept and solves.
    """

    def __init__(self, matrix, options: dict) -> None:
        import scipy.sparse.linalg

        lu = scipy.sparse.linalg.splu(matrix.tocsc(), **options)
        self._lu = None
        if not np.array_equal(lu.perm_r, lu.perm_c):
            self._lu = lu
            return
        lower, upper = lu.L, lu.U
        self._diagonal = upper.diagonal()
        del upper
        self._indptr, self._indices, self._data = lower.indptr, lower.indices, lower.data
        self._order = np.array(lu.perm_r)

    def solve(self, right: np.ndarray) -> np.ndarray:
        """``A^-1 right`` (a fresh array)."""
        if self._lu is not None:
            return self._lu.solve(right)
        out = np.empty(right.shape)
        _substitutions(self._indptr, self._indices, self._data, self._diagonal, self._order,
                       np.ascontiguousarray(right, dtype=np.float64), out)
        return out


@numba.njit(nogil=True, cache=True)
def _substitutions(indptr, indices, data, diagonal, order, right, out):   # pragma: no cover
    """``out = P^T L^-T D^-1 L^-1 P right`` for the unit lower factor L in compressed columns
    (entries on and above the diagonal skipped) and the permutation ``(P b)[order[i]] = b[i]``:
    forward by columns of L, backward by columns of L as rows of ``L^T``."""
    size = right.size
    work = np.empty(size)
    for i in range(size):
        work[order[i]] = right[i]
    for column in range(size):
        value = work[column]
        if value != 0.0:
            for entry in range(indptr[column], indptr[column + 1]):
                row = indices[entry]
                if row > column:
                    work[row] -= data[entry] * value
    for i in range(size):
        work[i] /= diagonal[i]
    for column in range(size - 1, -1, -1):
        total = work[column]
        for entry in range(indptr[column], indptr[column + 1]):
            row = indices[entry]
            if row > column:
                total -= data[entry] * work[row]
        work[column] = total
    for i in range(size):
        out[i] = work[order[i]]
