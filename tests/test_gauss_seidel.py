"""The compiled Gauss-Seidel sweeps (bem.leakage.gauss_seidel) against pyAMG's sweep and against the
definition."""

import numpy as np
import pytest
import scipy.sparse

from bem.leakage.gauss_seidel import backward_sweep, forward_sweep


def _matrix(size: int, seed: int) -> scipy.sparse.csr_matrix:
    """A random sparse matrix with a dominant diagonal and one row without a diagonal."""
    rng = np.random.default_rng(seed)
    matrix = scipy.sparse.random(size, size, density=0.05, random_state=seed, format="lil")
    matrix.setdiag(rng.uniform(2.0, 3.0, size))
    matrix[size // 2, size // 2] = 0.0
    return matrix.tocsr()


@pytest.mark.parametrize("sweep, order", [(forward_sweep, "forward"),
                                          (backward_sweep, "backward")])
def test_a_sweep_is_pyamgs_to_the_last_bit(sweep, order):
    from pyamg.relaxation.relaxation import gauss_seidel

    matrix = _matrix(300, 1)
    rng = np.random.default_rng(2)
    b, x = rng.standard_normal(300), rng.standard_normal(300)
    expected = x.copy()
    gauss_seidel(matrix, expected, b, sweep=order)
    sweep(matrix, x, b)
    assert np.array_equal(x, expected)


@pytest.mark.parametrize("sweep, rows", [(forward_sweep, range(40)),
                                         (backward_sweep, range(39, -1, -1))])
def test_a_sweep_updates_the_rows_in_turn(sweep, rows):
    """Each row solved for its unknown with the rows before it (in the sweep's order)
    already updated; a row without a diagonal keeps its value."""
    matrix = _matrix(40, 3)
    dense = matrix.toarray()
    rng = np.random.default_rng(4)
    b, x = rng.standard_normal(40), rng.standard_normal(40)
    expected = x.copy()
    for row in rows:
        if dense[row, row] != 0.0:
            off = dense[row] @ expected - dense[row, row] * expected[row]
            expected[row] = (b[row] - off) / dense[row, row]
    unchanged = x[20]
    sweep(matrix, x, b)
    np.testing.assert_allclose(x, expected, rtol=1e-13, atol=1e-13)
    assert x[20] == unchanged


def test_sweeps_converge_to_the_solution_of_a_diagonally_dominant_system():
    matrix = _matrix(200, 5) + scipy.sparse.eye(200, format="csr")
    b = np.random.default_rng(6).standard_normal(200)
    x = np.zeros(200)
    for _ in range(60):
        forward_sweep(matrix, x, b)
        backward_sweep(matrix, x, b)
    np.testing.assert_allclose(matrix @ x, b, atol=1e-10)


def test_a_matrix_in_another_form_is_refused():
    matrix = _matrix(20, 7)
    x, b = np.zeros(20), np.ones(20)
    for other in (matrix.tobsr(), matrix.tocsc(), matrix.toarray()):
        with pytest.raises(TypeError, match="CSR"):
            forward_sweep(other, x, b)
