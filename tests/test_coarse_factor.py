"""The coarsest level's exact solve of the Reynolds multigrid (bem.leakage.multigrid_cycle.CoarseFactor):
SuperLU's symmetric factor held as L D L^T, which solves what SuperLU's own factor solves."""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

from bem.leakage.flow_solver import _LU_OPTIONS
from bem.leakage.multigrid_cycle import CoarseFactor


def _spd(size: int, seed: int):
    """A random symmetric positive-definite sparse matrix of about six off-diagonal entries a
    row (a coarse level's count), in CSR."""
    rng = np.random.default_rng(seed)
    off = scipy.sparse.random(size, size, density=min(1.0, 6.0 / size), random_state=rng,
                              format="coo")
    off.data = -rng.uniform(0.01, 100.0, off.nnz)   # conductances over four decades
    off = off + off.T
    degree = -np.asarray(off.sum(axis=1)).ravel() + rng.uniform(1e-3, 1.0, size)
    return (scipy.sparse.diags(degree) + off).tocsr()


@pytest.mark.parametrize("size", [2, 7, 400])
def test_the_symmetric_factor_solves_as_superlu_does(size):
    matrix = _spd(size, size)
    right = np.random.default_rng(1).standard_normal(size)
    factor = CoarseFactor(matrix, _LU_OPTIONS)
    assert factor._lu is None   # only L and D are held
    expected = scipy.sparse.linalg.splu(matrix.tocsc(), **_LU_OPTIONS).solve(right)
    solution = factor.solve(right)
    np.testing.assert_allclose(solution, expected, rtol=1e-10,
                               atol=1e-12 * np.abs(expected).max())
    assert np.linalg.norm(matrix @ solution - right) <= 1e-10 * np.linalg.norm(right)
    # the operator is symmetric: u.(A^-1 v) = v.(A^-1 u)
    other = np.random.default_rng(2).standard_normal(size)
    assert other @ solution == pytest.approx(right @ factor.solve(other), rel=1e-10)


def test_a_pivoting_factor_is_kept_as_superlus():
    """Where SuperLU interchanges rows (a zero on the diagonal and partial pivoting), so that
    its factor is not symmetric, SuperLU's own factor is kept and solves."""
    matrix = scipy.sparse.csr_matrix(np.array([[0.0, 2.0, 0.0], [1.0, 0.0, 0.0],
                                               [0.0, 0.0, 3.0]]))
    factor = CoarseFactor(matrix, {"permc_spec": "NATURAL", "diag_pivot_thresh": 1.0})
    assert factor._lu is not None
    np.testing.assert_allclose(factor.solve(np.array([2.0, 1.0, 3.0])), [1.0, 1.0, 1.0])
