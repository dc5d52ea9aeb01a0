"""Expected cost of realization tasks: weights for a progress bar's ETA and for scheduling.

A realization's time is dominated by the BEM load path: per load point a Polonsky-Keer solve
of N² unknowns whose FFTs cost N² log N each and whose iteration count grows with N, plus the
stiffness solves when conductance or stiffness is asked for. Measured growth per doubling of
N (BEM path, 16 loads, tolerance 1e-8; README solver table and this module's calibration,
both on two shared cores): about x7 from 128 to 256, x9-10 from 256 to 1024, so
cost ∝ N^BEM_EXPONENT; the stiffness solves add about STIFFNESS_SHARE of the
path. Summits, GW curves and the discrete model cost a few per cent at most.

An ETA from fixed weights is only as good as the exponent; :func:`remaining_seconds` instead
learns one rate (seconds per unit of cost) per grid size from the tasks already done, and uses
the weights only to share it out and to bridge grid sizes not yet seen. Tasks answered from
the cache cost nothing (their ``computed`` log is empty) and do not skew the rate.

Use at the call site (the runner's executor loop)::

    order = sorted(unique, key=task_cost, reverse=True)   # longest first: shortest makespan
    done = []                                             # (task, result) pairs
    ...on each completion: done.append((task, result))
    eta = remaining_seconds(done, pending, workers)       # None until one task computed
    bar.total = sum(task_cost(t) for t in order)          # or advance by task_cost(task)
"""

from __future__ import annotations

from typing import Iterable

__all__ = ["BEM_EXPONENT", "STIFFNESS_SHARE", "task_cost", "remaining_seconds"]

#: Growth of a BEM load path's time with the grid size N (cost ∝ N^BEM_EXPONENT).
BEM_EXPONENT = 3.2
#: Extra time of the stiffness solves, as a share of the BEM load path.
STIFFNESS_SHARE = 0.8
#: Summits, the closed-form curves and the discrete model, as a share of one BEM path at N = 256.
ASPERITY_SHARE = 0.03
_ASPERITY_MODELS = ("gw", "improved_gw", "discrete", "discrete_no_interaction", "persson")


def _needs_stiffness(quantities) -> bool:
    return "stiffness" in quantities or "conductance" in quantities


def task_cost(task, computed: Iterable[str] | None = None) -> float:
    """Expected time of ``run_realization(task)``, in units of one BEM load path of 16 points
    at N = 256 without stiffness.

    Parameters
    ----------
    task : validation.runner.RealizationTask
    computed : iterable of str, optional
        The finished result's ``computed`` log: only what was actually computed is counted
        (a task answered from the cache costs 0). Default: everything the task may compute.
    """
    scale = (task.surface.n / 256.0) ** 2
    points = task.loads.count / 16.0
    log = None if computed is None else [entry.split()[0] for entry in computed]
    cost = 0.0
    if "bem" in task.models and (log is None or "bem" in log):
        bem = points * (task.surface.n / 256.0) ** BEM_EXPONENT
        cost += bem * (1.0 + (STIFFNESS_SHARE if _needs_stiffness(task.quantities) else 0.0))
    if any(m in task.models for m in _ASPERITY_MODELS) and (
            log is None or any(e.startswith(("summits", "discrete")) for e in log)):
        cost += ASPERITY_SHARE * scale * points
    return cost


def remaining_seconds(done, pending, workers: int = 1) -> float | None:
    """Expected wall time of the ``pending`` tasks, learnt from the ``done`` ones.

    Parameters
    ----------
    done : iterable of (task, result)
        Finished tasks with their :class:`~validation.runner.RealizationResult`
        (``result.seconds``: compute time per model; ``result.computed``: what was computed).
    pending : iterable of task
        Tasks not finished yet.
    workers : int
        Tasks running at once.

    Returns
    -------
    float or None
        Seconds; ``None`` while no finished task has computed anything (no rate known yet).
        Per grid size N the rate is (seconds spent) / (cost computed) over the done tasks of
        that N; an N not seen yet uses the rate of all done tasks.
    """
    spent: dict[int, list[float]] = {}
    for task, result in done:
        cost = task_cost(task, result.computed)
        if cost > 0:
            entry = spent.setdefault(task.surface.n, [0.0, 0.0])
            entry[0] += sum(result.seconds.values())
            entry[1] += cost
    if not spent:
        return None
    overall = sum(s for s, _ in spent.values()) / sum(c for _, c in spent.values())
    rates = {n: s / c for n, (s, c) in spent.items()}
    total = sum(task_cost(t) * rates.get(t.surface.n, overall) for t in pending)
    return total / max(1, int(workers))
