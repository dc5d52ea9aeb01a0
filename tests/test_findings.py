"""The paper's findings, checked on synthetic results whose verdict is known."""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from bem.common.curve import ContactCurve
from validation.judge.compare import compare_realizations
from validation.judge.findings import (
    CONTRADICTED,
    NEW,
    REPRODUCED,
    UNDECIDED,
    area_load_unchanged,
    check_findings,
    closest_models,
    improved_follows_discrete,
    interaction_shift,
    RANGED,
    majority,
    scatter_shrinks,
)
from validation.judge.claims import combine_points, decide_over_range, fraction_text

LOAD = np.logspace(-5, -2, 8)
BASE = dict(area=0.3 * LOAD, separation=np.linspace(3.0, 0.5, 8), conductance=20 * LOAD ** 0.9)
REALIZATIONS = 12
NOISE = np.random.default_rng(0).standard_normal((REALIZATIONS, 8))


def curve(area=1.0, separation=0.0, conductance=1.0, index=0, scatter=0.0):
    """A curve off BASE: area and conductance scaled, separation shifted (in sigma = 1)."""
    wobble = 1.0 + scatter * NOISE[index]
    return ContactCurve(separation=BASE["separation"] + separation, load=LOAD,
                        area=BASE["area"] * area * wobble, mean_pressure=LOAD, nominal_area=1.0,
                        e_star=1.0, conductance=BASE["conductance"] * conductance * wobble)


def results(bem_scatter=0.0, **models):
    """Realizations with the given model curves: name -> dict(area=, separation=, conductance=)."""
    out = []
    for index in range(REALIZATIONS):
        reference = curve(index=index, scatter=bem_scatter)
        # an exact reference: its error band is known to be zero (an unknown one decides nothing)
        exact = {f"{q}_error": np.zeros(LOAD.size) for q in ("area", "separation", "conductance")}
        curves = {"bem": dataclasses.replace(reference, extras=reference.extras | exact)}
        for name, change in models.items():
            curves[name] = curve(index=index, **change)
        task = SimpleNamespace(seed=index, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                               sweep_value=2.3,
                               quantities=("area", "separation", "conductance"))
        out.append(SimpleNamespace(task=task, curves=curves, sigma=1.0))
    return out


def test_majority_rule():
    yes, no = np.array([1, 1, 0, 0], bool), np.zeros(4, bool)
    assert majority(yes, no) == REPRODUCED
    assert majority(yes, np.array([0, 0, 0, 1], bool)) == UNDECIDED
    assert majority(no, np.array([1, 1, 0, 0], bool)) == CONTRADICTED
    assert majority(np.array([1, 0, 0, 0], bool), no) == UNDECIDED


def test_area_load_relation_unchanged_or_not():
    same = results(discrete=dict(area=1.03, scatter=0.01), discrete_no_interaction={})
    assert area_load_unchanged(same).verdict == REPRODUCED
    changed = results(discrete=dict(area=1.5, scatter=0.01), discrete_no_interaction={})
    finding = area_load_unchanged(changed)
    assert finding.verdict == CONTRADICTED and "outside at 8" in finding.evidence
    assert area_load_unchanged(results(discrete={})).verdict == UNDECIDED  # pair missing


def test_on_one_surface_the_interaction_findings_read_the_difference_itself():
    """Two models of the same surface differ by a number, not a sample: one realization
    decides (a) and (b) (with a confidence interval over one realization it never did)."""
    same = results(discrete=dict(area=1.03), discrete_no_interaction={})[:1]
    finding = area_load_unchanged(same)
    assert finding.verdict == REPRODUCED and "(on this surface) at 8 of 8" in finding.evidence
    changed = results(discrete=dict(area=1.5), discrete_no_interaction={})[:1]
    assert area_load_unchanged(changed).verdict == CONTRADICTED
    down = results(discrete=dict(separation=-0.4, conductance=0.7), discrete_no_interaction={})
    assert interaction_shift(down[:1], 0.05).verdict == REPRODUCED
    up = results(discrete=dict(separation=0.4, conductance=1.3), discrete_no_interaction={})
    assert interaction_shift(up[:1], 0.05).verdict == CONTRADICTED


def test_interaction_shift_direction_matters():
    down = results(discrete=dict(separation=-0.4, conductance=0.7), discrete_no_interaction={})
    assert interaction_shift(down, 0.05).verdict == REPRODUCED
    none = results(discrete=dict(separation=-0.001, conductance=0.999), discrete_no_interaction={})
    assert interaction_shift(none, 0.05).verdict == CONTRADICTED
    up = results(discrete=dict(separation=0.4, conductance=1.3), discrete_no_interaction={})
    assert interaction_shift(up, 0.05).verdict == CONTRADICTED
    half = results(discrete=dict(separation=-0.4, conductance=1.0), discrete_no_interaction={})
    assert interaction_shift(half, 0.05).verdict == CONTRADICTED  # no conductance shift


def test_scatter_shrinking_with_load():
    from validation.judge import findings

    rng = np.random.default_rng(1)
    base = results()
    for shrinking, expected in ((True, REPRODUCED), (False, CONTRADICTED)):
        spread = np.geomspace(0.5, 0.02, 8) if shrinking else np.geomspace(0.02, 0.5, 8)
        for r in base:
            factor = np.exp(spread * rng.standard_normal(8))
            r.curves["bem"] = ContactCurve(separation=BASE["separation"], load=LOAD,
                                           area=BASE["area"] * factor, mean_pressure=LOAD,
                                           nominal_area=1.0, e_star=1.0,
                                           conductance=BASE["conductance"] * factor)
        finding = findings.scatter_shrinks(base)
        assert finding.verdict == expected, finding.evidence
    # equal scatter at both ends: the F interval of the ratio straddles 1
    assert scatter_shrinks(results(bem_scatter=0.1)).verdict == UNDECIDED
    assert scatter_shrinks(results()[:1]).verdict == UNDECIDED


def test_improved_gw_follows_the_discrete_model_or_not():
    close = results(discrete={}, improved_gw=dict(area=1.02, separation=0.01, conductance=0.98),
                    gw=dict(area=1.02, separation=1.0, conductance=3.0))
    finding = improved_follows_discrete(close, 0.2)
    assert finding.verdict == REPRODUCED and "original GW" in finding.evidence
    far = results(discrete={}, improved_gw=dict(separation=1.0, conductance=3.0))
    assert improved_follows_discrete(far, 0.2).verdict == CONTRADICTED


def test_closest_model_and_where_none_holds():
    data = results(gw=dict(area=1.5, separation=1.0), discrete=dict(area=1.01, separation=0.01))
    comparison = compare_realizations(data, tolerances=(0.05, 0.2))
    finding = closest_models(comparison)
    assert finding.verdict == NEW
    assert "area: discrete (interaction) (8 of 8 points hold" in finding.evidence
    assert "at every load at least one holds" in finding.evidence
    assert "nowhere" not in finding.evidence
    worse = results(gw=dict(area=1.5), discrete=dict(area=1.3))
    text = closest_models(compare_realizations(worse, tolerances=(0.05, 0.2))).evidence
    assert f"area: no model holds within 0.2 anywhere; none holds at Load " \
           f"{LOAD[0]:.2g}–{LOAD[-1]:.2g}" in text


def test_all_findings_on_one_family():
    data = results(gw={}, improved_gw={}, discrete={}, discrete_no_interaction={})
    out = check_findings(data, compare_realizations(data), (0.05, 0.2))
    assert [f.key for f in out] == ["a", "b", "c", "d", "e"]
    assert out[1].verdict == CONTRADICTED  # identical curves: no shift


# ------------------------------------------------------------------------------------------
# a claim decided over the contact-area range of its points

FRACTIONS = np.geomspace(1e-3, 0.3, 8)


def _points(strip: str) -> tuple[np.ndarray, np.ndarray]:
    """Support and contradiction per point from a strip such as "??✔✔✔✘"."""
    return np.array([c == "✔" for c in strip]), np.array([c == "✘" for c in strip])


def test_a_claim_supported_everywhere_it_is_decided_is_reproduced():
    decided = decide_over_range(FRACTIONS, *_points("???✔✔✔✔✔"))
    assert decided.verdict == REPRODUCED and decided.verdict_text == REPRODUCED
    assert decided.tested_from == FRACTIONS[0] and decided.tested_to == FRACTIONS[-1]
    assert decided.reproduced_from == FRACTIONS[3] and decided.reproduced_to == FRACTIONS[-1]
    assert (decided.reproduced, decided.contradicted, decided.undecided) == (5, 0, 3)


def test_a_claim_contradicted_at_heavy_contact_is_reproduced_over_the_light_range():
    # the paper's headline at D 2.95: undecided at light load, held, contradicted at the end
    decided = decide_over_range(FRACTIONS, *_points("??✔✔✔?✘✘"))
    assert decided.verdict == RANGED
    assert (decided.reproduced_from, decided.reproduced_to) == (FRACTIONS[2], FRACTIONS[4])
    assert decided.verdict_text == (f"reproduced from {fraction_text(FRACTIONS[2])} to "
                                    f"{fraction_text(FRACTIONS[4])} contact")
    assert (decided.reproduced, decided.contradicted, decided.undecided) == (3, 2, 3)
    text = decided.describe(FRACTIONS, _points("??✔✔✔?✘✘")[1])
    assert f"contradicted at {fraction_text(FRACTIONS[6])}–{fraction_text(FRACTIONS[7])}" in text


def test_the_range_is_the_run_free_of_contradiction_with_the_most_support():
    # two runs split by a contradiction: the second holds more supporting points
    decided = decide_over_range(FRACTIONS, *_points("✔?✘✔?✔✔?"))
    assert (decided.reproduced_from, decided.reproduced_to) == (FRACTIONS[3], FRACTIONS[6])
    # equal support: the wider run in area fraction wins
    decided = decide_over_range(FRACTIONS, *_points("✔✔✘✔?✔✘?"))
    assert (decided.reproduced_from, decided.reproduced_to) == (FRACTIONS[3], FRACTIONS[5])
    # supported at one point only: one point is no range (undecided; contradicted where some
    # point contradicts it)
    one = decide_over_range(FRACTIONS, *_points("?✔??????"))
    assert one.verdict == UNDECIDED and np.isnan(one.reproduced_from)
    assert decide_over_range(FRACTIONS, *_points("?✔✘✘✘✘✘?")).verdict == CONTRADICTED
    two = decide_over_range(FRACTIONS, *_points("?✔✔?????"))
    assert two.verdict == RANGED and (two.reproduced_from, two.reproduced_to) == (
        FRACTIONS[1], FRACTIONS[2])


def test_a_claim_nowhere_supported_is_contradicted_or_undecided():
    assert decide_over_range(FRACTIONS, *_points("???✘????")).verdict == CONTRADICTED
    nothing = decide_over_range(FRACTIONS, *_points("????????"))
    assert nothing.verdict == UNDECIDED and np.isnan(nothing.reproduced_from)
    with pytest.raises(ValueError, match="one shape"):
        decide_over_range(FRACTIONS[:3], *_points("????????"))


def test_parts_of_a_claim_combine_per_point():
    support, against = combine_points([_points("✔✔?✔")[0], _points("✔?✔✘")[0]],
                                      [_points("✔✔?✔")[1], _points("✔?✔✘")[1]])
    assert support.tolist() == [True, False, False, False]
    assert against.tolist() == [False, False, False, True]
    some, every = combine_points([[1, 0, 0], [0, 0, 0]], [[0, 1, 1], [0, 0, 1]], every=False)
    assert some.tolist() == [True, False, False] and every.tolist() == [False, False, True]


def test_fractions_are_written_without_an_exponent():
    assert [fraction_text(f) for f in (0.00052, 0.024, 0.3, 1.0)] == \
        ["0.052 %", "2.4 %", "30 %", "100 %"]


def test_improved_gw_followed_over_part_of_the_range_says_which():
    """Improved GW within 0.2 of the discrete model at the light half of the path, 50 % off
    at the heavy half: reproduced from the lightest point to the middle, and findings.csv's
    range cells say so in area fractions of the reference."""
    ratio = np.where(np.arange(8) < 4, 1.02, 1.5)
    data = results(discrete={}, improved_gw=dict(area=ratio))
    fraction = data[0].curves["bem"].area_fraction
    finding = improved_follows_discrete(data, 0.2)
    assert finding.verdict == RANGED
    assert finding.verdict_text == (f"reproduced from {fraction_text(fraction[0])} to "
                                    f"{fraction_text(fraction[3])} contact")
    cells = finding.range_cells()
    np.testing.assert_allclose(cells[:4], [fraction[0], fraction[-1], fraction[0], fraction[3]])
    assert cells[4:] == [4, 4, 0]
    assert "reproduced from" in finding.evidence and "contradicted at" in finding.evidence
