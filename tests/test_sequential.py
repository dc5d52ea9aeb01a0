"""The sequential plan: look sizes, stopping reasons, and its error control proved by simulation
(synthetic errors whose mean lies on the tolerance: any verdict there is wrong in one of the two
limits, so the share of decided cells is the error rate)."""

import numpy as np
import pytest

from validation.run.sequential import LookPlan, look_plan, run_looks, undecided_share
from validation.judge.verdicts import UNDECIDED, classify, confidence_interval

TOL = 0.2


def test_look_sizes_grow_geometrically_to_the_budget():
    assert look_plan(25, 100).sizes == (25, 50, 100)
    assert look_plan(8, 32).sizes == (8, 16, 32)
    assert look_plan(2, 4).sizes == (2, 3, 4)
    assert look_plan(25, None).sizes == (25,) and look_plan(25, 25).sizes == (25,)
    assert look_plan(3, 4).sizes == (3, 4)            # rounding merges equal looks
    plan = look_plan(25, 100)
    assert plan.alphas == pytest.approx((0.05 / 7, 0.1 / 7, 0.2 / 7))  # in proportion to n
    assert sum(plan.alphas) == pytest.approx(0.05)
    assert plan.confidence_for(100) == plan.confidence_at(2) == pytest.approx(1 - 0.2 / 7)
    assert plan.confidence_for(37) == plan.confidence_at(0)  # not a look: the strictest
    assert look_plan(25, None).confidence_at(0) == pytest.approx(0.95)
    with pytest.raises(ValueError, match="planned"):
        look_plan(0, 10)
    with pytest.raises(ValueError, match="sizes"):
        LookPlan((5, 5))


def scripted(shares):
    """run_looks on a scene whose undecided share after each look is scripted."""
    asked = []
    record = run_looks(look_plan(10, 40), asked.append, lambda confidence: shares[len(asked)])
    return record, asked


def test_stops_when_nothing_is_undecided_when_the_share_stops_falling_or_at_the_budget():
    record, asked = scripted([0.0])
    assert asked == [] and record.used == (10,) and record.reason == "no undecided cell"
    record, asked = scripted([0.4, 0.4])
    assert asked == [20] and record.reason.startswith("the undecided share stopped falling")
    record, asked = scripted([0.4, 0.3, 0.2])
    assert asked == [20, 40] and record.reason.startswith("budget reached")
    assert "10 → 20 → 40 realizations in 3 looks of 3" in record.describe()
    record, _ = run_looks(look_plan(10, None), lambda n: None, lambda c: 0.5), None
    assert record.reason.startswith("planned realizations only")
    assert undecided_share([np.array(["holds", UNDECIDED]), np.array([UNDECIDED])]) == 2 / 3


def simulate(plan, means, std, trials, seed):
    """Run the sequential plan on synthetic scenes: one cell per entry of ``means`` (errors
    N(mean, std^2) per realization), every look's verdict at the plan's confidence; returns the
    final verdicts, shape (trials, cells), and the realizations each scene used."""
    rng = np.random.default_rng(seed)
    means = np.asarray(means, dtype=float)
    finals, used = [], []
    for _ in range(trials):
        errors = rng.normal(means, std, size=(plan.sizes[-1], means.size))
        available = [plan.sizes[0]]

        def verdict(confidence):
            interval = confidence_interval(errors[:available[0]], confidence)
            return classify(interval, 0.0, TOL)

        record = run_looks(plan, lambda n: available.__setitem__(0, n),
                           lambda confidence: undecided_share([verdict(confidence)]))
        finals.append(verdict(plan.confidence_at(len(record.used) - 1)))
        used.append(record.realizations)
    return np.array(finals), np.array(used)


TRIALS = 6000
SLACK = 3.5 * np.sqrt(0.05 * 0.95 / TRIALS)


@pytest.mark.parametrize("means", [[TOL], [TOL, -TOL, 0.0, 0.1, 0.3, 0.17, 0.23]])
def test_sequential_verdicts_on_the_boundary_are_wrong_at_most_5_percent(means):
    # The worst case for data-dependent stopping is a scene of one cell: it stops exactly when
    # that cell is decided. Cells elsewhere make the scene look again or stop for other reasons.
    plan = look_plan(8, 32)
    finals, used = simulate(plan, means, std=0.3, trials=TRIALS, seed=len(means))
    decided = finals[:, 0] != UNDECIDED  # the cell whose mean lies on +TOL
    assert decided.mean() <= 0.05 + SLACK
    # the plan looked again where cells were open (a lone cell decided at the first look stops
    # there; one still open at the second stops there too: its share did not fall)
    assert used.max() == (16 if len(means) == 1 else 32)
    assert used.min() == (8 if len(means) == 1 else 16)
    if len(means) > 1:
        assert (finals[:, 1] != UNDECIDED).mean() <= 0.05 + SLACK  # the one on -TOL


class Unsplit(LookPlan):
    """The same looks, each at 95 %: the 5 % not split."""

    def confidence_at(self, look: int) -> float:
        return 0.95


def test_looking_three_times_at_95_percent_would_fail_this_test():
    # The control: the same looks with the 5 % not split (95 % confidence at every look) decide
    # the boundary cell far more often than 5 % of the time, so the test above can fail.
    finals, _ = simulate(Unsplit((8, 16, 32)), [TOL], std=0.3, trials=TRIALS, seed=1)
    assert (finals[:, 0] != UNDECIDED).mean() > 0.05 + 2 * SLACK


def test_more_realizations_decide_cells_near_the_boundary():
    plan = look_plan(8, 32)
    finals, used = simulate(plan, [0.1, 0.3], std=0.15, trials=400, seed=9)
    single, _ = simulate(look_plan(8, None), [0.1, 0.3], std=0.15, trials=400, seed=9)
    assert (finals != UNDECIDED).mean() > (single != UNDECIDED).mean() + 0.2


def test_scene_budget_is_validated_and_scaled_in_quick_mode():
    from validation.scenes.scene import SceneError
    from validation.scenes.reader import load_scene, parse_scene

    base = {"surface": {"D": 2.3, "rms_slope": 0.1, "n": 32}}
    scene = parse_scene(base | {"realizations": {"count": 25, "max": 100}})
    assert scene.max_realizations == 100 and parse_scene(base).max_realizations is None
    quick = scene.quick_version()
    assert (quick.realizations, quick.max_realizations) == (3, 12)
    for bad in (10, 2.5, True):
        with pytest.raises(SceneError, match="realizations.max"):
            parse_scene(base | {"realizations": {"count": 25, "max": bad}}, source="s.toml")
    # the published paper scenes run their 25 realizations without looks (run time)
    assert load_scene("paper-wm-d205").max_realizations is None


def test_runner_adds_realizations_in_looks_and_the_cache_keeps_them(tmp_path):
    from validation import run_scenes
    from validation.scenes.reader import parse_scene

    scene = parse_scene({
        "name": "open", "surface": {"D": 2.3, "rms_slope": 0.1, "n": 16},
        "realizations": {"count": 2, "seed": 7, "max": 4},
        "loads": {"min": 1e-3, "max": 1e-2, "count": 3},
        "models": {"use": ["gw", "bem"]}, "quantities": {"use": ["area", "load", "separation"]},
        "bem": {"reference_error": False}}, source="test")
    (result,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    record = result.sequential
    assert record.used[0] == 2 and record.plan.sizes == (2, 3, 4)
    seeds = [r.task.seed for r in result.realizations[2.3]]
    assert seeds == list(range(7, 7 + record.realizations))  # the planned sequence, extended
    assert record.reason
    (again,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    assert again.sequential == record
    assert not [e for r in again.realizations[2.3] for e in r.computed if e.startswith("bem")]


def test_the_refinement_record_says_where_the_stiffness_and_leakage_were_solved_again():
    from validation.run.sequential import RefinementLevel, RefinementRecord

    level = RefinementLevel(1024, {2.05: (0, 1, 2, 3)}, {2.05: 1e-4}, {2.05: (2,)},
                            reference="bem_interface", stiffness={2.05: (1, 3)})
    text = RefinementRecord((level,), "grid limit reached").describe("D")
    assert text.startswith("refined on 1024² (interface): 4 load point(s) (stiffness at 2, "
                           "leakage at 1) at D = 2.05 (solver tolerance 1.0e-04)")
    # at every point (or none: no stiffness compared), nothing is said of the stiffness
    for stiffness in ({}, {2.05: (0, 1, 2, 3)}, {2.05: ()}):
        text = RefinementRecord((RefinementLevel(1024, {2.05: (0, 1, 2, 3)}, {2.05: 1e-4},
                                                 stiffness=stiffness),), "done").describe()
        assert "stiffness" not in text and "4 load point(s) (solver tolerance" in text
