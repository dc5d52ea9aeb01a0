"""The work arrays of the contact solvers (the contact iteration of
:mod:`bem.contact.constrained_cg`, the stiffness solve of :mod:`bem.contact.stiffness`): a grid's
preallocated workspace with its preconditioners, and values written at scattered points of an FFT
buffer. Their vector operations are in :mod:`bem.common.vectors`.
"""

from __future__ import annotations

import numpy as np

from bem.contact.coarse_correction import CoarseCorrection
from bem.elastic.halfspace import HalfSpace
from bem.contact.preconditioner import InverseKernel


class _Workspace:
    """Preallocated arrays of one grid, reused by every iteration (and along a load path)."""

    def __init__(self, shape: tuple[int, int], xp=np) -> None:
        self.shape, self.xp = shape, xp   # xp: the array module of the operator's device
        self._u: np.ndarray | None = None
        self.g = xp.empty(shape)  # u - z, the gap but for a constant
        self.work = xp.empty(shape)  # scratch of the direct sums
        self.flag = xp.empty(shape, dtype=bool)
        self._inverse_kernels: dict[str, InverseKernel] = {}   # by precision
        self.preconditioned = True  # whether the last solve used the preconditioner
        self.correction: CoarseCorrection | None = None  # its coarse correction at the end

    @property
    def u(self) -> np.ndarray:
        """The displacement of the iterate (allocated when the last one was handed out)."""
        if self._u is None:
            self._u = self.xp.empty(self.shape)
        return self._u

    def take_displacement(self) -> np.ndarray:
        """The displacement array, now the caller's: the next solve allocates a new one."""
        u, self._u = self.u, None
        return u

    def inverse_kernel(self, operator: HalfSpace, precision: str = "single") -> InverseKernel:
        """The preconditioner of ``operator``'s grid in ``precision``, built on first use: single
        for the contact iteration, double for the stiffness solve, whose stiffness (the sum of
        its solution) keeps the conjugate gradients' second-order accuracy only with a fixed
        symmetric preconditioner (with the single one its error grew from 0.002 to 0.07 of the
        tolerance on a WM load path, benchmarks/bench_solver_tolerance.py)."""
        kernel = self._inverse_kernels.get(precision)
        if kernel is None:
            kernel = self._inverse_kernels[precision] = InverseKernel(
                operator.shape, operator.spacing, e_star=operator.e_star,
                threads=operator.threads, device=operator.device, precision=precision)
        return kernel


class _Scatter:
    """Values on a set of grid points written into a work buffer that is zero elsewhere (an FFT
    input), clearing only the points written the time before.

    ``flat`` is the buffer as a flat array whose rows are ``row_stride`` apart (the zero-padded
    input of the non-periodic operator has twice as many columns as the grid).
    """

    def __init__(self, flat: np.ndarray, row_stride: int, columns: int) -> None:
        self.flat, self.row_stride, self.columns = flat, row_stride, columns
        self._written: np.ndarray | None = None  # None: unknown contents, clear everything

    def positions(self, indices: np.ndarray) -> np.ndarray:
        """Buffer positions of flat grid indices."""
        if self.row_stride == self.columns:
            return indices
        rows, columns = np.divmod(indices, self.columns)
        rows *= self.row_stride
        rows += columns
        return rows

    def write(self, positions: np.ndarray, values: np.ndarray | float) -> None:
        if self._written is None:
            self.flat.fill(0.0)
        elif self._written is not positions:
            self.flat[self._written] = 0.0
        self.flat[positions] = values
        self._written = positions

    def forget(self) -> None:
        """Someone else wrote the buffer: clear all of it next time."""
        self._written = None
