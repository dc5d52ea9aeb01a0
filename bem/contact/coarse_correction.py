"""Two-level preconditioner on a fixed contact set: the inverse kernel plus a coarse correction.

On a contact set C of many patches, the inverse-kernel preconditioner M (:mod:`bem.contact.preconditioner`)
restricted to C leaves the conjugate gradients converging at about 0.7 per iteration whatever the
contact fraction: it treats every oscillation within the patches well and the smooth part of the
pressure -- how much load each region of the window carries -- badly (Vollebregt 2014, who
deflates that part; Zhao, Vollebregt & Oosterlee 2014, who find the same smooth error components
left by the FFT preconditioner). The coarse space here is that smooth part: the window cut into
at most :data:`COARSE_CELLS` x :data:`COARSE_CELLS` square blocks, one coarse unknown per block
that holds contact, its shape function the indicator ``z_i`` of the block's contact pixels.

The preconditioner is the symmetric two-level additive one

    ``y = Pi M Pi r + Z E^-1 Z^T r``,   ``Pi = I - Z (Z^T Z)^-1 Z^T``

(Pi removes each block's mean on C; Z sums over the blocks' contact pixels; docs/theory.md,
eq. T26a), symmetric positive definite on C whenever E is. The Galerkin coarse matrix
``Z^T K Z`` would need one operator product per block; E approximates it by the interaction of
whole blocks -- a coarse half-space of the same kind (periodic, mirrored or not) with one pixel
per block -- scaled on both sides so that its diagonal is exact,
``E = S (K_coarse + gamma 1 1^T) S``, ``S_ii = sqrt(e_i / K_coarse,ii)`` with
``e_i = z_i^T K z_i`` (each block's own contact pixels, computed at once for all blocks by an
FFT of each block doubled), and ``gamma >= 0`` the least that gives the uniform pressure on C
its exact energy ``1_C^T K 1_C`` (the periodic kernels have none in their mean: with every block
in contact, ``K_coarse`` alone is singular). Both terms keep E symmetric positive definite.

Measured (``K_CC q = 1`` to 1e-6 on the contact sets of a noisy scan at 21 / 47 / 76 %
contact, the mirrored periodic operator): 512^2, 32 / 38 / 42 iterations with M alone, 22 / 24
/ 24 with this preconditioner, 17 / 20 / 22 with the exact Galerkin matrix; 1024^2, 39 / 60
(21 / 76 %) against 27 / 30, and 35 / 45 against 23 / 19 non-periodic. Cost per application:
two passes over C before M and two after it (block sums and shifts, compiled) and a solve with
a Cholesky factor of at most ``COARSE_CELLS^2`` unknowns; per contact set, an FFT of every block
doubled (four times the window's points) and the factorisation (at 1024 blocks, 30-70 ms).
"""

from __future__ import annotations

import math
import weakref

import numba
import numpy as np
import scipy.fft
import scipy.linalg

__all__ = ["CHURNING_CHANGE", "COARSE_CELLS", "REBUILD_CHANGE", "SETTLED_CHANGE", "SLOW_RATE",
           "SMALLEST_BLOCK", "TWO_LEVEL_GRID", "CoarseCorrection", "SettlingCorrection"]

#: Blocks per side of the window at most: the block is ``ceil(side / COARSE_CELLS)`` pixels, so
#: the coarse space has at most 1024 unknowns (a Cholesky factor of 8 MB, 30-70 ms). On the
#: noisy 512^2 scan's stiffness solves 32 x 32 blocks took 22-24 iterations, 16 x 16 blocks 25-30.
COARSE_CELLS = 32
#: Grids of at least this many points use the coarse correction (:mod:`bem.contact.constrained_cg`,
#: and the stiffness solve after it). At 1024^2 it took the stiffness solve on a noisy scan's contact sets (21 and 76 % contact) from
#: 1.29-1.37 / 2.69-2.84 s to 1.18 / 1.88 s (the mirrored operator) and from 1.86-2.03 /
#: 3.05-3.09 s to 1.36 / 1.73 s (non-periodic); at 512^2 its cost per contact set (block
#: energies, factorisation) and per iteration ate what the fewer iterations saved.
TWO_LEVEL_GRID = 1024 * 1024
#: The contact iteration builds the correction once at most this share of C joined or left it
#: in one iteration (before, C churns and each build would be spent on a passing set) ...
SETTLED_CHANGE = 0.01
#: ... if ``g.Mg`` fell by less than this factor per iteration over the last three (on a
#: smooth WM surface, periodic, 1024^2 at 18 and 44 % contact, M alone gave 0.27-0.30 and the
#: correction no fewer iterations; on the noisy scan 0.55 and 47 against 34 iterations, the
#: same surface non-periodic at 44 % 0.5 and 54 against 41) ...
SLOW_RATE = 0.4
#: ... and builds it again once this share of C has changed since (in between, E is kept and Z
#: follows C).
REBUILD_CHANGE = 0.1
#: ... and drops it for the rest of the solve when more than this share of C changed in one
#: iteration with it.
CHURNING_CHANGE = 0.05
#: Smallest block [pixels]: below it the coarse space is as fine as the patches themselves.
SMALLEST_BLOCK = 4


class _Coarse:
    """What depends on the operator only: the block size, the dense coarse operator between all
    blocks and the kernel's window of offsets below one block."""

    def __init__(self, operator) -> None:
        from bem.elastic.halfspace import HalfSpace

        rows, columns = operator.shape
        self.block = max(SMALLEST_BLOCK, math.ceil(max(rows, columns) / COARSE_CELLS))
        self.cells = (math.ceil(rows / self.block), math.ceil(columns / self.block))
        coarse = HalfSpace(self.cells, operator.spacing * self.block, e_star=operator.e_star,
                           periodic=operator.periodic, mirror=operator.mirror, backend="scipy",
                           threads=1)
        count = self.cells[0] * self.cells[1]
        pulse = np.zeros(count)
        self.matrix = np.empty((count, count))
        for cell in range(count):   # at most COARSE_CELLS^2 products of a 32 x 32 grid
            pulse[cell] = 1.0
            self.matrix[:, cell] = coarse.displacement(pulse.reshape(self.cells)).reshape(-1)
            pulse[cell] = 0.0
        self.matrix = 0.5 * (self.matrix + self.matrix.T)
        self.window_spectrum = self._window_spectrum(operator)

    def _window_spectrum(self, operator) -> np.ndarray:
        """rfft2 of the kernel's offsets ``|o| < block`` laid out circularly on ``2 block``."""
        rows, columns = operator.shape
        b = self.block
        pulse = np.zeros(operator.shape)
        centre = (rows // 2, columns // 2)
        pulse[centre] = 1.0
        response = operator.displacement(pulse)
        window = np.zeros((2 * b, 2 * b))
        offsets = np.arange(-(b - 1), b)
        rows_at = np.clip(centre[0] + offsets, 0, rows - 1)
        columns_at = np.clip(centre[1] + offsets, 0, columns - 1)
        window[np.ix_(offsets % (2 * b), offsets % (2 * b))] = response[np.ix_(rows_at,
                                                                               columns_at)]
        return scipy.fft.rfft2(window)


@numba.njit(nogil=True, cache=True)
def _block_sums(values: np.ndarray, block: np.ndarray, sums: np.ndarray) -> None:
    sums[:] = 0.0
    for i in range(values.size):
        sums[block[i]] += values[i]


@numba.njit(nogil=True, cache=True)
def _shifted(values: np.ndarray, block: np.ndarray, shift: np.ndarray, out: np.ndarray) -> None:
    for i in range(values.size):
        out[i] = values[i] + shift[block[i]]


@numba.njit(nogil=True, cache=True)
def _blocks_of(indices: np.ndarray, columns: int, block: int, cells_x: int, place: np.ndarray,
               out: np.ndarray, counts: np.ndarray) -> bool:
    """``out[i]``: the place of pixel ``indices[i]``'s block among E's (``place`` per coarse
    cell, -1 where E has none), ``counts`` per place; False at the first pixel without one."""
    counts[:] = 0.0
    for i in range(indices.size):
        row, column = divmod(indices[i], columns)
        where = place[(row // block) * cells_x + column // block]
        if where < 0:
            return False
        out[i] = where
        counts[where] += 1.0
    return True


_COARSE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _coarse(operator) -> _Coarse:
    """The operator's :class:`_Coarse`, built on first use and kept while the operator lives."""
    coarse = _COARSE.get(operator)
    if coarse is None:
        coarse = _COARSE[operator] = _Coarse(operator)
    return coarse


class CoarseCorrection:
    """The two-level preconditioner's coarse part on the contact pixels ``indices`` (module
    docstring).

    Parameters
    ----------
    operator : bem.elastic.halfspace.HalfSpace
        The half-space operator K (on the host).
    indices : numpy.ndarray
        Flat indices of the contact set C in the operator's grid.
    uniform_energy : float
        ``1_C^T K 1_C`` [length/pressure x pixels^2]: the energy of a unit uniform pressure on
        C, which fixes E's mean mode.

    Attributes
    ----------
    usable : bool
        False where E could not be factorised: then the correction must not be used (Pi M Pi
        alone removes the block means).
    """

    def __init__(self, operator, indices: np.ndarray, uniform_energy: float) -> None:
        self._coarse = coarse = _coarse(operator)
        self._columns = operator.shape[1]
        rows, columns = divmod(indices, self._columns)
        cell = (rows // coarse.block) * coarse.cells[1] + columns // coarse.block
        counts = np.bincount(cell, minlength=coarse.cells[0] * coarse.cells[1])
        used = np.flatnonzero(counts)
        self._place = np.cumsum(counts > 0) - 1   # a used block's place among the used ones
        self._place[counts == 0] = -1
        self._counts = np.empty(used.size)
        self.follow(indices)   # Z: each pixel's block, the blocks' counts
        own = self._own_energies(coarse, rows, columns, used)
        between = coarse.matrix[np.ix_(used, used)]
        scale = np.sqrt(own / np.diag(between))
        matrix = scale[:, None] * between * scale[None, :]
        # (einsum, not BLAS: OpenBLAS threads spin after a call and slow the next FFTs)
        shortfall = uniform_energy - float(np.einsum("i,ij,j->", scale, between, scale))
        if shortfall > 0.0:
            matrix += (shortfall / float(scale.sum()) ** 2) * np.outer(scale, scale)
        try:   # (one LAPACK call per contact set: the next FFT pays its threads' spin once)
            self._factor = scipy.linalg.cho_factor(matrix, check_finite=False)
            self.usable = bool(np.all(np.isfinite(self._factor[0])))
        except (np.linalg.LinAlgError, ValueError):
            self.usable = False

    @staticmethod
    def _own_energies(coarse: _Coarse, rows: np.ndarray, columns: np.ndarray,
                      used: np.ndarray) -> np.ndarray:
        """``e_i = z_i^T K z_i`` of every used block: each block's indicator on a doubled
        block, its autocorrelation against the kernel's window (Parseval)."""
        b = coarse.block
        cells_y, cells_x = coarse.cells
        energies = np.zeros(cells_y * cells_x)
        rows_of_block = rows // b
        for band in np.flatnonzero(np.bincount(rows_of_block)):   # a band at a time: bounded memory
            here = rows_of_block == band
            tiles = np.zeros((cells_x, 2 * b, 2 * b))
            tiles[columns[here] // b, rows[here] % b, columns[here] % b] = 1.0
            spectrum = scipy.fft.rfft2(tiles)
            power = spectrum.real**2 + spectrum.imag**2
            power[..., 1:b] *= 2.0   # the rfft's half: every column but 0 and b stands for two
            energies[band * cells_x:(band + 1) * cells_x] = np.einsum(
                "kij,ij->k", power, coarse.window_spectrum.real) / (2 * b) ** 2
        return energies[used]

    def follow(self, indices: np.ndarray) -> bool:
        """Keep E and move Z to the contact set ``indices`` (a few pixels joined or left):
        False, and nothing changed, when a pixel lies in a block E does not have."""
        block = np.empty(indices.size, dtype=np.int32)
        counts = np.empty(self._counts.size)
        if not _blocks_of(indices, self._columns, self._coarse.block, self._coarse.cells[1],
                          self._place, block, counts):
            return False
        self._block = block
        # a block left without contact keeps a count of one: its sums are zero anyway
        self._counts = np.maximum(counts, 1.0)
        return True

    def before(self, residual: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``Pi residual`` (to be preconditioned by M) and the residual's block sums
        ``Z^T residual`` (for :meth:`after`)."""
        sums = np.empty(self._counts.size)
        _block_sums(residual, self._block, sums)
        out = np.empty_like(residual)
        _shifted(residual, self._block, -sums / self._counts, out)
        return out, sums

    def after(self, preconditioned: np.ndarray, sums: np.ndarray) -> np.ndarray:
        """``Pi preconditioned + Z E^-1 sums`` (in place): the two-level preconditioned
        residual from M's output and :meth:`before`'s sums."""
        own = np.empty(self._counts.size)
        _block_sums(preconditioned, self._block, own)
        shift = scipy.linalg.cho_solve(self._factor, sums, check_finite=False)
        shift -= own / self._counts
        _shifted(preconditioned, self._block, shift, preconditioned)
        return preconditioned


class SettlingCorrection:
    """The coarse correction of a contact iteration, whose set C changes: built once C has
    settled (at most :data:`SETTLED_CHANGE` of its pixels joined or left in each of two
    iterations in a row) where M alone converges slowly (:data:`SLOW_RATE`), dropped for the
    rest of the solve if C then churns (:data:`CHURNING_CHANGE`) or E cannot be factorised,
    moved along with C (:meth:`CoarseCorrection.follow`) and built again once
    :data:`REBUILD_CHANGE` of C has changed since, or C reaches a block E does not have. Each
    build costs one product more (``1_C^T K 1_C``); it writes the operator's buffers.
    """

    def __init__(self, operator) -> None:
        self._operator = operator
        self.correction: CoarseCorrection | None = None
        self._changed = 0
        self._dropped = False
        self._settled = False
        self._norms: list[float] = []

    def update(self, indices: np.ndarray, changed: int, gradient_norm: float) -> bool:
        """Follow C after ``changed`` pixels joined or left it; ``gradient_norm`` is the last
        iteration's ``g.Mg``. True when the correction was (re)built (the preconditioner
        changed: the caller restarts its direction)."""
        self._changed += changed
        self._norms = (self._norms + [gradient_norm])[-4:]
        if self._dropped:
            return False
        if self.correction is None:
            settled = changed <= SETTLED_CHANGE * indices.size
            self._settled, was_settled = settled, self._settled
            if not (settled and was_settled):   # two iterations in a row: not a first step's
                return False
            if len(self._norms) < 4 or self._norms[-1] <= SLOW_RATE**3 * self._norms[0]:
                return False   # M alone converges fast: the correction would only cost
        elif changed > CHURNING_CHANGE * indices.size:
            self.correction, self._dropped = None, True   # C churns with it: M alone
            return True
        elif self._changed <= REBUILD_CHANGE * indices.size and (
                changed == 0 or self.correction.follow(indices)):
            return False
        uniform = np.zeros(self._operator.shape)
        uniform.reshape(-1)[indices] = 1.0
        energy = float(self._operator.displacement(uniform).reshape(-1)[indices].sum())
        self.correction = CoarseCorrection(self._operator, indices, energy)
        if not self.correction.usable:
            self.correction, self._dropped = None, True
        self._changed = 0
        return True
