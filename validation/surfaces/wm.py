"""Weierstrass-Mandelbrot rough surfaces.

The surface is eq. (11)-(12) of Ciavarella, Greenwood & Paggi (2008) (Yan & Komvopoulos /
Ausloos-Berman form; docs/theory.md, "Weierstrass-Mandelbrot surfaces")::

    z(x, y) = B sum_{m=1..M} sum_{n=0..n_max} gamma^{(D-3) n}
              [cos phi_mn - cos(2 pi gamma^n (x cos(pi m/M) + y sin(pi m/M)) / L + phi_mn)]
    B = L (G/L)^{D-2} (ln gamma / M)^{1/2}

Fast evaluation
---------------
Each term is a plane wave. With k = 2 pi gamma^n / L, c = cos(pi m / M), s = sin(pi m / M),
``cos(k c x + k s y + phi) = cos(k c x) cos(k s y + phi) - sin(k c x) sin(k s y + phi)``,
so the whole double sum is one matrix product of an (n x 2T) matrix of functions of y with a
(2T x n) matrix of functions of x (T = M (n_max + 1) terms): O(T n) trigonometric evaluations
and one BLAS product instead of T full-grid cosines.

A periodic surface (``periodic=True``; docs/theory.md, "A periodic WM surface", eq. T52)
-----------------------------------------------------------------------------------------
Eq. (11) is not periodic: its wavenumbers ``gamma^n`` (in units of 2 pi / L) are not whole
numbers. With ``periodic=True`` each term's wave vector
``k_mn = 2 pi gamma^n / L (cos(pi m/M), sin(pi m/M))`` is replaced by the nearest vector of
the period's lattice, ``2 pi / L (i_mn, j_mn)`` with ``i_mn = round(gamma^n cos(pi m/M))`` and
``j_mn = round(gamma^n sin(pi m/M))`` (:func:`wm_lattice`; halves round to even, as
:func:`numpy.rint`). Everything else of eqs. (11)-(12) is kept: gamma, n_max, M, D, the
amplitudes ``gamma^{(D-3) n}``, the phases phi_mn (the same draw for the same seed), B and the
rms-slope normalisation. Terms that round to the same lattice vector (or to opposite ones) stay
separate terms, each with its own amplitude and phase: their sum is one Fourier mode of random
phase. No term rounds to (0, 0): every wave vector is at least 2 pi / L long (gamma^0 = 1), and
the nearest lattice point of a vector of length >= 1 lattice unit is never the origin (its
larger component is >= 1/sqrt(2) > 1/2). The map is then exactly periodic on [0, L)^2.

The departure from eq. (11) is largest for the longest waves, gamma^0 = 1 ... gamma^3 = 3.4
lattice units: with the paper's gamma = 1.5, M = 10, the ten directions of n = 0 fall on the
five vectors (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0); a wave vector moves by up to 45 % of
its length at n = 0, 42 % at n = 1, 16 % at n = 2 and 11 % at n = 3 (its direction by up to
18 degrees, its magnitude by up to 41 %), and by at most half a lattice unit per component
for every term: below 1/(sqrt(2) gamma^n) of its length, 1.5 % at gamma^8 = 25.6.
"""

from __future__ import annotations

import math

import numpy as np

from bem.common import checks

from validation.surfaces.statistics import surface_statistics

__all__ = ["wm_surface", "wm_amplitude", "wm_lattice"]


def _check_integer(name: str, value: int, minimum: int) -> int:
    return checks.integer(name, value, minimum=minimum)


def _check_length(name: str, value: float) -> float:
    return checks.supported_magnitude(name, checks.positive(name, value))


def _check_wm_parameters(D: float, L: float, gamma: float, M: int, n_max: int = 0):
    """Checked (D, L, gamma, M) of eqs. (11)-(12); gamma**n_max must stay representable."""
    M = _check_integer("M", M, 1)
    D = checks.real_number("D", D, minimum=2.0, exclusive=True, maximum=3.0,
                           exclusive_maximum=True)
    gamma = checks.real_number("gamma", gamma, minimum=1.0, exclusive=True)
    L = _check_length("L", L)
    if n_max * math.log10(gamma) > 30.0:
        raise ValueError(f"gamma**n_max must be <= 1e30 (the frequency range of the surface), "
                         f"got gamma = {gamma!r}, n_max = {n_max}")
    return D, L, gamma, M


def wm_amplitude(G: float, *, D: float, L: float = 1.0, gamma: float = 1.5, M: int = 10) -> float:
    """Amplitude prefactor B of eq. (12): ``B = L (G/L)^(D-2) (ln gamma / M)^(1/2)`` [length].

    Parameters are those of :func:`wm_surface`: G > 0 and L > 0 [length], 2 < D < 3,
    gamma > 1, M >= 1 an integer.

    Raises
    ------
    ValueError, TypeError
        For a parameter outside those ranges (naming it).
    """
    D, L, gamma, M = _check_wm_parameters(D, L, gamma, M)
    G = _check_length("G", G)
    return L * (G / L) ** (D - 2.0) * math.sqrt(math.log(gamma) / M)


def wm_lattice(*, gamma: float = 1.5, M: int = 10, n_max: int = 8) -> np.ndarray:
    """Lattice vectors of the terms of a periodic WM surface (``wm_surface(periodic=True)``).

    Returns
    -------
    numpy.ndarray
        Integers of shape (M, n_max + 1, 2): ``[m - 1, n] = (i, j)``, the nearest lattice
        point ``(round(gamma^n cos(pi m/M)), round(gamma^n sin(pi m/M)))`` to term (m, n) of
        eq. (11) in units of 2 pi / L (its wave vector is ``2 pi (i, j) / L``; ties round to
        even). Never (0, 0) (module docstring). Several terms may share a vector; they stay
        separate terms, each with its own amplitude and phase.

    Raises
    ------
    ValueError, TypeError
        For gamma <= 1, M < 1, n_max < 0, or gamma**n_max above 1e30.
    """
    n_max = _check_integer("n_max", n_max, 0)
    _, _, gamma, M = _check_wm_parameters(2.5, 1.0, gamma, M, n_max)
    return _lattice(gamma, M, n_max)


def _lattice(gamma: float, M: int, n_max: int) -> np.ndarray:
    angles = np.pi * np.arange(1, M + 1) / M                       # (M,)
    magnitudes = gamma ** np.arange(n_max + 1)                     # (n_max+1,)
    vectors = np.stack((np.cos(angles)[:, None] * magnitudes[None, :],
                        np.sin(angles)[:, None] * magnitudes[None, :]), axis=-1)
    lattice = np.rint(vectors).astype(np.int64)
    assert np.all(np.any(lattice != 0, axis=-1)), "a WM term rounded to the zero vector"
    return lattice


def _unit_wm(n: int, D: float, L: float, gamma: float, M: int, phases: np.ndarray,
             side: float | None = None, periodic: bool = False) -> np.ndarray:
    """Eq. (11) with B = 1, mean not yet removed, on an n x n grid of the square of the given
    side (default L); row index y, column index x. ``periodic``: the wave vectors on the
    lattice of the period L (:func:`wm_lattice`)."""
    n_max = phases.shape[1] - 1
    coordinate = np.arange(n) * ((L if side is None else side) / n)
    weights = gamma ** ((D - 3.0) * np.arange(n_max + 1))          # (n_max+1,)
    if periodic:
        lattice = _lattice(gamma, M, n_max) * (2.0 * np.pi / L)    # (M, n_max+1, 2)
        kx, ky = lattice[..., 0].ravel(), lattice[..., 1].ravel()  # (T,)
    else:
        angles = np.pi * np.arange(1, M + 1) / M                       # (M,)
        wavenumbers = 2.0 * np.pi * gamma ** np.arange(n_max + 1) / L  # (n_max+1,)
        kx = (np.cos(angles)[:, None] * wavenumbers[None, :]).ravel()  # (T,)
        ky = (np.sin(angles)[:, None] * wavenumbers[None, :]).ravel()
    phase = phases.ravel()
    weight = np.broadcast_to(weights[None, :], (M, n_max + 1)).ravel()
    x_arg = coordinate[None, :] * kx[:, None]                      # (T, n) functions of x
    y_arg = coordinate[:, None] * ky[None, :] + phase[None, :]     # (n, T) functions of y
    left = np.concatenate((np.cos(y_arg) * weight, -np.sin(y_arg) * weight), axis=1)  # (n, 2T)
    right = np.concatenate((np.cos(x_arg), np.sin(x_arg)), axis=0)                     # (2T, n)
    heights = left @ right                                         # sum_t w_t cos(kx x + ky y + phi)
    np.subtract(np.sum(weight * np.cos(phase)), heights, out=heights)
    return heights


def wm_surface(
    n: int,
    *,
    D: float,
    G: float | None = None,
    rms_slope: float | None = None,
    L: float = 1.0,
    gamma: float = 1.5,
    M: int = 10,
    n_max: int = 8,
    seed: int | np.random.Generator | None = None,
    phases: np.ndarray | None = None,
    slope_grid: int | None = None,
    side: float | None = None,
    periodic: bool = False,
) -> np.ndarray:
    """Sample a Weierstrass-Mandelbrot surface, eqs. (11)-(12), on an n x n grid.

    Parameters
    ----------
    n : int
        Grid points per side (>= 2). Heights are sampled at ``x_i = i L / n`` and
        ``y_j = j L / n``, i, j = 0..n-1 (``side`` in place of L when given); the returned
        array is indexed ``heights[j, i]`` (row index j is y, column index i is x). The grid
        spacing is ``L / n`` (``side / n``).
    D : float
        Fractal dimension, 2 < D < 3.
    G : float, optional
        Amplitude scale [length] of eq. (12). Exactly one of ``G`` and ``rms_slope`` is given.
    rms_slope : float, optional
        Target rms gradient ``sqrt(<|grad z|^2>)`` [-] of the sampled surface, as measured by
        :func:`surface_statistics` (non-periodic finite differences; with ``periodic`` and the
        window of one period, ``side = L``, wrap-around differences at every point). The
        surface is linear in its amplitude B, so it is computed with B = 1 and scaled exactly.
    L : float
        Sample length [length]: the longest wavelength of eq. (11) and, unless ``side`` is
        given, the side of the sampled window L x L (the nominal contact area).
    gamma : float
        Frequency density, > 1.
    M : int
        Number of superposed ridges, >= 1.
    n_max : int
        Highest frequency index, >= 0.
    seed : int or numpy.random.Generator, optional
        Seed of ``numpy.random.default_rng`` for the phases phi_mn, drawn uniformly in
        [0, 2 pi) with shape (M, n_max + 1) (row m-1, column n).
    phases : array_like, optional
        Phases phi_mn [rad] of shape (M, n_max + 1); overrides ``seed`` so that any surface can
        be reproduced exactly.
    slope_grid : int, optional
        With ``rms_slope``: the grid (points per side, default ``n``) on which the rms gradient
        is measured to fix the amplitude. The measured slope depends slightly on the grid, so
        to sample *one* continuous surface on several grids (a mesh-convergence study, as in
        benchmarks/bench_bem.py and bench_area.py) give them all the same ``slope_grid``.
    side : float, optional
        Side [length] of the sampled square window, default L. The wavelengths stay those of
        L, so windows of several sides with the same phases (seed) are nested windows of one
        surface of the same statistics, larger ones reaching further (the window
        ``[0, side)^2`` always starts at the origin). With ``rms_slope`` each window is scaled
        to that slope on its own grid.
    periodic : bool
        Every wave vector on the nearest point of the lattice ``2 pi (i, j) / L`` of the period
        L (:func:`wm_lattice`; module docstring, docs/theory.md eq. T52): the surface is then
        exactly periodic with period L along x and y, and the window of side L one period of it.
        Default False: eq. (11) as the paper writes it, not periodic.

    Returns
    -------
    numpy.ndarray
        Heights [length], shape (n, n), with their mean removed. Not periodic unless
        ``periodic`` (then periodic with period L: one period when ``side = L``).

    Raises
    ------
    ValueError
        For parameters outside the ranges above, both or neither of ``G``/``rms_slope``,
        non-finite values, or phases of the wrong shape.
    TypeError
        For a ``periodic`` that is not a bool.
    """
    n = _check_integer("n", n, 2)
    slope_grid = n if slope_grid is None else _check_integer("slope_grid", slope_grid, 3)
    n_max = _check_integer("n_max", n_max, 0)
    D, L, gamma, M = _check_wm_parameters(D, L, gamma, M, n_max)
    side = L if side is None else _check_length("side", side)
    periodic = checks.flag("periodic", periodic)
    checks.supported_magnitude("side / n (the grid spacing)", side / max(n, slope_grid))
    if (G is None) == (rms_slope is None):
        raise ValueError("give exactly one of G (amplitude scale) and rms_slope (rms gradient)")
    if G is not None:
        G = _check_length("G", G)
    else:
        rms_slope = checks.supported_magnitude("rms_slope", checks.positive("rms_slope",
                                                                            rms_slope))

    rng = checks.random_generator("seed", seed)
    if phases is None:
        phases = rng.uniform(0.0, 2.0 * np.pi, size=(M, n_max + 1))
    else:
        phases = checks.real_array("phases", phases)
        if phases.shape != (M, n_max + 1):
            raise ValueError(
                f"phases must have shape (M, n_max + 1) = {(M, n_max + 1)}, got {phases.shape}"
            )
        if not np.all(np.isfinite(phases)):
            raise ValueError("phases must be finite")

    heights = _unit_wm(n, D, L, gamma, M, phases, side, periodic)
    heights -= heights.mean()
    if G is not None:
        heights *= wm_amplitude(G, D=D, L=L, gamma=gamma, M=M)
    else:
        unit = heights if slope_grid == n else _unit_wm(slope_grid, D, L, gamma, M, phases, side,
                                                        periodic)
        flat = np.all(unit == unit.flat[0])
        # one period: its slope from wrap-around differences at every point, as for a periodic
        # self-affine surface
        wrap = periodic and side == L
        unit_slope = 0.0 if flat else surface_statistics(unit, side / slope_grid,
                                                         periodic=wrap).rms_gradient
        if not unit_slope > 0.0:
            raise ValueError("the surface is flat on this grid; rms_slope cannot be reached")
        heights *= rms_slope / unit_slope
    return heights
