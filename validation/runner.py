"""The runner: from a scene to a plan, from a plan to results, computing only what is asked.

The plan of a surface scene is one :class:`RealizationTask` per (D, realization); when the scene
asks for the boundary-element reference's own error, every BEM curve carries per-point error
estimates (extras ``<quantity>_error``, :func:`bem.path.error_estimates`). A task computes,
in order and only when needed:

* the surface (only when a result that needs it is not cached; a theory scene has no tasks,
  so no surface);
* its summits (when an asperity model is asked for, or separations in units of sigma are);
* the BEM load path, with its stiffness solves only when conductance or stiffness is asked for;
* the GW and improved-GW curves fitted to the summits (cheap, never cached);
* the discrete-model load paths (with and without interaction), stiffness only when asked.

Summits, BEM and discrete load paths are cached (:mod:`validation.cache`) under keys that hash
exactly their inputs plus the package version. Every computation is logged in
``RealizationResult.computed`` so that what was done can be checked, not guessed.

Realizations fan out over any :class:`concurrent.futures.Executor`; identical tasks of
different scenes run once.
"""

from __future__ import annotations

import math
import sys
import time
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass, field, replace
from typing import Iterable

import numpy as np

from bem.curve import CURVE_QUANTITIES, ContactCurve
from validation.cache import Cache, cache_key
from validation.scene import BemSettings, LoadPath, Scene, SurfaceSpec
from validation.surfaces import wm_surface

__all__ = ["RealizationTask", "RealizationResult", "SceneResult", "plan_scene", "run_realization",
           "run_scenes", "Progress", "ASPERITY_MODELS"]

#: Models fitted to or built on the summits.
ASPERITY_MODELS = ("gw", "improved_gw", "discrete", "discrete_no_interaction")


_SOURCE_VERSION: str | None = None


def _version() -> str:
    """Package version plus a hash of the three packages' sources: results cached by one state
    of the code are never read back by another (a fixed bug does not survive in the cache)."""
    global _SOURCE_VERSION
    if _SOURCE_VERSION is None:
        import hashlib
        import pathlib

        from validation import __version__

        digest = hashlib.sha256()
        root = pathlib.Path(__file__).resolve().parents[1]
        for package in ("asperity", "bem", "validation"):
            for path in sorted((root / package).glob("*.py")):
                digest.update(path.name.encode())
                digest.update(path.read_bytes())
        _SOURCE_VERSION = f"{__version__}+{digest.hexdigest()[:16]}"
    return _SOURCE_VERSION


@dataclass(frozen=True)
class RealizationTask:
    """Everything one realization needs; hashable, so identical tasks run once."""

    surface: SurfaceSpec          # with a single D
    seed: int
    e_star: float
    loads: LoadPath
    models: tuple[str, ...]
    m: float
    quantities: tuple[str, ...]
    bem: BemSettings
    cache_dir: str | None = None
    purpose: str = "realization"  # or "reference-error" (BEM only, on a finer grid)
    slope_grid: int | None = None  # grid on which rms_slope fixes the amplitude (None: n)

    @property
    def D(self) -> float:
        return self.surface.D[0]

    def describe(self) -> str:
        return f"D={self.D:g} seed={self.seed} n={self.surface.n}"


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


@dataclass(frozen=True)
class SceneResult:
    """All results of one scene."""

    scene: Scene
    realizations: dict[float, list[RealizationResult]] = field(default_factory=dict)  # by D
    reference_error: dict[float, RealizationResult] = field(default_factory=dict)     # by D
    theory: dict | None = None
    seconds: float = 0.0  # wall time from the start of the run until this scene was complete


# --------------------------------------------------------------------------------------------
# planning

def plan_scene(scene: Scene, *, cache_dir: str | None = None) -> list[RealizationTask]:
    """The tasks a scene needs (none for a theory scene)."""
    if scene.kind == "theory":
        return []
    tasks = []
    for D in scene.surface.D:
        surface = replace(scene.surface, D=(D,))
        for k in range(scene.realizations):
            tasks.append(RealizationTask(surface=surface, seed=scene.seed + k, e_star=scene.e_star,
                                         loads=scene.loads, models=scene.models, m=scene.m,
                                         quantities=scene.quantities, bem=scene.bem,
                                         cache_dir=cache_dir))
    return tasks


# --------------------------------------------------------------------------------------------
# one realization

def _curve_arrays(curve: ContactCurve) -> dict[str, np.ndarray]:
    arrays = {name: getattr(curve, name) for name in CURVE_QUANTITIES if getattr(curve, name) is not None}
    arrays["nominal_area"] = np.array(curve.nominal_area)
    arrays["e_star"] = np.array(curve.e_star)
    for name, value in curve.extras.items():
        value = np.asarray(value)
        if value.ndim == 1 and value.shape == curve.load.shape and value.dtype.kind in "fiub":
            arrays[f"extra:{name}"] = value
    return arrays


def _curve_from_arrays(arrays: dict[str, np.ndarray]) -> ContactCurve:
    kwargs = {name: arrays[name] for name in CURVE_QUANTITIES if name in arrays}
    extras = {name[6:]: value for name, value in arrays.items() if name.startswith("extra:")}
    return ContactCurve(nominal_area=float(arrays["nominal_area"]), e_star=float(arrays["e_star"]),
                        extras=extras, **kwargs)


def _surface_inputs(task: RealizationTask) -> dict:
    s = task.surface
    return dict(family=s.family, D=task.D, rms_slope=s.rms_slope, G=s.G, gamma=s.gamma, M=s.M,
                n_max=s.n_max, L=s.L, n=s.n, seed=task.seed,
                slope_grid=task.slope_grid or s.n)


def _needs_stiffness(quantities: tuple[str, ...]) -> bool:
    return "stiffness" in quantities or "conductance" in quantities


def run_realization(task: RealizationTask) -> RealizationResult:
    """Compute one realization (a top-level function, so process pools can run it)."""
    import asperity
    import bem

    cache = Cache(task.cache_dir)
    version = _version()
    computed: list[str] = []
    seconds: dict[str, float] = {}
    s = task.surface
    sampled: list[np.ndarray] = []

    def heights() -> np.ndarray:
        # The surface is made only when a result that needs it is not in the cache.
        if not sampled:
            sampled.append(wm_surface(
                s.n, D=task.D, G=s.G, rms_slope=s.rms_slope, L=s.L, gamma=s.gamma, M=s.M,
                n_max=s.n_max, seed=task.seed,
                slope_grid=task.slope_grid if s.rms_slope is not None else None))
            computed.append(f"surface {task.describe()}")
        return sampled[0]
    spacing = s.spacing
    nominal_area = s.L**2
    surface_key = _surface_inputs(task)

    wants_summits = any(m in task.models for m in ASPERITY_MODELS) or task.loads.quantity == "separation"
    summits, sigma, summit_mean = None, math.nan, math.nan
    if wants_summits:
        key = cache_key("summits", version, surface=surface_key)
        arrays = cache.load(key)
        if arrays is None:
            summits = asperity.find_summits(heights(), spacing)
            cache.store(key, asperity.summits_to_arrays(summits))
            computed.append(f"summits {task.describe()}")
        else:
            summits = asperity.summits_from_arrays(arrays)
        sigma = float(np.std(summits.height))
        summit_mean = float(np.mean(summits.height))

    stiffness = _needs_stiffness(task.quantities)
    # Contact counts are cheap and always computed; stiffness solves only when asked for. The
    # cache keys hold this flag, not the scene's quantity list, so that listing "contacts" or
    # "stiffness" instead of "conductance" reuses the same solves.
    curve_quantities = ("area", "load", "separation", "contacts") + (
        ("stiffness", "conductance") if stiffness else ())
    values = np.array(task.loads.values())
    curves: dict[str, ContactCurve] = {}

    def cached_curve(model: str, key: str, compute) -> None:
        # A load path from the cache, or computed, stored and logged (with its stiffness
        # solves, when asked for); a cache hit costs 0 s.
        arrays = cache.load(key)
        if arrays is not None:
            curves[model], seconds[model] = _curve_from_arrays(arrays), 0.0
            return
        start = time.perf_counter()
        curve = compute()
        seconds[model] = time.perf_counter() - start
        cache.store(key, _curve_arrays(curve))
        computed.append(f"{model} {task.describe()}")
        if stiffness:
            computed.append(f"{model}-stiffness {task.describe()}")
        curves[model] = curve

    loads = None
    if task.loads.quantity == "load":
        loads = values * task.e_star * nominal_area
    if "bem" in task.models:
        path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)
        cached_curve("bem", cache_key("bem", version, surface=surface_key, e_star=task.e_star,
                                      settings=task.bem, stiffness=stiffness, **path),
                     lambda: bem.contact_curve(heights(), spacing, e_star=task.e_star,
                                               periodic=task.bem.periodic, tol=task.bem.tol,
                                               max_iter=task.bem.max_iter,
                                               quantities=curve_quantities,
                                               error_estimate=task.bem.reference_error, **path))
        if loads is None:  # separation path: the other models follow the reference's loads
            loads = curves["bem"].load

    for model in ("gw", "improved_gw"):
        if model in task.models:
            start = time.perf_counter()
            theory = (summits.greenwood_williamson(nominal_area, e_star=task.e_star) if model == "gw"
                      else summits.improved_greenwood_williamson(nominal_area, e_star=task.e_star,
                                                                 m=task.m))
            curves[model] = (theory.at_load(loads) if loads is not None
                             else theory.at_separation(values * sigma))
            seconds[model] = time.perf_counter() - start
            computed.append(f"{model} {task.describe()}")

    for model, interaction in (("discrete", True), ("discrete_no_interaction", False)):
        if model not in task.models:
            continue
        path = dict(loads=loads) if loads is not None else dict(separations=values * sigma)

        def solve(interaction=interaction):
            discrete = asperity.DiscreteAsperityModel(summits, e_star=task.e_star,
                                                      interaction=interaction)
            if loads is not None:
                return discrete.at_load(loads, quantities=curve_quantities)
            return discrete.at_separation(values * sigma, quantities=curve_quantities)

        cached_curve(model, cache_key("discrete", version, surface=surface_key, e_star=task.e_star,
                                      interaction=interaction, stiffness=stiffness, **path), solve)

    return RealizationResult(task=task, curves=curves, sigma=sigma, summit_mean=summit_mean,
                             summit_count=0 if summits is None else int(np.size(summits.height)),
                             computed=tuple(computed),
                             seconds=seconds)


# --------------------------------------------------------------------------------------------
# many scenes

class Progress:
    """A text progress bar on a stream: work done and left, elapsed time."""

    def __init__(self, total: int, *, stream=None, label: str = "realizations", width: int = 30):
        self.total, self.done, self.label, self.width = total, 0, label, width
        self.stream = sys.stderr if stream is None else stream
        self.start = time.perf_counter()
        self.interactive = hasattr(self.stream, "isatty") and self.stream.isatty()
        if total:
            self._draw()

    def advance(self, what: str = "") -> None:
        self.done += 1
        self._draw(what)

    def _draw(self, what: str = "") -> None:
        filled = int(self.width * self.done / max(self.total, 1))
        bar = "#" * filled + "-" * (self.width - filled)
        elapsed = time.perf_counter() - self.start
        line = (f"[{bar}] {self.done}/{self.total} {self.label}, {self.total - self.done} left, "
                f"{elapsed:.0f} s" + (f"  ({what})" if what else ""))
        if self.interactive:
            self.stream.write("\r" + line + ("\n" if self.done == self.total else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


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
        Draw a progress bar on ``stream`` (stderr by default).
    """
    from validation.theory import theory_curves

    scenes = list(scenes)
    names = [scene.name for scene in scenes]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ValueError(f"scene names must be unique in one run (they name the report's files); "
                         f"repeated: {', '.join(duplicates)}")
    started = time.perf_counter()
    plans = [plan_scene(scene, cache_dir=cache_dir) for scene in scenes]
    unique = list(dict.fromkeys(task for tasks in plans for task in tasks))
    bar = Progress(len(unique), stream=stream) if progress and unique else None
    results: dict[RealizationTask, RealizationResult] = {}
    if executor is None:
        for task in unique:
            results[task] = run_realization(task)
            if bar:
                bar.advance(task.describe())
    else:
        futures: dict[Future, RealizationTask] = {executor.submit(run_realization, t): t for t in unique}
        for future in as_completed(futures):
            task = futures[future]
            results[task] = future.result()
            if bar:
                bar.advance(task.describe())
    out = []
    for scene, plan in zip(scenes, plans):
        if scene.kind == "theory":
            out.append(SceneResult(scene=scene, theory=theory_curves(scene.theory),
                                   seconds=time.perf_counter() - started))
            continue
        by_d: dict[float, list[RealizationResult]] = {}
        reference: dict[float, RealizationResult] = {}
        for task in plan:
            if task.purpose == "reference-error":
                reference[task.D] = results[task]
            else:
                by_d.setdefault(task.D, []).append(results[task])
        out.append(SceneResult(scene=scene, realizations=by_d, reference_error=reference,
                               seconds=time.perf_counter() - started))
    return out
