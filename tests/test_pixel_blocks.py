"""The pixel-block aggregates of the Reynolds multigrid (bem.leakage.pixel_blocks): the grid's 2 x 2
blocks, split where a block's connections are weak, a part hanging on weak connections alone
kept in its block."""

import numpy as np
import pytest
import scipy.sparse

from bem.leakage.pixel_blocks import BLOCK_STRENGTH, aggregates, block_hierarchy


def _grid_matrix(cells: np.ndarray, horizontal: np.ndarray, vertical: np.ndarray):
    """The 5-point matrix of the unknowns ``cells`` (row-major) with face conductances
    ``horizontal[j, i]`` between (j, i) and (j, i + 1) and ``vertical[j, i]`` between (j, i)
    and (j + 1, i), and a unit conductance to ground on each cell (positive definite)."""
    index = np.full(cells.shape, -1)
    index[cells] = np.arange(np.count_nonzero(cells))
    tails, heads, values = [], [], []
    for conductance, step in ((horizontal, (0, 1)), (vertical, (1, 0))):
        for j, i in zip(*np.nonzero(cells)):
            jj, ii = j + step[0], i + step[1]
            if jj < cells.shape[0] and ii < cells.shape[1] and cells[jj, ii]:
                tails.append(index[j, i]), heads.append(index[jj, ii])
                values.append(conductance[j, i])
    n = np.count_nonzero(cells)
    off = scipy.sparse.coo_matrix((values, (tails, heads)), shape=(n, n))
    off = off + off.T
    degree = np.asarray(off.sum(axis=1)).ravel() + 1.0
    return (scipy.sparse.diags(degree) - off).tocsr()


def _groups(operator) -> list[set[int]]:
    labels = operator.indices
    return sorted((set(np.flatnonzero(labels == k)) for k in range(operator.shape[1])),
                  key=min)


def test_uniform_connections_give_the_grids_two_by_two_blocks():
    cells = np.array([[1, 1, 0], [0, 1, 1], [1, 0, 0]], dtype=bool)
    ones = np.ones(cells.shape)
    operator, rows, columns = aggregates(_grid_matrix(cells, ones, ones), *np.nonzero(cells))
    # unknowns in row-major order: (0,0) (0,1) (1,1) (1,2) (2,0)
    assert _groups(operator) == [{0, 1, 2}, {3}, {4}]
    assert operator.format == "csr" and np.all(operator.data == 1.0)
    np.testing.assert_array_equal(np.c_[rows, columns], [[0, 0], [0, 1], [1, 0]])


def test_a_weak_face_splits_its_block_where_both_parts_hold_on_to_their_neighbours():
    cells = np.ones((2, 4), dtype=bool)
    horizontal, vertical = np.ones((2, 4)), np.ones((2, 4))
    # the left block: (0,0)-(0,1) and (1,0)-(1,1) strong, the vertical faces between them weak;
    # both rows go on strongly into the right block, which stays whole
    vertical[0, 0] = vertical[0, 1] = 0.9 * BLOCK_STRENGTH
    operator, rows, columns = aggregates(_grid_matrix(cells, horizontal, vertical),
                                         *np.nonzero(cells))
    # unknowns: (0,0) (0,1) (0,2) (0,3) (1,0) (1,1) (1,2) (1,3)
    assert _groups(operator) == [{0, 1}, {2, 3, 6, 7}, {4, 5}]
    np.testing.assert_array_equal(np.c_[rows, columns], [[0, 0], [0, 1], [0, 0]])
    # at the strength, the faces hold the block together
    vertical[0, 0] = vertical[0, 1] = BLOCK_STRENGTH
    operator, _, _ = aggregates(_grid_matrix(cells, horizontal, vertical), *np.nonzero(cells))
    assert _groups(operator) == [{0, 1, 4, 5}, {2, 3, 6, 7}]


def test_a_part_hanging_on_weak_connections_stays_in_its_blocks_largest_part():
    """A part of a block with no strong connection leaving the block would be a coarse unknown
    held by weak coefficients alone (a nearly singular coarse row): it is merged into its
    block's largest part; a diagonal pair (no face between them) is merged the same way."""
    cells = np.ones((2, 4), dtype=bool)
    horizontal, vertical = np.ones((2, 4)), np.ones((2, 4))
    # (1,0) is joined to (0,0) and (1,1) only weakly, and has no neighbour outside its block
    vertical[0, 0] = horizontal[1, 0] = 0.1
    operator, _, _ = aggregates(_grid_matrix(cells, horizontal, vertical), *np.nonzero(cells))
    # unknowns: (0,0) (0,1) (0,2) (0,3) (1,0) (1,1) (1,2) (1,3)
    assert _groups(operator) == [{0, 1, 4, 5}, {2, 3, 6, 7}]
    # the same, but (1,0) strongly joined to (2,0) below, outside its block: a part of its own
    cells = np.ones((3, 4), dtype=bool)
    horizontal, vertical = np.ones((3, 4)), np.ones((3, 4))
    vertical[0, 0] = horizontal[1, 0] = 0.1
    operator, _, _ = aggregates(_grid_matrix(cells, horizontal, vertical), *np.nonzero(cells))
    # unknowns: row 0 are 0-3, row 1 4-7, row 2 8-11
    assert _groups(operator) == [{0, 1, 5}, {2, 3, 6, 7}, {4}, {8, 9}, {10, 11}]
    # a diagonal pair: two parts, the one without an outside neighbour kept with the other
    cells = np.array([[1, 0, 1], [0, 1, 1]], dtype=bool)
    ones = np.ones(cells.shape)
    operator, _, _ = aggregates(_grid_matrix(cells, ones, ones), *np.nonzero(cells))
    # unknowns: (0,0) (0,2) (1,1) (1,2); (0,0) touches nothing, (1,1) touches (1,2)
    assert _groups(operator) == [{0, 2}, {1, 3}]


def test_strength_is_judged_from_either_end_of_a_connection():
    """A face weak for one cell (whose other faces are far stronger) but strong for the other
    keeps the two together: the test is symmetric."""
    cells = np.ones((2, 2), dtype=bool)
    horizontal, vertical = np.ones((2, 2)), np.ones((2, 2))
    horizontal[0, 0] = 10.0        # (0,0)-(0,1) strong
    vertical[0, 0] = 1.0           # (0,0)-(1,0): a tenth of (0,0)'s largest, all of (1,0)'s
    horizontal[1, 0] = 0.5         # (1,0)-(1,1)
    vertical[0, 1] = 0.1           # (0,1)-(1,1): weak for both
    operator, _, _ = aggregates(_grid_matrix(cells, horizontal, vertical), *np.nonzero(cells))
    assert _groups(operator) == [{0, 1, 2, 3}]


@pytest.mark.parametrize("levels", [2, 3])
def test_the_hierarchy_is_the_galerkin_product_of_its_interpolations(levels):
    rng = np.random.default_rng(5)
    cells = rng.uniform(size=(24, 24)) > 0.2
    matrix = _grid_matrix(cells, rng.uniform(0.01, 1.0, cells.shape),
                          rng.uniform(0.01, 1.0, cells.shape))
    near_null = rng.uniform(0.5, 2.0, (matrix.shape[0], 1))   # (a Jacobi scale's 1/D)
    hierarchy = block_hierarchy(matrix, near_null, cells, levels, "splu")
    assert len(hierarchy.levels) == levels
    candidate = near_null[:, 0]
    for fine, coarse in zip(hierarchy.levels, hierarchy.levels[1:]):
        expected = (fine.P.T @ fine.A @ fine.P).toarray()
        np.testing.assert_allclose(coarse.A.toarray(), expected, rtol=1e-12, atol=1e-14)
        assert coarse.A.format == "csr" and coarse.A.has_canonical_format
        rows = [coarse.A.indices[a:b] for a, b in zip(coarse.A.indptr, coarse.A.indptr[1:])]
        assert all(np.all(np.diff(row) > 0) for row in rows)   # sorted, no duplicates
        # piecewise constant, fitted to the near-null vector: each column is the candidate on
        # its aggregate, normalised, and the coarse candidate is that norm
        interpolation = fine.P.toarray()
        assert np.all(interpolation >= 0) and np.all((interpolation > 0).sum(axis=1) == 1)
        label = interpolation.argmax(axis=1)
        norms = np.sqrt(np.bincount(label, weights=candidate**2))
        np.testing.assert_allclose(interpolation[np.arange(label.size), label],
                                   candidate / norms[label], rtol=1e-14)
        candidate = norms
