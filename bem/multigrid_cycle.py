"""One V-cycle of a pyAMG multigrid hierarchy as a preconditioner, smoothed by the compiled
Gauss-Seidel sweeps of :mod:`bem.gauss_seidel` (the Reynolds solves' multigrid,
:mod:`bem.flow_solver`)."""

from __future__ import annotations

import numpy as np

from bem.gauss_seidel import backward_sweep, forward_sweep

__all__ = ["VCycle"]


class VCycle:
    """One V-cycle of a pyAMG hierarchy from a zero guess, as ``cycle @ residual``: its levels'
    interpolations and coarse solver, in pyAMG's order, and its Gauss-Seidel smoothing by the
    compiled sweeps of :mod:`bem.gauss_seidel`, which release the GIL (pyAMG's hold it, and
    the contact path beside the leakage waits on every sweep): one forward sweep before the
    coarse correction and one backward after it, or with ``symmetric`` a forward and a
    backward sweep on either side (pyAMG's smoothed-aggregation default). Without the residual
    norms that pyAMG's own preconditioner computes around each cycle for its stopping test
    (two products with the finest matrix and three norms per application, a tenth of a 1024^2
    solve, and BLAS calls whose threads then spin on the path's cores)."""

    def __init__(self, hierarchy, *, symmetric: bool = False) -> None:
        self.levels, self.coarse_solver = hierarchy.levels, hierarchy.coarse_solver
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
