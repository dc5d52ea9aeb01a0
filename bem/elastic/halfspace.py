"""The elastic half-space as a linear operator: pressure on a grid -> surface displacement.

Conventions (docs/theory.md, "The reference")
---------------------------------------------
Pressure ``p`` is positive in compression and uniform over each pixel of side ``spacing`` h;
the displacement ``u = K * p`` is positive into the body (a point force P lowers the surface by
``P / (pi E* r)`` at distance r). Grids are indexed ``[j, i]`` (row j is y, column i is x).

* Non-periodic (``periodic=False``): ``u[j, i] = sum_{l, k} G[j - l, i - k] p[l, k]`` with G
  Love's (1929) displacement at offset ``(j - l, i - k) h`` under unit pressure on one pixel
  (:func:`bem.elastic.kernel.love_pixel_displacement`, asinh form). The discrete convolution is exact
  (no wrap-around) by the DC-FFT method (Liu, Wang & Liu 2000): G sampled on a 2N x 2N grid in
  wrap-around order, the pressure zero-padded to 2N x 2N, and the first N x N block kept
  (:class:`bem.elastic.fft.PaddedRealFFT2` skips the transforms of the zero rows and of the discarded
  output rows: about 3/4 of the work of a full 2N x 2N transform pair).
  The displacement vanishes in the far field, the reference of the separation.
* Mirror (``periodic=True, mirror=True``): the grid is one quadrant of the period 2L x 2L of
  its even (mirror) extension (:func:`bem.interface.mirror_extension`), on the periodic
  half-space below. An even pressure field has an even displacement, and the product is one of
  type-II cosine transforms of the quadrant, the wavevectors ``q = pi (k_x / L_x, k_y / L_y)``
  of the extension's modes: the periodic solution of the extension at a quarter of its points
  (even grids: :class:`bem.elastic.mirror_product.MirrorProduct`; odd ones and the GPU: cosine transforms).
* Periodic (``periodic=True``): the grid is one period L x L of a periodic surface and
  ``u_hat(q) = 2 p_hat(q) / (E* |q|)`` for ``q != 0`` with ``q = 2 pi (k_x / L_x, k_y / L_y)``
  the wavevector of the discrete Fourier mode. At ``q = 0`` we set ``u_hat(0) = 0``: the mean
  displacement is zero (a uniform pressure on an infinite periodic half-space has no finite
  displacement), so the mean plane of the deformed surface equals that of the undeformed one.

FFT normalisation
-----------------
With the unnormalised forward DFT ``X[k] = sum_n x[n] exp(-2 pi i k.n / M)`` over the M points
of the convolution grid (2N x 2N non-periodic, N x N periodic), the operator is
``u = IDFT(K_hat X)`` with ``IDFT(Y)[n] = (1/M) sum_k Y[k] exp(+2 pi i k.n / M)``. The stored
spectrum ``K_hat`` is the DFT of the sampled kernel G (non-periodic; real because G is even), or
``2 / (E* |q|)`` evaluated at the DFT wavevectors (periodic; already in the units of a
continuous transform because the DFT pair with 1/M is the Fourier series of a periodic field).
The factor ``1/M`` is folded into the stored spectrum, so one forward and one unnormalised
inverse FFT make one product.
"""

from __future__ import annotations

import math

import numpy as np

from bem.common import checks
from bem.elastic.device import array_module, to_host
from bem.elastic.fft import CosineTransform2, PaddedRealFFT2, RealFFT2
from bem.elastic.fft_threads import fft_threads
from bem.elastic.kernel import kernel_spectrum, love_quadrant

__all__ = ["HalfSpace"]


class HalfSpace:
    """Surface displacement of an elastic half-space under a pixel-wise uniform pressure.

    Built once per (shape, spacing, E*, periodic): it owns the kernel spectrum and the FFT plans.
    See the module docstring for the kernels, the q = 0 convention and the FFT normalisation.
    An operator owns work buffers, so it is not thread-safe: use one per thread (processes
    each build their own anyway).

    Parameters
    ----------
    shape : tuple of int
        Grid shape (rows, columns) of the pressure and displacement arrays.
    spacing : float
        Grid step h [length]; the grid covers ``L_y x L_x = (rows h) x (columns h)``.
    e_star : float
        Composite modulus E* [pressure].
    periodic : bool
        Periodic half-space (spectral kernel) instead of the isolated, non-periodic one
        (Love's pixel kernel, DC-FFT).
    mirror : bool
        With ``periodic``: the grid is a quadrant of its mirror extension's period (module
        docstring). Its contact edges, patches and flow do not wrap around (:attr:`wraps`).
    backend : {"auto", "pyfftw", "scipy"}
        FFT backend (:class:`bem.elastic.fft.RealFFT2`); both give the same result to rounding.
    threads : int, optional
        FFT threads. Default (:func:`fft_threads`): one below a 1024 x 1024 convolution grid,
        where threads gain little; above, the calling thread and the CPUs available to the
        process that are idle when the operator is built. On a busy machine a multi-threaded
        FFT waits for its descheduled threads: a 2-thread FFT pair took 40-48 ms for any size from 128^2
        to 1024^2 here under a load of 5 on 2 cores, against 0.06-21 ms on one thread.
    planner_effort : str, optional
        pyFFTW planner effort; default "FFTW_MEASURE" for convolution grids of 1024 x 1024
        points or more (planning 0.5-1.5 s once per grid size and machine: FFTW keeps the
        wisdom for the process, :mod:`bem.elastic.wisdom` in a file for the next ones; up to 2x faster
        transforms measured here) and "FFTW_ESTIMATE" below, where measuring planned no faster
        transforms.
    device : {"cpu", "gpu"}
        Where the products run: numpy and pyFFTW/scipy, or CuPy and cuFFT on a CUDA GPU
        (:mod:`bem.elastic.device`; ``backend``, ``threads`` and ``planner_effort`` are the CPU's). On the
        GPU the work buffers are CuPy arrays, :meth:`displacement` still takes and returns
        numpy arrays, and point sources are always added by products.

    Attributes
    ----------
    shape, spacing, e_star, periodic, device
        As given.
    xp : module
        The array module of the device's fields (numpy or cupy).
    convolution_shape : tuple of int
        Shape of the FFT grid: ``2 * shape`` non-periodic, ``shape`` periodic.
    backend : str
        The FFT backend actually used.
    threads : int
        FFT threads used.
    direct_source_limit : int
        Up to this many point sources, the solver adds their displacement by direct sums of
        :attr:`influence` instead of an FFT product (cost model in ``__init__``).
    planner_effort : str
        pyFFTW planner effort used (ignored by the scipy backend).
    """

    def __init__(self, shape: tuple[int, int], spacing: float, *, e_star: float = 1.0,
                 periodic: bool = False, backend: str = "auto", threads: int | None = None,
                 planner_effort: str | None = None, mirror: bool = False,
                 device: str = "cpu") -> None:
        self.xp = array_module(device)   # (checks the device's name and that it is there)
        self.device = device
        if not isinstance(shape, (tuple, list)) or len(shape) != 2:
            raise ValueError(f"shape must be a pair of positive integers, got {shape!r}")
        shape = tuple(checks.integer("shape", s, minimum=1) for s in shape)
        self.shape: tuple[int, int] = shape
        self.spacing = checks.contact_number("spacing", spacing, minimum=0.0, exclusive=True)
        self.e_star = checks.contact_number("e_star", e_star, minimum=0.0, exclusive=True)
        if not isinstance(periodic, (bool, np.bool_)):
            raise ValueError(f"periodic must be True or False, got {periodic!r}")
        self.periodic = bool(periodic)
        self.mirror = checks.flag("mirror", mirror)
        if self.mirror and not self.periodic:
            raise ValueError("mirror needs periodic=True (the extension's period is solved)")
        ny, nx = shape
        self.convolution_shape = (ny, nx) if self.periodic else (2 * ny, 2 * nx)
        if threads is None:
            threads = fft_threads(self.convolution_shape)
        if planner_effort is None:
            large = self.convolution_shape[0] * self.convolution_shape[1] >= 1024 * 1024
            planner_effort = "FFTW_MEASURE" if large else "FFTW_ESTIMATE"
        self._folded = self.mirror and self.device != "gpu" and ny % 2 == 0 and nx % 2 == 0
        if self.device == "gpu":
            from bem.elastic.fft_device import device_transform

            self._fft = device_transform(self.xp, self.shape, periodic=self.periodic,
                                         mirror=self.mirror)
        elif self._folded:
            from bem.elastic.mirror_product import MirrorProduct   # (numba: imported where used)

            self._fft = MirrorProduct(self.shape, backend=backend, threads=threads,
                                      planner_effort=planner_effort)
        elif self.mirror:
            self._fft = CosineTransform2(self.shape, backend=backend, threads=threads,
                                         planner_effort=planner_effort)
        elif self.periodic:
            self._fft = RealFFT2(self.convolution_shape, backend=backend, threads=threads,
                                 planner_effort=planner_effort)
        else:
            self._fft = PaddedRealFFT2(self.shape, backend=backend, threads=threads,
                                       planner_effort=planner_effort)
        self.backend = self._fft.backend
        self.threads = self._fft.threads
        self.planner_effort = planner_effort
        # K_hat / M (1/M folded in), real, each value twice: the one stored copy of the kernel
        # (32 bytes per grid point non-periodic), so that the product is one real multiply in
        # place over the float view of the complex spectrum (a complex-by-real multiply took
        # 2.3 times as long at 1024^2)
        self._scaled_spectrum = kernel_spectrum(self.shape, self.spacing, self.e_star,
                                                periodic=self.periodic,
                                                mirror=self.mirror) / self._fft.size
        if not self.mirror:   # complex spectrum: each value twice
            self._scaled_spectrum = np.repeat(self._scaled_spectrum, 2, axis=1)
        self._scaled_spectrum = self.xp.asarray(self._scaled_spectrum)
        self._influence: np.ndarray | None = None
        self._self_influence: float | None = None
        self._coarse: HalfSpace | None = None
        # Point sources below this count are cheaper to add by direct summation
        # (_add_sources, 2 passes over the grid each) than by one FFT product: a product costs
        # ~ M log2 M for M convolution points; measured break-even counts, with the products
        # planned by FFTW_MEASURE and one thread, were 0.15-0.24 of log2(M) M / (rows columns)
        # (10.6 / 15.8 / 18.9 sources non-periodic at 256^2 / 512^2 / 1024^2, 4.0 / 4.8
        # periodic at 512^2 / 1024^2), hence the factor 0.2.
        size = self.convolution_shape[0] * self.convolution_shape[1]
        self.direct_source_limit = int(0.2 * math.log2(max(size, 2)) * size / (ny * nx))
        if self.mirror or self.device == "gpu":   # a mirror quadrant's response is not a
            self.direct_source_limit = 0           # translation; a GPU product is cheap

    # -- construction --------------------------------------------------------------------------

    @property
    def kernel_spectrum(self) -> np.ndarray:
        """``K_hat`` [length/pressure] in the unnormalised DFT convention of the module
        docstring, shape of the rfft spectrum of the convolution grid (fresh, read-only)."""
        spectrum = to_host(self._scaled_spectrum if self.mirror
                           else self._scaled_spectrum[:, ::2]) * self._fft.size
        spectrum.setflags(write=False)
        return spectrum

    # -- the operator --------------------------------------------------------------------------

    def displacement(self, pressure: np.ndarray) -> np.ndarray:
        """Surface displacement ``u = K * p`` [length] of a pressure field [pressure].

        Parameters
        ----------
        pressure : array_like
            Finite pixel pressures of shape ``shape`` (any sign: the operator is linear).

        Returns
        -------
        numpy.ndarray
            A fresh float64 array of ``shape``, positive into the body under compression.
        """
        pressure = checks.real_array("pressure", pressure, finite=False)
        if pressure.shape != self.shape:
            raise ValueError(f"pressure must have shape {self.shape}, got {pressure.shape}")
        if not np.all(np.isfinite(pressure)):
            raise ValueError("pressure must be finite (no NaN or inf)")
        out = self.xp.empty(self.shape)
        self._apply(self.xp.asarray(pressure), out)
        return to_host(out)

    def _apply(self, pressure: np.ndarray, out: np.ndarray) -> None:
        """``out[...] = K * pressure`` without checks or allocations (the solvers' hot path)."""
        # (non-periodic: the padding around input_block stays zero; the transforms only read it)
        self._fft.input_block[...] = pressure
        self._transform_direction()
        out[...] = self._fft.output_block

    def _direction_buffers(self) -> tuple[np.ndarray, np.ndarray]:
        """The FFT input and output blocks (views of ``shape``) for :meth:`_transform_direction`;
        any other product overwrites both."""
        return self._fft.input_block, self._fft.output_block

    def _flat_direction_buffers(self) -> tuple[np.ndarray, np.ndarray, int]:
        """The FFT input and output as flat arrays and their row stride (elements), for
        scattered reads and writes at grid points ``(j, i) -> j row_stride + i``."""
        return self._fft.input_flat, self._fft.output_flat, self._fft.row_stride

    def _transform_direction(self) -> None:
        """Output block = K * input block, in the FFT buffers (no copies)."""
        fft = self._fft
        if self._folded:   # the mirror product of an even grid, by a real FFT pair
            return fft.execute(self._scaled_spectrum)
        fft.execute_forward()
        spectrum = fft.spectrum_buffer.view(np.float64)
        np.multiply(spectrum, self._scaled_spectrum, out=spectrum)
        fft.execute_inverse()

    def coarse(self) -> HalfSpace:
        """The operator of every other grid point: half the shape, twice the spacing, same E*,
        periodicity and threads; built on first use and kept (the solver's nested starts).

        Raises
        ------
        ValueError
            If a side of the grid is odd.
        """
        if self.shape[0] % 2 or self.shape[1] % 2:
            raise ValueError(f"the coarse operator needs an even grid, got shape {self.shape}")
        if self._coarse is None:
            self._coarse = HalfSpace((self.shape[0] // 2, self.shape[1] // 2),
                                     2.0 * self.spacing, e_star=self.e_star,
                                     periodic=self.periodic, backend=self.backend,
                                     threads=self.threads, mirror=self.mirror,
                                     device=self.device)
        return self._coarse

    # -- real-space influence coefficients ---------------------------------------------------

    @property
    def influence(self) -> np.ndarray:
        """Influence coefficients of non-negative offsets, shape ``shape`` [length/pressure].

        Non-periodic: ``G[j, i]``, the displacement at offset ``(j, i)`` pixels (either sign: G
        is even in both). Periodic: the displacement at offset ``(j, i)`` summed over all periodic
        images with the zero-mean convention, one period (offset ``-j`` is row ``rows - j``).
        Computed on first use and cached; read-only.
        """
        if self._influence is None:
            ny, nx = self.shape
            if self.mirror:
                influence = self._pulse_response()
            elif self.periodic:
                inverse = RealFFT2(self.shape, backend="scipy", threads=1)
                influence = inverse.inverse(self.kernel_spectrum.astype(complex))
            else:
                influence = love_quadrant(ny, nx, self.spacing, self.e_star)
            influence.setflags(write=False)
            self._influence = influence
        return self._influence

    @property
    def centred_kernel(self) -> np.ndarray:
        """Influence coefficients ``C`` of shape ``(2 rows - 1, 2 columns - 1)`` [length/pressure].

        ``C[rows - 1 + dj, columns - 1 + di]`` is the displacement at offset ``(dj, di)`` pixels
        from a pixel under unit pressure (periodic: summed over all periodic images, with the
        zero-mean convention). Built from :attr:`influence` on each access (4 times its memory:
        the solver does not use it); read-only.
        """
        ny, nx = self.shape
        influence = self.influence
        if self.periodic:
            rows, cols = np.arange(-(ny - 1), ny) % ny, np.arange(-(nx - 1), nx) % nx
        else:
            rows, cols = np.abs(np.arange(-(ny - 1), ny)), np.abs(np.arange(-(nx - 1), nx))
        centred = np.ascontiguousarray(influence[np.ix_(rows, cols)])
        centred.setflags(write=False)
        return centred

    @property
    def self_influence(self) -> float:
        """Displacement of a pixel under unit pressure on itself [length/pressure], kept; a
        mirror operator (no direct sums) keeps it without :attr:`influence` (32 MB at 2048^2)."""
        if self._self_influence is None:
            fresh = self._influence is None and self.mirror
            self._self_influence = float((self._pulse_response() if fresh
                                          else self.influence)[0, 0])
        return self._self_influence

    def _pulse_response(self) -> np.ndarray:
        """The displacement under unit pressure on pixel (0, 0) (and a mirror's images)."""
        pulse = np.zeros(self.shape)
        pulse[0, 0] = 1.0
        return self.displacement(pulse)

    def _add_sources(self, flat_indices: np.ndarray, values: np.ndarray, out: np.ndarray,
                     work: np.ndarray) -> None:
        """``out += K * (sum of point pressures values at flat_indices)`` by direct summation.

        Cost ``len(values) * rows * columns``: cheaper than an FFT product for a handful of
        pixels. ``work`` is scratch of ``shape``. Each source adds :attr:`influence` in four
        blocks: offsets of either sign along each axis (reflected non-periodic, wrapped
        periodic).
        """
        influence = self.influence
        ny, nx = self.shape
        rows, cols = np.divmod(flat_indices, nx)
        for row, col, value in zip(rows.tolist(), cols.tolist(), values.tolist()):
            for target_rows, source_rows in self._blocks(row, ny):
                for target_cols, source_cols in self._blocks(col, nx):
                    scratch = work[target_rows, target_cols]
                    np.multiply(influence[source_rows, source_cols], value, out=scratch)
                    out[target_rows, target_cols] += scratch

    def _blocks(self, index: int, size: int) -> tuple[tuple[slice, slice], ...]:
        """(target, source) slices along one axis for a source at ``index``: targets at and
        after it, then before it (empty blocks left out)."""
        after = (slice(index, size), slice(0, size - index))
        if index == 0:
            return (after,)
        if self.periodic:  # offset -k is row size - k
            before = (slice(0, index), slice(size - index, size))
        else:  # offset -k is offset k: rows index, index - 1, ..., 1
            before = (slice(0, index), slice(index, 0, -1))
        return after, before

    @property
    def wraps(self) -> bool:
        """Whether the grid's opposite edges are neighbours (periodic, not a mirror quadrant):
        for contact edges, patches and the Reynolds flow."""
        return self.periodic and not self.mirror

    def __repr__(self) -> str:
        return (f"HalfSpace(shape={self.shape}, spacing={self.spacing!r}, e_star={self.e_star!r}, "
                f"periodic={self.periodic}, mirror={self.mirror}, backend={self.backend!r}, "
                f"device={self.device!r})")
