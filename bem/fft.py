"""Real two-dimensional FFTs with planned pyFFTW transforms and a scipy.fft fallback.

Normalisation: ``forward`` is the unnormalised DFT ``X[k] = sum_n x[n] exp(-2 pi i k.n / N)``
(numpy's ``rfft2``), ``inverse`` divides by the number of points (numpy's ``irfft2``), so
``inverse(forward(x)) == x``. Both backends give the same numbers to rounding (about 1e-15
relative).

The backend is pyFFTW when it is installed (plans made once per shape, threads = CPU count),
otherwise ``scipy.fft`` with ``workers`` = CPU count. ``backend="scipy"`` forces the fallback.
"""

from __future__ import annotations

import os

import numpy as np
import scipy.fft

try:  # pyFFTW is optional at run time
    import pyfftw
    import pyfftw.builders
except ImportError:  # pragma: no cover - exercised by a subprocess test
    pyfftw = None

__all__ = ["RealFFT2", "have_pyfftw", "default_threads"]


def have_pyfftw() -> bool:
    """Whether pyFFTW could be imported."""
    return pyfftw is not None


def default_threads() -> int:
    """Number of threads for FFTs: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


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
        pyFFTW planner effort, e.g. "FFTW_MEASURE" (default) or "FFTW_ESTIMATE".

    Notes
    -----
    ``forward`` and ``inverse`` return fresh arrays the caller owns (never an internal buffer).
    """

    def __init__(self, shape: tuple[int, int], *, backend: str = "auto", threads: int | None = None,
                 planner_effort: str = "FFTW_MEASURE") -> None:
        shape = tuple(int(s) for s in shape)
        if len(shape) != 2 or min(shape) < 1:
            raise ValueError(f"shape must be two positive integers, got {shape!r}")
        if backend not in ("auto", "pyfftw", "scipy"):
            raise ValueError(f"backend must be 'auto', 'pyfftw' or 'scipy', got {backend!r}")
        if backend == "pyfftw" and pyfftw is None:
            raise ValueError("backend='pyfftw' was asked for but pyFFTW is not installed")
        self.shape = shape
        self.spectrum_shape = (shape[0], shape[1] // 2 + 1)
        self.threads = default_threads() if threads is None else int(threads)
        self.backend = "pyfftw" if (backend != "scipy" and pyfftw is not None) else "scipy"
        if self.backend == "pyfftw":
            real = pyfftw.empty_aligned(shape, dtype=np.float64)
            self._forward = pyfftw.builders.rfft2(
                real, threads=self.threads, planner_effort=planner_effort,
                overwrite_input=False, avoid_copy=False, auto_align_input=True)
            spectrum = pyfftw.empty_aligned(self.spectrum_shape, dtype=np.complex128)
            self._inverse = pyfftw.builders.irfft2(
                spectrum, s=shape, threads=self.threads, planner_effort=planner_effort,
                avoid_copy=False, auto_align_input=True)

    def forward(self, real: np.ndarray) -> np.ndarray:
        """Unnormalised real-to-complex DFT of an array of ``shape``."""
        if self.backend == "pyfftw":
            # Copy into the planned (aligned) input buffer: the caller's array is never touched.
            self._forward.input_array[...] = real
            return self._forward().copy()
        return scipy.fft.rfft2(real, s=self.shape, workers=self.threads)

    def inverse(self, spectrum: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`forward` (divides by the number of points)."""
        if self.backend == "pyfftw":
            # A complex-to-real FFTW transform destroys its input: always work on the buffer.
            self._inverse.input_array[...] = spectrum
            return self._inverse().copy()
        return scipy.fft.irfft2(spectrum, s=self.shape, workers=self.threads)
