"""Inverse-kernel preconditioner of the half-space operator on a contact set.

The half-space operator K acts on a pressure field like ``2 / (E* |q|)`` in Fourier space
(docs/theory.md, "8. The reference"), so its condition number on an n x n grid grows like n and so does
the number of conjugate-gradient iterations of the unpreconditioned contact solver. The
preconditioner is the inverse symbol on the n x n grid taken as one period,

    ``M r = IDFT( (E* / 2) |q|_eff  DFT(r) )``,   ``|q|_eff = max(|q|, q_0)``

with ``q = 2 pi (k_x / L, k_y / L)`` the DFT wavevectors, ``L = n h``, and ``q_0 = 2 pi / L`` the
lowest non-zero wavenumber (it stands in at q = 0, where the periodic kernel has no value).
Restricted to the contact set C, ``P_C M P_C`` is symmetric positive (semi-)definite, so it is
a valid preconditioner for the conjugate gradients on C (Vollebregt 2014, "A new solver for the
elastic normal contact problem using conjugate gradients, deflation, and an FFT-based
preconditioner", J. Comput. Phys. 257). For the periodic half-space it is the exact inverse of
K (full contact converges in one step); for the non-periodic one (Love's kernel, DC-FFT) it is
the inverse of the kernel's periodic continuum limit, a spectrally equivalent operator.

Cost: one real FFT pair of the n x n grid (a quarter to a third of the non-periodic operator's
padded pair), in its own buffers, in single precision on the CPU: a preconditioner only shapes the
search direction (the gap, the step and the stopping rule stay in double precision), and the
float32 pair takes 55 ms against 99 ms at 2048^2 on one core (13.6 against 19.7 ms at 1024^2).
"""

from __future__ import annotations

import math

import numpy as np

from bem.common import checks
from bem.elastic.device import array_module
from bem.elastic.fft import PRECISIONS, RealFFT2

__all__ = ["InverseKernel"]

#: Grids of at least this many points are planned with FFTW_MEASURE: one 1024^2 pair took 7.0
#: ms against 9.8 ms planned by FFTW_ESTIMATE (0.80 against 0.87 ms at 512^2, no gain below);
#: the plans are measured once per machine (:mod:`bem.elastic.wisdom`).
_MEASURED_GRID = 512 * 512


class InverseKernel:
    """``M = (E*/2) |q|`` on the grid as one period (module docstring); owns its FFT buffers.

    Parameters
    ----------
    shape : tuple of int
        Grid shape (rows, columns).
    spacing : float
        Grid step h [length].
    e_star : float
        Composite modulus E* [pressure].
    backend, threads
        As for :class:`bem.elastic.fft.RealFFT2`.
    device : {"cpu", "gpu"}
        Where it runs (:mod:`bem.elastic.device`); its blocks are then arrays of that device.
    planner_effort : str, optional
        As for :class:`bem.elastic.fft.RealFFT2`; default "FFTW_MEASURE" from 512 x 512 points on,
        "FFTW_ESTIMATE" below.
    precision : {"single", "double"}
        Of the FFT pair on the CPU (module docstring; the GPU's is double).

    Attributes
    ----------
    input_block, output_block : numpy.ndarray
        Work arrays of ``shape`` (float32 in single precision): :meth:`execute` computes
        ``output = M input``; a caller reads the output as float64 (:meth:`read`).
    """

    def __init__(self, shape: tuple[int, int], spacing: float, *, e_star: float = 1.0,
                 backend: str = "auto", threads: int | None = None,
                 planner_effort: str | None = None, device: str = "cpu",
                 precision: str = "single") -> None:
        self.shape = tuple(int(s) for s in shape)
        checks.choice("precision", precision, PRECISIONS)
        if planner_effort is None:
            planner_effort = ("FFTW_MEASURE" if self.shape[0] * self.shape[1] >= _MEASURED_GRID
                              else "FFTW_ESTIMATE")
        xp = array_module(device)
        if device == "gpu":
            from bem.elastic.fft_device import DeviceRealFFT2

            self._fft = DeviceRealFFT2(xp, self.shape)
        else:
            self._fft = RealFFT2(self.shape, backend=backend, threads=threads,
                                 planner_effort=planner_effort, precision=precision)
        ny, nx = self.shape
        qy = 2.0 * math.pi * np.fft.fftfreq(ny, d=spacing)
        qx = 2.0 * math.pi * np.fft.rfftfreq(nx, d=spacing)
        q = np.hypot(qy[:, None], qx[None, :])
        q[0, 0] = 2.0 * math.pi / (max(ny, nx) * spacing)
        symbol = 0.5 * e_star * q / self._fft.size
        # each value twice: one real multiply over the float view of the complex spectrum
        self._scaled_symbol = xp.asarray(np.repeat(symbol, 2, axis=1),
                                         dtype=self._fft.real_buffer.dtype)
        self.input_block = self._fft.real_buffer
        self.output_block = self._fft.output_buffer
        self._output_flat = self.output_block.reshape(-1)

    def execute(self) -> None:
        """``output_block = M input_block`` (``input_block`` is kept)."""
        fft = self._fft
        fft.execute_forward()
        spectrum = fft.spectrum_buffer.view(fft.real_buffer.dtype)
        np.multiply(spectrum, self._scaled_symbol, out=spectrum)
        fft.execute_inverse()

    def read(self, positions: np.ndarray) -> np.ndarray:
        """The output at the flat ``positions`` as a fresh float64 array."""
        return self._output_flat[positions].astype(np.float64, copy=False)
