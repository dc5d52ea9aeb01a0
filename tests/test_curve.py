"""The shared contact-curve record."""

import pickle

import numpy as np
import pytest

from bem.common.curve import ContactCurve


def make(**extra):
    base = dict(separation=[2.0, 1.0], load=[1.0, 3.0], area=[0.1, 0.4], mean_pressure=[1.0, 3.0],
                nominal_area=4.0, e_star=2.0)
    base.update(extra)
    return ContactCurve(**base)


def test_fields_are_read_only_copies():
    load = np.array([1.0, 3.0])
    curve = make(load=load)
    load[0] = 99.0
    assert curve.load[0] == 1.0
    with pytest.raises(ValueError):
        curve.load[0] = 5.0
    assert curve.stiffness is None
    np.testing.assert_allclose(curve.area_fraction, [0.025, 0.1])


def test_extras_are_a_mapping_and_survive_pickle():
    curve = make(extras={"effective_separation": np.array([2.5, 1.5])})
    np.testing.assert_array_equal(curve.extras["effective_separation"], [2.5, 1.5])
    with pytest.warns(DeprecationWarning, match="extras"):
        np.testing.assert_array_equal(curve.effective_separation, [2.5, 1.5])
    clone = pickle.loads(pickle.dumps(curve))
    np.testing.assert_array_equal(clone.extras["effective_separation"], [2.5, 1.5])
    np.testing.assert_array_equal(clone.load, curve.load)
    with pytest.raises(AttributeError):
        _ = curve.not_a_field


def test_quantity_not_computed_is_an_error():
    with pytest.raises(ValueError, match="stiffness"):
        make().quantity("stiffness")


@pytest.mark.parametrize("kwargs, match", [
    (dict(area=[0.1, 0.2, 0.3]), "area"),
    (dict(nominal_area=0.0), "nominal_area"),
    (dict(e_star=float("nan")), "e_star"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        make(**kwargs)


def test_reshaped_moves_fields_and_per_point_extras():
    curve = make(extras={"converged": [True, False], "forces": np.ones((2, 3)), "tol": 1e-3})
    column = curve.reshaped((2, 1))
    assert column.load.shape == (2, 1) and column.extras["forces"].shape == (2, 1, 3)
    assert column.extras["converged"].shape == (2, 1) and column.extras["tol"] == 1e-3
    with pytest.raises(ValueError, match="shape"):
        curve.reshaped((3,))
