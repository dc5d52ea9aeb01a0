"""The FFT pairs of :mod:`bem.elastic.fft` on a GPU: the same buffers and methods, in CuPy arrays, with
cuFFT through :mod:`cupyx.scipy.fft` (which caches its plans per shape).

:func:`device_transform` builds the pair a :class:`bem.HalfSpace` or the preconditioner asks
for on the GPU: :class:`DeviceRealFFT2` (periodic), :class:`DeviceCosineTransform2` (the mirror
quadrant) and :class:`DevicePaddedRealFFT2` (the zero-padded block of the non-periodic
operator). Each has the attributes of its CPU counterpart (``real_buffer`` or ``input_block``,
``spectrum_buffer``, ``output_buffer`` or ``output_block``, the flat views and ``row_stride``,
``size``) and the same unnormalised conventions, so the operator's product and the solvers'
scattered reads and writes run unchanged on them. The padded pair transforms the padded array
whole (cuFFT has no pruned plans; the zero rows cost a quarter more than the CPU's pruned pair).
"""

from __future__ import annotations

from types import ModuleType

__all__ = ["DeviceCosineTransform2", "DevicePaddedRealFFT2", "DeviceRealFFT2",
           "device_transform"]


def _fft_module(xp: ModuleType) -> ModuleType:
    """The scipy.fft-like module of the array module ``xp`` (cupyx.scipy.fft for CuPy)."""
    module = getattr(xp, "scipy_fft", None)   # an array module may bring its own
    if module is not None:
        return module
    import cupyx.scipy.fft

    return cupyx.scipy.fft


class _DevicePair:
    """Shared set-up: zeroed real input, spectrum and real output buffers on the device."""

    backend = "cupy"
    threads = 1

    def __init__(self, xp: ModuleType, shape: tuple[int, int], input_shape: tuple[int, int],
                 spectrum_shape: tuple[int, int], spectrum_dtype, size: int) -> None:
        self.xp, self.fft = xp, _fft_module(xp)
        self.shape = tuple(shape)
        self.spectrum_shape = tuple(spectrum_shape)
        self.size = int(size)
        self.real_buffer = xp.zeros(input_shape, dtype=xp.float64)
        self.spectrum_buffer = xp.zeros(spectrum_shape, dtype=spectrum_dtype)
        self.output_buffer = xp.zeros(input_shape, dtype=xp.float64)
        rows, columns = shape
        self.input_block = self.real_buffer[:rows, :columns]
        self.output_block = self.output_buffer[:rows, :columns]
        self.input_flat = self.real_buffer.reshape(-1)
        self.output_flat = self.output_buffer.reshape(-1)
        self.row_stride = input_shape[1]


class DeviceRealFFT2(_DevicePair):
    """:class:`bem.elastic.fft.RealFFT2` on the device."""

    def __init__(self, xp: ModuleType, shape: tuple[int, int]) -> None:
        rows, columns = shape
        super().__init__(xp, shape, shape, (rows, columns // 2 + 1), xp.complex128,
                         rows * columns)

    def execute_forward(self) -> None:
        """``spectrum_buffer = rfft2(real_buffer)`` (unnormalised)."""
        self.spectrum_buffer[...] = self.fft.rfft2(self.real_buffer)

    def execute_inverse(self) -> None:
        """``output_buffer = size * irfft2(spectrum_buffer)``."""
        self.output_buffer[...] = self.fft.irfft2(self.spectrum_buffer, s=self.shape,
                                                  norm="forward")


class DeviceCosineTransform2(_DevicePair):
    """:class:`bem.elastic.fft.CosineTransform2` on the device (DCT-II forward, DCT-III inverse)."""

    def __init__(self, xp: ModuleType, shape: tuple[int, int]) -> None:
        rows, columns = shape
        super().__init__(xp, shape, shape, shape, xp.float64, 4 * rows * columns)

    def execute_forward(self) -> None:
        """``spectrum_buffer = DCT-II(real_buffer)`` along both axes (unnormalised)."""
        self.spectrum_buffer[...] = self.fft.dctn(self.real_buffer, type=2)

    def execute_inverse(self) -> None:
        """``output_buffer = DCT-III(spectrum_buffer)``: ``size`` times the inverse."""
        self.output_buffer[...] = self.fft.dctn(self.spectrum_buffer, type=3)


class DevicePaddedRealFFT2(_DevicePair):
    """:class:`bem.elastic.fft.PaddedRealFFT2` on the device: the block in the corner of a padded
    array of twice its size; rows of the output block ``row_stride = 2 columns`` apart."""

    def __init__(self, xp: ModuleType, shape: tuple[int, int]) -> None:
        rows, columns = shape
        self.padded_shape = (2 * rows, 2 * columns)
        super().__init__(xp, shape, self.padded_shape, (2 * rows, columns + 1), xp.complex128,
                         4 * rows * columns)

    def execute_forward(self) -> None:
        """``spectrum_buffer = rfft2(input_block zero-padded to 2 x shape)`` (unnormalised)."""
        self.spectrum_buffer[...] = self.fft.rfft2(self.real_buffer)

    def execute_inverse(self) -> None:
        """``output_block = size * irfft2(spectrum_buffer)[:rows, :columns]``."""
        self.output_buffer[...] = self.fft.irfft2(self.spectrum_buffer, s=self.padded_shape,
                                                  norm="forward")


def device_transform(xp: ModuleType, shape: tuple[int, int], *, periodic: bool,
                     mirror: bool) -> _DevicePair:
    """The device pair of a half-space operator of grid ``shape``."""
    if mirror:
        return DeviceCosineTransform2(xp, shape)
    if periodic:
        return DeviceRealFFT2(xp, shape)
    return DevicePaddedRealFFT2(xp, shape)
