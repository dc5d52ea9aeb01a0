"""Gauss-Seidel sweeps of a sparse matrix in CSR form, compiled, releasing the GIL.

The smoother of the Reynolds solves' multigrid (:mod:`bem.flow_solver`). pyAMG's own sweep
(``pyamg.relaxation.relaxation.gauss_seidel``) computes the same iterate but holds the GIL for
the whole sweep (tens of milliseconds on a 1024^2 gap), and a check solves its leakage in a
thread beside the contact path (:mod:`bem.background_flow`), whose Python steps between
transforms then wait for every sweep to end. This sweep takes the rows in the same order and
sums each row in the same order, so its iterate is pyAMG's to the last bit.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["backward_sweep", "forward_sweep"]


@numba.njit(nogil=True, cache=True)
def _sweep(indptr, indices, data, x, b, first, stop, step):   # pragma: no cover (compiled)
    for row in range(first, stop, step):
        total = 0.0
        diagonal = 0.0
        for entry in range(indptr[row], indptr[row + 1]):
            column = indices[entry]
            if column == row:
                diagonal = data[entry]
            else:
                total += data[entry] * x[column]
        if diagonal != 0.0:
            x[row] = (b[row] - total) / diagonal


def _rows(matrix):
    """The CSR arrays of ``matrix`` (a TypeError for any other form: BSR's blocks, say, would
    be swept as something else)."""
    if getattr(matrix, "format", None) != "csr":
        raise TypeError(f"matrix must be a scipy.sparse matrix in CSR form, got "
                        f"{type(matrix).__name__} ({getattr(matrix, 'format', 'not sparse')})")
    return matrix.indptr, matrix.indices, matrix.data


def forward_sweep(matrix, x: np.ndarray, b: np.ndarray) -> None:
    """One Gauss-Seidel sweep of ``matrix @ x = b`` over the rows in increasing order, in
    place: ``x_i <- (b_i - sum_{j != i} a_ij x_j) / a_ii`` with the rows before ``i`` already
    updated (rows with a zero diagonal are left as they are).

    Parameters
    ----------
    matrix : scipy.sparse.csr_matrix or csr_array
        Square matrix in CSR form (float64 entries).
    x : numpy.ndarray
        Current iterate (float64, contiguous), updated in place.
    b : numpy.ndarray
        Right-hand side (float64).

    Raises
    ------
    TypeError
        ``matrix`` not in CSR form.
    """
    _sweep(*_rows(matrix), x, b, 0, matrix.shape[0], 1)


def backward_sweep(matrix, x: np.ndarray, b: np.ndarray) -> None:
    """One Gauss-Seidel sweep over the rows in decreasing order, in place (otherwise as
    :func:`forward_sweep`): after a forward sweep, the symmetric sweep that keeps a V-cycle
    symmetric."""
    _sweep(*_rows(matrix), x, b, matrix.shape[0] - 1, -1, -1)
