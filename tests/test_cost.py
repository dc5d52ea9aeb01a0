"""Task weights for the progress bar: ordering, cache hits, and an ETA learnt per grid size."""

from dataclasses import replace
from types import SimpleNamespace

import pytest

from validation.run.cost import BEM_EXPONENT, remaining_seconds, schedule, task_cost
from validation.run.realization import plan_scene
from validation.scenes.reader import load_scene


@pytest.fixture(scope="module")
def tasks():
    plan = plan_scene(load_scene("paper-wm-d205"))  # 25 realizations at n = 512
    assert len(plan) == 25 and {task.surface.n for task in plan} == {512}
    # and one BEM-only task on twice the grid, of another size and cost
    fine = replace(plan[0], surface=replace(plan[0].surface, n=1024), models=("bem",))
    return plan + [fine]


def test_weights_follow_grid_loads_and_stiffness(tasks):
    realization, fine = tasks[0], tasks[-1]
    bem_only = replace(realization, models=("bem",))
    assert task_cost(fine) / task_cost(bem_only) == pytest.approx(2 ** BEM_EXPONENT)
    fewer = replace(realization, loads=replace(realization.loads, count=8))
    assert task_cost(fewer) == pytest.approx(task_cost(realization) / 2)
    no_stiffness = replace(realization, quantities=("area", "load", "separation"))
    assert task_cost(no_stiffness) < task_cost(realization)


def test_cache_hits_cost_nothing(tasks):
    task = tasks[0]
    assert task_cost(task, computed=("gw D=2.05 seed=0 n=512",)) == 0.0
    full = ("summits x", "bem x", "bem-stiffness x", "discrete x")
    assert task_cost(task, computed=full) == pytest.approx(task_cost(task))


def test_remaining_time_is_learnt_per_grid_size(tasks):
    small, big = tasks[0], tasks[-1]
    assert remaining_seconds([], [small, big]) is None
    cached = SimpleNamespace(seconds={"bem": 0.0}, computed=())
    # one 512 task took exactly 10 s per unit of cost: every pending 512 task costs the same
    ran = SimpleNamespace(seconds={"bem": 10.0 * task_cost(small)},
                          computed=("summits a", "bem a", "discrete a"))
    pending = [small] * 4
    assert remaining_seconds([(small, cached), (small, ran)], pending, workers=2) == \
        pytest.approx(4 * 10.0 * task_cost(small) / 2)
    # a grid size not seen yet borrows the overall rate; once seen, its own rate counts
    assert remaining_seconds([(small, ran)], [big]) == pytest.approx(10.0 * task_cost(big))
    slow = SimpleNamespace(seconds={"bem": 30.0 * task_cost(big)}, computed=("bem b",))
    assert remaining_seconds([(small, ran), (big, slow)], [big, small]) == \
        pytest.approx(30.0 * task_cost(big) + 10.0 * task_cost(small))
    # the first task of a size (set-up included) stops counting once a second one is done
    warm = SimpleNamespace(seconds={"bem": 8.0 * task_cost(small)}, computed=ran.computed)
    assert remaining_seconds([(small, ran), (small, warm)], [small]) == \
        pytest.approx(8.0 * task_cost(small))


def test_schedule_leads_with_one_task_per_grid_size(tasks):
    small = replace(tasks[0], surface=replace(tasks[0].surface, n=128))
    order = schedule(tasks + [small])
    assert [t.surface.n for t in order[:3]] == [1024, 512, 128]
    assert sorted(order, key=id) == sorted(tasks + [small], key=id)
    rest = [task_cost(t) for t in order[3:]]
    assert rest == sorted(rest, reverse=True)
