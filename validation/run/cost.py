"""Expected cost of realization tasks: weights for a progress bar's ETA and for scheduling.

A realization's time is dominated by the BEM load path: per load point a constrained
conjugate-gradient solve of N² unknowns whose FFTs cost N² log N each; with the preconditioned,
nested solver the iteration count barely grows with N, but the larger FFTs fall out of the
processor's caches. Measured (WM D = 2.5, 16 loads from 1e-5 to 1e-2, tolerance 1e-8, two
cores): a path takes 1.8 s at N = 256 and 10.9 s at N = 512 (x6.1 per doubling), so cost ∝
N^BEM_EXPONENT; the stiffness solves add 0.3 (N = 256) to 0.6 (N = 512) of the path,
STIFFNESS_SHARE on average. Summits, GW curves and the discrete model cost a fixed, small share
per task.

An ETA from fixed weights is only as good as the exponent; :func:`remaining_seconds` instead
learns one rate (seconds per unit of cost) per grid size from the tasks already done, and uses
the weights only to share it out and to bridge grid sizes not yet seen. Tasks answered from
the cache cost nothing (their ``computed`` log is empty) and do not skew the rate.

Use at the call site (the runner's executor loop)::

    order = schedule(unique)          # one task per grid size first, then longest first
    done = []                                             # (task, result) pairs
    ...on each completion: done.append((task, result))
    eta = remaining_seconds(done, pending, workers, elapsed)  # None until a task computed
    bar.total = sum(task_cost(t) for t in order)          # or advance by task_cost(task)
"""

from __future__ import annotations

import math
from typing import Iterable

from validation.common import models

__all__ = ["BEM_EXPONENT", "STIFFNESS_SHARE", "task_cost", "schedule", "remaining_seconds"]

#: Growth of a BEM load path's time with the grid size N (cost ∝ N^BEM_EXPONENT).
BEM_EXPONENT = 2.6
#: Extra time of the stiffness solves, as a share of the BEM load path.
STIFFNESS_SHARE = 0.5
#: Surface, summits, the closed-form curves and the discrete model, as a share of one BEM path
#: at N = 256. Nearly independent of N: a WM surface's summits are set by its highest
#: frequency, not by the grid (measured 0.05-0.2 s per task at N = 128 and 256).
ASPERITY_SHARE = 0.02


def _needs_stiffness(quantities) -> bool:
    return "stiffness" in quantities or "conductance" in quantities


def task_cost(task, computed: Iterable[str] | None = None) -> float:
    """Expected time of ``run_realization(task)``, in units of one BEM load path of 16 points
    at N = 256 without stiffness.

    Parameters
    ----------
    task : validation.run.realization.RealizationTask
    computed : iterable of str, optional
        The finished result's ``computed`` log: only what was actually computed is counted
        (a task answered from the cache costs 0). Default: everything the task may compute.
    """
    points = task.loads.count / 16.0
    log = None if computed is None else [entry.split()[0] for entry in computed]
    cost = 0.0
    references = [m for m in task.models if m in models.names() and models.entry(m).reference]
    if references and (log is None or any(m in log for m in references)):
        side = math.sqrt(math.prod(task.surface.grid))    # n, or sqrt(N M) of a tile
        bem = points * (side / 256.0) ** BEM_EXPONENT
        cost += bem * (1.0 + (STIFFNESS_SHARE if _needs_stiffness(task.quantities) else 0.0))
    others = [m for m in task.models if m in models.names() and not models.entry(m).reference]
    # what counts is work that a cache hit saves: the summits and the cached models' paths
    # (closed-form curves cost next to nothing, cached or not)
    saved = ("summits",) + tuple(m for m in others if models.entry(m).cached
                                 and not models.entry(m).closed_form)
    if others and (log is None or any(e.split("-")[0] in saved for e in log)):
        cost += ASPERITY_SHARE * points
    return cost


def schedule(tasks) -> list:
    """Tasks in the order to submit them: the costliest task of every grid size first (so that
    a rate is learnt for each size early), then the rest longest first (a short makespan: no
    long task is left to run alone at the end)."""
    ordered = sorted(tasks, key=task_cost, reverse=True)
    first: dict[tuple[int, int], object] = {}
    for task in ordered:
        first.setdefault(task.surface.grid, task)
    leaders = list(first.values())
    return leaders + [task for task in ordered if task not in leaders]


def remaining_seconds(done, pending, workers: int = 1, elapsed: float | None = None
                      ) -> float | None:
    """Expected wall time of the ``pending`` tasks, learnt from the ``done`` ones.

    Parameters
    ----------
    done : iterable of (task, result)
        Finished tasks with their :class:`~validation.run.realization.RealizationResult`
        (``result.seconds``: compute time per model; ``result.computed``: what was computed).
    pending : iterable of task
        Tasks not finished yet.
    workers : int
        Tasks running at once.
    elapsed : float, optional
        Wall time since the first task started [s]. When given, the estimate is scaled by
        elapsed x workers / (model seconds of the done tasks), which adds what the models'
        own timers miss (surfaces, summits, process start, waiting for a shared core).

    Returns
    -------
    float or None
        Seconds; ``None`` while no finished task has computed anything (no rate known yet).
        Per grid size N the rate is (seconds spent) / (cost computed) over the done tasks of
        that N, the first one left out once there are two (it also pays one-off set-up); an N
        not seen yet uses the rate of all done tasks.
    """
    spent: dict[tuple[int, int], list[tuple[float, float]]] = {}
    for task, result in done:
        cost = task_cost(task, result.computed)
        if cost > 0:
            spent.setdefault(task.surface.grid, []).append((sum(result.seconds.values()), cost))
    if not spent:
        return None
    timed = sum(s for pairs in spent.values() for s, _ in pairs)
    # the first task of a grid size also pays one-off set-up (FFT plans, imports): once a
    # second one is done, the first is left out of that size's rate
    spent = {n: pairs[1:] if len(pairs) > 1 else pairs for n, pairs in spent.items()}
    totals = {n: (sum(s for s, _ in pairs), sum(c for _, c in pairs)) for n, pairs in spent.items()}
    overall = sum(s for s, _ in totals.values()) / sum(c for _, c in totals.values())
    rates = {n: s / c for n, (s, c) in totals.items()}
    total = sum(task_cost(t) * rates.get(t.surface.grid, overall) for t in pending)
    scale = elapsed * max(1, int(workers)) / timed if elapsed and timed > 0 else 1.0
    return scale * total / max(1, int(workers))
