"""Errors at equal load and validity ranges, on synthetic curves with known errors."""

import numpy as np
import pytest

from bem.common.curve import ContactCurve
from validation.judge.compare import curve_errors, summarise_errors


def curve(load, area, separation, conductance=None):
    load = np.asarray(load, float)
    return ContactCurve(separation=separation, load=load, area=area, mean_pressure=load,
                        nominal_area=1.0, e_star=1.0, conductance=conductance)


def test_curve_errors_known_values():
    load = np.array([1.0, 2.0, 4.0])
    ref = curve(load, [0.1, 0.2, 0.4], [3.0, 2.0, 1.0], [1.0, 2.0, 3.0])
    model = curve(load, [0.11, 0.2, 0.2], [3.5, 2.0, 0.0], [1.0, 1.0, 6.0])
    errors = curve_errors(model, ref, sigma=0.5, quantities=("area", "separation", "conductance"))
    np.testing.assert_allclose(errors["area"], [0.1, 0.0, -0.5], atol=1e-15)
    np.testing.assert_allclose(errors["separation"], [1.0, 0.0, -2.0])
    np.testing.assert_allclose(errors["conductance"], [0.0, -0.5, 1.0])


def test_a_load_the_model_did_not_reach_is_not_compared():
    # the second point ended at load 3 where 2 was asked (an unconverged solve): NaN, no error
    errors = curve_errors(curve([1, 3], [1.1, 1], [1, 1]), curve([1, 2], [1, 1], [1, 1]), 1.0,
                          ("area",))
    np.testing.assert_allclose(errors["area"], [0.1, np.nan])
    with pytest.raises(ValueError, match="same load points"):
        curve_errors(curve([1, 2], [1, 1], [1, 1]), curve([1, 2, 3], [1, 1, 1], [1, 1, 1]), 1.0,
                     ("area",))


def test_summarise_errors_mean_and_sample_std():
    summary = summarise_errors("area", [np.array([0.1, 0.2]), np.array([0.3, np.nan])])
    np.testing.assert_allclose(summary.mean, [0.2, 0.2])
    np.testing.assert_allclose(summary.std, [np.std([0.1, 0.3], ddof=1), 0.0])
    assert summary.count == 2


def realization(seed, load, model_area, model_separation, converged=(True, True, True),
                reference_extras=None, sigma=1.0):
    """A synthetic realization: a BEM reference curve and a GW curve with known errors."""
    from types import SimpleNamespace

    extras = {"converged": np.array(converged)} | dict(reference_extras or {})
    reference = ContactCurve(separation=[3.0, 2.0, 1.0], load=load, area=[0.01, 0.05, 0.2],
                             mean_pressure=load, nominal_area=1.0, e_star=1.0, extras=extras)
    model = ContactCurve(separation=model_separation, load=load, area=model_area,
                         mean_pressure=load, nominal_area=1.0, e_star=1.0)
    task = SimpleNamespace(seed=seed, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                           quantities=("area", "separation"), sweep_value=2.3)
    return SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=sigma)


LOAD = np.array([1e-4, 1e-3, 1e-2])
AREA = np.array([0.01, 0.05, 0.2])


def test_compare_realizations_on_synthetic_results():
    # Two realizations with known errors: area +10 % and +30 % (mean +20 %, sample std 14.1 %),
    # separation exactly 0.5 sigma high; a non-converged reference point drops out.
    from validation.judge.compare import compare_realizations

    exact = {"area_error": np.zeros(3), "separation_error": np.zeros(3)}  # a band of zero
    results = [realization(0, LOAD, 1.1 * AREA, [3.5, 2.5, 1.5], reference_extras=exact),
               realization(1, LOAD, 1.3 * AREA, [3.5, 2.5, 1.5], converged=(True, True, False),
                           reference_extras=exact)]
    comparison = compare_realizations(results, tolerances=(0.25, 0.6))
    area = comparison.models[("gw", "area")]
    np.testing.assert_allclose(area.summary.mean[:2], 0.2)
    np.testing.assert_allclose(area.summary.std[:2], np.std([0.1, 0.3], ddof=1))
    np.testing.assert_allclose(area.summary.mean[2], 0.1)  # only the converged realization
    assert area.unconverged == 1
    # two realizations 0.2 apart: t(0.975, 1) = 12.7 makes the interval +-1.27 wide
    np.testing.assert_allclose(area.interval.half_width[:2], 12.706 * 0.1, rtol=1e-4)
    assert [area.counts(i) for i in (0, 1)] == [{"holds": 0, "fails": 0, "undecided": 3}] * 2
    assert not area.ranges[1].holds_anywhere
    # identical separation errors in both realizations: a zero-width interval at 0.5 sigma
    separation = comparison.models[("gw", "separation")]
    np.testing.assert_allclose(separation.summary.mean, 0.5)
    # the last point has one converged realization: no interval, so no verdict
    assert list(separation.verdicts[0]) == ["fails", "fails", "undecided"]
    assert list(separation.verdicts[1]) == ["holds", "holds", "undecided"]
    assert (separation.ranges[1].first, separation.ranges[1].last) == (0, 1)
    assert comparison.band_source["separation"].startswith("per-point")
    np.testing.assert_allclose(comparison.area_fraction, AREA)
    np.testing.assert_allclose(comparison.load, LOAD)


def test_a_band_not_estimated_is_nan_and_decides_nothing():
    # the same errors without the reference's own error estimates: the band is unknown, never
    # zero, so not even the separation's clear 0.5 sigma miss of a 0.25 tolerance is a failure
    from validation.judge.compare import NOT_ESTIMATED, compare_realizations

    results = [realization(k, LOAD, 1.1 * AREA, [3.5, 2.5, 1.5]) for k in (0, 1)]
    comparison = compare_realizations(results, tolerances=(0.25, 0.6))
    separation = comparison.models[("gw", "separation")]
    assert np.all(np.isnan(separation.band))
    assert comparison.band_source["separation"] == NOT_ESTIMATED
    assert all(set(v) == {"undecided"} for v in separation.verdicts)
    assert not any(r.holds_anywhere for r in separation.ranges)


def test_reference_band_from_per_point_error_estimates():
    # The BEM curves carry absolute error estimates: area 0.002 of 0.01 (20 %) at the first
    # point, 1 % at the others; separation 0.01 and 0.03 (in units of sigma = 0.5 and 1).
    from validation.judge.compare import compare_realizations

    extras = {"area_error": AREA * [0.2, 0.01, 0.01], "separation_error": np.full(3, 0.01)}
    results = [realization(0, LOAD, AREA, [3.0, 2.0, 1.0], reference_extras=extras, sigma=0.5),
               realization(1, LOAD, AREA, [3.0, 2.0, 1.0], sigma=1.0,
                           reference_extras=extras | {"separation_error": np.full(3, 0.03)})]
    comparison = compare_realizations(results, tolerances=(0.05, 0.2))
    area = comparison.models[("gw", "area")]
    np.testing.assert_allclose(area.band, [0.2, 0.01, 0.01])
    # exact agreement: undecided where the reference resolves only 20 % (> 0.05 / 4)
    assert list(area.verdicts[0]) == ["undecided", "holds", "holds"]
    separation = comparison.models[("gw", "separation")]
    np.testing.assert_allclose(separation.band, (0.01 / 0.5 + 0.03 / 1.0) / 2)
    assert comparison.band_source["area"].startswith("per-point")


def test_a_model_compared_with_another_reference_field():
    # a model whose separation is compared with the reference's mean gap (Persson's theory)
    from validation.judge.compare import compare_realizations

    gap = {"mean_gap": np.array([3.2, 2.2, 1.2])}
    results = [realization(k, LOAD, AREA, [3.2, 2.2, 1.2], reference_extras=gap) for k in (0, 1)]
    fields = {"gw": {"separation": "mean_gap"}}
    comparison = compare_realizations(results, reference_fields=fields)
    separation = comparison.models[("gw", "separation")]
    np.testing.assert_allclose(separation.summary.mean, 0.0, atol=1e-12)
    assert separation.reference_field == "mean_gap"
    identity = compare_realizations(results, reference_fields={})
    np.testing.assert_allclose(identity.models[("gw", "separation")].summary.mean, 0.2)


def test_the_registry_says_which_reference_field_a_model_is_compared_with():
    # by default the fields come from the registry: a model registered with
    # reference_fields={"separation": "mean_gap"} is compared with the BEM's mean gap, the others
    # with its separation; no name of a model is needed outside the registry
    from validation.common import models
    from validation.judge.compare import compare_realizations

    gap = {"mean_gap": np.array([3.2, 2.2, 1.2])}
    results = [realization(k, LOAD, AREA, [3.2, 2.2, 1.2], reference_extras=gap) for k in (0, 1)]
    models.register("test_gap_model", lambda inputs: None, label="gap model", default=False,
                    reference_fields={"separation": "mean_gap"})
    try:
        for r in results:
            r.curves["test_gap_model"] = r.curves["gw"]
        comparison = compare_realizations(results)
    finally:
        models.unregister("test_gap_model")
    gap_model = comparison.models[("test_gap_model", "separation")]
    assert gap_model.reference_field == "mean_gap"
    np.testing.assert_allclose(gap_model.summary.mean, 0.0, atol=1e-12)
    gw = comparison.models[("gw", "separation")]
    assert gw.reference_field == "separation"
    np.testing.assert_allclose(gw.summary.mean, 0.2)
    assert models.entry("persson").reference_fields == {"separation": "mean_gap"}


def test_the_reference_is_the_registered_reference_whatever_its_name():
    # the registry, not a model name, says which curve is the reference
    from validation.common import models
    from validation.judge.compare import compare_realizations

    results = [realization(k, LOAD, 1.1 * AREA, [3.0, 2.0, 1.0]) for k in (0, 1)]
    for r in results:
        r.curves["exact"] = r.curves.pop("bem")
    with pytest.raises(ValueError, match="reference"):
        compare_realizations(results)  # "exact" is not registered as a reference
    models.register("exact", lambda inputs: None, label="exact", default=False, reference=True)
    try:
        comparison = compare_realizations(results)
    finally:
        models.unregister("exact")
    np.testing.assert_allclose(comparison.models[("gw", "area")].summary.mean, 0.1)
    assert ("exact", "area") not in comparison.models


# --------------------------------------------------------------------------------------------
# leakage: the log-ratio error (docs/theory.md, eq. L7) and the sealing rule

def leaky(load, leakage, extras=None):
    load = np.asarray(load, float)
    return ContactCurve(separation=[3.0, 2.0, 1.0, 0.5], load=load, area=[0.01, 0.05, 0.2, 0.4],
                        mean_pressure=load, nominal_area=1.0, e_star=1.0, leakage=leakage,
                        extras=extras or {})


LEAK_LOAD = np.array([1e-4, 1e-3, 1e-2, 2e-2])


def test_leakage_error_is_the_log_ratio_and_sealing_disagreements_are_undefined():
    from validation.judge.compare import sealing_disagreements

    reference = leaky(LEAK_LOAD, [2.0, 1.0, 0.5, 0.0])
    model = leaky(LEAK_LOAD, [4.0, 0.5, 0.0, 0.0])
    (error,) = curve_errors(model, reference, 1.0, ("leakage",)).values()
    # a factor 2 in h_eff either way is +-ln 2 (a factor 8 in Q); both sealed agree exactly;
    # one sealed and one not is undefined, never 0
    np.testing.assert_allclose(error[:2], [np.log(2.0), -np.log(2.0)], rtol=1e-14)
    assert np.isnan(error[2]) and error[3] == 0.0
    disagree, resolved = sealing_disagreements(model, reference)
    np.testing.assert_array_equal(disagree, [False, False, True, False])
    np.testing.assert_array_equal(resolved, disagree)        # no estimate: taken as exact
    # the reference's estimate decides whether it resolves the disagreement: open by less
    # than its error (0.5 +- 0.6) cannot tell sealed from open
    uncertain = leaky(LEAK_LOAD, [2.0, 1.0, 0.5, 0.0],
                      {"leakage_error": np.array([0.1, 0.1, 0.6, 0.0])})
    assert not sealing_disagreements(model, uncertain)[1].any()
    # a sealed reference whose half-grid solution leaks is not sure to be sealed either
    opened = leaky(LEAK_LOAD, [2.0, 1.0, 0.5, 0.1])
    sealed = leaky(LEAK_LOAD, [2.0, 1.0, 0.5, 0.0], {"leakage_error": np.array([0, 0, 0, 0.05])})
    disagree, resolved = sealing_disagreements(opened, sealed)
    np.testing.assert_array_equal(disagree, [False, False, False, True])
    assert not resolved.any()


def leak_realizations(model_factor, model_sealed=(), errors=(0.0, 0.0, 0.0, 0.0), count=6):
    """Realizations where the model's h_eff is ``model_factor`` times the BEM's (a seeded
    scatter of 1 % around it), sealed at the point indices ``model_sealed``; the BEM's error
    estimate ``errors`` (default exact; None: not estimated, so its band is unknown)."""
    from types import SimpleNamespace

    rng = np.random.default_rng(4)
    base = np.array([2.0, 1.0, 0.5, 0.2])
    out = []
    for seed in range(count):
        extras = {} if errors is None else {"leakage_error": np.asarray(errors, float)}
        reference = leaky(LEAK_LOAD, base, extras)
        values = base * model_factor * np.exp(0.01 * rng.standard_normal(4))
        values[list(model_sealed)] = 0.0
        task = SimpleNamespace(seed=seed, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                               quantities=("area", "leakage"), sweep_value=2.3)
        out.append(SimpleNamespace(task=task, curves={"bem": reference,
                                                      "gw": leaky(LEAK_LOAD, values)}, sigma=1.0))
    return out


def test_leakage_verdicts_follow_the_log_error_and_the_sealing_rule():
    from validation.judge.compare import compare_realizations
    from validation.judge.verdicts import FAILS, HOLDS, REFERENCE_BAND, UNDECIDED

    close = compare_realizations(leak_realizations(1.02), tolerances=(0.05, 0.2))
    entry = close.models[("gw", "leakage")]
    np.testing.assert_allclose(entry.summary.mean, np.log(1.02), atol=0.02)
    assert list(entry.verdicts[0]) == [HOLDS] * 4
    np.testing.assert_array_equal(entry.sealing, 0)
    # h_eff 30 % high (Q 2.2 times): within 0.05 fails, within 0.2 fails too (ln 1.3 = 0.26)
    far = compare_realizations(leak_realizations(1.3), tolerances=(0.05, 0.3))
    assert list(far.models[("gw", "leakage")].verdicts[0]) == [FAILS] * 4
    assert list(far.models[("gw", "leakage")].verdicts[1]) == [HOLDS] * 4
    # sealed where the BEM leaks: the point fails at every tolerance, and its error is not 0
    sealed = compare_realizations(leak_realizations(1.0, model_sealed=[3]), tolerances=(0.05, 1.0))
    entry = sealed.models[("gw", "leakage")]
    assert [v[3] for v in entry.verdicts] == [FAILS, FAILS]
    assert np.isnan(entry.summary.mean[3]) and entry.sealing[3] == 6 == entry.sealing_resolved[3]
    assert list(entry.verdicts[1][:3]) == [HOLDS] * 3
    # ... unless the BEM's own error could make it sealed: undecided
    unsure = compare_realizations(leak_realizations(1.0, model_sealed=[3],
                                                    errors=[0.0, 0.0, 0.0, 0.3]),
                                  tolerances=(0.05, 1.0))
    entry = unsure.models[("gw", "leakage")]
    assert [v[3] for v in entry.verdicts] == [UNDECIDED, UNDECIDED]
    assert entry.sealing[3] == 6 and entry.sealing_resolved[3] == 0
    # the reasons agree: the BEM's estimate (a finer reference) decides; nothing holds per
    # surface where some surface's error is infinite
    assert [entry.reasons(i)[3] for i in range(2)] == [REFERENCE_BAND] * 2
    assert all(v[3] != HOLDS for v in entry.surface_verdicts)
    assert all(entry.reasons(i)[3] == "" for i in range(2) for entry in
               [sealed.models[("gw", "leakage")]])
    # a BEM without an error estimate: its band is unknown, nothing is decided to hold
    unknown = compare_realizations(leak_realizations(1.02, errors=None), tolerances=(0.05, 0.2))
    assert HOLDS not in list(unknown.models[("gw", "leakage")].verdicts[0])


def test_leakage_band_is_the_relative_estimate_and_a_sealed_reference_is_exact_only_if_sure():
    from validation.judge.bands import _log_band

    band = _log_band(np.array([[0.02, 0.0, 0.0], [0.04, 0.0, 0.1]]),
                     np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    np.testing.assert_allclose(band[:2], [0.03, 0.0])
    assert band[2] == np.inf
