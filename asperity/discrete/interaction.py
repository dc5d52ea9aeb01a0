"""First-order elastic interaction of asperities: fast sums of point-force displacements.

A point force P_j on the elastic half-space lowers the surface at distance r by
``P_j / (pi E* r)`` (docs/theory.md, eq. T2). The discrete asperity model (docs/theory.md, "The
discrete asperity model", step 3) needs, at every asperity centre i, the interaction sum::

    u_i = sum_{j != i} P_j / (pi E* r_ij)                                   [length]

over the loaded asperities j, and products of the same kernel with other vectors (Newton and
stiffness solves). :class:`PointForceInteraction` evaluates these sums exactly (to rounding) with
memory linear in the number of asperities, choosing per call the cheaper of two methods:

* ``"fft"`` (summits on the lattice of a height map): the forces are placed on the grid, and the
  sum is the discrete convolution of that lattice with the kernel ``1/(pi E* r)`` sampled at the
  lattice offsets (0 at r = 0). Aperiodic summits: the bounding box of the summits (rounded up to a
  fast FFT length), zero-padded to twice its size, so there is no wrap-around (the transforms
  skip the padding's zero rows: :class:`bem.elastic.fft.PaddedRealFFT2`) and the result equals the
  direct sum to rounding (about 1e-15 relative; verified against the direct sum in the tests).
  Periodic summits: the convolution on the periodic grid itself with the *minimum-image* kernel
  (each pair interacts once, through its shortest periodic distance). A full periodic lattice sum
  of 1/r diverges in two dimensions unless a uniform background is removed, which would change
  the separation reference; the minimum image keeps the far-field reference of docs/theory.md and is
  exact for the nearest periodic copy. Cost O(M log M) for an M-point padded grid, whatever the
  number of forces.
* ``"direct"`` (any positions): blocked dense sums, memory O(block x N_sources) with blocks of
  about 2^20 entries (8 MB), cost O(N_sources x N_targets), about 15 ns per pair. The discrete
  model only sums over *loaded* asperities and evaluates at asperities *above the rigid plane*;
  its Krylov solves reuse a cached dense block of the loaded set while that has at most 4e6
  entries (32 MB, about 2000 contacts). Beyond that every product costs N_loaded^2 pairs, so
  arbitrary positions with many thousands of simultaneous contacts are slow (measured: 10^4
  random summits, 3700 contacts, about 200 s for a 30-step load path against about 2 s on a
  lattice). Summits of a height map always lie on its lattice; for user-supplied sets, give
  ``Summits.from_points(..., spacing=...)`` to use the FFT.

``"auto"`` (the default) compares the estimated costs of the two for each call. The kernel
spectrum and FFT plan are built once, on first use.

FFT normalisation: :class:`bem.elastic.fft.RealFFT2` (unnormalised forward, inverse divides by the
number of points), so ``inverse(forward(forces) * forward(kernel))`` is the circular convolution.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from bem.common import checks
from bem.elastic.device import array_module, to_host
from bem.elastic.fft import BACKENDS

__all__ = ["PointForceInteraction"]

#: Entries of one block of a direct sum (8 MB of float64 per temporary).
_BLOCK_ENTRIES = 1 << 20
#: Largest dense block (rows x columns) :meth:`PointForceInteraction.linear_map` caches (32 MB).
_DENSE_LIMIT = 4_000_000
# Rough costs in seconds (medians measured on the development machine; they only steer the
# choice of method, never the result): one pair of a direct sum (or of building a dense block),
# one entry of a dense matrix-vector product, and one padded-grid point x log2(points) of an FFT
# convolution (forward, multiply, inverse).
_DIRECT_PAIR_COST = 1.5e-8
_DENSE_ENTRY_COST = 1.0e-9
_FFT_POINT_COST = 1.1e-9
_METHODS = ("auto", "fft", "direct")


def _as_index(name: str, value, n: int) -> np.ndarray:
    if checks.real_array(name, value).ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of integer asperity indices")
    index = checks.integer_array(name, value)
    if index.size and (index.min() < 0 or index.max() >= n):
        raise ValueError(f"{name} must lie in [0, {n}), got values in "
                         f"[{index.min()}, {index.max()}]")
    return index


def _check_lattice(x, y, spacing, row, column) -> tuple[np.ndarray, np.ndarray]:
    """Lattice indices (>= 0, integer) that agree with the positions: ``x = column * spacing``
    and ``y = row * spacing`` to 1e-9 relative."""
    row = checks.integer_array("row", row, minimum=0)
    column = checks.integer_array("column", column, minimum=0)
    if row.shape != x.shape or column.shape != x.shape:
        raise ValueError("row and column must have one entry per position")
    for axis, name, position, index in (("x", "column", x, column), ("y", "row", y, row)):
        tolerance = 1e-9 * max(spacing, float(np.max(np.abs(position), initial=0.0)))
        if np.any(np.abs(position - index * spacing) > tolerance):
            raise ValueError(f"positions {axis} contradict the {name} indices: every position "
                             f"must be (column * spacing, row * spacing)")
    return row, column


class PointForceInteraction:
    """Interaction sums ``u_i = sum_{j != i} P_j / (pi E* r_ij)`` at asperity centres.

    Parameters
    ----------
    x, y : array_like
        Asperity positions [length], 1-D, distinct.
    e_star : float
        Composite modulus E* [pressure].
    spacing : float, optional
        Lattice spacing [length] when every position is ``(column * spacing, row * spacing)``
        with the integer ``row``/``column`` given: enables the exact FFT method.
    row, column : array_like of int, optional
        Lattice indices (y and x), required with ``spacing``.
    shape : tuple of int, optional
        Lattice shape (rows, columns): the period of a periodic lattice. Required if
        ``periodic``.
    periodic : bool
        Minimum-image interaction on a periodic lattice of ``shape`` (see the module docstring).
    method : {"auto", "fft", "direct"}
        How sums are evaluated; "fft" needs a lattice.
    fft_backend : {"auto", "pyfftw", "scipy"}
        Backend of :class:`bem.elastic.fft.RealFFT2`.
    threads : int
        FFT threads (default 1: on a busy machine multi-threaded small FFTs are slower).
    device : {"cpu", "gpu"}
        Where the FFT sums run (:mod:`bem.elastic.device`): on a GPU the lattice, the kernel spectrum
        and the transforms are CuPy arrays and cuFFT (:mod:`bem.elastic.fft_device`), the forces and
        the sums at the targets numpy arrays (moved per call); the method chosen is the CPU's.

    Notes
    -----
    Every sum is exact up to rounding; the methods differ only in cost. ``displacement`` never
    keeps a reference to its inputs and returns a fresh array.
    """

    def __init__(self, x, y, *, e_star: float = 1.0, spacing: float | None = None, row=None,
                 column=None, shape: tuple[int, int] | None = None, periodic: bool = False,
                 method: str = "auto", fft_backend: str = "auto", threads: int = 1,
                 device: str = "cpu") -> None:
        x = np.array(checks.real_array("x", x), dtype=float).ravel()
        y = np.array(checks.real_array("y", y), dtype=float).ravel()
        if x.shape != y.shape:
            raise ValueError(f"x and y must have the same length, got {x.size} and {y.size}")
        e_star = checks.positive("e_star", e_star)
        method = checks.choice("method", method, _METHODS)
        fft_backend = checks.choice("fft_backend", fft_backend, BACKENDS)
        threads = checks.integer("threads", threads, minimum=1)
        periodic = checks.flag("periodic", periodic)
        array_module(device)   # a GPU asked for where there is none: said now
        self.device = device
        if x.size > 1 and np.unique(np.stack((x, y), axis=1), axis=0).shape[0] != x.size:
            # a point force at zero distance is undefined, and the lattice FFT would keep only
            # one of two coincident forces: the methods would disagree
            raise ValueError("positions x, y must be distinct (duplicate positions given)")
        self.x, self.y = x, y
        self.x.setflags(write=False)
        self.y.setflags(write=False)
        self.size = x.size
        self.e_star = e_star
        self.method = method
        self.periodic = bool(periodic)
        self._factor = 1.0 / (math.pi * e_star)
        self._fft_backend = fft_backend
        self._threads = int(threads)
        self._fft = None
        self.lattice = spacing is not None
        if self.lattice:
            spacing = checks.positive("spacing", spacing)
            if row is None or column is None:
                raise ValueError("row and column lattice indices are required with spacing")
            row, column = _check_lattice(x, y, spacing, row, column)
            self.spacing = spacing
            self.row, self.column = row, column
        elif method == "fft":
            raise ValueError("method='fft' needs lattice positions (spacing, row, column)")
        if self.periodic:
            if shape is None or not self.lattice:
                raise ValueError("periodic interaction needs a lattice (spacing, row, column) "
                                 "and its shape")
            if not isinstance(shape, (tuple, list)) or len(shape) != 2:
                raise ValueError(f"shape must be a pair of positive integers, got {shape!r}")
            shape = tuple(checks.integer("shape", s, minimum=1) for s in shape)
            if (self.row.size and (self.row.min() < 0 or self.row.max() >= shape[0]
                                   or self.column.min() < 0 or self.column.max() >= shape[1])):
                raise ValueError("lattice indices must lie inside the periodic shape")
            self.period = (shape[1] * self.spacing, shape[0] * self.spacing)  # (x, y)
            self.shape = shape
        if self.lattice:
            if self.periodic:
                self._row_local, self._column_local = self.row, self.column
                self._fft_shape = self.shape
            else:
                import scipy.fft
                row0 = self.row.min() if self.row.size else 0
                column0 = self.column.min() if self.column.size else 0
                self._row_local = self.row - row0
                self._column_local = self.column - column0
                extent = (int(self._row_local.max(initial=0)) + 1,
                          int(self._column_local.max(initial=0)) + 1)
                # the summits' block (rounded up to a fast FFT length), zero-padded to twice
                # its size: no wrap-around (bem.elastic.fft.PaddedRealFFT2 skips the zero rows)
                self._block = tuple(scipy.fft.next_fast_len(e, real=True) for e in extent)
                self._fft_shape = (2 * self._block[0], 2 * self._block[1])
            points = self._fft_shape[0] * self._fft_shape[1]
            self._fft_cost = _FFT_POINT_COST * points * max(1.0, math.log2(points))

    @property
    def _xp(self):
        """The array module of the device (looked up, not kept: a module does not pickle, and
        process pools pickle models)."""
        return array_module(self.device)

    @classmethod
    def from_summits(cls, summits, *, e_star: float = 1.0, method: str = "auto",
                     **kwargs) -> "PointForceInteraction":
        """Build the operator of a :class:`asperity.Summits` record (lattice when it has one)."""
        from asperity.gw.summits import Summits

        if not isinstance(summits, Summits):
            raise checks.InputTypeError(f"summits must be an asperity.Summits, got "
                                        f"{type(summits).__name__}")
        if summits.row is not None:
            return cls(summits.x, summits.y, e_star=e_star, spacing=summits.spacing,
                       row=summits.row, column=summits.column, shape=summits.shape,
                       periodic=summits.periodic, method=method, **kwargs)
        return cls(summits.x, summits.y, e_star=e_star, method=method, **kwargs)

    # ------------------------------------------------------------------ choice of method
    def _choose(self, n_sources: int, n_targets: int, method: str | None) -> str:
        method = self.method if method is None else method
        if method not in _METHODS:
            raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
        if method == "fft" and not self.lattice:
            raise ValueError("method='fft' needs lattice positions")
        if method != "auto":
            return method
        if not self.lattice:
            return "direct"
        return "fft" if self._fft_cost < _DIRECT_PAIR_COST * n_sources * n_targets else "direct"

    # ------------------------------------------------------------------ kernels
    def _kernel_spectrum(self) -> np.ndarray:
        if self._fft is None:
            from bem.elastic.fft import PaddedRealFFT2, RealFFT2
            rows, columns = self._fft_shape
            # Wrap-around offsets: index k holds offset k (k <= P/2) or k - P; the distance uses
            # |offset| = min(k, P - k), which is also the periodic minimum image.
            k = np.arange(rows)
            l = np.arange(columns)
            k = np.minimum(k, rows - k).astype(float)
            l = np.minimum(l, columns - l).astype(float)
            distance = self.spacing * np.sqrt(k[:, None] ** 2 + l[None, :] ** 2)
            kernel = np.zeros_like(distance)
            np.divide(self._factor, distance, out=kernel, where=distance > 0)
            # The kernel is even in both offsets, so its spectrum is real (up to rounding); the
            # 1/size of the unnormalised inverse is folded into it.
            if self.device == "gpu":
                from bem.elastic.fft_device import DevicePaddedRealFFT2, DeviceRealFFT2

                xp = self._xp
                fft = (DeviceRealFFT2(xp, self._fft_shape) if self.periodic
                       else DevicePaddedRealFFT2(xp, self._block))
                self._spectrum = xp.asarray(np.fft.rfft2(kernel).real / fft.size)
                self._grid, self._out = fft.input_block, fft.output_block
            elif self.periodic:
                fft = RealFFT2(self._fft_shape, backend=self._fft_backend,
                               threads=self._threads, planner_effort="FFTW_ESTIMATE")
                self._spectrum = fft.forward(kernel).real / fft.size
                fft.real_buffer.fill(0.0)          # forward() may have used it as its input
                self._grid, self._out = fft.real_buffer, fft.output_buffer
            else:
                fft = PaddedRealFFT2(self._block, backend=self._fft_backend,
                                     threads=self._threads, planner_effort="FFTW_MEASURE")
                self._spectrum = np.fft.rfft2(kernel).real / fft.size
                self._grid, self._out = fft.input_block, fft.output_block
            self._placed = (self._xp.zeros(0, dtype=np.intp), self._xp.zeros(0, dtype=np.intp))
            self._fft = fft
        return self._spectrum

    def _pair_block(self, targets: np.ndarray, sources: np.ndarray) -> np.ndarray:
        """Dense block ``1/(pi E* r)`` of shape (targets, sources), 0 where r = 0."""
        if self.lattice:
            # Look the kernel up by lattice offset: the same numbers as the formula below.
            table = self._offset_table()
            rows = np.abs(self._row_local[targets, None] - self._row_local[None, sources])
            columns = np.abs(self._column_local[targets, None] - self._column_local[None, sources])
            return table[rows, columns]
        dx = self.x[targets, None] - self.x[None, sources]
        dy = self.y[targets, None] - self.y[None, sources]
        if self.periodic:
            dx -= self.period[0] * np.rint(dx / self.period[0])
            dy -= self.period[1] * np.rint(dy / self.period[1])
        dx *= dx
        dy *= dy
        dx += dy
        np.sqrt(dx, out=dx)
        block = np.zeros_like(dx)
        np.divide(self._factor, dx, out=block, where=dx > 0)
        return block

    def _offset_table(self) -> np.ndarray:
        """Kernel 1/(pi E* r) by absolute lattice offset (|row|, |column|); minimum image."""
        if getattr(self, "_table", None) is None:
            if self.periodic:
                rows, columns = self.shape
            else:
                rows = int(self._row_local.max(initial=0)) + 1
                columns = int(self._column_local.max(initial=0)) + 1
            k = np.arange(rows, dtype=float)
            l = np.arange(columns, dtype=float)
            if self.periodic:
                k = np.minimum(k, rows - k)
                l = np.minimum(l, columns - l)
            distance = self.spacing * np.sqrt(k[:, None] ** 2 + l[None, :] ** 2)
            table = np.zeros_like(distance)
            np.divide(self._factor, distance, out=table, where=distance > 0)
            self._table = table
        return self._table

    # ------------------------------------------------------------------ products
    def displacement(self, forces, *, sources=None, targets=None, method: str | None = None
                     ) -> np.ndarray:
        """Interaction displacement [length] at ``targets`` due to ``forces`` at ``sources``.

        Parameters
        ----------
        forces : array_like
            Point forces [force], one per source (positive in compression).
        sources, targets : array_like of int, optional
            Asperity indices (default: all asperities). A source never acts on itself.
        method : {"auto", "fft", "direct"}, optional
            Override the operator's method for this call.

        Returns
        -------
        numpy.ndarray
            ``u_t = sum_{s in sources, s != t} P_s / (pi E* r_ts)``, one entry per target.
        """
        sources = np.arange(self.size) if sources is None else _as_index("sources", sources,
                                                                          self.size)
        targets = np.arange(self.size) if targets is None else _as_index("targets", targets,
                                                                          self.size)
        forces = checks.real_array("forces", forces).ravel()
        if forces.shape != sources.shape:
            raise ValueError(f"forces must have one entry per source ({sources.size}), "
                             f"got {forces.size}")
        if sources.size == 0 or targets.size == 0:
            return np.zeros(targets.size)
        if self._choose(sources.size, targets.size, method) == "fft":
            return self._fft_sum(forces, sources, targets)
        return self._direct_sum(forces, sources, targets)

    def _fft_sum(self, forces, sources, targets):
        spectrum = self._kernel_spectrum()
        fft = self._fft
        grid = self._grid               # zero except where the previous call placed forces
        xp = self._xp   # (numpy: asarray and to_host return their argument)
        grid[self._placed] = 0.0
        placed = (xp.asarray(self._row_local[sources]), xp.asarray(self._column_local[sources]))
        # Positions are distinct, so plain assignment places every force (no accumulation).
        grid[placed] = xp.asarray(forces)
        self._placed = placed
        fft.execute_forward()
        np.multiply(fft.spectrum_buffer, spectrum, out=fft.spectrum_buffer)
        fft.execute_inverse()
        return to_host(self._out[xp.asarray(self._row_local[targets]),
                                 xp.asarray(self._column_local[targets])])

    def _direct_sum(self, forces, sources, targets):
        out = np.empty(targets.size)
        block = max(1, _BLOCK_ENTRIES // sources.size)
        for start in range(0, targets.size, block):
            stop = min(start + block, targets.size)
            out[start:stop] = self._pair_block(targets[start:stop], sources) @ forces
        return out

    def linear_map(self, indices, *, products: int = 20) -> Callable[[np.ndarray], np.ndarray]:
        """The kernel restricted to one set of asperities, as a function ``t -> G_II t``.

        For repeated products on a fixed set (Krylov solves), with ``products`` the expected
        number of products: a cached dense block (at most 4e6 entries, 32 MB) when building it
        and ``products`` dense products is estimated cheaper than the FFT or direct sums,
        otherwise the cheaper of those per product.
        """
        indices = _as_index("indices", indices, self.size)
        products = checks.integer("products", products, minimum=1)
        n = indices.size
        if n == 0:
            return lambda values: np.zeros(0)
        method = self._choose(n, n, None)
        pairs = float(n) * n
        per_product = self._fft_cost if method == "fft" else _DIRECT_PAIR_COST * pairs
        dense_cost = (_DIRECT_PAIR_COST + products * _DENSE_ENTRY_COST) * pairs
        if (pairs <= _DENSE_LIMIT and self.method != "fft"
                and dense_cost < products * per_product):
            matrix = self._pair_block(indices, indices)
            return lambda values: matrix @ values
        return lambda values: self.displacement(values, sources=indices, targets=indices,
                                                method=method)
