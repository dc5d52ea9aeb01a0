"""One realization: from a scene to its tasks, from a task to the curves of every model asked for.

The plan of a surface scene is one :class:`RealizationTask` per (sweep value, realization): the
swept parameter is the fractal dimension D of a WM family, the Hurst exponent H of a
self-affine one; a measured map has one value and its tiles as realizations
(:mod:`validation.surfaces.families`). When the scene asks for the boundary-element reference's
own error, every BEM curve carries per-point error estimates (extras ``<quantity>_error``,
:func:`bem.contact.path_errors.error_estimates`: the same path on half the grid). A task computes, in order
and only when needed:

* the surface (only when a result that needs it is not cached; a theory scene has no tasks,
  so no surface);
* its summits (when a model whose registry entry ``needs_summits`` is asked for, or
  separations in units of sigma are);
* the reference model's path (the BEM; on a separation path the others follow its loads), then
  every other model the scene lists, each built by its registry entry
  (:mod:`validation.common.models`); stiffness solves only when conductance or stiffness is asked
  for, leakage (the BEM's Reynolds solves on its gaps) only when leakage is;
* with ``[sampling] factors``, the models fitted to summits again on every k-th grid point, at
  the reference's loads (:mod:`validation.run.sampling`; the BEM is not solved again).

Summits and the paths of models registered as ``cached`` (the BEM, the discrete models,
Persson) are cached (:mod:`validation.run.cache`) under keys that hash exactly their inputs plus
the package version; the GW closed forms are recomputed. Every computation is logged in
``RealizationResult.computed`` so that what was done can be checked, not guessed.
:mod:`validation.run.runner` runs many tasks over an executor.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from bem.common.background import BackgroundCall
from bem.common.curve import ContactCurve
from bem.common.heap import map_large_arrays
from validation.common import models
from validation.common.models import ModelInputs
from validation.run import sampling
from validation.run.refine import REFINED, refined_extension
from validation.run.starts import KeptPressures, keeps_starts, starts_key
from validation.run.cache import (Cache, cache_key, curve_arrays, curve_from_arrays,
                                  model_quantities, needs_leakage, needs_stiffness,
                                  source_version)
from validation.scenes.scene import BemSettings, LoadPath, Scene, SurfaceSpec
from validation.surfaces.families import surface_heights, surface_identity

__all__ = ["RealizationTask", "RealizationResult", "plan_scene", "run_realization"]


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
    nominal_size: float | None = None  # Scene.nominal_size

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
                                         cache_dir=cache_dir, sampling=scene.sampling,
                                         nominal_size=scene.nominal_size))
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
    """The heights, made on first call only (when a result that needs them is not cached; the
    models computed in a second thread may ask at the same time)."""
    sampled: list[np.ndarray] = []
    lock = threading.Lock()

    def heights() -> np.ndarray:
        with lock:
            if not sampled:
                made = surface_heights(task.surface, task.seed)
                # read-only: every model shares this one array (the reference's solver copies
                # a writable one, 32 MB at 2048^2)
                made.setflags(write=False)
                sampled.append(made)
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
    # a reference a finer grid may refine keeps its pressures: the finer path's starts
    pressures = None
    if item.name in REFINED and keeps_starts(log.task, log.task.surface.n):
        pressures = KeptPressures()
        inputs = inputs.with_bem_options(
            callback=lambda index, solution: pressures.add(index, solution.pressure))
    model = item.factory(inputs)
    if "loads" in path:
        curve = model.at_load(path["loads"], quantities=quantities)
    else:
        curve = model.at_separation(path["separations"], quantities=quantities)
    log.seconds[item.name] = time.perf_counter() - start
    log.did(item.name)
    if pressures:
        task = log.task
        pressures.store(cache, starts_key(task, task.surface.n,
                                          refined_extension(item.name, task)))
    if key is not None:
        cache.store(key, curve_arrays(curve))
        if stiffness:
            log.did(f"{item.name}-stiffness")
        if leakage:
            log.did(f"{item.name}-leakage")
    return curve


def _curves(task, inputs, loads, values, sigma, quantities, cache, log, overlap):
    """Every model's curve and the loads of the path: the reference first, since on a
    separation path the other models follow its loads; on a load path, with ``overlap``, the
    others beside it in a thread."""
    order = sorted(task.models, key=lambda name: not models.entry(name).reference)
    reference = [name for name in order if models.entry(name).reference]
    others = [name for name in order if name not in reference]

    def curves_of(names: list[str], path: dict) -> dict[str, ContactCurve]:
        return {name: _model_curve(models.entry(name), inputs, path, quantities, cache, log)
                for name in names}
    if overlap and loads is not None and reference and others:
        path = dict(loads=loads)
        beside = BackgroundCall(curves_of, others, path, name="models")
        curves = curves_of(reference, path)
        curves.update(beside.result())
        return {name: curves[name] for name in order}, loads
    curves: dict[str, ContactCurve] = {}
    for name in order:
        path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)
        curves.update(curves_of([name], path))
        if name in reference and loads is None:
            loads = curves[name].load
    return curves, loads


def run_realization(task: RealizationTask, *, overlap: bool = False) -> RealizationResult:
    """Compute one realization (a top-level function, so process pools can run it).

    With ``overlap`` on a load path, the other models are computed in a second thread while
    the reference is solved (they do not need its loads; the heavy parts of both, FFTs,
    dense products and sparse factorisations, release the GIL): for a realization that runs
    alone in its process, so that it uses a second core. The curves are the same either way.
    """
    map_large_arrays()   # freed grids given back, in whichever process this runs (bem.common.heap)
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
                                          error_estimate=task.bem.reference_error,
                                          device=task.bem.device),
                         periodic_surface=task.surface.one_period or task.bem.periodic,
                         nominal_size=task.nominal_size)
    curves, loads = _curves(task, inputs, loads, values, sigma, quantities, cache, log, overlap)
    path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)
    sampled = sampling.sample_realization(
        task, heights, summits, inputs, curves, cache, log, version=source_version(),
        curve=lambda item, at: _model_curve(item, at, path, quantities, cache, log))
    return RealizationResult(
        task=task, curves=curves, sigma=sigma,
        summit_mean=math.nan if summits is None else float(np.mean(summits.height)),
        summit_count=0 if summits is None else int(np.size(summits.height)),
        computed=tuple(log.computed), seconds=log.seconds, sampled=sampled)
