"""How right is the progress ETA? Run a small mixed-grid plan task by task and compare, after
every task, the predicted remaining time (validation.run.cost.remaining_seconds) with the time
that actually remained.

    python benchmarks/bench_eta.py [N]     # realizations on N x N (default 128), reference on 2N

Prints one line per finished task and the largest relative ETA error once a quarter of the
work is done. One worker, no cache. Timings on a shared machine are noisy.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace

from validation.run.cost import remaining_seconds, schedule, task_cost
from validation.run.realization import plan_scene, run_realization
from validation.scenes.reader import load_scene


def main(n: int = 128) -> None:
    tasks = []
    for name in ("paper-wm-d205", "paper-wm-d295"):
        scene = load_scene(name).quick_version()
        scene = replace(scene, surface=replace(scene.surface, n=n))
        tasks += plan_scene(scene)
    tasks = schedule(dict.fromkeys(tasks))
    start, done, stamps, predictions = time.perf_counter(), [], [], []
    for index, task in enumerate(tasks):
        result = run_realization(task)
        done.append((task, result))
        stamps.append(time.perf_counter() - start)
        predictions.append(remaining_seconds(done, tasks[index + 1:], workers=1, elapsed=stamps[-1]))
    total = stamps[-1]
    work = [task_cost(t) for t in tasks]
    worst = 0.0
    for index, (stamp, predicted) in enumerate(zip(stamps, predictions)):
        actual = total - stamp
        share = sum(work[:index + 1]) / sum(work)
        error = (predicted - actual) / actual if predicted is not None and actual > 0 else float("nan")
        if share >= 0.25 and actual > 0:
            worst = max(worst, abs(error))
        print(f"{index + 1:3d}/{len(tasks)} n={tasks[index].surface.n:5d} done {100 * share:5.1f} % "
              f"of cost, {stamp:7.1f} s; remaining: predicted {predicted or float('nan'):7.1f} s, "
              f"actual {actual:7.1f} s ({100 * error:+.0f} %)")
    print(f"total {total:.1f} s; largest ETA error after a quarter of the work: {100 * worst:.0f} %")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 128)
