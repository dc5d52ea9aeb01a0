"""A finer reference where its band decides: the same surface solved on a twice finer grid.

At load points whose reference band keeps a cell undecided, the boundary-element reference is
solved again on the grid of ``2 n`` points per side covering the same window, and recursively
on ``4 n``, ... up to ``[bem] max_grid`` (docs/theory.md, "Finer reference where the band
decides", eq. T39), on the finer sample of the same surface
(:func:`validation.run.finer_sample.refined_heights`). The finer solve's band is the estimate of
eq. (T32) from the finer grid and the one below it (whose solve is already there), and its
solver tolerance follows the band it is expected to have (eq. T40): a solver error of at most
1 % of the band.
"""

from __future__ import annotations

import math
from concurrent.futures import Executor, Future
from dataclasses import dataclass, replace

import numpy as np

from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.elastic.fft_threads import default_threads
from bem.common.heap import map_large_arrays
from bem.leakage.background_flow import BackgroundLeakage
from bem.interface import method_error
from bem.contact.path_errors import error_estimates
from validation.run.finer_sample import refined_heights
from validation.run.cache import (Cache, cache_key, curve_arrays, curve_from_arrays,
                                  model_quantities, needs_leakage, needs_stiffness,
                                  source_version)
from validation.run.starts import KeptPressures, keeps_starts, load_starts, starts_key
from validation.surfaces.families import surface_identity

__all__ = ["MAX_LEAKAGE_GRID", "REFINED", "SOLVER_ERROR", "SOLVER_SHARE", "STIFFNESS_FIELDS",
           "RefineJob", "interface_extension", "merge_job", "merge_points", "refine_points",
           "refined_extension", "run_job", "solve_jobs", "solver_tolerance", "unavailable"]

#: Bound on the solver error of conductance (relative) and separation, mean gap (in units of
#: sigma) per unit of the solver tolerance (T25): measured against tol = 1e-12 on WM surfaces
#: (D = 2.05 and 2.95, 256 x 256, Load 1e-5 to 1e-2, tol 1e-3 to 1e-8;
#: benchmarks/bench_solver_tolerance.py) the largest ratio error / tol is 0.041, on a noisy
#: 512 x 512 scan with the interface operator 0.061 at tol 1e-4. The area's error is a few edge
#: pixels instead, not proportional to tol (docs/theory.md eq. T40).
SOLVER_ERROR = 0.1
#: Share of the expected band the solver may spend (eq. T40).
SOLVER_SHARE = 0.01
#: The references a finer grid can refine: the finite window's (the non-periodic problem) and
#: the interface's (its periodic or mirror-extended problem). The reference of a nominal square
#: (bem_nominal) keeps its band.
REFINED = ("bem", "bem_interface")
#: The curve fields of the stiffness solve (bem.contact.stiffness), which a refinement may skip.
STIFFNESS_FIELDS = ("stiffness", "conductance")
#: Loosest solver tolerance a refined solve uses.
LOOSEST_TOLERANCE = 1e-4
#: Largest grid (points per side) on which a finer reference solves the leakage again; on
#: finer grids the leakage and its band stay those of the grid below. At 1024^2 one Reynolds
#: solve (bem.leakage.flow_solver's multigrid) takes 3-6 s and under 1 GB; at 2048^2 13-195 s per
#: direction and 1.45 GB (1.8 % contact), beyond the memory a check of a 1024^2 scan is to
#: keep to.
MAX_LEAKAGE_GRID = 1024


def unavailable(scene) -> str | None:
    """Why the scene's reference cannot be refined (None when it can)."""
    s, bem = scene.surface, scene.bem
    if getattr(bem, "max_grid", None) is None:
        return "no grid limit ([bem] max_grid, in quick mode [quick] max_grid, not set)"
    if scene.loads.quantity != "load":
        return "only load paths are refined (a separation path's loads differ per realization)"
    if not bem.reference_error:
        return "the reference carries no band ([bem] reference_error = false)"
    if 2 * s.n > bem.max_grid:
        return f"the scene grid {s.n} is already at the limit max_grid = {bem.max_grid}"
    return None


def solver_tolerance(band: float, floor: float) -> float:
    """Solver tolerance (T25) whose error is at most :data:`SOLVER_SHARE` of ``band`` (eq.
    T40): ``SOLVER_SHARE * band / SOLVER_ERROR``, between ``floor`` (the scene's tolerance)
    and :data:`LOOSEST_TOLERANCE`."""
    if not math.isfinite(band) or band <= 0.0:
        return floor
    return float(min(max(SOLVER_SHARE * band / SOLVER_ERROR, floor), LOOSEST_TOLERANCE))


def _take(curve: ContactCurve, index: np.ndarray) -> ContactCurve:
    """The curve at the points ``index`` only (fields and per-point extras)."""
    state = {name: (None if getattr(curve, name) is None else getattr(curve, name)[index])
             for name in CURVE_QUANTITIES}
    extras = {key: np.asarray(value)[index] for key, value in curve.extras.items()
              if np.ndim(value) >= 1 and np.shape(value)[0] == curve.load.size}
    return ContactCurve(nominal_area=curve.nominal_area, e_star=curve.e_star, extras=extras,
                        **state)


def merge_points(curve: ContactCurve, index: np.ndarray, finer: ContactCurve, grid: int,
                 spacing: float, base_grid: int) -> ContactCurve:
    """``curve`` with the points ``index`` replaced by the finer solve ``finer`` (at those
    points, on ``grid`` points per side, spacing ``spacing``), their error estimates taken from
    the finer solve and the points replaced (eq. T32), and extra ``grid`` (points per side of
    the solve behind each point; ``base_grid`` where no finer solve replaced it) updated."""
    index = np.asarray(index, dtype=int)
    coarse = _take(curve, index)
    state = {name: getattr(curve, name) for name in CURVE_QUANTITIES}
    for name, value in state.items():
        if value is not None and getattr(finer, name) is not None:
            state[name] = np.array(value, dtype=float)
            state[name][index] = getattr(finer, name)
    extras = {key: np.array(value) for key, value in curve.extras.items()}
    estimates = error_estimates(finer, coarse, spacing)
    for key, value in list(finer.extras.items()) + list(estimates.items()):
        if key in extras and np.ndim(extras[key]) == 1 and np.size(value) == index.size:
            extras[key] = extras[key].astype(np.result_type(extras[key], np.asarray(value)))
            extras[key][index] = value
    for key in estimates:
        # a new estimate holds no method bound (bem.interface.method_error), whatever the one
        # it replaced held: none is to be taken out of it when the bound is added again
        method = key.removesuffix("_error") + "_method_error"
        if key in extras and method in extras and method not in finer.extras:
            extras[method] = extras[method].astype(float)
            extras[method][index] = 0.0
    extras["converged"] = np.asarray(curve.extras.get("converged", np.ones(curve.load.shape,
                                                                            bool)), bool).copy()
    extras["converged"][index] = (np.asarray(finer.extras["converged"], bool)
                                  & np.asarray(coarse.extras.get("converged", True), bool))
    grids = np.asarray(curve.extras.get("grid", np.full(curve.load.shape, base_grid)),
                       dtype=float).copy()
    grids[index] = grid
    extras["grid"] = grids
    return replace(curve, **{k: v for k, v in state.items() if v is not None}, extras=extras)


@dataclass(frozen=True)
class RefineJob:
    """One realization's reference to solve on a finer grid at some of its load points."""

    task: object                  # validation.run.realization.RealizationTask
    points: tuple[int, ...]       # load point indices
    factor: int                   # grid = factor * task.surface.n
    tol: float                    # solver tolerance of the finer solve (T40)
    # the load point indices (among ``points``) where the leakage is solved too, when the
    # scene asks for it; elsewhere the finer curve's leakage is NaN (not solved)
    leakage_points: tuple[int, ...] = ()
    # the reference refined: the window's (None: the non-periodic problem of the task) or the
    # interface's, by the extension bem.InterfaceModel uses ("mirror" or "periodic")
    extension: str | None = None
    # the load point indices (among ``points``) where the stiffness is solved again too (a
    # stiffness cell is held by the band there; None: all of them); elsewhere the stiffness and
    # its band stay those of the grid below, and the finer path skips those stiffness solves
    # (at 1024^2 each takes about half the time of its point's contact solve)
    stiffness_points: tuple[int, ...] | None = None

    def stiffness_at(self) -> tuple[int, ...]:
        """The load point indices among ``points`` whose stiffness is solved again."""
        if self.stiffness_points is None:
            return self.points
        chosen = set(self.stiffness_points)
        return tuple(k for k in self.points if k in chosen)


def refined_extension(reference: str, task) -> str | None:
    """The extension a finer solve of ``reference`` (one of :data:`REFINED`) uses: None for
    the window's problem, the interface's otherwise (:func:`interface_extension`)."""
    return None if reference == "bem" else interface_extension(task)


def interface_extension(task) -> str:
    """How the interface reference of ``task`` makes a period of its heights (the registry's
    choice: the map itself when it is one period of a periodic surface, else its mirror)."""
    return "periodic" if task.surface.one_period or task.bem.periodic else "mirror"


def merge_job(curve: ContactCurve, job: RefineJob, finer: ContactCurve,
              grid: int) -> ContactCurve:
    """``curve`` (a realization's reference) with the points of ``job`` replaced by its finer
    solve ``finer`` on ``grid`` points per side (:func:`merge_points`); the leakage, and its
    band, only at the job's ``leakage_points``, the stiffness and conductance only at its
    stiffness points (elsewhere those of the grid below stay)."""
    s = job.task.surface
    leaky, stiff = set(job.leakage_points), set(job.stiffness_at())
    # the points in four groups by what was solved again there: the fields not solved again
    # keep the grid below's values, with their band
    for leakage in (False, True):
        for stiffness in (False, True):
            positions = [k for k, point in enumerate(job.points)
                         if (point in leaky) == leakage and (point in stiff) == stiffness]
            if not positions:
                continue
            dropped = ({} if leakage else {"leakage": None}) | (
                {} if stiffness else {name: None for name in STIFFNESS_FIELDS})
            part = replace(_take(finer, np.array(positions)), **dropped)
            curve = merge_points(curve, np.array([job.points[k] for k in positions]), part,
                                 grid, s.L / grid, s.n)
    if job.extension == "mirror" and "window_rms_height" in curve.extras:
        # the interface's band holds the mirror method's own error at every grid (eq. T50)
        extras = dict(curve.extras)
        extras.update(method_error(curve, extras, extras["window_rms_height"],
                                   index=list(job.points)))
        curve = replace(curve, extras=extras)
    return curve


def refine_points(job: RefineJob, cache: Cache) -> tuple[ContactCurve, bool]:
    """The finer solve of ``job`` at its points (from the cache when there), and whether it
    was computed now. Loads are the task's, in the scene's dimensionless form times E* L^2."""
    from bem.contact.concurrent_path import concurrent_curve

    task = job.task
    s = task.surface
    values = np.array(task.loads.values())[list(job.points)]
    loads = values * task.e_star * s.L**2
    stiff = set(job.stiffness_at()) if needs_stiffness(task.quantities) else set()
    stiffness = tuple(k for k in job.points if k in stiff)
    wanted = set(job.leakage_points) if needs_leakage(task.quantities) else set()
    leaky = tuple(k for k in job.points if k in wanted)
    quantities = tuple(q for q in model_quantities(task.quantities) if q != "leakage"
                       and (bool(stiffness) or q not in STIFFNESS_FIELDS))
    key = cache_key("bem-refined", source_version(), surface=surface_identity(s, task.seed),
                    factor=job.factor, loads=loads, e_star=task.e_star, stiffness=stiffness,
                    leakage_points=leaky, extension=job.extension,
                    periodic=task.bem.periodic, tol=job.tol, max_iter=task.bem.max_iter)
    cached = cache.load(key, decode=curve_from_arrays)
    if cached is not None:
        return cached, False
    heights = refined_heights(s, task.seed, job.factor)
    spacing = s.spacing / job.factor
    # the interface: the periodic half-space, a mirror extension's period solved on the map
    # itself by cosine transforms (bem.interface), its flow not wrapping around
    periodic = task.bem.periodic or job.extension is not None
    mirror = job.extension == "mirror"
    # One path through every point (a second path for the leakage points alone started cold),
    # dealt to concurrent sub-paths (bem.contact.concurrent_path: one per free core), the Reynolds
    # solves of the points that need them after it: beside it they would take a core from the
    # sub-paths, whose FFT threads are chosen when their operators are built.
    positions = {index for index, k in enumerate(job.points) if k in wanted}
    gaps, pressures = {}, KeptPressures()
    grid = job.factor * s.n
    # the grid below's pressures at these loads are the nested iteration's coarse solutions
    # (validation.run.starts); this grid's are kept for the next, where there is one
    starts = load_starts(cache, starts_key(task, grid // 2, job.extension), job.points)
    kept = keeps_starts(task, grid)

    def keep(index: int, solution) -> None:
        if index in positions:
            gaps[index] = solution.fluid_gap
        if kept:
            pressures.add(job.points[index], solution.pressure)

    curve = concurrent_curve(heights, spacing, loads=loads, quantities=quantities,
                             e_star=task.e_star, periodic=periodic, tol=job.tol,
                             max_iter=task.bem.max_iter,
                             callback=keep if leaky or kept else None,
                             mirror=mirror, device=task.bem.device, coarse_pressures=starts,
                             stiffness_at=[index for index, k in enumerate(job.points)
                                           if k in stiff],
                             # one GPU runs one path at a time
                             parts=1 if task.bem.device == "gpu" else None)
    pressures.store(cache, starts_key(task, grid, job.extension))
    if leaky:
        # the path done, its cores and memory free: both directions at once where two cores
        flow = BackgroundLeakage(spacing, periodic=periodic and not mirror,
                                 parallel=default_threads() > 1)
        for index in sorted(gaps):
            flow.submit(index, gaps.pop(index))
        leakage = np.full(len(job.points), np.nan)
        for index, value in flow.results().items():
            leakage[index] = value
        curve = replace(curve, leakage=leakage)
    cache.store(key, curve_arrays(curve))
    return curve, True


def run_job(job: RefineJob, cache_dir: str | None) -> tuple[ContactCurve, bool]:
    """:func:`refine_points` with its own cache handle (a top-level function, so that process
    pools and clusters can run it)."""
    map_large_arrays()   # freed grids given back, in whichever process this runs (bem.common.heap)
    return refine_points(job, Cache(cache_dir))


def solve_jobs(jobs: list[RefineJob], executor: Executor | None, cache_dir: str | None,
               bar=None) -> list[tuple[ContactCurve, bool]]:
    """Run ``jobs`` (:func:`run_job`) in this process or over ``executor``; results in the
    order of ``jobs``. ``bar`` (a :class:`validation.run.progress.Progress`, optional) advances
    per job and is closed at the end; an interruption or a failed job cancels every job not yet
    started, as the runner does for realizations."""
    futures: list[Future] = []
    out = []
    try:
        if executor is not None:
            futures = [executor.submit(run_job, job, cache_dir) for job in jobs]
        for index, job in enumerate(jobs):
            out.append(run_job(job, cache_dir) if executor is None else futures[index].result())
            if bar:
                bar.advance(f"finer reference {job.factor * job.task.surface.n}² "
                            f"{job.task.describe()}")
    except BaseException:
        for future in futures:
            future.cancel()
        raise
    finally:
        if bar:
            bar.close()
    return out
