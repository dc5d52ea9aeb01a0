"""The runner: from a scene to a plan, from a plan to results, computing only what is asked.

The plan of a surface scene is one :class:`RealizationTask` per (sweep value, realization): the
swept parameter is the fractal dimension D of a WM family, the Hurst exponent H of a
self-affine one; a measured map has one value and its tiles as realizations
(:mod:`validation.surfaces.families`). When the scene asks for the boundary-element reference's
own error, every BEM curve carries per-point error estimates (extras ``<quantity>_error``,
:func:`bem.path.error_estimates`: the same path on half the grid). A task computes, in order
and only when needed:

* the surface (only when a result that needs it is not cached; a theory scene has no tasks,
  so no surface);
* its summits (when a model whose registry entry ``needs_summits`` is asked for, or
  separations in units of sigma are);
* the reference model's path (the BEM; on a separation path the others follow its loads), then
  every other model the scene lists, each built by its registry entry
  (:mod:`validation.run.models`); stiffness solves only when conductance or stiffness is asked
  for, leakage (the BEM's Reynolds solves on its gaps) only when leakage is;
* with ``[sampling] factors``, the models fitted to summits again on every k-th grid point, at
  the reference's loads (:mod:`validation.run.sampling`; the BEM is not solved again).

Summits and the paths of models registered as ``cached`` (the BEM, the discrete models,
Persson) are cached (:mod:`validation.run.cache`) under keys that hash exactly their inputs plus
the package version; the GW closed forms are recomputed. Every computation is logged in
``RealizationResult.computed`` so that what was done can be checked, not guessed.

Realizations fan out over any :class:`concurrent.futures.Executor`; identical tasks of
different scenes run once, and so do tasks that differ only in their quantities (with the
union of them). Then a scene with a reference, where its cells are undecided, gets a finer
reference where the band decides (``[bem] max_grid``, :mod:`validation.run.refine`) and more
realizations, look by look (``[realizations] max``, :mod:`validation.run.sequential`); its
result records both and why they stopped.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable

import numpy as np

from bem import checks
from bem.curve import ContactCurve
from validation.run import models, sampling
from validation.run.cache import (Cache, cache_key, curve_arrays, curve_from_arrays,
                                  model_quantities, needs_leakage, needs_stiffness,
                                  source_version)
from validation.run.models import ModelInputs
from validation.run.cost import remaining_seconds, schedule
from validation.run.progress import Progress
from validation.run.refine import solve_jobs
from validation.run.sequential import RefinementRecord, SequentialRecord, decide_scene
from validation.scenes.scene import BemSettings, LoadPath, Scene, SurfaceSpec
from validation.surfaces.families import surface_heights, surface_identity

__all__ = ["RealizationTask", "RealizationResult", "SceneResult", "model_quantities",
           "plan_scene", "run_realization", "run_scenes", "Progress"]

def __getattr__(name: str):
    # ASPERITY_MODELS was a fixed list; the registry now says which models need summits.
    if name == "ASPERITY_MODELS":
        import warnings

        warnings.warn("validation.run.runner.ASPERITY_MODELS is deprecated: use "
                      "validation.run.models.entry(name).needs_summits", DeprecationWarning,
                      stacklevel=2)
        return tuple(n for n in models.names() if models.entry(n).needs_summits)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass(frozen=True)
class RealizationTask:
    """Everything one realization needs; hashable, so identical tasks run once."""

    surface: SurfaceSpec          # with a single sweep value
    seed: int                     # the tile index for a measured map
    e_star: float
    loads: LoadPath
    models: tuple[str, ...]
    m: float
    quantities: tuple[str, ...]
    bem: BemSettings
    cache_dir: str | None = None
    sampling: tuple[int, ...] = (1,)   # sampling intervals in grid steps (Scene.sampling)

    @property
    def sweep_value(self) -> float:
        """The value of the family's swept parameter (D, H; 0 for a measured map)."""
        return self.surface.sweep_values[0]

    @property
    def D(self) -> float | None:
        """Fractal dimension of a WM surface (None for another family)."""
        return self.surface.D[0] if self.surface.family == "wm" else None

    def describe(self) -> str:
        s = self.surface
        if s.family == "file":
            return f"tile={self.seed + 1}/{s.tiles} grid={'x'.join(map(str, s.grid))}"
        return f"{s.sweep_name}={self.sweep_value:g} seed={self.seed} n={s.n}"


@dataclass(frozen=True)
class RealizationResult:
    """Curves of every model asked for, on one realization, with what was computed."""

    task: RealizationTask
    curves: dict[str, ContactCurve]
    sigma: float                  # std of the summit heights [length] (nan without summits)
    summit_mean: float            # mean summit height above the mean plane [length]
    summit_count: int
    computed: tuple[str, ...]     # log of computations actually done (cache hits excluded)
    seconds: dict[str, float]     # wall time per model (0 for a cache hit)
    # the summit-fitted models at every sampling interval of task.sampling (finest first)
    sampled: tuple[sampling.Sampled, ...] = ()


@dataclass(frozen=True)
class SceneResult:
    """All results of one scene."""

    scene: Scene
    # by sweep value (D, H; 0 for a measured map): scene.surface.sweep_name says which
    realizations: dict[float, list[RealizationResult]] = field(default_factory=dict)
    theory: dict | None = None
    seconds: float = 0.0  # wall time from the start of the run until this scene was complete
    sequential: SequentialRecord | None = None  # the looks taken (scenes with a reference)
    refinement: RefinementRecord | None = None  # the finer reference where its band decides


# --------------------------------------------------------------------------------------------
# planning

def plan_scene(scene: Scene, *, cache_dir: str | None = None) -> list[RealizationTask]:
    """The tasks a scene needs (none for a theory scene)."""
    if scene.kind == "theory":
        return []
    tasks = []
    measured = scene.surface.family == "file"
    for value in scene.surface.sweep_values:
        surface = scene.surface.at(value)
        for k in range(scene.realizations):
            seed = k if measured else scene.seed + k
            tasks.append(RealizationTask(surface=surface, seed=seed, e_star=scene.e_star,
                                         loads=scene.loads, models=scene.models, m=scene.m,
                                         quantities=scene.quantities, bem=scene.bem,
                                         cache_dir=cache_dir, sampling=scene.sampling))
    return tasks


# --------------------------------------------------------------------------------------------
# one realization

def _surface_inputs(task: RealizationTask) -> dict:
    return surface_identity(task.surface, task.seed)


@dataclass
class _Log:
    """What one realization computed (cache hits excluded) and each model's wall time."""

    task: RealizationTask
    computed: list[str] = field(default_factory=list)
    seconds: dict[str, float] = field(default_factory=dict)

    def did(self, what: str) -> None:
        self.computed.append(f"{what} {self.task.describe()}")


def _surface_maker(task: RealizationTask, log: _Log) -> Callable[[], np.ndarray]:
    """The heights, made on first call only (when a result that needs them is not cached)."""
    sampled: list[np.ndarray] = []

    def heights() -> np.ndarray:
        if not sampled:
            sampled.append(surface_heights(task.surface, task.seed))
            log.did("surface")
        return sampled[0]
    return heights


def _summits(task: RealizationTask, cache: Cache, log: _Log, heights):
    """The summits from the cache, or found, stored and logged; None when nobody needs them."""
    import asperity

    if not (any(models.entry(name).needs_summits for name in task.models)
            or task.loads.quantity == "separation"):
        return None
    key = cache_key("summits", source_version(), surface=_surface_inputs(task))
    summits = cache.load(key, decode=asperity.summits_from_arrays)
    if summits is not None:
        return summits
    summits = asperity.find_summits(heights(), task.surface.spacing)
    cache.store(key, asperity.summits_to_arrays(summits))
    log.did("summits")
    return summits


def _model_curve(item: models.ModelEntry, inputs: ModelInputs, path: dict,
                 quantities: tuple[str, ...], cache: Cache, log: _Log) -> ContactCurve:
    """One model's curve along the path; expensive models from or into the cache (a cache
    hit costs 0 s and is not logged)."""
    key = None
    stiffness, leakage = needs_stiffness(quantities), needs_leakage(quantities)
    if item.cached:
        key = cache_key(item.name, source_version(), surface=_surface_inputs(log.task),
                        e_star=inputs.e_star, stiffness=stiffness, leakage=leakage,
                        **item.settings(inputs), **path)
        cached = cache.load(key, decode=curve_from_arrays)
        if cached is not None:
            log.seconds[item.name] = 0.0
            return cached
    start = time.perf_counter()
    model = item.factory(inputs)
    if "loads" in path:
        curve = model.at_load(path["loads"], quantities=quantities)
    else:
        curve = model.at_separation(path["separations"], quantities=quantities)
    log.seconds[item.name] = time.perf_counter() - start
    log.did(item.name)
    if key is not None:
        cache.store(key, curve_arrays(curve))
        if stiffness:
            log.did(f"{item.name}-stiffness")
        if leakage:
            log.did(f"{item.name}-leakage")
    return curve


def run_realization(task: RealizationTask) -> RealizationResult:
    """Compute one realization (a top-level function, so process pools can run it)."""
    cache, log = Cache(task.cache_dir), _Log(task)
    heights = _surface_maker(task, log)
    summits = _summits(task, cache, log, heights)
    sigma = math.nan if summits is None else float(np.std(summits.height))
    # Contact counts are cheap and always computed; stiffness and leakage solves only when
    # asked for. The cache keys hold these flags, not the scene's quantity list, so that
    # listing "contacts" or "stiffness" instead of "conductance" reuses the same solves.
    quantities = model_quantities(task.quantities)
    values = np.array(task.loads.values())
    nominal_area = task.surface.L**2          # L = sqrt(area) for a rectangular tile
    loads = values * task.e_star * nominal_area if task.loads.quantity == "load" else None
    inputs = ModelInputs(spacing=task.surface.spacing, nominal_area=nominal_area,
                         heights=heights, summits=summits, e_star=task.e_star, m=task.m,
                         bem_options=dict(periodic=task.bem.periodic, tol=task.bem.tol,
                                          max_iter=task.bem.max_iter,
                                          # an even grid along both sides: the scene
                                          # checks it (a measured map's tiles are made even)
                                          error_estimate=task.bem.reference_error))
    curves: dict[str, ContactCurve] = {}
    # The reference first: on a separation path the other models follow its loads.
    for name in sorted(task.models, key=lambda name: not models.entry(name).reference):
        item = models.entry(name)
        path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)
        curves[name] = _model_curve(item, inputs, path, quantities, cache, log)
        if item.reference and loads is None:
            loads = curves[name].load
    path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)
    sampled = sampling.sample_realization(
        task, heights, summits, inputs, curves, cache, log, version=source_version(),
        curve=lambda item, at: _model_curve(item, at, path, quantities, cache, log))
    return RealizationResult(
        task=task, curves=curves, sigma=sigma,
        summit_mean=math.nan if summits is None else float(np.mean(summits.height)),
        summit_count=0 if summits is None else int(np.size(summits.height)),
        computed=tuple(log.computed), seconds=log.seconds, sampled=sampled)


# --------------------------------------------------------------------------------------------
# many scenes

def _run_tasks(tasks: list[RealizationTask], executor: Executor | None, bar: Progress | None
               ) -> dict[RealizationTask, RealizationResult]:
    """Run the tasks (in the given order) in this process or over ``executor``; the bar shows
    an ETA learnt from the tasks already done (:func:`validation.run.cost.remaining_seconds`)."""
    started = time.perf_counter()
    workers = 1 if executor is None else max(1, int(getattr(executor, "_max_workers", 1)))
    results: dict[RealizationTask, RealizationResult] = {}

    def finished(task: RealizationTask, result: RealizationResult) -> None:
        results[task] = result
        if bar:
            pending = [t for t in tasks if t not in results]
            eta = remaining_seconds(list(results.items()), pending, workers,
                                    time.perf_counter() - started) if pending else 0.0
            bar.advance(task.describe(), eta=eta)

    futures: dict[Future, RealizationTask] = {}
    try:
        if executor is None:
            for task in tasks:
                finished(task, run_realization(task))
        else:
            futures = {executor.submit(run_realization, t): t for t in tasks}
            for future in as_completed(futures):
                finished(futures[future], future.result())
    except BaseException:
        # interrupted (Ctrl-C) or a realization failed: nothing queued may start any more
        for future in futures:
            future.cancel()
        raise
    finally:
        if bar:
            bar.close()
    return results


def _merged_tasks(tasks: Iterable[RealizationTask]) -> dict[RealizationTask, RealizationTask]:
    """Task -> the task run for it: tasks that differ only in their quantities run once, with
    the union of the quantities (a scene that asks for leakage and one that does not share the
    same realizations, and the first pays for the leakage of both)."""
    groups: dict[RealizationTask, list[RealizationTask]] = {}
    for task in tasks:
        groups.setdefault(replace(task, quantities=()), []).append(task)
    run_for = {}
    for key, group in groups.items():
        union = tuple(dict.fromkeys(q for task in group for q in task.quantities))
        run = group[0] if all(t == group[0] for t in group) else replace(key, quantities=union)
        run_for.update((task, run) for task in group)
    return run_for


def run_scenes(scenes: Iterable[Scene], *, executor: Executor | None = None,
               cache_dir: str | None = None, progress: bool = True, stream=None
               ) -> list[SceneResult]:
    """Run scenes: theory scenes in-process, realization tasks over ``executor``.

    Parameters
    ----------
    scenes : iterable of Scene
    executor : concurrent.futures.Executor, optional
        Where realization tasks run; ``None`` runs them in this process, one after another.
    cache_dir : str, optional
        Cache folder; ``None`` disables the cache.
    progress : bool
        Draw a progress bar on ``stream`` (a text stream; stderr by default).
    """
    from validation.run.theory import theory_curves

    scenes = list(checks.instances("scenes", scenes, Scene))
    checks.flag("progress", progress)
    if cache_dir is not None:
        checks.file_path("cache_dir", cache_dir)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise checks.InputTypeError(f"executor must be a concurrent.futures.Executor (with a "
                                    f"submit method) or None, got {type(executor).__name__}")
    if stream is not None and not callable(getattr(stream, "write", None)):
        raise checks.InputTypeError(f"stream must be a text stream (with a write method) or "
                                    f"None, got {type(stream).__name__}")
    names = [scene.name for scene in scenes]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ValueError(f"scene names must be unique in one run (they name the report's files); "
                         f"repeated: {', '.join(duplicates)}")
    started = time.perf_counter()
    plans = [plan_scene(scene, cache_dir=cache_dir) for scene in scenes]
    run_for = _merged_tasks(task for tasks in plans for task in tasks)
    unique = schedule(dict.fromkeys(run_for.values()))
    done = _run_tasks(unique, executor, Progress(len(unique), stream=stream)
                      if progress and unique else None)
    # each scene sees its own task (so its own quantities) beside the shared curves
    results = {task: done[run] if run == task else replace(done[run], task=task)
               for task, run in run_for.items()}
    out = []
    for scene, plan in zip(scenes, plans):
        if scene.kind == "theory":
            out.append(SceneResult(scene=scene, theory=theory_curves(scene.theory),
                                   seconds=time.perf_counter() - started))
            continue
        by_value: dict[float, list[RealizationResult]] = {}
        for task in plan:
            by_value.setdefault(task.sweep_value, []).append(results[task])
        out.append(SceneResult(scene=scene, realizations=by_value,
                               seconds=time.perf_counter() - started))
    # after the planned realizations: a finer reference, then more realizations, where cells
    # are undecided (scene by scene)
    for index, result in enumerate(out):
        records = _decide(result, executor, cache_dir, progress, stream)
        if records is not None:
            out[index] = replace(result, refinement=records[0], sequential=records[1],
                                 seconds=time.perf_counter() - started)
    return out


def _decide(result: SceneResult, executor: Executor | None, cache_dir: str | None,
            progress: bool, stream) -> tuple[RefinementRecord, SequentialRecord] | None:
    """:func:`validation.run.sequential.decide_scene` on a scene's result (its realizations
    extended in place) with this run's executor, cache and progress bars; None for a scene
    without a BEM reference (nothing to decide)."""
    scene = result.scene
    if scene.kind == "theory" or not set(scene.models) & set(models.reference_names()):
        return None

    def run(count: int) -> list[RealizationResult]:
        known = {r.task for value in result.realizations.values() for r in value}
        tasks = [t for t in plan_scene(replace(scene, realizations=count), cache_dir=cache_dir)
                 if t not in known]
        done = _run_tasks(tasks, executor, Progress(len(tasks), stream=stream)
                          if progress and tasks else None)
        return [done[task] for task in tasks]  # in seed order

    def solve(jobs: list) -> list:
        return solve_jobs(jobs, executor, cache_dir,
                          Progress(len(jobs), stream=stream) if progress and jobs else None)

    return decide_scene(scene, result.realizations, run, solve)
