"""Bad-input catalogue: every public entry point of :mod:`validation.campaigns.bad_input`'s table, every
scalar and array parameter, against hypothesis-drawn bad values.

A new entry point is covered by adding one row to the table (``validation/campaigns/_bad_input_*.py``);
``test_every_exported_name_has_a_row`` fails when an exported name or a public method has none. The
rules (bem.common.checks): a value that is never valid gets a ``ValueError``/``TypeError`` naming the
parameter; an extreme but finite value gets a finite result or such an error; valid variants
(read-only arrays, nested lists, numpy scalars) are accepted.
"""

from __future__ import annotations

import importlib
import inspect
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from bem.common import checks
from validation.campaigns._bad_input_table import NO_ROW
from validation.campaigns.bad_input import (GOOD, NAMED_DOMAINS, bad_arrays, classify, entry_points,
                                              run_campaign)

ENTRIES = entry_points()
SCALARS = [(entry, name, domain) for entry in ENTRIES for name, domain in entry.scalars.items()]
ARRAYS = [(entry, name, domain) for entry in ENTRIES for name, domain in entry.arrays.items()]

#: Few examples per (entry point, parameter), as the table has ~100 of them: a tenth of the
#: profile's count (4 under HYPOTHESIS_PROFILE=ci, 100 under "thorough").
CATALOGUE = settings(max_examples=max(3, settings.default.max_examples // 10), deadline=None,
                     suppress_health_check=[HealthCheck.too_slow,
                                            HealthCheck.function_scoped_fixture])

never_numbers = st.one_of(
    st.text(max_size=8),
    st.floats(allow_nan=False, allow_infinity=False).map(repr),       # '0.5'-like strings
    st.none(),
    st.booleans(),
    st.complex_numbers(allow_nan=False, allow_infinity=False, max_magnitude=1e6),
    st.sampled_from([math.nan, math.inf, -math.inf, np.nan, np.float64(np.inf)]),
    st.lists(st.floats(allow_nan=False), min_size=1, max_size=3),
    st.lists(st.floats(allow_nan=False), min_size=1, max_size=3).map(np.array),
    st.binary(max_size=4),
)
finite_floats = st.floats(allow_nan=False, allow_infinity=False)


def _identify(case):
    entry, name, _ = case
    return f"{entry.name}:{name}"


def _positive_pair(value) -> bool:
    """Whether ``value`` is two positive finite numbers (a valid size of rows and columns)."""
    try:
        pair = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return pair.shape == (2,) and bool(np.all(np.isfinite(pair) & (pair > 0)))


def _must_reject(entry, name, domain, value):
    if value is None and "optional" in domain:
        return
    # any string is valid text, and a valid path (not written to by the catalogue)
    assume(not (isinstance(value, str) and domain.startswith(("text", "path"))))
    # a physical size may be a pair of positive lengths (rows, columns): [1.0, 1.0] is one
    assume(not (domain == "object size" and _positive_pair(value)))
    outcome, detail = classify(entry, name, value, invalid=True)
    assert outcome == "clear error", (entry.name, name, value, outcome, detail)


@pytest.mark.parametrize("case", SCALARS, ids=_identify)
@CATALOGUE
@given(value=never_numbers)
def test_scalar_that_is_never_a_number_is_a_clear_error(case, value):
    entry, name, domain = case
    _must_reject(entry, name, domain, value)


@pytest.mark.parametrize("case", SCALARS, ids=_identify)
@CATALOGUE
@given(value=finite_floats)
def test_finite_scalar_gives_a_finite_result_or_a_clear_error(case, value):
    entry, name, domain = case
    invalid = ((domain.startswith("positive") and value <= 0)
               or (domain.startswith("non_negative") and value < 0)
               or domain.startswith(("integer", "text", "path") + NAMED_DOMAINS))
    outcome, detail = classify(entry, name, value, invalid=invalid)
    assert outcome in GOOD, (entry.name, name, value, outcome, detail)


@st.composite
def broken_arrays(draw, valid, domain=""):
    """A valid array with one entry made NaN/inf, or recast to complex/strings/bools/objects,
    or replaced by a scalar string or None."""
    valid = np.array(valid, dtype=float)
    kinds = ["complex", "strings", "objects", "text", "none"]
    kinds += [] if "nan" in domain else ["nan"]
    kinds += [] if "mask" in domain else ["bools"]
    kind = draw(st.sampled_from(kinds if "inf" in domain else ["-inf", *kinds]))
    if kind in ("nan", "-inf"):
        broken = valid.copy()
        broken.flat[draw(st.integers(0, valid.size - 1))] = math.nan if kind == "nan" else -math.inf
        return broken
    if kind == "complex":
        return valid + 1j * draw(st.floats(1e-300, 1e300))
    if kind == "strings":
        return valid.astype(str)
    if kind == "bools":
        return valid > np.median(valid)
    if kind == "objects":
        return np.array([draw(st.text(min_size=1, max_size=3))] * valid.size, dtype=object)
    return None if kind == "none" else draw(st.text(max_size=5))


@pytest.mark.parametrize("case", ARRAYS, ids=_identify)
@CATALOGUE
@given(data=st.data())
def test_broken_array_is_a_clear_error(case, data):
    entry, name, domain = case
    value = data.draw(broken_arrays(entry.arguments()[name], domain))
    _must_reject(entry, name, domain, value)


@pytest.mark.parametrize("case", ARRAYS, ids=_identify)
@CATALOGUE
@given(scale=st.floats(1e-300, 1e300), flip=st.booleans())
def test_rescaled_array_gives_a_finite_result_or_a_clear_error(case, scale, flip):
    entry, name, _ = case
    valid = np.array(entry.arguments()[name], dtype=float)
    value = valid * (-scale if flip else scale)
    outcome, detail = classify(entry, name, value, invalid=False)
    assert outcome in GOOD, (entry.name, name, scale, outcome, detail)


@pytest.mark.parametrize("case", ARRAYS, ids=_identify)
def test_read_only_and_listed_arrays_are_accepted(case):
    entry, name, _ = case
    for value, label, invalid in bad_arrays(entry.arguments()[name]):
        if invalid is None and label != "inf entry":
            outcome, detail = classify(entry, name, value, invalid=None)
            assert outcome == "plausible result", (entry.name, name, label, outcome, detail)


def _public_methods(cls) -> list[str]:
    """Public methods of a class (its own or inherited from the project) taking an argument."""
    found = []
    for klass in cls.__mro__:
        if klass.__module__.split(".")[0] not in ("asperity", "bem", "validation"):
            continue
        for attribute, value in vars(klass).items():
            function = getattr(value, "__func__", value)
            if attribute.startswith("_") or not inspect.isfunction(function):
                continue
            parameters = list(inspect.signature(function).parameters)[1:]   # self or cls
            if parameters and attribute not in found:
                found.append(attribute)
    return found


def _required_rows() -> dict[str, set[str]]:
    """Row name -> the names that satisfy it (an object exported twice has two)."""
    import asperity
    import bem
    import validation

    exported = {}
    for package in (asperity, bem, validation):
        for attribute in package.__all__:
            exported.setdefault(id(getattr(package, attribute)), []).append(
                f"{package.__name__}.{attribute}")
    required = {}
    for names in exported.values():
        package, _, attribute = names[0].partition(".")
        value = getattr(importlib.import_module(package), attribute)
        if any(name in NO_ROW for name in names):
            continue
        required[names[0]] = set(names)
        if inspect.isclass(value):
            for method in _public_methods(value):
                required[f"{attribute}.{method}"] = {f"{attribute}.{method}"}
    return required


def test_every_exported_name_has_a_row():
    """Every name in asperity, bem and validation's __all__ (constructors of classes too) and every
    public method with arguments of an exported class has a row, so coverage cannot shrink."""
    have = {entry.name.partition("(")[0].strip() for entry in ENTRIES}
    missing = sorted(name for name, aliases in _required_rows().items() if not aliases & have)
    assert missing == [], f"exported names without a row in the bad-input table: {missing}"


def test_the_coverage_check_can_fail(monkeypatch):
    import asperity

    monkeypatch.setattr(asperity, "__all__", [*asperity.__all__, "unlisted_function"],
                        raising=True)
    monkeypatch.setattr(asperity, "unlisted_function", lambda x: x, raising=False)
    assert "asperity.unlisted_function" in _required_rows()
    with pytest.raises(AssertionError, match="unlisted_function"):
        test_every_exported_name_has_a_row()


def test_rows_name_exported_objects_and_no_row_is_stale():
    """A row named after a package attribute names an exported one; NO_ROW lists exported names."""
    import asperity
    import bem
    import validation

    exported = {f"{p.__name__}.{a}" for p in (asperity, bem, validation) for a in p.__all__}
    packaged = {entry.name.partition("(")[0].strip() for entry in ENTRIES
                if entry.name.split(".")[0] in ("asperity", "bem", "validation")}
    assert sorted(packaged - exported) == []
    assert sorted(set(NO_ROW) - exported) == []


@pytest.mark.slow
def test_the_fixed_campaign_has_no_bad_outcome():
    bad = [row for row in run_campaign() if row[3] not in GOOD]
    assert bad == []


# ---------------------------------------------------------------------------------------------
# the rules of bem.common.checks themselves

@pytest.mark.parametrize("value", ["0.5", True, np.bool_(False), 1 + 0j, None, [1.0], b"1"])
def test_real_number_rejects_non_numbers_with_a_type_error_naming_the_parameter(value):
    with pytest.raises(TypeError, match="spacing"):
        checks.real_number("spacing", value)
    with pytest.raises(ValueError, match="spacing"):   # still caught by old `except ValueError`
        checks.positive("spacing", value)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 10**400])
def test_real_number_rejects_non_finite_values(value):
    with pytest.raises(ValueError, match="load must be a finite real number"):
        checks.real_number("load", value)


def test_real_number_states_the_allowed_range():
    with pytest.raises(ValueError, match=r"D must be a finite real number > 2 and < 3, got 3"):
        checks.real_number("D", 3, minimum=2, exclusive=True, maximum=3, exclusive_maximum=True)
    assert checks.real_number("x", np.float32(0.5)) == 0.5
    assert checks.real_number("x", np.array(2.0)) == 2.0


def test_integer_rejects_floats_and_bools():
    for value in (2.0, True, "2", None):
        with pytest.raises(TypeError, match="threads"):
            checks.integer("threads", value, minimum=1)
    with pytest.raises(ValueError, match="threads must be an integer >= 1, got 0"):
        checks.integer("threads", 0, minimum=1)
    assert checks.integer("threads", np.int64(3), minimum=1) == 3


def test_real_array_accepts_read_only_input_without_copying():
    values = np.arange(6.0).reshape(2, 3)
    values.setflags(write=False)
    assert checks.real_array("heights", values) is values
    assert np.array_equal(checks.height_map("heights", np.ones((3, 3)).tolist()), np.ones((3, 3)))


def test_contact_heights_copy_unless_nothing_can_change_them():
    """A contact problem's heights are a fresh copy, except a read-only float64 array that owns
    its data (a model's frozen heights), which nothing can change: that one is used as it is."""
    frozen = np.arange(16.0).reshape(4, 4).copy()
    frozen.setflags(write=False)
    assert checks.contact_heights("heights", frozen, minimum=4) is frozen
    writable = np.arange(16.0).reshape(4, 4)
    view = frozen[:, :]          # read-only, but a view of another array's data
    integers = np.arange(16).reshape(4, 4)
    integers.setflags(write=False)
    for values in (writable, view, integers):
        copy = checks.contact_heights("heights", values, minimum=4)
        assert copy is not values and copy.dtype == np.float64 and copy.flags.writeable
        assert not np.shares_memory(copy, frozen) and np.array_equal(copy, values)
    with pytest.raises(ValueError, match="max |heights|"):
        huge = np.full((4, 4), -1e300)
        huge.setflags(write=False)
        checks.contact_heights("heights", huge, minimum=4)


@pytest.mark.parametrize("values, error", [
    (np.ones((3, 3), dtype=complex), TypeError), (np.full((3, 3), "1"), TypeError),
    (np.ones((3, 3), dtype=bool), TypeError), ([[1.0, 2.0], [3.0]], ValueError),
    (np.ones(9), ValueError), (np.ones((2, 3)), ValueError), (np.ones((3, 4)), ValueError)])
def test_height_map_rejects_bad_arrays_naming_the_parameter(values, error):
    with pytest.raises(error, match="heights"):
        checks.height_map("heights", values, square=True)


def test_supported_magnitude_states_the_range():
    assert checks.supported_magnitude("load", 0.0) == 0.0
    with pytest.raises(ValueError, match=r"load = 1e\+200 is outside the supported range.*1e\+30"):
        checks.supported_magnitude("load", 1e200)


# ---------------------------------------------------------------------------------------------
# the audited cases, one regression test each (Z16 = wm_surface(16, D=2.3, rms_slope=0.1, seed=1))

def _z16():
    from validation import wm_surface

    return wm_surface(16, D=2.3, rms_slope=0.1, seed=1)


@pytest.mark.parametrize("arguments, match", [
    (dict(G=-1.0, D=2.3), "G must be a finite real number > 0"),
    (dict(G=1e-3, D=2.3, M=0), "M must be an integer >= 1"),
    (dict(G=math.nan, D=2.3), "G must be a finite real number"),
    (dict(G=1e-3, D=math.nan), "D must be a finite real number > 2 and < 3"),
    (dict(G=1e-3, D=2.3, gamma=1.0), "gamma must be a finite real number > 1"),
    (dict(G=1e-3, D=2.3, L="1"), "L must be a finite real number > 0")])
def test_wm_amplitude_checks_its_parameters(arguments, match):
    from validation import wm_amplitude

    with pytest.raises(ValueError, match=match):
        wm_amplitude(**arguments)


@pytest.mark.parametrize("arguments, match", [
    (dict(load=1e200), "load = 1e\\+200 is outside the supported range"),
    (dict(load=1e-3, spacing=1e160), "spacing = 1e\\+160 is outside the supported range"),
    (dict(load=1e-3, spacing=1e-300), "spacing = 1e-300 is outside the supported range"),
    (dict(load=1e-3, e_star=1e-300), "e_star = 1e-300 is outside the supported range")])
def test_solve_contact_states_the_supported_range(arguments, match):
    import bem

    arguments = {"spacing": 1 / 16, **arguments}
    with pytest.raises(ValueError, match=match):
        bem.solve_contact(_z16(), **arguments)


def test_complex_heights_are_rejected_not_truncated():
    import asperity
    import bem
    from validation import surface_statistics

    z = _z16() + 1e-3j
    for call in (lambda: bem.solve_contact(z, 1 / 16, load=1e-3),
                 lambda: bem.contact_curve(z, 1 / 16, loads=[1e-3]),
                 lambda: asperity.find_summits(z, 1 / 16),
                 lambda: surface_statistics(z, 1 / 16)):
        with pytest.raises(TypeError, match="heights must be real numbers.*complex"):
            call()
    with pytest.raises(TypeError, match="pressure must be real numbers.*complex"):
        bem.HalfSpace((16, 16), 1 / 16).displacement(z)


def test_curve_errors_rejects_what_used_to_give_silent_nans():
    from asperity import GreenwoodWilliamson
    from validation import curve_errors

    curve = GreenwoodWilliamson(50.0, 0.05, 0.01).at_load([1e-4, 1e-3])
    with pytest.raises(ValueError, match="sigma must be a finite real number > 0, got 0.0"):
        curve_errors(curve, curve, 0.0, ("separation",))
    with pytest.raises(ValueError, match="sigma must be a finite real number > 0, got -1"):
        curve_errors(curve, curve, -1, ("separation",))
    with pytest.raises(ValueError, match=r"quantities must be among .* unknown \['bogus'\]"):
        curve_errors(curve, curve, 0.01, ("bogus",))
    with pytest.raises(TypeError, match="quantities must be a tuple of names"):
        curve_errors(curve, curve, 0.01, "separation")
    errors = curve_errors(curve, curve, 0.01, ("separation", "area"))
    assert set(errors) == {"separation", "area"} and all(np.all(e == 0) for e in errors.values())


def test_nan_inputs_of_closed_form_models_are_errors():
    from asperity import ImprovedGreenwoodWilliamson, dimensionless_pressure

    with pytest.raises(ValueError, match="mean_pressure must be finite"):
        dimensionless_pressure([math.nan], 50.0, 0.05, 0.01, 1.0)
    with pytest.raises(ValueError, match=r"h must be finite or \+inf, got NaN"):
        ImprovedGreenwoodWilliamson(50.0, 0.05, 0.01).effective_reduced_separation([math.nan])


def test_gw_raises_where_its_load_overflows_like_improved_gw():
    from asperity import GreenwoodWilliamson, ImprovedGreenwoodWilliamson

    for model in (GreenwoodWilliamson(50.0, 0.05, 0.01), ImprovedGreenwoodWilliamson(50.0, 0.05,
                                                                                     0.01)):
        with pytest.raises(ValueError, match="separation"):
            model.at_separation([-1e300])
    assert np.isfinite(GreenwoodWilliamson(50.0, 0.05, 0.01).at_separation([-1e10]).load).all()


def test_periodic_full_contact_warns_of_infinite_stiffness():
    import bem

    z = _z16()
    with pytest.warns(bem.ConvergenceWarning, match="full contact of a periodic surface"):
        solution = bem.solve_contact(z, 1 / 16, load=1e3, periodic=True, stiffness=True)
    assert solution.stiffness == math.inf and solution.area_fraction == 1.0


def test_non_convergence_message_never_reports_an_infinite_pressure_change():
    import bem

    with pytest.warns(bem.ConvergenceWarning) as caught:
        solution = bem.solve_contact(_z16(), 1 / 16, load=1e-3, max_iter=1)
    assert not solution.converged
    assert "inf" not in solution.message and "inf" not in str(caught[0].message)


@pytest.mark.parametrize("lattice, match", [
    (dict(row=[0, 0], column=[0, 0]), "positions x contradict the column indices"),
    (dict(row=[0, 0], column=[0, 0.5]), "column must be integers"),
    (dict(row=[0, -1], column=[0, 1]), "row must be integers >= 0"),
    (dict(row=[0, 0], column=[0, 1], threads=0), "threads must be an integer >= 1"),
    (dict(row=[0, 0], column=[0, 1], threads=1.0), "threads must be an integer")])
def test_point_force_interaction_rejects_inconsistent_lattices(lattice, match):
    from asperity import PointForceInteraction

    with pytest.raises(ValueError, match=match):
        PointForceInteraction([0.0, 1.0], [0.0, 0.0], spacing=1.0, **lattice)


def test_extreme_scales_give_right_results_or_clear_errors():
    from asperity import find_summits
    from validation import wm_surface

    z = _z16()
    plain = find_summits(z, 1 / 16)
    for scale in (1e300, 1e-300):
        scaled = find_summits(z * scale, 1 / 16)
        assert scaled.count == plain.count > 0
        np.testing.assert_allclose(scaled.radius, plain.radius / scale, rtol=1e-12)
    with pytest.raises(ValueError, match="L = 1e-300 is outside the supported range"):
        wm_surface(16, D=2.3, rms_slope=0.1, seed=1, L=1e-300)


def test_numeric_strings_bools_and_fractional_shapes_are_type_errors():
    import bem
    from asperity import GreenwoodWilliamson

    with pytest.raises(TypeError, match="shape must be an integer"):
        bem.HalfSpace((16.5, 16), 0.1)
    with pytest.raises(TypeError, match="spacing must be a finite real number"):
        bem.solve_contact(_z16(), "0.0625", load=1e-3)
    with pytest.raises(TypeError, match="mean must be a finite real number"):
        GreenwoodWilliamson(50.0, 0.05, 0.01, mean=True)
