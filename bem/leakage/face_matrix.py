"""The Reynolds flow system's matrix held by its faces (:mod:`bem.leakage.flow`).

The finite-volume system of eq. T43 couples each cell only to its four neighbours on the pixel
grid, with the coefficient ``-T`` of the face between them, and the matrix is symmetric: one
number per face holds both of its entries. :class:`FaceMatrix` keeps, for each unknown (the
grid's cells in the system, numbered in row-major order), the coefficient of its face to the
next cell along axis 1 and along axis 0 and its diagonal, beside the grid's map of the unknowns'
numbers: 24 bytes per unknown and 4 per cell, where compressed rows (CSR) of the same matrix take
about 64 (five values of 8 bytes, five column numbers of 4, a row pointer). At 2048^2 that is
the difference between 0.1 and 0.26 GB held for the whole of a multigrid solve. Its product, its
Gauss-Seidel sweeps (the multigrid's finest smoother) and the rows the multigrid's aggregation
reads are compiled walks over the grid that release the GIL; :meth:`FaceMatrix.tocsr` gives
the compressed rows where a sparse factorisation or algebraic coarsening needs them.

A face to a neighbour outside the system, or a closed face (``T = 0``), has the coefficient 0
and no entry in the compressed rows. On a periodic grid the faces of the last column and row
join the first (a grid two cells wide has two faces between the same pair of cells, whose
entries are summed).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["FaceMatrix"]


class FaceMatrix:
    """A symmetric 5-point matrix of the unknowns of a pixel grid, by faces (module docstring).

    Parameters
    ----------
    index : numpy.ndarray
        int32 map of the grid: the number of each cell's unknown (row-major order), -1 for a
        cell outside the system.
    right, down : numpy.ndarray
        float64 per unknown: the entry ``A[u, v]`` of the face to the next cell along axis 1
        (``right``) and along axis 0 (``down``), 0 where there is no open face.
    diagonal : numpy.ndarray
        float64 per unknown: ``A[u, u]``.
    periodic : bool
        Whether the last column and row have faces to the first.
    """

    format = "faces"

    def __init__(self, index: np.ndarray, right: np.ndarray, down: np.ndarray,
                 diagonal: np.ndarray, periodic: bool) -> None:
        if periodic and min(index.shape) < 2:
            raise ValueError(f"index must be at least 2 x 2 on a periodic grid (a cell's face to "
                             f"itself is no coupling), got shape {index.shape}")
        self.index, self.right, self.down = index, right, down
        self._diagonal, self.periodic = diagonal, bool(periodic)
        self.shape = (diagonal.size, diagonal.size)
        self.dtype = np.dtype(np.float64)

    def diagonal(self) -> np.ndarray:
        """``A[u, u]`` per unknown (the array held, not a copy)."""
        return self._diagonal

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        out = np.empty(self.shape[0])
        _product(self.index, self.right, self.down, self._diagonal, self.periodic,
                 np.ascontiguousarray(x, dtype=np.float64), out)
        return out

    def scale(self, scale: np.ndarray) -> None:
        """``A <- S A S`` in place for ``S = diag(scale)`` (each entry times the scale of its row,
        then of its column)."""
        for values, axis in ((self.right, 1), (self.down, 0)):
            values *= scale
            values *= scale[_neighbour_unknowns(self.index, axis, self.periodic)]
        self._diagonal *= scale
        self._diagonal *= scale

    def sweep(self, x: np.ndarray, b: np.ndarray, *, forward: bool) -> None:
        """One Gauss-Seidel sweep of ``A x = b`` in place, over the unknowns in increasing
        (``forward``) or decreasing order (as :func:`bem.leakage.gauss_seidel.forward_sweep`)."""
        _sweep(self.index, self.right, self.down, self._diagonal, self.periodic, x, b, forward)

    def tocsr(self):
        """The same matrix in compressed rows (scipy.sparse.csr_array, each row's columns
        sorted, no entry for a coefficient of 0)."""
        import scipy.sparse

        columns = np.full((self.shape[0], 5), -1, dtype=np.int32)
        values = np.zeros((self.shape[0], 5))
        columns[:, 2], values[:, 2] = np.arange(self.shape[0], dtype=np.int32), self._diagonal
        for values_after, axis, before, after in ((self.right, 1, 1, 3), (self.down, 0, 0, 4)):
            head = _neighbour_unknowns(self.index, axis, self.periodic)
            columns[:, after] = np.where(values_after != 0.0, head, -1)
            values[:, after] = values_after
            # the face before an unknown is the face after its previous neighbour
            tail = _neighbour_unknowns(self.index, axis, self.periodic, step=1)
            open_before = tail >= 0
            columns[open_before, before] = np.where(
                values_after[tail[open_before]] != 0.0, tail[open_before], -1)
            values[open_before, before] = values_after[tail[open_before]]
        present = columns >= 0
        indptr = np.zeros(self.shape[0] + 1, dtype=np.int32)
        np.cumsum(np.count_nonzero(present, axis=1), out=indptr[1:])
        matrix = scipy.sparse.csr_array((values[present], columns[present], indptr),
                                        shape=self.shape)
        matrix.has_canonical_format = False
        matrix.sum_duplicates()   # (sorts each row's columns; sums a periodic side of two cells)
        return matrix

    def tocsc(self):
        """The same matrix in compressed columns (symmetric: the rows' arrays)."""
        return self.tocsr().tocsc()


def _neighbour_unknowns(index: np.ndarray, axis: int, periodic: bool, step: int = -1
                        ) -> np.ndarray:
    """Per unknown, the unknown of the cell one further along ``axis`` (``step=-1``; one back
    for ``step=1``), -1 where there is none (outside the system, or past a non-periodic
    edge)."""
    neighbour = np.roll(index, step, axis=axis)
    if not periodic:
        edge = [slice(None), slice(None)]
        edge[axis] = -1 if step == -1 else 0
        neighbour[tuple(edge)] = -1
    return neighbour[index >= 0]


@numba.njit(nogil=True, cache=True)
def _neighbours(index, j, i, periodic):   # pragma: no cover (compiled)
    """The unknowns above, left of, right of and below cell (j, i) (-1: none)."""
    rows, columns = index.shape
    up = left = right = down = -1
    if j > 0:
        up = index[j - 1, i]
    elif periodic:
        up = index[rows - 1, i]
    if i > 0:
        left = index[j, i - 1]
    elif periodic:
        left = index[j, columns - 1]
    if i + 1 < columns:
        right = index[j, i + 1]
    elif periodic:
        right = index[j, 0]
    if j + 1 < rows:
        down = index[j + 1, i]
    elif periodic:
        down = index[0, i]
    return up, left, right, down


@numba.njit(nogil=True, cache=True, inline="always")
def face_row(index, right, down, diagonal, periodic, j, i, columns,
             values):   # pragma: no cover (compiled)
    """The entries of the row of cell (j, i)'s unknown into ``columns`` and ``values`` (at least
    five long): above, left, diagonal, right, below (on a non-periodic grid, the order of their
    columns), the zero ones left out; returns their count."""
    rows, width = index.shape
    u = index[j, i]
    if 0 < j < rows - 1 and 0 < i < width - 1:   # (an interior cell: no edge to test)
        up, left, after, below = index[j - 1, i], index[j, i - 1], index[j, i + 1], index[j + 1, i]
    else:
        up, left, after, below = _neighbours(index, j, i, periodic)
    count = 0
    if up >= 0 and down[up] != 0.0:
        columns[count], values[count] = up, down[up]
        count += 1
    if left >= 0 and right[left] != 0.0:
        columns[count], values[count] = left, right[left]
        count += 1
    columns[count], values[count] = u, diagonal[u]
    count += 1
    if after >= 0 and right[u] != 0.0:
        columns[count], values[count] = after, right[u]
        count += 1
    if below >= 0 and down[u] != 0.0:
        columns[count], values[count] = below, down[u]
        count += 1
    return count


@numba.njit(nogil=True, cache=True)
def _edge_sum(index, right, down, diagonal, periodic, x, j, i, u,
              with_diagonal):   # pragma: no cover (compiled)
    """``sum_v A[u, v] x[v]`` over the row of cell (j, i) on the grid's edge (its neighbours
    across the edge periodic or absent), the diagonal only ``with_diagonal``; summed in the
    order of :func:`face_row`."""
    up, left, after, below = _neighbours(index, j, i, periodic)
    total = 0.0
    if up >= 0:
        total += down[up] * x[up]
    if left >= 0:
        total += right[left] * x[left]
    if with_diagonal:
        total += diagonal[u] * x[u]
    if after >= 0:
        total += right[u] * x[after]
    if below >= 0:
        total += down[u] * x[below]
    return total


# The walks below take an interior cell's four neighbours without tests of the edges (most
# cells: a test per neighbour, or a periodic flag, in the inner loop made the sweep three
# times slower than the compressed rows' sweep); a cell on the edge goes through _edge_sum.
# The interior sum is written out in each walk: as a compiled helper shared by both (inlined
# or not) it made the product and the sweep 2-6 times slower.


@numba.njit(nogil=True, cache=True)
def _product(index, right, down, diagonal, periodic, x, out):   # pragma: no cover (compiled)
    rows, columns = index.shape
    for j in range(rows):
        edge_row = j == 0 or j == rows - 1
        for i in range(columns):
            u = index[j, i]
            if u < 0:
                continue
            if edge_row or i == 0 or i == columns - 1:
                out[u] = _edge_sum(index, right, down, diagonal, periodic, x, j, i, u, True)
                continue
            total = 0.0
            v = index[j - 1, i]
            if v >= 0:
                total += down[v] * x[v]
            v = index[j, i - 1]
            if v >= 0:
                total += right[v] * x[v]
            total += diagonal[u] * x[u]
            v = index[j, i + 1]
            if v >= 0:
                total += right[u] * x[v]
            v = index[j + 1, i]
            if v >= 0:
                total += down[u] * x[v]
            out[u] = total


@numba.njit(nogil=True, cache=True)
def _sweep(index, right, down, diagonal, periodic, x, b, forward):   # pragma: no cover
    rows, columns = index.shape
    for row in range(rows):
        j = row if forward else rows - 1 - row
        edge_row = j == 0 or j == rows - 1
        for column in range(columns):
            i = column if forward else columns - 1 - column
            u = index[j, i]
            if u < 0 or diagonal[u] == 0.0:
                continue
            if edge_row or i == 0 or i == columns - 1:
                total = _edge_sum(index, right, down, diagonal, periodic, x, j, i, u, False)
            else:
                total = 0.0
                v = index[j - 1, i]
                if v >= 0:
                    total += down[v] * x[v]
                v = index[j, i - 1]
                if v >= 0:
                    total += right[v] * x[v]
                v = index[j, i + 1]
                if v >= 0:
                    total += right[u] * x[v]
                v = index[j + 1, i]
                if v >= 0:
                    total += down[u] * x[v]
            x[u] = (b[u] - total) / diagonal[u]
