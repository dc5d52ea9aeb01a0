"""The two-level preconditioner of the contact and stiffness solves (bem/contact/coarse_correction.py).

The contract: each block's own energy ``z_i^T K z_i`` is exact (against products of the
operator), the preconditioner is symmetric positive definite on the contact set, and the
stiffness solve and the contact iteration reach the same solution in fewer iterations on a
contact set of many patches.
"""

import numpy as np
import pytest
import scipy.ndimage

import bem.contact.constrained_cg
import bem.contact.stiffness
from bem import HalfSpace, solve_contact
from bem.contact.coarse_correction import CoarseCorrection, SettlingCorrection, _coarse
from bem.contact.preconditioner import InverseKernel
from bem.contact.stiffness import _stiffness


def _rough(n: int, seed: int = 3) -> np.ndarray:
    """A rough periodic surface of unit rms height, correlated over a few pixels."""
    heights = scipy.ndimage.gaussian_filter(np.random.default_rng(seed).normal(size=(n, n)),
                                            2.0, mode="wrap")
    return heights / heights.std()


def _patches(n: int, fraction: float) -> np.ndarray:
    """A contact set of many patches: the highest ``fraction`` of a rough surface."""
    heights = _rough(n)
    return heights >= np.quantile(heights, 1.0 - fraction)


def _matrix(operator: HalfSpace, indices: np.ndarray) -> np.ndarray:
    """K restricted to the pixels ``indices``, column by column."""
    columns = []
    for index in indices:
        pulse = np.zeros(operator.shape)
        pulse.flat[index] = 1.0
        columns.append(operator.displacement(pulse).reshape(-1)[indices])
    return np.array(columns).T


@pytest.mark.parametrize("periodic", [False, True])
def test_each_blocks_own_energy_is_exact(periodic):
    operator = HalfSpace((48, 40), 1e-6, e_star=2e9, periodic=periodic)
    indices = np.flatnonzero(_patches(48, 0.3)[:, :40])
    coarse = _coarse(operator)
    rows, columns = np.divmod(indices, operator.shape[1])
    cell = (rows // coarse.block) * coarse.cells[1] + columns // coarse.block
    used = np.unique(cell)
    energies = CoarseCorrection._own_energies(coarse, rows, columns, used)
    stiffness = _matrix(operator, indices)
    for place, block in enumerate(used):
        inside = cell == block
        assert energies[place] == pytest.approx(stiffness[np.ix_(inside, inside)].sum(),
                                                rel=1e-10)


@pytest.mark.parametrize("kind", ["non-periodic", "periodic", "mirror"])
@pytest.mark.parametrize("fraction", [0.2, 0.9])
def test_the_two_level_preconditioner_is_symmetric_positive_definite(kind, fraction):
    n = 32
    operator = HalfSpace((n, n), 1.0, periodic=kind != "non-periodic", mirror=kind == "mirror")
    # (double precision: the product's symmetry is tested to 1e-9, beyond float32's rounding)
    preconditioner = InverseKernel((n, n), 1.0, precision="double")
    indices = np.flatnonzero(_patches(n, fraction))
    one = np.ones(indices.size)
    uniform = float(one @ _matrix(operator, indices) @ one)
    correction = CoarseCorrection(operator, indices, uniform)
    assert correction.usable

    def apply(values):
        without_means, sums = correction.before(values)
        preconditioner.input_block[...] = 0.0
        preconditioner.input_block.flat[indices] = without_means
        preconditioner.execute()
        return correction.after(preconditioner.output_block.reshape(-1)[indices].copy(), sums)

    matrix = np.array([apply(column) for column in np.eye(indices.size)]).T
    assert np.allclose(matrix, matrix.T, atol=1e-9 * np.abs(matrix).max())
    assert np.linalg.eigvalsh(0.5 * (matrix + matrix.T)).min() > 0.0


@pytest.mark.parametrize("kind", ["non-periodic", "mirror"])
def test_stiffness_is_the_same_in_fewer_iterations(kind):
    n = 256
    operator = HalfSpace((n, n), 1.0, periodic=kind == "mirror", mirror=kind == "mirror")
    preconditioner = InverseKernel((n, n), 1.0, precision="double")   # (the stiffness solve's)
    contact = _patches(n, 0.7)   # (measured: 33 -> 20 iterations non-periodic, 38 -> 27 mirror)
    one_level = _stiffness(operator, contact, tol=1e-9, max_iter=500,
                           preconditioner=preconditioner)
    indices = np.flatnonzero(contact)
    uniform = float(operator.displacement(contact.astype(float)).reshape(-1)[indices].sum())
    two_level = _stiffness(operator, contact, tol=1e-9, max_iter=500,
                           preconditioner=preconditioner,
                           correction=CoarseCorrection(operator, indices, uniform))
    assert one_level[1] and two_level[1]
    assert two_level[0] == pytest.approx(one_level[0], rel=1e-8)
    assert two_level[2] <= 0.8 * one_level[2]


def test_contact_iteration_reaches_the_same_state_in_fewer_iterations(monkeypatch):
    n = 256
    heights = 1e-6 * _rough(n)
    load = 0.1 * 1e9 * (n * 1e-6) ** 2   # 37 % contact
    one_level = solve_contact(heights, 1e-6, load=load, e_star=1e9, tol=1e-6, stiffness=True)
    monkeypatch.setattr(bem.contact.constrained_cg, "TWO_LEVEL_GRID", 0)
    two_level = solve_contact(heights, 1e-6, load=load, e_star=1e9, tol=1e-6, stiffness=True)
    assert one_level.converged and two_level.converged
    np.testing.assert_array_equal(two_level.pressure > 0, one_level.pressure > 0)
    assert two_level.separation == pytest.approx(one_level.separation, rel=1e-6)
    assert two_level.stiffness == pytest.approx(one_level.stiffness, rel=1e-6)
    # (measured: 32 -> 24 iterations)
    assert two_level.iterations <= 0.85 * one_level.iterations


def test_the_contact_iterations_correction_waits_for_a_settled_set_and_leaves_a_churning_one():
    operator = HalfSpace((64, 64), 1.0, periodic=True)
    indices = np.flatnonzero(_patches(64, 0.4))
    size = indices.size
    settling = SettlingCorrection(operator)
    assert not settling.update(indices, size // 2, 1.0)    # churning: not built
    assert not settling.update(indices, 0, 0.8)            # settled once: not yet
    assert not settling.update(indices, 0, 0.64)           # twice, too few norms
    assert settling.update(indices, 0, 0.5)                # slow (0.8 per iteration): built
    built = settling.correction
    assert built is not None and built.usable
    assert not settling.update(indices[1:], 1, 0.4)        # a pixel left: followed
    assert settling.correction is built
    step = int(0.03 * size)   # below CHURNING_CHANGE, adding up past REBUILD_CHANGE
    assert not any(settling.update(indices, step, 0.3) for _ in range(3))
    assert settling.correction is built
    assert settling.update(indices, step, 0.2)             # 12 % since: built again
    assert settling.correction is not built and settling.correction is not None
    assert settling.update(indices, size // 4, 0.1)        # churns with it: dropped
    assert settling.correction is None
    assert not settling.update(indices, 0, 0.1) and not settling.update(indices, 0, 0.1)
    assert settling.correction is None                     # for the rest of the solve


def test_no_correction_where_the_inverse_symbol_alone_converges_fast():
    operator = HalfSpace((64, 64), 1.0, periodic=True)
    indices = np.flatnonzero(_patches(64, 0.4))
    settling = SettlingCorrection(operator)
    for norm in (1.0, 0.25, 0.06, 0.015, 0.004, 0.001):   # 0.25 per iteration: fast
        assert not settling.update(indices, 0, norm)
    assert settling.correction is None
