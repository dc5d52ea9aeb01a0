"""Four odd inputs to the public calls, each refused with a message naming what is wrong (or
answered as documented): curves at different loads, unsorted loads, a curve field of text, a
modulus outside the supported magnitudes."""

from __future__ import annotations

import numpy as np
import pytest

import asperity
import bem
import validation

GW = dict(density=500.0, radius=0.1, sigma=1e-3, area=1.0, e_star=1.0)


def test_curves_that_share_no_load_have_no_error():
    model = asperity.GreenwoodWilliamson(**GW)
    at = model.at_separation(np.array([1e-3, 2e-3, 3e-3]))
    elsewhere = model.at_separation(np.array([1.5e-3, 2.5e-3, 3.5e-3]))
    with pytest.raises(ValueError, match="share no load.*load_rtol"):
        validation.curve_errors(at, elsewhere, 1e-3, ("area",))
    # one shared load: compared there, NaN (unreached) elsewhere, as documented
    partly = model.at_separation(np.array([1e-3, 2.5e-3, 3.5e-3]))
    errors = validation.curve_errors(partly, at, 1e-3, ("area",))["area"]
    assert errors[0] == 0.0 and np.isnan(errors[1:]).all()


def test_a_validity_range_needs_increasing_loads():
    loads, errors = np.array([1e-3, 1e-5, 1e-4]), np.array([0.1, 0.05, 0.3])
    with pytest.raises(ValueError, match="loads must increase.*argsort"):
        validation.validity_range(loads, errors, 0.2, area_fraction=np.array([0.1, 0.001, 0.01]))
    order = np.argsort(loads)
    found = validation.validity_range(loads[order], errors[order], 0.2,
                                      area_fraction=np.array([0.001, 0.01, 0.1]))
    assert (found.load_min, found.load_max) == (1e-5, 1e-5)
    assert found.area_fraction_min == found.area_fraction_max == 0.001


@pytest.mark.parametrize("field", ["load", "area", "separation"])
def test_a_curve_field_of_text_is_refused_naming_it(field):
    values = dict(separation=[1.0], load=[1.0], area=[1.0], mean_pressure=[1.0])
    values[field] = ["a"]
    with pytest.raises(TypeError, match=f"ContactCurve field '{field}' must be real numbers"):
        bem.ContactCurve(**values, nominal_area=1.0, e_star=1.0)
    with pytest.raises(TypeError, match="'load'.*complex"):
        bem.ContactCurve(**(values | {field: [1.0], "load": [1j]}), nominal_area=1.0, e_star=1.0)
    # NaN and infinity stay allowed: unreached points, an infinite stiffness
    curve = bem.ContactCurve(**(values | {field: [1.0]}), stiffness=[np.inf], nominal_area=1.0,
                             e_star=1.0)
    assert np.isinf(curve.stiffness).all()


@pytest.mark.parametrize("e_star", [1e-300, 1e300])
def test_a_modulus_outside_the_supported_magnitudes_is_refused(e_star):
    heights = validation.wm_surface(64, D=2.3, rms_slope=0.1, seed=1)
    summits = asperity.find_summits(heights, 1 / 64)
    with pytest.raises(ValueError, match="e_star = .* outside the supported range"):
        asperity.DiscreteAsperityModel(summits, e_star=e_star)
