"""The runner: many realizations over an executor, scene by scene.

A scene's tasks (:func:`validation.run.realization.plan_scene`) fan out over any
:class:`concurrent.futures.Executor`, in the order of their expected cost
(:mod:`validation.run.cost`), with a progress bar; each computes one realization
(:func:`validation.run.realization.run_realization`). Identical tasks of different scenes run
once, and so do tasks that differ only in their quantities (with the union of them)
(:func:`run_planned`). Where a scene's cells stay undecided, the judge asks for more
(:mod:`validation.judge.decide`): realizations of the next seeds (:func:`more_realizations`)
and the reference on finer grids (:func:`solve_refinements`, :mod:`validation.run.refine`); a
scene's result records both (:mod:`validation.run.sequential`).
"""

from __future__ import annotations

import time
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass, field, replace
from typing import Iterable

from bem.common import checks
from bem.common.curve import ContactCurve
from validation.common import models
from validation.run.cache import model_quantities
from validation.run.cost import remaining_seconds, schedule
from validation.run.progress import Progress
from validation.run.realization import RealizationResult, RealizationTask, plan_scene, run_realization
from validation.run.refine import RefineJob, solve_jobs
from validation.run.sequential import RefinementRecord, SequentialRecord
from validation.scenes.scene import Scene

__all__ = ["SceneResult", "model_quantities", "more_realizations", "run_planned",
           "solve_refinements", "Progress"]


def __getattr__(name: str):
    # ASPERITY_MODELS was a fixed list; the registry now says which models need summits.
    if name == "ASPERITY_MODELS":
        import warnings

        warnings.warn("validation.run.runner.ASPERITY_MODELS is deprecated: use "
                      "validation.common.models.entry(name).needs_summits", DeprecationWarning,
                      stacklevel=2)
        return tuple(n for n in models.names() if models.entry(n).needs_summits)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
            for task in tasks:   # alone in this process: the models beside the reference
                finished(task, run_realization(task, overlap=True))
        else:
            # fewer tasks than workers: each task's models beside its reference
            overlap = len(tasks) < workers
            futures = {executor.submit(run_realization, t, overlap=overlap): t for t in tasks}
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


def _check_where(executor, cache_dir, progress, stream=None) -> None:
    """Check where and how the run computes (the keywords of :func:`run_planned`)."""
    checks.flag("progress", progress)
    if cache_dir is not None:
        checks.file_path("cache_dir", cache_dir)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise checks.InputTypeError(f"executor must be a concurrent.futures.Executor (with a "
                                    f"submit method) or None, got {type(executor).__name__}")
    if stream is not None and not callable(getattr(stream, "write", None)):
        raise checks.InputTypeError(f"stream must be a text stream (with a write method) or "
                                    f"None, got {type(stream).__name__}")


def _bar(count: int, progress: bool, stream) -> Progress | None:
    return Progress(count, stream=stream) if progress and count else None


def run_planned(scenes: Iterable[Scene], *, executor: Executor | None = None,
                cache_dir: str | None = None, progress: bool = True, stream=None
                ) -> list[SceneResult]:
    """Run the planned realizations of scenes: theory scenes in-process, realization tasks over
    ``executor``. More realizations and a finer reference where cells stay undecided are
    :func:`validation.judge.decide.run_scenes`' (which calls this first).

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
    _check_where(executor, cache_dir, progress, stream)
    names = [scene.name for scene in scenes]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ValueError(f"scene names must be unique in one run (they name the report's files); "
                         f"repeated: {', '.join(duplicates)}")
    started = time.perf_counter()
    plans = [plan_scene(scene, cache_dir=cache_dir) for scene in scenes]
    run_for = _merged_tasks(task for tasks in plans for task in tasks)
    unique = schedule(dict.fromkeys(run_for.values()))
    done = _run_tasks(unique, executor, _bar(len(unique), progress, stream))
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
    return out


def more_realizations(result: SceneResult, count: int, *, executor: Executor | None = None,
                      cache_dir: str | None = None, progress: bool = True, stream=None
                      ) -> list[RealizationResult]:
    """The realizations that the first ``count`` seeds of every sweep value of ``result``'s
    scene add to those it has, in seed order (keywords as in :func:`run_planned`)."""
    if not isinstance(result, SceneResult):
        raise checks.InputTypeError(f"result must be a SceneResult, got {type(result).__name__}")
    count = checks.integer("count", count, minimum=1)
    _check_where(executor, cache_dir, progress, stream)
    known = {r.task for value in result.realizations.values() for r in value}
    tasks = [t for t in plan_scene(replace(result.scene, realizations=count), cache_dir=cache_dir)
             if t not in known]
    done = _run_tasks(tasks, executor, _bar(len(tasks), progress, stream))
    return [done[task] for task in tasks]


def solve_refinements(jobs: list[RefineJob], *, executor: Executor | None = None,
                      cache_dir: str | None = None, progress: bool = True, stream=None
                      ) -> list[tuple[ContactCurve, bool]]:
    """The finer reference's jobs solved over ``executor`` with a progress bar
    (:func:`validation.run.refine.solve_jobs`; keywords as in :func:`run_planned`)."""
    jobs = list(checks.instances("jobs", jobs, RefineJob))
    _check_where(executor, cache_dir, progress, stream)
    return solve_jobs(jobs, executor, cache_dir, _bar(len(jobs), progress, stream))
