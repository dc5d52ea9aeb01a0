"""Real two-dimensional FFTs with planned pyFFTW transforms and a scipy.fft fallback.

Normalisation: ``forward`` is the unnormalised DFT ``X[k] = sum_n x[n] exp(-2 pi i k.n / N)``
(numpy's ``rfft2``), ``inverse`` divides by the number of points (numpy's ``irfft2``), so
``inverse(forward(x)) == x``. Both backends give the same numbers to rounding (about 1e-15
relative).

The backend is pyFFTW when it is installed (plans made once per shape, threads = CPU count),
otherwise ``scipy.fft`` with ``workers`` = CPU count. ``backend="scipy"`` forces the fallback.

Besides the allocating ``forward``/``inverse`` pair, a :class:`RealFFT2` owns three aligned work
buffers, ``real_buffer`` -> ``spectrum_buffer`` -> ``output_buffer``, and transforms between
them in place with :meth:`RealFFT2.execute_forward` and :meth:`RealFFT2.execute_inverse` (the
latter unnormalised). ``real_buffer`` is only read by the transforms, so a zero-padded input
keeps its padding from call to call.
Solvers that call the same transform thousands of times use these to avoid allocations and
copies; the buffers belong to the transform object and are overwritten by every call.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from bem.common import checks
from bem.elastic.fft_threads import default_threads
from bem.elastic.wisdom import load_wisdom, pyfftw, save_wisdom  # pyfftw: None where not installed

__all__ = ["COSINE_FFTW_LIMIT", "PRECISIONS", "RealFFT2", "CosineTransform2", "PaddedRealFFT2", "have_pyfftw"]

#: FFT backends: pyFFTW when installed ("auto"), or one of the two by name.
BACKENDS = ("auto", "pyfftw", "scipy")
#: Cosine transforms (:class:`CosineTransform2`) of grids with more points than this use FFTW
#: under ``backend="auto"``, smaller ones scipy's.
COSINE_FFTW_LIMIT = 512 * 512
_PLANNER_EFFORTS = ("FFTW_ESTIMATE", "FFTW_MEASURE", "FFTW_PATIENT", "FFTW_EXHAUSTIVE")
#: Floating-point precisions of :class:`RealFFT2`.
PRECISIONS = ("double", "single")


def have_pyfftw() -> bool:
    """Whether pyFFTW could be imported."""
    return pyfftw is not None


def _empty(shape: tuple[int, ...], dtype) -> np.ndarray:
    if pyfftw is not None:
        return pyfftw.empty_aligned(shape, dtype=dtype)
    return np.empty(shape, dtype=dtype)


def _check_arguments(shape, backend: str, threads: int | None, planner_effort: str
                     ) -> tuple[int, int]:
    """Checked shape of an FFT pair, after checking its other arguments."""
    if not isinstance(shape, (tuple, list)) or len(shape) != 2:
        raise ValueError(f"shape must be two positive integers, got {shape!r}")
    shape = tuple(checks.integer("shape", s, minimum=1) for s in shape)
    if checks.choice("backend", backend, BACKENDS) == "pyfftw" and pyfftw is None:
        raise ValueError("backend='pyfftw' was asked for but pyFFTW is not installed")
    checks.choice("planner_effort", planner_effort, _PLANNER_EFFORTS)
    checks.optional_integer("threads", threads, minimum=1)
    return shape


def _plan_pair(transform, spectrum_dtype, forward, inverse, planner_effort: str,
               real_dtype=np.float64) -> None:
    """Give ``transform`` (its ``shape``, ``spectrum_shape``, ``backend`` and ``threads`` set)
    its zeroed real (``real_dtype``), spectrum and output buffers, the pyFFTW plans of the
    ``forward`` and ``inverse`` directions between them, and the names a convolution reads them
    by (``input_block``, ``output_block``, ``input_flat``, ``output_flat``, ``row_stride``)."""
    shape = transform.shape
    transform.real_buffer = _empty(shape, real_dtype)
    transform.spectrum_buffer = _empty(transform.spectrum_shape, spectrum_dtype)
    transform.output_buffer = _empty(shape, real_dtype)
    if transform.backend == "pyfftw":
        load_wisdom()
        # Plans bind the two buffers; FFTW_MEASURE scribbles on them while planning.
        transform._plan_forward = pyfftw.FFTW(
            transform.real_buffer, transform.spectrum_buffer, axes=(0, 1), direction=forward,
            flags=(planner_effort,), threads=transform.threads)
        transform._plan_inverse = pyfftw.FFTW(
            transform.spectrum_buffer, transform.output_buffer, axes=(0, 1), direction=inverse,
            flags=(planner_effort, "FFTW_DESTROY_INPUT"), threads=transform.threads)
        if planner_effort != "FFTW_ESTIMATE":
            save_wisdom()
    transform.real_buffer.fill(0.0)
    transform.spectrum_buffer.fill(0.0)
    transform.output_buffer.fill(0.0)
    # the names shared with PaddedRealFFT2, so a convolution can use either
    transform.input_block = transform.real_buffer
    transform.output_block = transform.output_buffer
    transform.input_flat = transform.real_buffer.reshape(-1)
    transform.output_flat = transform.output_buffer.reshape(-1)
    transform.row_stride = shape[1]


class RealFFT2:
    """Planned real 2-D FFT pair of one real shape.

    Parameters
    ----------
    shape : tuple of int
        Real-space shape (rows, columns).
    backend : {"auto", "pyfftw", "scipy"}
        "auto" uses pyFFTW when installed.
    threads : int, optional
        Threads (pyFFTW) or workers (scipy); default: :func:`default_threads`.
    planner_effort : str
        pyFFTW planner effort, e.g. "FFTW_MEASURE" (default) or "FFTW_ESTIMATE". Planning with
        FFTW_MEASURE takes 0.3-1.3 s for 256^2 to 2048^2 here (once per shape and machine: FFTW
        keeps the wisdom for the process, :mod:`bem.elastic.wisdom` in a file for the next ones) and
        overwrites the work buffers.
    precision : {"double", "single"}
        Floating point of the buffers and transforms: float64/complex128 (default) or
        float32/complex64 (relative error about 1e-7; a 2048^2 pair in 55 ms against 99 ms on
        one core here), for products that need not be exact, such as a preconditioner's.

    Attributes
    ----------
    real_buffer : numpy.ndarray
        Real work array of ``shape`` (float64, float32 in single precision), input of
        :meth:`execute_forward` (never written by the transforms).
    spectrum_buffer : numpy.ndarray
        complex128 (complex64) work array of ``spectrum_shape = (rows, columns // 2 + 1)``.
    output_buffer : numpy.ndarray
        Real work array of ``shape``, output of :meth:`execute_inverse`.
    input_flat, output_flat, row_stride
        The input and output buffers as flat arrays, rows ``row_stride`` elements apart
        (``columns`` here), for reading and writing scattered points.

    Notes
    -----
    ``forward`` and ``inverse`` return fresh arrays the caller owns (never an internal buffer).
    """

    def __init__(self, shape: tuple[int, int], *, backend: str = "auto", threads: int | None = None,
                 planner_effort: str = "FFTW_MEASURE", precision: str = "double") -> None:
        shape = _check_arguments(shape, backend, threads, planner_effort)
        single = checks.choice("precision", precision, PRECISIONS) == "single"
        self.shape = shape
        self.spectrum_shape = (shape[0], shape[1] // 2 + 1)
        self.size = shape[0] * shape[1]
        self.threads = default_threads() if threads is None else int(threads)
        self.backend = "pyfftw" if (backend != "scipy" and pyfftw is not None) else "scipy"
        _plan_pair(self, np.complex64 if single else np.complex128, "FFTW_FORWARD",
                   "FFTW_BACKWARD", planner_effort, np.float32 if single else np.float64)

    # -- in-place transforms between the owned buffers -------------------------------------

    def execute_forward(self) -> None:
        """``spectrum_buffer = rfft2(real_buffer)`` (unnormalised); ``real_buffer`` is kept."""
        if self.backend == "pyfftw":
            self._plan_forward.execute()
        else:
            self.spectrum_buffer[...] = scipy.fft.rfft2(self.real_buffer, workers=self.threads)

    def execute_inverse(self) -> None:
        """``output_buffer = size * irfft2(spectrum_buffer)``: unnormalised, destroys the spectrum.

        The caller folds the ``1 / size`` factor into whatever it multiplies the spectrum by.
        """
        if self.backend == "pyfftw":
            self._plan_inverse.execute()
        else:
            self.output_buffer[...] = scipy.fft.irfft2(self.spectrum_buffer, s=self.shape,
                                                       norm="forward", workers=self.threads)

    # -- allocating transforms ----------------------------------------------------------------

    def forward(self, real: np.ndarray) -> np.ndarray:
        """Unnormalised real-to-complex DFT of an array of ``shape`` (fresh array)."""
        real = np.asarray(real, dtype=self.real_buffer.dtype)
        if real.shape != self.shape:
            raise ValueError(f"real must have shape {self.shape}, got {real.shape}")
        if self.backend == "pyfftw":
            self.real_buffer[...] = real
            self._plan_forward.execute()
            return self.spectrum_buffer.copy()
        return scipy.fft.rfft2(real, workers=self.threads)

    def inverse(self, spectrum: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`forward` (divides by the number of points; fresh array)."""
        spectrum = np.asarray(spectrum, dtype=self.spectrum_buffer.dtype)
        if spectrum.shape != self.spectrum_shape:
            raise ValueError(f"spectrum must have shape {self.spectrum_shape}, got {spectrum.shape}")
        if self.backend == "pyfftw":
            # A complex-to-real FFTW transform destroys its input: always work on the buffer.
            self.spectrum_buffer[...] = spectrum
            self._plan_inverse.execute()
            return self.output_buffer / self.size
        return scipy.fft.irfft2(spectrum, s=self.shape, workers=self.threads)


class CosineTransform2:
    """Planned 2-D cosine transform pair of one real shape: the DFT of the even (mirror)
    extension of an array, computed on the array itself.

    A 2N x 2M field even about the lines half a pixel beyond the edges of its N x M quadrant
    (:func:`bem.interface.mirror_extension`) has a real DFT that is the type-II cosine
    transform of the quadrant (up to a phase the inverse undoes), so a convolution of such
    fields with an even kernel is a product of type-II cosine transforms: a quarter of the
    points of the extension's FFT.

    ``backend="auto"`` is FFTW's real-to-real transforms (pyFFTW, when installed) on grids of
    more than :data:`COSINE_FFTW_LIMIT` points, scipy's (pocketfft) up to it. A forward and
    inverse pair (median of 12 alternating with the other backend; one thread, FFTW_MEASURE):
    2048^2 114 ms against scipy's 175 ms (two threads 82 against 112 ms), 1024^2 38 against
    40 ms; at 128^2 to 512^2 the two were equal (0.2-0.3, 1.7, 9.7 ms), and scipy plans
    nothing. ``"pyfftw"`` and ``"scipy"`` force one.

    ``execute_forward``: ``spectrum_buffer = DCT-II(input_block)`` along both axes
    (``X[k] = 2 sum_n x[n] cos(pi k (2n + 1) / 2N)``, FFTW's REDFT10); ``execute_inverse``:
    ``output_block = DCT-III(spectrum_buffer)`` (REDFT01), which returns ``size = 4 N M``
    times the input of the forward transform. The attributes are those of :class:`RealFFT2`
    (``spectrum_buffer`` is real), so a half-space operator can use either. The mirror
    operator uses it on grids with an odd side; on even ones one real FFT pair of the
    reordered grid computes its product in 0.5-0.9 of the time at 512^2 to 2048^2
    (:class:`bem.elastic.mirror_product.MirrorProduct`, ``benchmarks/bench_mirror_product.py``).
    """

    def __init__(self, shape: tuple[int, int], *, backend: str = "auto", threads: int | None = None,
                 planner_effort: str = "FFTW_MEASURE") -> None:
        shape = _check_arguments(shape, backend, threads, planner_effort)
        self.shape = shape
        self.spectrum_shape = shape
        self.size = 4 * shape[0] * shape[1]
        self.threads = default_threads() if threads is None else int(threads)
        large = shape[0] * shape[1] > COSINE_FFTW_LIMIT
        self.backend = "pyfftw" if pyfftw is not None and (
            backend == "pyfftw" or (backend == "auto" and large)) else "scipy"
        _plan_pair(self, np.float64, ("FFTW_REDFT10", "FFTW_REDFT10"),
                   ("FFTW_REDFT01", "FFTW_REDFT01"), planner_effort)

    def execute_forward(self) -> None:
        """``spectrum_buffer = DCT-II(real_buffer)`` (unnormalised); ``real_buffer`` is kept."""
        if self.backend == "pyfftw":
            self._plan_forward.execute()
        else:
            self.spectrum_buffer[...] = scipy.fft.dctn(self.real_buffer, type=2,
                                                       workers=self.threads)

    def execute_inverse(self) -> None:
        """``output_buffer = DCT-III(spectrum_buffer)``: ``size`` times the inverse of the
        forward transform; destroys the spectrum."""
        if self.backend == "pyfftw":
            self._plan_inverse.execute()
        else:
            self.output_buffer[...] = scipy.fft.dctn(self.spectrum_buffer, type=3,
                                                     workers=self.threads)


class PaddedRealFFT2:
    """Real 2-D FFT pair of an array zero-padded to twice its size, pruned of the zero work.

    The forward transform of a ``(rows, columns)`` block placed in the corner of a
    ``(2 rows, 2 columns)`` array of zeros, and of the inverse only the corner block: the
    spectrum is the same as ``rfft2`` of the padded array (shape ``(2 rows, columns + 1)``), but
    the transforms along rows run over the ``rows`` non-zero rows only (forward) and the
    ``rows`` rows that are kept (inverse), which saves about a quarter of the work of a full
    transform pair of the padded size. This is the linear (non-circular) convolution of the
    DC-FFT method.

    Parameters
    ----------
    shape : tuple of int
        The block's shape (rows, columns); the padded grid is twice that.
    backend, threads, planner_effort
        As for :class:`RealFFT2`.

    Attributes
    ----------
    input_block : numpy.ndarray
        float64 view of shape ``shape``: the caller writes the block here before
        :meth:`execute_forward` (the padding is never written by the transforms).
    spectrum_buffer : numpy.ndarray
        complex128 array of shape ``(2 rows, columns + 1)``.
    output_block : numpy.ndarray
        float64 view of shape ``shape``: ``size`` times the first block of the inverse, after
        :meth:`execute_inverse` (unnormalised, like :meth:`RealFFT2.execute_inverse`).
    input_flat, output_flat, row_stride
        The arrays holding the two blocks as flat arrays, block rows ``row_stride = 2 columns``
        elements apart (the padding of the input is zero, and must stay so).
    size : int
        Number of points of the padded grid, ``4 rows columns``.
    """

    def __init__(self, shape: tuple[int, int], *, backend: str = "auto", threads: int | None = None,
                 planner_effort: str = "FFTW_MEASURE") -> None:
        shape = _check_arguments(shape, backend, threads, planner_effort)
        rows, columns = shape
        self.shape = shape
        self.padded_shape = (2 * rows, 2 * columns)
        self.spectrum_shape = (2 * rows, columns + 1)
        self.size = 4 * rows * columns
        self.threads = default_threads() if threads is None else int(threads)
        self.backend = "pyfftw" if (backend != "scipy" and pyfftw is not None) else "scipy"
        self._rows_in = _empty((rows, 2 * columns), np.float64)        # padded along x only
        self.spectrum_buffer = _empty(self.spectrum_shape, np.complex128)
        self._rows_out = _empty((rows, 2 * columns), np.float64)
        if self.backend == "pyfftw":
            # rows: r2c of the non-zero rows into the first half of the spectrum; columns: in
            # place over the whole spectrum (in-place column transforms planned faster than
            # out-of-place ones here); inverse in the reverse order, rows only for kept rows.
            flags = (planner_effort,)
            load_wisdom()
            self._plan_rows = pyfftw.FFTW(
                self._rows_in, self.spectrum_buffer[:rows], axes=(1,), direction="FFTW_FORWARD",
                flags=flags, threads=self.threads)
            self._plan_columns = pyfftw.FFTW(
                self.spectrum_buffer, self.spectrum_buffer, axes=(0,), direction="FFTW_FORWARD",
                flags=flags, threads=self.threads)
            self._plan_columns_inverse = pyfftw.FFTW(
                self.spectrum_buffer, self.spectrum_buffer, axes=(0,),
                direction="FFTW_BACKWARD", flags=flags, threads=self.threads)
            self._plan_rows_inverse = pyfftw.FFTW(
                self.spectrum_buffer[:rows], self._rows_out, axes=(1,),
                direction="FFTW_BACKWARD", flags=flags + ("FFTW_DESTROY_INPUT",),
                threads=self.threads)
            if planner_effort != "FFTW_ESTIMATE":
                save_wisdom()
        for array in (self._rows_in, self.spectrum_buffer, self._rows_out):
            array.fill(0.0)
        self.input_block = self._rows_in[:, :columns]
        self.output_block = self._rows_out[:, :columns]
        self.input_flat = self._rows_in.reshape(-1)
        self.output_flat = self._rows_out.reshape(-1)
        self.row_stride = 2 * columns

    def execute_forward(self) -> None:
        """``spectrum_buffer = rfft2(input_block zero-padded to 2 x shape)`` (unnormalised)."""
        rows = self.shape[0]
        if self.backend == "pyfftw":
            self._plan_rows.execute()
            self.spectrum_buffer[rows:] = 0.0  # the zero rows of the padded block
            self._plan_columns.execute()
        else:
            self.spectrum_buffer[...] = scipy.fft.fft(
                scipy.fft.rfft(self._rows_in, axis=1, workers=self.threads),
                n=2 * rows, axis=0, workers=self.threads)

    def execute_inverse(self) -> None:
        """``output_block = size * irfft2(spectrum_buffer)[:rows, :columns]``; destroys the
        spectrum."""
        rows = self.shape[0]
        if self.backend == "pyfftw":
            self._plan_columns_inverse.execute()
            self._plan_rows_inverse.execute()
        else:
            columns = scipy.fft.ifft(self.spectrum_buffer, axis=0, norm="forward",
                                     workers=self.threads)
            self._rows_out[...] = scipy.fft.irfft(columns[:rows], n=self.padded_shape[1],
                                                  axis=1, norm="forward", workers=self.threads)
