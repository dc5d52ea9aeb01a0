"""The Reynolds system held by its faces (bem.leakage.face_matrix): its product, scaling, Gauss-Seidel
sweeps and rows against the same matrix in compressed rows, and the pixel-block hierarchy
built from it against the one built from its compressed rows."""

import numpy as np
import pytest

from bem.leakage.face_matrix import FaceMatrix
from bem.leakage.flow import _flow_system, spanning_cells
from bem.leakage.gauss_seidel import backward_sweep, forward_sweep
from bem.leakage.pixel_blocks import aggregates, block_hierarchy

BOTH = pytest.mark.parametrize("periodic", [False, True])


def _system(shape, periodic, seed=0):
    """A flow system of a random gap with closed cells, assembled by faces."""
    rng = np.random.default_rng(seed)
    for _ in range(100):
        k = rng.uniform(0.0, 1.0, shape) ** 3
        k[rng.uniform(size=shape) < 0.25] = 0.0
        cells = spanning_cells(k > 0, periodic=periodic)
        if cells.any():
            return _flow_system(k, cells, periodic)[0], cells
    raise AssertionError("no random gap leaks")


@BOTH
@pytest.mark.parametrize("shape", [(2, 2), (2, 5), (3, 2), (9, 7), (40, 31)])
def test_product_and_scaling_are_those_of_the_compressed_rows(periodic, shape):
    matrix, _ = _system(shape, periodic, seed=sum(shape))
    rows = matrix.tocsr()
    rng = np.random.default_rng(1)
    x = rng.standard_normal(matrix.shape[0])
    np.testing.assert_allclose(matrix @ x, rows @ x, rtol=1e-13, atol=1e-13 * np.abs(x).max())
    np.testing.assert_array_equal(matrix.diagonal(), rows.diagonal())
    scale = rng.uniform(0.5, 2.0, matrix.shape[0])
    matrix.scale(scale)
    expected = (rows.multiply(scale[:, None]).multiply(scale[None, :])).toarray()
    np.testing.assert_allclose(matrix.tocsr().toarray(), expected, rtol=1e-14, atol=0.0)


def test_the_product_sums_each_row_in_the_order_of_its_columns():
    # a window's rows, summed above, left, diagonal, right, below: the compressed rows' product
    # to the last bit
    matrix, _ = _system((40, 31), False, seed=3)
    x = np.random.default_rng(2).standard_normal(matrix.shape[0])
    np.testing.assert_array_equal(matrix @ x, matrix.tocsr() @ x)


@pytest.mark.parametrize("sweep", [forward_sweep, backward_sweep])
def test_sweeps_are_those_of_the_compressed_rows_to_the_bit(sweep):
    matrix, _ = _system((33, 24), False, seed=4)
    rows = matrix.tocsr()
    rng = np.random.default_rng(5)
    b, start = rng.standard_normal(matrix.shape[0]), rng.standard_normal(matrix.shape[0])
    by_faces, by_rows = start.copy(), start.copy()
    for _ in range(3):
        sweep(matrix, by_faces, b)
        sweep(rows, by_rows, b)
    np.testing.assert_array_equal(by_faces, by_rows)
    assert not np.array_equal(by_faces, start)


@pytest.mark.parametrize("shape", [(2, 6), (5, 2), (12, 10)])
def test_periodic_sweeps_are_those_of_the_compressed_rows(shape):
    # faces across the edges (and two between the same cells of a grid two wide) in the sweep;
    # the rows' terms are summed in another order there, so equal to rounding
    matrix, _ = _system(shape, True, seed=6)
    rows = matrix.tocsr()
    rng = np.random.default_rng(7)
    b, start = rng.standard_normal(matrix.shape[0]), rng.standard_normal(matrix.shape[0])
    for sweep in (forward_sweep, backward_sweep):
        by_faces, by_rows = start.copy(), start.copy()
        sweep(matrix, by_faces, b)
        sweep(rows, by_rows, b)
        np.testing.assert_allclose(by_faces, by_rows, rtol=1e-12, atol=1e-12)
        assert not np.allclose(by_faces, start)


def test_a_sweep_refuses_other_forms():
    import scipy.sparse

    with pytest.raises(TypeError, match="CSR form or a bem.leakage.face_matrix.FaceMatrix"):
        forward_sweep(scipy.sparse.bsr_matrix(np.eye(2)), np.zeros(2), np.ones(2))


def test_the_pixel_blocks_from_the_faces_are_those_from_the_compressed_rows():
    matrix, cells = _system((48, 40), False, seed=8)
    scale = 1.0 / np.sqrt(matrix.diagonal())
    matrix.scale(scale)
    rows = matrix.tocsr()
    positions = np.nonzero(cells)
    by_faces, by_rows = aggregates(matrix, *positions), aggregates(rows, *positions)
    np.testing.assert_array_equal(by_faces[0].indices, by_rows[0].indices)
    np.testing.assert_array_equal(by_faces[1], by_rows[1])
    near_null = (1.0 / scale)[:, None]
    faces_levels = block_hierarchy(matrix, near_null, cells, 3, "splu").levels
    rows_levels = block_hierarchy(rows, near_null, cells, 3, "splu").levels
    assert faces_levels[0].A is matrix
    for built, expected in zip(faces_levels[1:], rows_levels[1:]):
        np.testing.assert_array_equal(built.A.indptr, expected.A.indptr)
        np.testing.assert_array_equal(built.A.indices, expected.A.indices)
        np.testing.assert_allclose(built.A.data, expected.A.data, rtol=1e-14, atol=1e-15)
    for built, expected in zip(faces_levels[:-1], rows_levels[:-1]):
        np.testing.assert_array_equal(built.P.toarray(), expected.P.toarray())


def test_closed_faces_have_no_entry():
    # two cells side by side whose face is closed (T = 0) and one open face below each
    index = np.array([[0, 1], [2, 3]], dtype=np.int32)
    right = np.array([0.0, 0.0, -1.0, 0.0])
    down = np.array([-2.0, -3.0, 0.0, 0.0])
    matrix = FaceMatrix(index, right, down, np.array([2.0, 3.0, 3.0, 1.0]) + 1.0, False)
    rows = matrix.tocsr()
    assert rows.nnz == 4 + 2 * 3
    np.testing.assert_array_equal(rows.toarray(), [[3, 0, -2, 0], [0, 4, 0, -3],
                                                   [-2, 0, 4, -1], [0, -3, -1, 2]])


@pytest.mark.parametrize("shape", [(2, 7), (6, 2), (2, 2)])
def test_a_periodic_system_two_cells_wide_is_aggregated_as_its_compressed_rows(shape):
    # two faces join the same two cells there: their connection is their sum, as in CSR
    for seed in range(12):
        matrix, cells = _system(shape, True, seed=seed)
        positions = np.nonzero(cells)
        by_faces, by_rows = aggregates(matrix, *positions), aggregates(matrix.tocsr(), *positions)
        np.testing.assert_array_equal(by_faces[0].indices, by_rows[0].indices)
        levels = block_hierarchy(matrix, np.ones((matrix.shape[0], 1)), cells, 2, "splu").levels
        assert levels[0].A.format == "csr"


@pytest.mark.parametrize("shape", [(1, 5), (4, 1)])
def test_a_periodic_axis_of_one_cell_is_refused(shape):
    n = shape[0] * shape[1]
    index = np.arange(n, dtype=np.int32).reshape(shape)
    with pytest.raises(ValueError, match="at least 2 x 2 on a periodic grid"):
        FaceMatrix(index, np.zeros(n), np.zeros(n), np.ones(n), True)
    FaceMatrix(index, np.zeros(n), np.zeros(n), np.ones(n), False)   # a window may be one wide
