"""Regression tests of the bad-input classes found by the extended campaign
(benchmarks/bad_input_campaign.py): options given as strings, None, complex numbers or arrays,
fractional counts, contact maps that are not booleans, extreme GW parameters, mismatched
lengths, wrong-type objects and paths. Every error names the parameter and what is allowed;
no message of numpy or the standard library ("could not convert string to float",
"SeedSequence", "invalid literal for int()") reaches the user."""

from __future__ import annotations

import math

import numpy as np
import pytest

import asperity
import bem
import validation

LIBRARY_MESSAGES = ("could not convert", "SeedSequence", "invalid literal", "truth value",
                    "not subscriptable", "has no attribute")


def _z():
    return validation.wm_surface(8, D=2.3, rms_slope=0.1, seed=1)


def _summits():
    return asperity.find_summits(_z(), 1 / 8)


OPTIONS = {
    "tol (solve_contact)": ("tol", lambda v: bem.solve_contact(_z(), 1 / 8, load=1e-3, tol=v)),
    "tol (discrete model)": ("tol", lambda v: asperity.DiscreteAsperityModel(_summits(), tol=v)),
    "threads (HalfSpace)": ("threads", lambda v: bem.HalfSpace((8, 8), 1 / 8, threads=v)),
    "backend (HalfSpace)": ("backend", lambda v: bem.HalfSpace((8, 8), 1 / 8, backend=v)),
    "fft_backend (point forces)": ("fft_backend", lambda v: asperity.PointForceInteraction(
        [0.0, 1.0], [0.0, 0.0], spacing=1.0, row=[0, 0], column=[0, 1], fft_backend=v)),
    "seed (WM)": ("seed", lambda v: validation.wm_surface(8, D=2.3, rms_slope=0.1, seed=v)),
    "seed (self-affine)": ("seed", lambda v: validation.self_affine_surface(
        8, hurst=0.8, rms_height=1.0, seed=v)),
}
#: None is valid here: fresh entropy for a seed, the default thread count for an FFT.
OPTIONAL = {"seed (WM)", "seed (self-affine)", "threads (HalfSpace)"}


@pytest.mark.parametrize("option", OPTIONS)
@pytest.mark.parametrize("value", ["abc", "1e-6", "0.5", None, 1 + 1j, np.array([1.0, 2.0]),
                                   b"1", [1]], ids=repr)
def test_options_of_the_wrong_type_name_the_parameter(option, value):
    name, call = OPTIONS[option]
    if value is None and option in OPTIONAL:
        call(value)
        return
    with pytest.raises((TypeError, ValueError)) as caught:
        call(value)
    message = str(caught.value)
    assert name in message, message
    assert not any(text in message for text in LIBRARY_MESSAGES), message


def test_fractional_thread_counts_and_numeric_string_tolerances_are_refused():
    for threads in (2.5, 1.0, True):
        with pytest.raises(TypeError, match="threads must be an integer >= 1"):
            bem.HalfSpace((8, 8), 1 / 8, threads=threads)
    assert bem.HalfSpace((8, 8), 1 / 8, threads=np.int64(1)).threads == 1
    with pytest.raises(TypeError, match=r"tol must be a finite real number > 0 and < 1"):
        asperity.DiscreteAsperityModel(_summits(), tol="1e-6")
    with pytest.raises(ValueError, match=r"tol must be a finite real number > 0 and < 1, got 2"):
        asperity.DiscreteAsperityModel(_summits(), tol=2.0)


def test_seeds_are_integers_or_generators():
    first = validation.wm_surface(8, D=2.3, rms_slope=0.1, seed=7)
    again = validation.wm_surface(8, D=2.3, rms_slope=0.1, seed=np.random.default_rng(7))
    np.testing.assert_array_equal(first, again)
    np.testing.assert_array_equal(first, validation.wm_surface(8, D=2.3, rms_slope=0.1,
                                                               seed=np.int32(7)))
    for seed in (-1, 2.0, True):
        with pytest.raises(ValueError, match="seed must be None, an integer >= 0 or a numpy"):
            validation.wm_surface(8, D=2.3, rms_slope=0.1, seed=seed)


@pytest.mark.parametrize("fill, error", [
    (math.nan, ValueError), (math.inf, ValueError), (-math.inf, ValueError), (0.5, ValueError),
    ("a", TypeError), (1 + 1j, TypeError), (object(), TypeError)], ids=repr)
def test_count_contacts_refuses_maps_that_are_not_booleans(fill, error):
    contact = np.array([[fill] * 4] * 4)
    with pytest.raises(error, match="contact must be"):
        bem.count_contacts(contact)


def test_count_contacts_counts_booleans_and_zeros_and_ones_alike():
    contact = np.zeros((6, 6), dtype=bool)
    contact[0, 0] = contact[0, 5] = contact[3, 2:4] = True
    assert bem.count_contacts(contact) == 3
    assert bem.count_contacts(contact.astype(float)) == 3
    assert bem.count_contacts(contact.astype(int).tolist()) == 3
    assert bem.count_contacts(contact, periodic=True) == 2    # (0,0) and (0,5) touch across x
    with pytest.raises(TypeError, match="periodic must be True or False"):
        bem.count_contacts(contact, periodic="yes")


@pytest.mark.parametrize("model", [asperity.GreenwoodWilliamson,
                                   asperity.ImprovedGreenwoodWilliamson])
@pytest.mark.parametrize("sigma", [1e300, 1e-300, 1e31])
def test_gw_with_a_summit_sigma_outside_the_supported_range_is_a_clear_error(model, sigma):
    # W_ref = eta A E* R^(1/2) sigma^(3/2) overflows (1e300) or underflows to 0 (1e-300): the
    # magnitudes of every length and modulus are held to the project's supported range
    with pytest.raises(ValueError, match="sigma = .* is outside the supported range"):
        model(50.0, 0.05, sigma)
    with pytest.raises(ValueError, match=r"mean must be a finite real number >= -1e\+30"):
        model(50.0, 0.05, 0.01, mean=-sigma if sigma > 1 else -1e300)
    assert model(50.0, 0.05, 0.01, mean=1e-300).mean == 1e-300    # an offset may be tiny


def test_gw_is_scale_invariant_across_the_supported_range():
    """Lengths scaled by s, loads by s^2 (E* fixed): separations scale by s, area by s^2."""
    base = asperity.GreenwoodWilliamson(50.0, 0.05, 0.01).at_load([1e-4, 1e-3])
    for s in (1e-12, 1e12):
        scaled = asperity.GreenwoodWilliamson(50.0 / s**2, 0.05 * s, 0.01 * s,
                                              area=s**2).at_load([1e-4 * s**2, 1e-3 * s**2])
        np.testing.assert_allclose(scaled.separation, base.separation * s, rtol=1e-9)
        np.testing.assert_allclose(scaled.area, base.area * s**2, rtol=1e-9)


def test_validity_range_names_mismatched_lengths():
    with pytest.raises(ValueError, match=r"loads and errors .* shapes \(3,\) and \(2,\)"):
        validation.validity_range([1.0, 2.0, 3.0], [0.1, 0.2], 0.5)
    with pytest.raises(ValueError, match=r"area_fraction must have the length of loads"):
        validation.validity_range([1.0, 2.0, 3.0], [0.1, 0.2, 0.1], 0.5, [0.1])
    with pytest.raises(TypeError, match="tolerance must be a finite real number > 0"):
        validation.validity_range([1.0, 2.0], [0.1, 0.2], "0.5")
    found = validation.validity_range([1.0, 2.0, 3.0], [0.1, 0.9, 0.1], 0.5, [0.1, 0.2, 0.3])
    assert (found.first, found.last, found.area_fraction_min) == (0, 0, 0.1)


@pytest.mark.parametrize("value", ["results", None, 3.0, [1, 2], {"a": 1}, [object()]],
                         ids=repr)
def test_comparison_and_runner_refuse_wrong_objects_with_a_type_error(value):
    with pytest.raises(TypeError, match="results must be a sequence of realization results"):
        validation.compare_realizations(value)
    with pytest.raises(TypeError, match="scenes must be a sequence of Scene"):
        validation.run_scenes(value, progress=False)


def test_runner_options_are_checked():
    with pytest.raises(TypeError, match="progress must be True or False"):
        validation.run_scenes([], progress="no")
    with pytest.raises(TypeError, match="executor must be a concurrent.futures.Executor"):
        validation.run_scenes([], executor="pool")
    assert validation.run_scenes((), progress=False) == []


@pytest.mark.parametrize("value", [None, 3, b"scene.toml", ["paper-theory"]], ids=repr)
def test_paths_of_the_wrong_type_name_the_parameter(value):
    with pytest.raises(TypeError, match="name_or_path must be a path"):
        validation.load_scene(value)
    with pytest.raises(TypeError, match="path must be a path"):
        validation.read_topography(value)
    with pytest.raises(TypeError, match="data must be a dict"):
        validation.parse_scene(value)


def test_other_options_found_unchecked_are_checked():
    spectrum = asperity.radial_power_spectrum(_z(), 1 / 8)
    with pytest.raises(TypeError, match="order must be a finite real number"):
        spectrum.moment("2")
    with pytest.raises(ValueError, match="window must be one of"):
        asperity.radial_power_spectrum(_z(), 1 / 8, window=np.array(["hann", "none"]))
    with pytest.raises(ValueError, match="gamma must be a finite real number > 0 and <= 1"):
        asperity.separation_kernel([1.0], gamma=1.5)
    with pytest.raises(ValueError, match=r"x must be >= 0"):
        asperity.separation_kernel([-1.0])
    curve = asperity.GreenwoodWilliamson(50.0, 0.05, 0.01).at_load([1e-3])
    with pytest.raises(TypeError, match="name must be a quantity name"):
        curve.quantity(["area"])
    with pytest.raises(ValueError, match="name must be a computed field or an extra"):
        curve.quantity("pressure")
    with pytest.raises(TypeError, match="m must be a finite real number >= 0"):
        asperity.DiscreteAsperityModel(_summits(), interaction=False, m="1")
    with pytest.raises(ValueError, match="reference_model must be a model of the results"):
        validation.compare_realizations(_results(), reference_model="")
    with pytest.raises(TypeError, match="channel must be an integer"):
        validation.read_topography("examples/example_topography.txt", channel=0.5)


def _results():
    from types import SimpleNamespace

    curve = asperity.GreenwoodWilliamson(50.0, 0.05, 0.01).at_load([1e-4, 1e-3])
    task = SimpleNamespace(seed=0, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                           quantities=("area",), sweep_value=2.3)
    return [SimpleNamespace(task=task, curves={"bem": curve, "gw": curve}, sigma=0.01)]


# ---------------------------------------------------------------------------------------------
# found when the campaign grew to every exported name

def test_a_flat_surface_has_no_statistics_and_says_why():
    with pytest.raises(ValueError, match=r"heights is flat.*rms height, gradient and curvature "
                                         r"are 0 and Nayak's parameter .* is undefined"):
        validation.surface_statistics(np.full((8, 8), 0.3), 1 / 8)
    checkerboard = np.indices((8, 8)).sum(axis=0) % 2 * 1.0     # central differences all 0
    assert validation.surface_statistics(checkerboard, 1 / 8, periodic=True).nayak == math.inf


def test_objects_and_callbacks_of_the_wrong_kind_are_type_errors_naming_them():
    curve = asperity.GreenwoodWilliamson(50.0, 0.05, 0.01).at_load([1e-3])
    for call, match in [
            (lambda: bem.contact_curve(_z(), 1 / 8, loads=[1e-4], callback="print"),
             "callback must be a callable or None"),
            (lambda: asperity.dimensionless(None, 0.01, 1.0), "curve must be a bem.ContactCurve"),
            (lambda: asperity.summits_to_arrays([1.0]), "summits must be an asperity.Summits"),
            (lambda: asperity.Summits.from_arrays(None), "arrays must be a mapping"),
            (lambda: asperity.PointForceInteraction.from_summits("abc"),
             "summits must be an asperity.Summits"),
            (lambda: validation.curve_errors([1.0], curve, 0.01, ("area",)),
             "model must be a bem.ContactCurve"),
            (lambda: validation.run_scenes((), progress=False, stream="stderr"),
             "stream must be a text stream"),
            (lambda: curve.reshaped("1"), "shape must be a tuple of integers")]:
        with pytest.raises(TypeError, match=match):
            call()


def test_result_records_check_their_fields():
    solution = bem.solve_contact(_z(), 1 / 8, load=1e-3, tol=1e-6)
    fields = {name: getattr(solution, name) for name in solution.__dataclass_fields__}
    rebuilt = bem.ContactSolution(**{**fields, "pixel_area": None})
    assert rebuilt.pixel_area == pytest.approx(solution.pixel_area, rel=1e-12)
    with pytest.raises(ValueError, match="gap must be finite"):
        bem.ContactSolution(**{**fields, "gap": np.full(_z().shape, np.nan)})
    with pytest.raises(TypeError, match="load must be a finite real number"):
        bem.ContactSolution(**{**fields, "load": "1"})
    with pytest.raises(TypeError, match="separation must be real numbers"):
        asperity.DimensionlessCurve(separation=["a"], load=[1.0], area=[1.0])
    with pytest.raises(TypeError, match="rms_height must be a finite real number"):
        validation.SurfaceStatistics(None, 0.1, 1.0, 1.0, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="unit must be one of"):
        validation.Topography(_z(), 1 / 8, (1.0, 1.0), "inch", "memory")


def test_options_are_checked_when_given_not_at_the_first_use():
    with pytest.raises(TypeError, match=r"options must be keywords of bem.contact_curve.*'tolerance'"):
        bem.BoundaryElementModel(_z(), 1 / 8, tolerance=1e-6)
    with pytest.raises(TypeError, match="max_iter must be an integer"):
        bem.BoundaryElementModel(_z(), 1 / 8, max_iter="50")
    with pytest.raises(ValueError, match="heights must be finite"):
        bem.BoundaryElementModel(np.full((8, 8), np.nan), 1 / 8)
    with pytest.raises(ValueError, match=r"confidence must be a finite real number >= 0.5"):
        validation.compare_realizations(_results() * 3, confidence=1e-300)
    with pytest.raises(ValueError, match=r"max \|load\| = .* is outside the supported range"):
        asperity.DiscreteAsperityModel(_summits()).at_load([1e301])
    with pytest.raises(ValueError, match=r"max \|separation\| = .* is outside the supported"):
        asperity.DiscreteAsperityModel(_summits()).at_separation([-1e205])


def test_a_validity_range_over_no_loads_is_an_error_not_nan_bounds():
    with pytest.raises(ValueError, match="loads must have at least 1 entries, got 0"):
        validation.validity_range([], [], 0.1)
    nowhere = validation.validity_range([1.0, 2.0], [1.0, 1.0], 0.1)
    assert not nowhere.holds_anywhere and nowhere.describe() == "nowhere"
