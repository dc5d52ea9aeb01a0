"""The pixel-block multigrid hierarchy of the Reynolds solves (:mod:`bem.leakage.flow_solver`).

Each level's aggregates are the 2 x 2 blocks of the level below, on the pixel grid: a block's
unknowns (up to four pixels on the finest level, the aggregates of up to four blocks on the
next) form one aggregate where strong connections join them, and are split into the parts that
they do not join. A connection is strong when its coefficient is at least
:data:`BLOCK_STRENGTH` of the largest off-diagonal coefficient in the row of either end (the
classical measure of strength, taken from both sides so that the test is symmetric). Near
percolation the flow crosses a block through a thin neck, or not at all, and one coarse
pressure for both sides of it interpolates the pressure badly.

A part of a block with no strong connection leaving the block stays in its block's largest
part that has one (in one aggregate with its block's other such parts where none has):
hanging on the rest of the grid by weak connections alone, it would be a coarse unknown whose
row is nearly singular, and such parts made the coarse levels so ill-conditioned (the
coarsest LU's error on a random vector 4e-3 against 6e-9) that the V-cycle stopped being a
symmetric preconditioner in floating point and the conjugate gradients did not converge on a
1024^2 gap at 28 % contact. With that rule, from the linear pressure drop on one core: 28
iterations (2.4 s) on that gap, 167 (49 s) on a 2048^2 gap at 22 % contact, 36 on a 512^2 gap
at 29 %; whole blocks took 47, 812 (191 s) and 58 under a looser stopping rule
(the solver's rule now asks more).

The interpolation is piecewise constant on the aggregates, fitted to the near-null vector (what
pyAMG's ``fit_candidates`` computes for one candidate), and the coarse operators are the
Galerkin products (a compiled merge of each aggregate's rows), held in CSR with the restriction
as the interpolation's transpose (a view, no copy). The finest operator may be the flow system
held by its faces (:class:`bem.leakage.face_matrix.FaceMatrix`): its aggregates and Galerkin product are
read from the faces, and it stays the finest level's operator as it is.
"""

from __future__ import annotations

import numba
import numpy as np

from bem.leakage.face_matrix import face_row

__all__ = ["BLOCK_STRENGTH", "aggregates", "block_hierarchy"]

#: A connection is strong (inside a block it keeps its two ends in one aggregate) when its
#: coefficient is at least this share of the largest off-diagonal one in the row of either
#: end. On a 2048^2 gap at 22 % contact 0.25 took 83 iterations where 0.5 took 71 (both without
#: the rule for parts that hang on weak connections); a larger share splits more blocks, and
#: the coarse levels grow.
BLOCK_STRENGTH = 0.5


@numba.njit(nogil=True, cache=True)
def _root(parent, node):  # pragma: no cover (compiled)
    while parent[node] != node:
        parent[node] = parent[parent[node]]
        node = parent[node]
    return node


@numba.njit(nogil=True, cache=True)
def _parts(indptr, indices, data, block, blocks, strength):  # pragma: no cover (compiled)
    """The aggregate of each unknown of a CSR matrix whose 2 x 2 block is ``block`` (of
    ``blocks``): the parts of each block that strong connections join (union-find), a part
    without a strong connection leaving its block merged into the block's largest part that has
    one (the one with the lowest root among equals; without any, the block's parts are one);
    aggregates numbered in order of first member."""
    rows = indptr.size - 1
    largest = np.zeros(rows)
    for row in range(rows):
        for entry in range(indptr[row], indptr[row + 1]):
            if indices[entry] != row:
                largest[row] = max(largest[row], abs(data[entry]))
    parent = np.arange(rows)
    anchored = np.zeros(rows, dtype=np.bool_)
    for row in range(rows):
        for entry in range(indptr[row], indptr[row + 1]):
            column = indices[entry]
            value = abs(data[entry])
            if column == row or (value < strength * largest[row]
                                 and value < strength * largest[column]):
                continue
            if block[column] != block[row]:
                anchored[row] = True
            elif column > row:
                one, other = _root(parent, row), _root(parent, column)
                parent[max(one, other)] = min(one, other)
    return _labels(parent, anchored, block, blocks)


@numba.njit(nogil=True, cache=True)
def _face_parts(index, right, down, periodic, block, blocks,
                strength):  # pragma: no cover (compiled)
    """:func:`_parts` of a matrix held by its faces (:class:`bem.leakage.face_matrix.FaceMatrix`): each
    open face tested once, from the unknown before it."""
    unknowns = right.size
    largest = np.zeros(unknowns)
    rows, columns = index.shape
    for j in range(rows):
        for i in range(columns):
            row = index[j, i]
            if row < 0:
                continue
            for axis in range(2):
                column, value = _face_after(index, right, down, periodic, j, i, row, axis)
                if column >= 0 and value != 0.0:
                    largest[row] = max(largest[row], abs(value))
                    largest[column] = max(largest[column], abs(value))
    parent = np.arange(unknowns)
    anchored = np.zeros(unknowns, dtype=np.bool_)
    for j in range(rows):
        for i in range(columns):
            row = index[j, i]
            if row < 0:
                continue
            for axis in range(2):
                column, value = _face_after(index, right, down, periodic, j, i, row, axis)
                value = abs(value)
                if column < 0 or value == 0.0 or (value < strength * largest[row]
                                                  and value < strength * largest[column]):
                    continue
                if block[column] != block[row]:
                    anchored[row] = anchored[column] = True
                else:
                    one, other = _root(parent, row), _root(parent, column)
                    parent[max(one, other)] = min(one, other)
    return _labels(parent, anchored, block, blocks)


@numba.njit(nogil=True, cache=True, inline="always")
def _face_after(index, right, down, periodic, j, i, row, axis):   # pragma: no cover (compiled)
    """The unknown one cell further along ``axis`` from unknown ``row`` at (j, i) (-1: none)
    and the coefficient of the face between them."""
    rows, columns = index.shape
    if axis == 1:
        if i + 1 < columns:
            return np.int64(index[j, i + 1]), right[row]
        return np.int64(index[j, 0] if periodic else -1), right[row]
    if j + 1 < rows:
        return np.int64(index[j + 1, i]), down[row]
    return np.int64(index[0, i] if periodic else -1), down[row]


@numba.njit(nogil=True, cache=True)
def _labels(parent, anchored, block, blocks):  # pragma: no cover (compiled)
    """The aggregates of :func:`_parts` from the union-find ``parent`` of the strong
    connections inside blocks and whether a strong connection leaves each unknown's block."""
    rows = parent.size
    size = np.zeros(rows, dtype=np.int64)
    roots = np.empty(rows, dtype=np.int64)
    for row in range(rows):
        root = roots[row] = _root(parent, row)
        size[root] += 1
        anchored[root] |= anchored[row]
    main = np.full(blocks, -1)
    for row in range(rows):
        root, home = roots[row], block[row]
        best = main[home]
        if best < 0 or (anchored[root], size[root], -root) > (anchored[best], size[best], -best):
            main[home] = root
    label = np.full(rows, -1, dtype=np.int32)
    number = np.full(rows, -1, dtype=np.int32)
    count = 0
    for row in range(rows):
        root = roots[row]
        if not anchored[root]:
            root = main[block[row]]
        if number[root] < 0:
            number[root] = count
            count += 1
        label[row] = number[root]
    return label, count


def aggregates(matrix, rows: np.ndarray, columns: np.ndarray):
    """The aggregates of the unknowns of ``matrix`` at pixel-block positions ``rows``,
    ``columns`` (one per unknown): the 2 x 2 blocks of positions, each split into its parts
    joined by strong connections, a part hanging on weak connections alone kept in its block's
    largest part (module docstring). ``matrix`` is in CSR, or a non-periodic
    :class:`bem.leakage.face_matrix.FaceMatrix` whose unknowns lie at these grid positions (a periodic
    one is read in CSR: on a grid two cells wide two of its faces join the same cells, and
    their connection is their sum).

    Returns
    -------
    (scipy.sparse.csr_matrix, numpy.ndarray, numpy.ndarray)
        The aggregation operator (unknowns x aggregates, one 1 per row) and the block position
        of each aggregate on the next level (``rows // 2``, ``columns // 2``).
    """
    import scipy.sparse

    unknowns = matrix.shape[0]
    coarse_rows, coarse_columns = rows // 2, columns // 2
    width = int(coarse_columns.max(initial=0)) + 1
    block = coarse_rows * width + coarse_columns
    blocks = int(block.max(initial=0)) + 1
    if getattr(matrix, "format", None) == "faces" and matrix.periodic:
        matrix = matrix.tocsr()
    if getattr(matrix, "format", None) == "faces":
        label, count = _face_parts(matrix.index, matrix.right, matrix.down, matrix.periodic,
                                   block, blocks, BLOCK_STRENGTH)
    else:
        label, count = _parts(matrix.indptr, matrix.indices, matrix.data, block, blocks,
                              BLOCK_STRENGTH)
    operator = scipy.sparse.csr_matrix(
        (np.ones(unknowns), label, np.arange(unknowns + 1, dtype=np.int32)),
        shape=(unknowns, count))
    positions = np.empty((2, count), dtype=rows.dtype)
    positions[0, label], positions[1, label] = coarse_rows, coarse_columns
    return operator, positions[0], positions[1]


def block_hierarchy(scaled, near_null: np.ndarray, cells: np.ndarray, levels: int,
                    coarse_solver):
    """A pyAMG multilevel hierarchy of ``levels`` levels of pixel blocks for the Jacobi-scaled
    matrix ``scaled`` (CSR, or held by its faces: a non-periodic
    :class:`bem.leakage.face_matrix.FaceMatrix` stays the finest level's operator as it is) of the
    unknowns ``cells`` (a 2-D map, unknowns in
    row-major order), with the near-null vector ``near_null`` (one column) and pyAMG's
    ``coarse_solver`` (e.g. ``("splu", options)``) on the coarsest level.

    The interpolation of an aggregate is the near-null vector on it, normalised (pyAMG's
    ``fit_candidates`` for one candidate; its norm is the coarse candidate), and the coarse
    operator the Galerkin product ``P^T A P`` by a compiled merge of each aggregate's rows
    (:func:`_galerkin`): scipy's two sparse products held 400 MB of intermediates at 2048^2,
    more than the rest of the solve at that moment.
    """
    import scipy.sparse
    from pyamg.multilevel import MultilevelSolver

    rows, columns = np.nonzero(cells)
    if getattr(scaled, "format", None) == "faces" and scaled.periodic:
        scaled = scaled.tocsr()   # (aggregates: a periodic system is read in CSR)
    matrix, candidates, built = scaled, np.asarray(near_null, dtype=np.float64).reshape(-1), []
    for _ in range(levels - 1):
        fine_rows, fine_columns = rows, columns
        operator, rows, columns = aggregates(matrix, rows, columns)
        label, count = operator.indices, operator.shape[1]
        norms = np.sqrt(np.bincount(label, weights=candidates * candidates, minlength=count))
        weights = candidates / norms[label]
        level = MultilevelSolver.Level()
        level.A = matrix
        level.P = scipy.sparse.csr_matrix((weights, label, operator.indptr),
                                          shape=operator.shape)
        level.R = level.P.T
        built.append(level)
        order = np.argsort(label, kind="stable").astype(np.int32)
        starts = np.searchsorted(label[order], np.arange(count + 1)).astype(np.int64)
        if getattr(matrix, "format", None) == "faces":
            indptr, indices, data = _face_galerkin(
                matrix.index, matrix.right, matrix.down, matrix.diagonal(), matrix.periodic,
                fine_rows, fine_columns, label, weights, starts, order, count)
        else:
            indptr, indices, data = _galerkin(matrix.indptr, matrix.indices, matrix.data,
                                              label, weights, starts, order, count)
        del fine_rows, fine_columns   # (a level's grid positions: 67 MB on a 2048^2 grid)
        matrix = scipy.sparse.csr_matrix((data, indices, indptr), shape=(count, count))
        candidates = norms
    last = MultilevelSolver.Level()
    last.A = matrix
    return MultilevelSolver(built + [last], coarse_solver=coarse_solver)


@numba.njit(nogil=True, cache=True)
def _galerkin(indptr, indices, data, label, weights, starts, members,
              count):   # pragma: no cover (compiled)
    """The CSR arrays of ``P^T A P`` for the CSR matrix A and the interpolation P with one
    entry per row (row i: ``weights[i]`` in column ``label[i]``); the members of aggregate I
    are ``members[starts[I]:starts[I + 1]]``. Row by row: the entries of the aggregate's rows,
    their columns mapped to aggregates and summed in a dense row indexed by a marker (two
    passes: the counts, then the values), each row's columns sorted."""
    marker = np.full(count, -1, dtype=np.int64)
    sizes = np.zeros(count + 1, dtype=np.int64)
    for aggregate in range(count):
        for member in range(starts[aggregate], starts[aggregate + 1]):
            row = members[member]
            for entry in range(indptr[row], indptr[row + 1]):
                column = label[indices[entry]]
                if marker[column] != aggregate:
                    marker[column] = aggregate
                    sizes[aggregate + 1] += 1
    out_indptr = np.cumsum(sizes).astype(np.int32)
    out_indices = np.empty(out_indptr[-1], dtype=np.int32)
    out_data = np.empty(out_indptr[-1])
    position = np.full(count, -1, dtype=np.int64)
    for aggregate in range(count):
        first = out_indptr[aggregate]
        filled = first
        for member in range(starts[aggregate], starts[aggregate + 1]):
            row = members[member]
            row_weight = weights[row]
            for entry in range(indptr[row], indptr[row + 1]):
                fine = indices[entry]
                column = label[fine]
                value = row_weight * data[entry] * weights[fine]
                if position[column] < first:
                    position[column] = filled
                    out_indices[filled] = column
                    out_data[filled] = value
                    filled += 1
                else:
                    out_data[position[column]] += value
        _sort_row(out_indices, out_data, first, filled)
    return out_indptr, out_indices, out_data


@numba.njit(nogil=True, cache=True)
def _face_galerkin(index, right, down, diagonal, periodic, rows, columns, label, weights,
                   starts, members, count):   # pragma: no cover (compiled)
    """:func:`_galerkin` of a matrix held by its faces (:class:`bem.leakage.face_matrix.FaceMatrix`,
    its unknowns at grid positions ``rows``, ``columns``), each row's entries read from its
    faces (:func:`bem.leakage.face_matrix.face_row`). The two passes are written out as in
    :func:`_galerkin`: shared compiled helpers for them (or one row reader for both forms) made
    both products 1.3-3.5 times slower."""
    row_columns = np.empty(5, dtype=np.int64)
    row_values = np.empty(5)
    marker = np.full(count, -1, dtype=np.int64)
    sizes = np.zeros(count + 1, dtype=np.int64)
    for aggregate in range(count):
        for member in range(starts[aggregate], starts[aggregate + 1]):
            row = members[member]
            entries = face_row(index, right, down, diagonal, periodic, rows[row],
                               columns[row], row_columns, row_values)
            for entry in range(entries):
                column = label[row_columns[entry]]
                if marker[column] != aggregate:
                    marker[column] = aggregate
                    sizes[aggregate + 1] += 1
    out_indptr = np.cumsum(sizes).astype(np.int32)
    out_indices = np.empty(out_indptr[-1], dtype=np.int32)
    out_data = np.empty(out_indptr[-1])
    position = np.full(count, -1, dtype=np.int64)
    for aggregate in range(count):
        first = out_indptr[aggregate]
        filled = first
        for member in range(starts[aggregate], starts[aggregate + 1]):
            row = members[member]
            row_weight = weights[row]
            entries = face_row(index, right, down, diagonal, periodic, rows[row],
                               columns[row], row_columns, row_values)
            for entry in range(entries):
                fine = row_columns[entry]
                column = label[fine]
                value = row_weight * row_values[entry] * weights[fine]
                if position[column] < first:
                    position[column] = filled
                    out_indices[filled] = column
                    out_data[filled] = value
                    filled += 1
                else:
                    out_data[position[column]] += value
        _sort_row(out_indices, out_data, first, filled)
    return out_indptr, out_indices, out_data


@numba.njit(nogil=True, cache=True, inline="always")
def _sort_row(out_indices, out_data, first, filled):   # pragma: no cover (compiled)
    """Sort a row's few columns in place (insertion sort, values alongside)."""
    for a in range(first + 1, filled):
        key_column, key_value = out_indices[a], out_data[a]
        b = a - 1
        while b >= first and out_indices[b] > key_column:
            out_indices[b + 1], out_data[b + 1] = out_indices[b], out_data[b]
            b -= 1
        out_indices[b + 1], out_data[b + 1] = key_column, key_value
