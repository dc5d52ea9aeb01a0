"""The linear solve of the Reynolds flow system (:mod:`bem.leakage.flow`): sparse LU for gaps up to
:data:`DIRECT_SOLVE_LIMIT` cells, conjugate gradients preconditioned by aggregation multigrid on
the pixel grid above.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

from bem.leakage.flow_cg import _conjugate_gradients
from bem.leakage.multigrid_cycle import VCycle
from bem.leakage.pixel_blocks import block_hierarchy
from bem.common.warnings import ConvergenceWarning

__all__ = ["ALGEBRAIC_TOLERANCE", "COARSEST_LIMIT", "DIRECT_SOLVE_LIMIT",
           "DIRECT_SWITCH_ITERATIONS", "DIRECT_SWITCH_LIMIT", "FEWER_LEVELS_ITERATIONS", "FlowStart",
           "LU_FALLBACK_ITERATIONS",
           "MULTIGRID_LEVELS", "MULTIGRID_TOLERANCE", "multigrid_levels", "next_start", "solved_directly"]


#: Gaps of up to this many cells are solved by sparse LU, larger ones by multigrid-preconditioned
#: conjugate gradients (:func:`_solve_pressure`). On the 24 gaps of a 256^2 path (a noisy scan's
#: half grid, 0.1-27 % contact) two levels took 3.8-4.5 s against 8.7-9.0 s for the LU, the
#: apertures within 3e-7; at 512^2 the multigrid took 0.3-0.9 s against 0.6-1.9 s, at 1024^2
#: 2.3-12 s against 3.8-10 s and 0.5 GB against 1.5 GB (one core; the LU faster only on rough
#: gaps at heavy contact; docs/guide/benchmarks.md, "The leakage reference"). The same limit
#: holds for periodic gaps: on the 16 periodic BEM gaps of a 512^2 WM path (D 2.05 and 2.95,
#: 0.04-21 % contact) the multigrid took 0.26-0.57 s (9-16 iterations) against the LU's
#: 0.9-4.0 s, at 1024^2 (self-affine, 1-28 % contact) 2.7-3.5 s (30-70 iterations) against
#: 3.3-17 s, the apertures within 3e-8.
DIRECT_SOLVE_LIMIT = 128 * 128
#: A gap is switched to the sparse LU after a slow multigrid neighbour
#: (:data:`DIRECT_SWITCH_ITERATIONS`) up to this many cells only (a 2048^2 factor would hold
#: several GB); above it a multigrid solve of the pixel blocks that stops short of its rule goes
#: on from its last iterate with algebraic coarsening (:func:`_solve_pressure`).
DIRECT_SWITCH_LIMIT = 1024 * 1024
#: The coarsest grid of the multigrid is solved by sparse LU once it has at most this many
#: cells and at most a sixteenth of the grid's, a quarter once the path's multigrid has been
#: slow (:data:`FEWER_LEVELS_ITERATIONS`), or at :data:`MULTIGRID_LEVELS` levels
#: (:func:`multigrid_levels`): three levels at 256^2 and 512^2 (two after a slow solve), three
#: at 1024^2, four at 2048^2.
COARSEST_LIMIT = 256 * 256
#: Most levels of the multigrid: each level of unsmoothed aggregation adds iterations (12-17
#: at three levels, 17-35 at four on the same 1024^2 gaps), so a 1024^2 grid gets three (the
#: coarsest 256^2) and a 2048^2 grid four (the coarsest 256^2 again: with three, a 512^2 factor
#: per cycle, and the iteration stalled at a relative residual of 1.3e-7 after 1000 iterations
#: on a gap near percolation).
MULTIGRID_LEVELS = 4
#: Relative residual ``||b - A p|| / ||b||`` (of the Jacobi-scaled system) the multigrid's
#: conjugate gradients must also reach before the estimate may stop them: the estimate can be
#: fooled by a plateau of the convergence (on a gap near percolation it stopped with an aperture
#: error of 5e-7), the residual alone by a gap whose g^3 spans more decades (at 1e-6 it left
#: 6e-6 in the aperture of the test gap).
MULTIGRID_TOLERANCE = 1e-6
#: Relative residual of the algebraic multigrid (a gap above :data:`DIRECT_SWITCH_LIMIT` on
#: which the pixel blocks stopped short), which
#: stops on it alone: at 1e-7 it left 1.8e-7 in the aperture of the test gap, at 1e-8 3e-6 on one
#: whose g^3 spans more decades, and the estimate of :data:`~bem.leakage.flow_cg.DISSIPATION_TOLERANCE` with a residual
#: of 1e-6 left 7e-6 there.
ALGEBRAIC_TOLERANCE = 1e-9
#: A multigrid solve of a gap of at most :data:`DIRECT_SWITCH_LIMIT` cells that has not met its
#: rule after this many iterations is abandoned for the sparse LU of the same system (exact),
#: and the path goes on by the LU: a solve of 50 iterations costs about the LU's time
#: (:data:`DIRECT_SWITCH_ITERATIONS`), so at most two factorisations' worth is spent first.
#: Without it, a 512^2 gap near percolation of a WM path ran to the 1000 iterations of
#: :data:`bem.leakage.flow_cg.MULTIGRID_MAX_ITERATIONS` and returned an unsettled iterate.
LU_FALLBACK_ITERATIONS = 100
#: A gap whose previous neighbour along a path (:class:`FlowStart`) took at least this many
#: multigrid iterations, or was itself solved by LU in its place, is solved by sparse LU up to
#: :data:`DIRECT_SWITCH_LIMIT` cells. Near percolation the pixel blocks converge slowly while
#: the factor gets cheaper (fewer open cells): on an interferometer map's 960^2 gaps at 18 % and
#: 30 % contact the multigrid took 126-239 iterations, 10-18 s, from the previous load's
#: pressure, the LU 3.6-6.7 s and 0.8-1.3 GB (1024^2); the iterations grow along a path
#: (13, 22, 42, 126, 150 there), and a multigrid solve costs about the LU's time at 50.
DIRECT_SWITCH_ITERATIONS = 40
#: A gap whose previous neighbour along a path (:class:`FlowStart`) took at least this many
#: multigrid iterations, or whose path was slow before, gets the multigrid's larger coarsest
#: level (a quarter of the grid instead of a sixteenth, :func:`multigrid_levels`): below 1024^2
#: one level fewer. The coarsest level's LU is most of a light gap's solve on two levels (a
#: 512^2 gap: its 256^2 factor 0.25-0.3 s of 0.5 s, for 6-8 iterations); on three the factor is
#: 128^2 and the iterations a few more, but near percolation they grow (21, 23, then 109 on the
#: x gaps of a noisy 512^2 scan's path, 8 and 13 on two levels). A 512^2 solve on three levels
#: costs what one on two does at about this many iterations. On that path's 24 gaps (x and y,
#: one thread) 8.1-10.3 s against 12.7-15.3 s on two levels, the apertures within 2e-7 of the LU's
#: where the two levels' were.
FEWER_LEVELS_ITERATIONS = 16
_LU_OPTIONS = dict(permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})


@dataclass(frozen=True)
class FlowStart:
    """What a Reynolds solve hands the next one along a path (the same grid and direction):
    its pressure, a map of the grid oriented along the flow with NaN off the solved cells, where
    the next iterative solve begins (:func:`_start`; None: from the linear drop), and its
    multigrid ``iterations`` (None: solved by sparse LU), by which the next chooses its solver
    (:data:`DIRECT_SWITCH_ITERATIONS`), and whether the path's multigrid has been ``slow``
    (:data:`FEWER_LEVELS_ITERATIONS`; it stays so along the path, whose gaps close towards
    percolation), by which the next chooses its levels (:func:`multigrid_levels`).
    :func:`next_start` makes one.
    """

    pressure: np.ndarray | None
    iterations: int | None
    slow: bool = False


def next_start(pressure: np.ndarray, iterations: int | None,
               start: FlowStart | None) -> FlowStart:
    """The :class:`FlowStart` a solve hands the next gap: its pressure map and ``iterations``
    (None: sparse LU), slow once it or a solve before it along the path (``start``) took
    :data:`FEWER_LEVELS_ITERATIONS` or more iterations, or was solved by the LU. The map is
    dropped (the next gap starts from the linear drop) once slow on a grid of more than
    :data:`DIRECT_SWITCH_LIMIT` cells (:func:`_solve_pressure`)."""
    slow = (start is not None and start.slow) or iterations is None \
        or iterations >= FEWER_LEVELS_ITERATIONS
    # above the LU switch's limit a slow path's next gap starts from the linear drop (near
    # percolation the previous pressure can be wrong where regions hang on thin necks), and
    # its map is not kept
    return FlowStart(None if slow and pressure.size > DIRECT_SWITCH_LIMIT else pressure,
                     iterations, slow)


def multigrid_levels(cells: int, grid: int | None = None, *, slow: bool = False) -> int:
    """Levels of the multigrid for a gap of ``cells`` unknowns on a grid of ``grid`` cells
    (default: ``cells``): halve the grid until at most :data:`COARSEST_LIMIT` unknowns and at
    most a sixteenth of the grid are left (a quarter when the path's multigrid has been
    ``slow``, :data:`FEWER_LEVELS_ITERATIONS`), with at most :data:`MULTIGRID_LEVELS` levels.
    One level, the LU solving the whole system, when ``cells`` is within the coarsest limit
    of a slow path (at most :data:`COARSEST_LIMIT` and a quarter of the grid)."""
    if grid is None:
        limit = largest = COARSEST_LIMIT
    else:
        largest = min(COARSEST_LIMIT, grid // 4)
        limit = largest if slow else min(COARSEST_LIMIT, grid // 16)
    if cells <= largest:
        return 1
    levels = 1
    while cells > limit and levels < MULTIGRID_LEVELS:
        cells = math.ceil(cells / 4)
        levels += 1
    return levels


def _compressed_rows(hierarchy) -> None:
    """Every level's operator, interpolation and restriction of a pyAMG hierarchy in CSR, in
    place: smoothed aggregation with one near-null vector builds them as BSR of 1 x 1 blocks,
    whose Gauss-Seidel sweep and products are several times slower per unknown than CSR's (a
    sweep of the 512^2 second level of a 1024^2 gap 17 ms against 14 ms for the 1024^2 first;
    in CSR the solve took 20 % less, the same iterates); the compiled sweeps of
    :class:`bem.leakage.multigrid_cycle.VCycle` take CSR (or a system held by its faces) only. The
    restriction is the interpolation's transpose (pyAMG's for a symmetric system), kept as its
    CSC view rather than a copy (128 MB at 2048^2; the same products to the bit: both sum a
    coarse entry's fine terms in the same order)."""
    for level in hierarchy.levels:
        level.A = level.A.tocsr()
        if hasattr(level, "P"):
            level.P = level.P.tocsr()
            level.R = level.P.T


def _solve_pressure(matrix, rhs: np.ndarray, cells: np.ndarray, periodic: bool,
                    dissipation: Callable[..., float],
                    start: FlowStart | None = None) -> tuple[np.ndarray, int | None]:
    """``A p = b`` for the symmetric positive-definite flow system of the unknowns ``cells``
    (a 2-D map of the grid's cells in the system, numbered in row-major order; ``periodic``:
    the system of a periodic gap, grounded at one cell per cluster). ``dissipation(p)`` is
    the energy the system minimises (eq. T43; a grounded system adds the grounding's own
    term, which vanishes at the solution), which the multigrid's stopping rule follows;
    ``dissipation(y, scale)`` that of the pressure ``scale * y`` (without a copy of it).

    Up to :data:`DIRECT_SOLVE_LIMIT` grid cells by sparse LU (SuperLU): fill-reducing order by
    minimum degree on the symmetric pattern (``MMD_AT_PLUS_A``, half the fill of the default
    column order on these grids), no pivoting (``diag_pivot_thresh=0``: elimination of a
    symmetric positive definite matrix is stable in any order); exact whatever the contrast of
    g^3 (which spans 20 decades in a contact gap). Above, the factor's flops and memory grow
    as n^1.5 (0.33-0.42 s at 256^2, 7-13 s and 1.5 GB at 1024^2), and the system is solved by
    conjugate gradients preconditioned with one V-cycle of aggregation multigrid on the pixel
    grid: the 2 x 2 blocks of cells, split where their connections are weak, are the
    aggregates, level after level (:func:`multigrid_levels`, :mod:`bem.leakage.pixel_blocks`), with
    piecewise-constant interpolation (no prolongation smoothing: smoothing it took more time
    than it saved),
    one forward and one backward Gauss-Seidel sweep, and the coarsest grid solved by the same
    sparse LU (its factor held as ``L D L^T``, :class:`bem.leakage.multigrid_cycle.CoarseFactor`).
    It is built on the Jacobi-scaled matrix ``D A D`` (``D = diag(A)^-1/2``) with the scaled
    constant ``1/D`` as its near-null space, and iterates until the dissipation is
    known to :data:`~bem.leakage.flow_cg.DISSIPATION_TOLERANCE` (:func:`_conjugate_gradients`; ``matrix`` and ``rhs``
    are scaled in place). The geometric aggregates
    follow the pixels, split only inside a block, which algebraic coarsening (smoothed
    aggregation with evolution strength, classical Ruge-Stueben) did not beat on these gaps:
    their setup alone took as long as this whole solve, and on 2048^2 gaps (1.8 / 22 %
    contact) 54-69 s against 13 s and more than 300 s against 195 s (whole blocks), at
    2.8-3.0 GB against 1.3-1.8 GB. A periodic gap (grounded at one cell per cluster) is
    solved the same way: the split blocks converge there as on a window (9-16 iterations on
    512^2 WM gaps, 30-70 on 1024^2 self-affine ones). A solve of the pixel
    blocks of more than :data:`DIRECT_SWITCH_LIMIT` cells that stops short of its rule goes on
    from its last iterate with algebraic coarsening: smoothed aggregation with the evolution
    strength of connection, which follows the thin necks that carry the flow near percolation,
    with a symmetric Gauss-Seidel sweep on either side, to a relative residual of
    :data:`ALGEBRAIC_TOLERANCE` alone (the estimate was fooled there; if that too stops short,
    it warns, :class:`bem.common.warnings.ConvergenceWarning`, and returns its last iterate);
    up to that size, a multigrid solve that has not met its rule in
    :data:`LU_FALLBACK_ITERATIONS` iterations is abandoned for the sparse LU (exact). ``start``, the
    :class:`FlowStart` of a neighbouring load's gap on the grid, gives the pressure where the
    conjugate gradients begin (:func:`_start`; the stopping rule is the same from any start: the
    residual relative to ``b``, the energy's decrements), except on a gap of more than
    :data:`DIRECT_SWITCH_LIMIT` cells once the path has been slow
    (:data:`FEWER_LEVELS_ITERATIONS`), which starts from the linear drop: near percolation the
    previous pressure can be wrong where regions hang on thin necks (a 2048^2 gap at 22 %
    contact took 532 iterations from it, 177 from the drop; but a 960^2 gap at 30 % 118 from
    it and 313 from the drop, and below that size a slow path goes on by the LU), and, when
    that solve took
    :data:`DIRECT_SWITCH_ITERATIONS` or more, or was itself switched to the LU, this gap is
    solved by the LU (up to :data:`DIRECT_SWITCH_LIMIT` cells): the gaps of a
    load path close towards percolation, where the pixel blocks converge slowly. Returns the
    pressure of the unknowns and the multigrid's iterations (None for the LU).
    """
    import scipy.sparse.linalg   # where used (start-up of a warm report)

    levels = multigrid_levels(int(np.count_nonzero(cells)), cells.size,
                              slow=start is not None and start.slow)
    # (few unknowns on a large grid, one level: the LU is the whole solve)
    if solved_directly(cells.size, start) or levels == 1:
        return scipy.sparse.linalg.splu(matrix.tocsc(), **_LU_OPTIONS).solve(rhs), None
    # D A D in place (the matrix held by its faces, bem.leakage.face_matrix)
    scale = 1.0 / np.sqrt(matrix.diagonal())
    matrix.scale(scale)
    scaled = matrix
    rhs *= scale
    previous = None if start is None else start.pressure
    # (each start is made after its V-cycle's coarsest factor, not beside that factor's peak)
    factorable = cells.size <= DIRECT_SWITCH_LIMIT
    solution, iterations, settled = _conjugate_gradients(
        scaled, rhs, VCycle(_hierarchy(scaled, scale, cells, levels), factor_options=_LU_OPTIONS),
        lambda pressure: dissipation(pressure, scale), MULTIGRID_TOLERANCE,
        _start(previous, cells, periodic, scale),
        most=LU_FALLBACK_ITERATIONS if factorable else None)
    if settled:
        return solution * scale, iterations
    if factorable:   # stopped short: the sparse LU of the same (scaled) system, exact
        del solution
        return (scipy.sparse.linalg.splu(scaled.tocsc(), **_LU_OPTIONS).solve(rhs) * scale,
                None)
    # above the switch's limit: on from here, coarsening algebraically
    scaled = scaled.tocsr()   # (pyAMG's coarsening reads compressed rows)
    solution, extra, settled = _conjugate_gradients(
        scaled, rhs, VCycle(_hierarchy(scaled, scale, cells, 0), symmetric=True,
                            factor_options=_LU_OPTIONS), None, ALGEBRAIC_TOLERANCE, solution)
    iterations += extra
    _warn_unsettled(settled, cells.size, iterations)
    return solution * scale, iterations


def solved_directly(size: int, start: FlowStart | None) -> bool:
    """Whether the flow system of a gap of ``size`` grid cells is solved by sparse LU
    (:func:`_solve_pressure`): up to :data:`DIRECT_SOLVE_LIMIT` cells, and up to
    :data:`DIRECT_SWITCH_LIMIT` after a slow multigrid neighbour ``start`` (or one that was
    itself solved so)."""
    if size <= DIRECT_SOLVE_LIMIT:
        return True
    return size <= DIRECT_SWITCH_LIMIT and start is not None and (
        start.iterations is None or start.iterations >= DIRECT_SWITCH_ITERATIONS)


def _hierarchy(scaled, scale: np.ndarray, cells: np.ndarray, levels: int):
    """The pyAMG hierarchy of the Jacobi-scaled matrix ``scaled`` (``scale`` = ``D``, the
    near-null space ``1/D``), in CSR: ``levels`` levels of the pixel grid's 2 x 2 blocks of
    ``cells``, split where their connections are weak (:mod:`bem.leakage.pixel_blocks`), or for
    ``levels = 0`` algebraic coarsening (:func:`_solve_pressure`)."""
    near_null = (1.0 / scale)[:, None]
    if levels:
        return block_hierarchy(scaled, near_null, cells, levels, ("splu", _LU_OPTIONS))
    import pyamg

    hierarchy = pyamg.smoothed_aggregation_solver(scaled, B=near_null, strength="evolution",
                                                  coarse_solver=("splu", _LU_OPTIONS))
    _compressed_rows(hierarchy)
    return hierarchy


def _warn_unsettled(settled: bool, cells: int, iterations: int) -> None:
    """The warning of a multigrid solve that stopped short of its rule (its last iterate is
    returned)."""
    if not settled:
        warnings.warn(f"hydraulic_aperture: the multigrid solve of {cells} cells did not "
                      f"converge in {iterations} iterations", ConvergenceWarning, stacklevel=4)


def _start(start: np.ndarray | None, cells: np.ndarray, periodic: bool,
           scale: np.ndarray | None = None) -> np.ndarray:
    """The pressure of each unknown of ``cells`` to begin the iterative solve with: the map
    ``start`` where it has a value, elsewhere (and without one) the linear drop from inlet to
    outlet, or zero when periodic (the fluctuation's mean); divided by ``scale`` when given
    (the Jacobi-scaled system's unknowns)."""
    if periodic:
        guess = np.zeros(cells.shape)
    else:
        columns = cells.shape[1]
        guess = np.broadcast_to(1.0 - (np.arange(columns) + 0.5) / columns, cells.shape).copy()
    if start is not None and start.shape == cells.shape:
        known = np.isfinite(start)
        guess[known] = start[known]
    guess = guess[cells]
    if scale is not None:
        guess /= scale
    return guess
