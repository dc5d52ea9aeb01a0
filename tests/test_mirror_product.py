"""The mirror (interface) half-space product by one real FFT pair (bem.elastic.mirror_product)."""

import numpy as np
import pytest
import scipy.fft

from bem import HalfSpace
from bem.elastic.fft import have_pyfftw
from bem.elastic.mirror_product import MirrorProduct

needs_pyfftw = pytest.mark.skipif(not have_pyfftw(), reason="pyFFTW not installed")
BACKENDS = ["scipy", pytest.param("pyfftw", marks=needs_pyfftw)]


def _extension_displacement(pressure: np.ndarray, spacing: float, e_star: float) -> np.ndarray:
    """The periodic half-space's displacement under the even extension of ``pressure`` (the
    field and its mirror images, period twice the grid), on the grid itself: the periodic
    kernel 2 / (E* |q|) of the 2N x 2M period, by a complex FFT of the whole extension."""
    rows, columns = pressure.shape
    extension = np.block([[pressure, pressure[:, ::-1]],
                          [pressure[::-1], pressure[::-1, ::-1]]])
    qy = 2 * np.pi * np.fft.fftfreq(2 * rows, d=spacing)
    qx = 2 * np.pi * np.fft.fftfreq(2 * columns, d=spacing)
    q = np.hypot(qy[:, None], qx[None, :])
    kernel = np.divide(2.0 / e_star, q, out=np.zeros_like(q), where=q > 0)
    return np.fft.ifft2(kernel * np.fft.fft2(extension)).real[:rows, :columns]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("shape", [(2, 2), (6, 10), (16, 16), (32, 18), (7, 8), (9, 9)])
def test_mirror_product_is_the_periodic_product_of_the_even_extension(shape, backend):
    # even sides: the folded real-FFT product; odd ones: cosine transforms
    rng = np.random.default_rng(sum(shape))
    pressure = rng.random(shape)
    operator = HalfSpace(shape, 0.7, e_star=3.0, periodic=True, mirror=True, backend=backend)
    expected = _extension_displacement(pressure, 0.7, 3.0)
    np.testing.assert_allclose(operator.displacement(pressure), expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("shape", [(2, 4), (8, 6), (20, 12)])
def test_folded_product_equals_cosine_transforms_for_any_real_multiplier(shape, backend):
    # a multiplier without the kernel's symmetries exercises every coupling term, including
    # the rows and columns at 0 and N/2 whose reflections are themselves or absent
    rng = np.random.default_rng(3)
    block, multiplier = rng.normal(size=shape), rng.normal(size=shape)
    product = MirrorProduct(shape, backend=backend, planner_effort="FFTW_ESTIMATE")
    product.input_block[...] = block
    product.execute(multiplier / product.size)
    expected = scipy.fft.idctn(multiplier * scipy.fft.dctn(block, type=2), type=2)
    np.testing.assert_allclose(product.output_block, expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())
    np.testing.assert_array_equal(product.input_block, block)   # kept for the next product
    product.execute(multiplier / product.size)
    np.testing.assert_allclose(product.output_block, expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("shape", [(7, 8), (8, 7), (1, 2)])
def test_folded_product_needs_even_sides(shape):
    with pytest.raises(ValueError, match="even sides"):
        MirrorProduct(shape)
