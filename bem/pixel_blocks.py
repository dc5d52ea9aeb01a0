"""The pixel-block multigrid hierarchy of the Reynolds solves (:mod:`bem.flow_solver`).

Each level's aggregates are the 2 x 2 blocks of the level below, on the pixel grid: a block's
unknowns (up to four pixels on the finest level, up to four aggregates of the level below on
the next) form one aggregate where they are joined by strong connections, and are split into
the parts that are not. A connection is strong when its coefficient is at least
:data:`BLOCK_STRENGTH` of the largest off-diagonal coefficient of the row of either end (the
classical measure of strength, taken from both sides so that the test is symmetric). Near
percolation the flow crosses a block through a thin neck, or not at all, and a block averaged
over both sides of it interpolates the pressure badly: split, the conjugate gradients took 71
instead of 269 iterations on a 2048^2 gap at 22 % contact (four levels), 11 instead of 15
on a 1024^2 gap at 17 %, 16 instead of 30 on a 512^2 gap at 32 % (three levels).

The interpolation is piecewise constant on the aggregates, fitted to the near-null vector
(pyAMG's ``fit_candidates``), and the coarse operators are the Galerkin products; the levels
are held in CSR, the restriction as the interpolation's transpose (a view, no copy).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["BLOCK_STRENGTH", "aggregates", "block_hierarchy"]

#: A connection inside a block is strong (keeps its two ends in one aggregate) when its
#: coefficient is at least this share of the largest off-diagonal one in the row of either end.
#: On the gaps above, 0.25 took 83 / 12 / 19 iterations where 0.5 took 71 / 11 / 16 and no
#: split 269 / 15 / 30; a larger share splits more blocks, and the coarse levels grow (the
#: 2048^2 gap's coarsest 128 thousand unknowns instead of 76).
BLOCK_STRENGTH = 0.5


@numba.njit(nogil=True, cache=True)
def _strong_in_block(indptr, indices, data, block, strength):   # pragma: no cover (compiled)
    rows = indptr.size - 1
    largest = np.zeros(rows)
    for row in range(rows):
        for entry in range(indptr[row], indptr[row + 1]):
            if indices[entry] != row:
                largest[row] = max(largest[row], abs(data[entry]))
    strong = np.zeros(data.size, dtype=np.bool_)
    for row in range(rows):
        for entry in range(indptr[row], indptr[row + 1]):
            column = indices[entry]
            if column > row and block[column] == block[row]:
                value = abs(data[entry])
                strong[entry] = value >= strength * largest[row] \
                    or value >= strength * largest[column]
    return strong


def aggregates(matrix, rows: np.ndarray, columns: np.ndarray):
    """The aggregates of the unknowns of ``matrix`` (CSR) at pixel-block positions ``rows``,
    ``columns`` (one per unknown): the 2 x 2 blocks of positions, each split into its parts
    joined by strong connections (module docstring).

    Returns
    -------
    (scipy.sparse.csr_matrix, numpy.ndarray, numpy.ndarray)
        The aggregation operator (unknowns x aggregates, one 1 per row) and the block position
        of each aggregate on the next level (``rows // 2``, ``columns // 2``).
    """
    import scipy.sparse
    from scipy.sparse.csgraph import connected_components

    unknowns = matrix.shape[0]
    coarse_rows, coarse_columns = rows // 2, columns // 2
    block = coarse_rows * (int(coarse_columns.max(initial=0)) + 1) + coarse_columns
    strong = np.flatnonzero(_strong_in_block(matrix.indptr, matrix.indices, matrix.data,
                                             block, BLOCK_STRENGTH))
    tails = np.searchsorted(matrix.indptr, strong, side="right") - 1
    graph = scipy.sparse.coo_array((np.ones(strong.size, dtype=np.int8),
                                    (tails, matrix.indices[strong])), shape=(unknowns, unknowns))
    count, label = connected_components(graph, directed=False)
    operator = scipy.sparse.csr_matrix(
        (np.ones(unknowns), np.asarray(label, dtype=np.int32),
         np.arange(unknowns + 1, dtype=np.int32)), shape=(unknowns, count))
    positions = np.empty((2, count), dtype=rows.dtype)
    positions[0, label], positions[1, label] = coarse_rows, coarse_columns
    return operator, positions[0], positions[1]


def block_hierarchy(scaled, near_null: np.ndarray, cells: np.ndarray, levels: int,
                    coarse_solver):
    """A pyAMG multilevel hierarchy of ``levels`` levels of split pixel blocks for the
    Jacobi-scaled matrix ``scaled`` (CSR) of the unknowns ``cells`` (a 2-D map, unknowns in
    row-major order), with the near-null vector ``near_null`` and pyAMG's ``coarse_solver``
    (e.g. ``("splu", options)``) on the coarsest level."""
    from pyamg.aggregation import fit_candidates
    from pyamg.multilevel import MultilevelSolver

    rows, columns = np.nonzero(cells)
    matrix, candidates, built = scaled, near_null.reshape(-1, 1), []
    for _ in range(levels - 1):
        operator, rows, columns = aggregates(matrix, rows, columns)
        interpolation, candidates = fit_candidates(operator, candidates)
        level = MultilevelSolver.Level()
        level.A, level.P = matrix, interpolation.tocsr()
        level.R = level.P.T
        built.append(level)
        matrix = (level.R @ (matrix @ level.P)).tocsr()
    last = MultilevelSolver.Level()
    last.A = matrix
    return MultilevelSolver(built + [last], coarse_solver=coarse_solver)
