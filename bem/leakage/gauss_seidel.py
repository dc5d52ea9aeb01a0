"""Gauss-Seidel sweeps of a sparse matrix in CSR form (or held by its faces,
:class:`bem.leakage.face_matrix.FaceMatrix`), compiled, releasing the GIL.

The smoother of the Reynolds solves' multigrid (:mod:`bem.leakage.flow_solver`). pyAMG's own sweep
(``pyamg.relaxation.relaxation.gauss_seidel``) computes the same iterate but holds the GIL for
the whole sweep (tens of milliseconds on a 1024^2 gap), and a check solves its leakage in a
thread beside the contact path (:mod:`bem.leakage.background_flow`), whose Python steps between
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


def _swept(matrix, x: np.ndarray, b: np.ndarray, forward: bool) -> None:
    """The sweep of ``matrix`` in CSR form or held by its faces (a TypeError for any other
    form: BSR's blocks, say, would be swept as something else)."""
    form = getattr(matrix, "format", None)
    if form == "faces":
        matrix.sweep(x, b, forward=forward)
    elif form == "csr":
        rows = matrix.shape[0]
        _sweep(matrix.indptr, matrix.indices, matrix.data, x, b,
               *((0, rows, 1) if forward else (rows - 1, -1, -1)))
    else:
        raise TypeError(f"matrix must be a scipy.sparse matrix in CSR form or a "
                        f"bem.leakage.face_matrix.FaceMatrix, got {type(matrix).__name__} "
                        f"({form or 'not sparse'})")


def forward_sweep(matrix, x: np.ndarray, b: np.ndarray) -> None:
    """One Gauss-Seidel sweep of ``matrix @ x = b`` over the rows in increasing order, in
    place: ``x_i <- (b_i - sum_{j != i} a_ij x_j) / a_ii`` with the rows before ``i`` already
    updated (rows with a zero diagonal are left as they are).

    Parameters
    ----------
    matrix : scipy.sparse.csr_matrix, csr_array or bem.leakage.face_matrix.FaceMatrix
        Square matrix in CSR form (float64 entries), or a 5-point matrix held by its faces
        (swept in the order of its unknowns, each row summed above, left, right, below: in the
        order of its columns but across a periodic edge, where the sum differs from the CSR
        sweep's by rounding).
    x : numpy.ndarray
        Current iterate (float64, contiguous), updated in place.
    b : numpy.ndarray
        Right-hand side (float64).

    Raises
    ------
    TypeError
        ``matrix`` neither in CSR form nor held by its faces.
    """
    _swept(matrix, x, b, True)


def backward_sweep(matrix, x: np.ndarray, b: np.ndarray) -> None:
    """One Gauss-Seidel sweep over the rows in decreasing order, in place (otherwise as
    :func:`forward_sweep`): after a forward sweep, the symmetric sweep that keeps a V-cycle
    symmetric."""
    _swept(matrix, x, b, False)
