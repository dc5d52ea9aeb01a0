"""The contact-model contract (bem.model), checked for every registered model.

A model registered in :mod:`validation.common.models` is picked up here automatically. The BEM runs on
a 32 x 32 grid; the asperity models use the summits of the same surface.
"""

import pickle
import warnings

import numpy as np
import pytest

import bem
from bem.common.curve import CURVE_QUANTITIES
from bem.model import ALWAYS_FILLED
from validation.common import models
from validation.surfaces.wm import wm_surface

N = 32
E_STAR = 2.0
OPTIONAL = ("contacts", "stiffness", "conductance", "leakage")
#: Registered models that do not predict ``leakage``: it stays None even when asked for (none:
#: the BEM's is the Reynolds flow through its gap, bem.leakage.flow).
WITHOUT_LEAKAGE: set[str] = set()


def predicts(item, name: str) -> bool:
    """Whether the registered model fills the optional quantity ``name`` when asked for."""
    if name == "contacts":
        return item.contacts != "none"
    if name == "leakage":
        return item.name not in WITHOUT_LEAKAGE
    return True


@pytest.fixture(scope="module")
def surface():
    heights = wm_surface(N, D=2.3, rms_slope=0.1, seed=3)
    inputs = models.ModelInputs(spacing=1.0 / N, nominal_area=1.0, heights=heights,
                                e_star=E_STAR, m=1.0, bem_options=dict(tol=1e-11))
    summits = inputs.summits()
    assert summits.count >= 10
    return inputs, float(np.mean(summits.height)), float(np.std(summits.height))


@pytest.fixture(scope="module", params=models.names())
def case(request, surface):
    inputs, mean, sigma = surface
    if request.param == "bem_nominal":    # the reference of a nominal square needs its side
        inputs = models.ModelInputs(spacing=inputs.spacing, nominal_area=1.0,
                                    heights=inputs.heights(), e_star=E_STAR, m=1.0,
                                    bem_options=inputs.bem_options, nominal_size=4.0)
    model = models.build(request.param, inputs)
    # Separations from light contact (2 sigma above the mean summit) to heavy (at the mean).
    separations = mean + sigma * np.linspace(2.0, 0.0, 6)
    return models.entry(request.param), model, separations, sigma


def quiet(function, *args, **kwargs):
    """Call without the validity warnings some models issue at heavy load."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return function(*args, **kwargs)


def test_satisfies_the_protocol(case):
    item, model, _, _ = case
    assert isinstance(model, bem.ContactModel)
    assert isinstance(model.name, str) and model.name
    assert item.label and item.name in models.names()


@pytest.mark.parametrize("shape", [(), (3,), (2, 2), (0,)])
@pytest.mark.parametrize("control", ["load", "separation"])
def test_shapes_and_dtypes_follow_numpy(case, shape, control):
    item, model, separations, _ = case
    if control == "load":
        values = np.resize(quiet(model.at_separation, separations[1:5]).load, shape)
        curve = quiet(model.at_load, values.reshape(shape) if shape else float(values))
    else:
        values = np.resize(separations[1:5], shape)
        curve = quiet(model.at_separation, values.reshape(shape) if shape else float(values))
    for name in CURVE_QUANTITIES:
        value = getattr(curve, name)
        if not predicts(item, name):
            # e.g. a theory that predicts no count (an empty curve may carry an empty array)
            assert value is None or value.shape == shape == (0,)
            continue
        assert value.shape == shape and value.dtype == np.float64, name
    converged = curve.extras["converged"]
    assert converged.shape == shape and converged.dtype == bool


def test_the_catalogue_asks_every_model_for_leakage():
    # the spectral theories and the BEM included: each one's leakage is compared in reports
    assert {"bem", "gw_spectral", "improved_gw_spectral", "bgt"} <= set(models.names())
    assert not WITHOUT_LEAKAGE & set(models.names())


def test_quantities_not_asked_for_are_not_computed(case):
    item, model, separations, _ = case
    for quantities in ((), ("area",), ("contacts",), ("stiffness",), ("leakage",)):
        curve = quiet(model.at_separation, separations[2:4], quantities=quantities)
        for name in OPTIONAL:
            computed = name in quantities and predicts(item, name)
            assert (getattr(curve, name) is None) == (not computed), (quantities, name)
        for name in ALWAYS_FILLED:
            assert getattr(curve, name).shape == (2,)


def test_load_area_and_contacts_grow_as_separation_falls(case):
    item, model, separations, _ = case
    curve = quiet(model.at_separation, separations)
    assert curve.extras["converged"].all()
    assert np.all(np.diff(curve.load) > 0) and np.all(np.diff(curve.area) >= 0)
    if item.contacts == "asperities":       # patches may merge; asperities only join
        assert np.all(np.diff(curve.contacts) >= 0)
    assert curve.load[-1] > 0 and curve.area[-1] > 0


def test_leakage_is_positive_and_falls_as_the_separation_falls(case):
    item, model, separations, sigma = case
    if not predicts(item, "leakage"):
        pytest.skip(f"{item.name} does not predict leakage")
    curve = quiet(model.at_separation, separations, quantities=("leakage",))
    leakage = curve.leakage
    assert leakage.shape == separations.shape and np.all(leakage >= 0)
    assert leakage[0] > 0                           # light contact leaks
    assert np.all(np.diff(leakage) <= 0)            # never more as the surfaces close
    open_gap = leakage > 0
    assert np.all(np.diff(leakage[open_gap]) < 0)
    zero = quiet(model.at_load, 0.0, quantities=("leakage",))     # first contact (or none)
    loaded = quiet(model.at_separation, separations, quantities=()).load > 0
    assert zero.leakage.shape == () and zero.leakage > leakage[loaded].max()


def test_load_inverts_separation(case):
    item, model, separations, sigma = case
    if not item.inverse_consistent:
        pytest.skip(f"{item.name}: at_load is exact, at_separation an approximation")
    forward = quiet(model.at_separation, separations)
    loaded = forward.load > 0
    back = quiet(model.at_load, forward.load[loaded])
    assert back.extras["converged"].all()
    np.testing.assert_allclose(back.separation, separations[loaded], rtol=0, atol=1e-6 * sigma)
    np.testing.assert_allclose(back.load, forward.load[loaded], rtol=1e-8)


def test_stiffness_is_minus_the_load_slope(case):
    _, model, separations, sigma = case
    d = separations[2:5]
    h = 1e-5 * sigma
    curve = quiet(model.at_separation, d)
    up = quiet(model.at_separation, d + h, quantities=())
    down = quiet(model.at_separation, d - h, quantities=())
    slope = (down.load - up.load) / (2 * h)
    np.testing.assert_allclose(curve.stiffness, slope, rtol=2e-3)


def test_conductance_is_twice_stiffness_over_e_star(case):
    _, model, separations, _ = case
    curve = quiet(model.at_separation, separations)
    assert curve.e_star == E_STAR
    np.testing.assert_allclose(curve.conductance, 2 * curve.stiffness / E_STAR, rtol=1e-14)


def test_zero_load_is_first_contact(case):
    _, model, separations, sigma = case
    zero = quiet(model.at_load, 0.0)
    assert zero.load == 0 and zero.area == 0 and zero.extras["converged"]
    curve = quiet(model.at_separation, separations)
    loaded = curve.load > 0
    assert zero.separation > separations[loaded].max()   # above every loaded separation
    if np.isfinite(zero.separation):                     # the first contact itself
        touching = quiet(model.at_separation, [zero.separation, zero.separation - 1e-9 * sigma])
        assert touching.load[0] == 0 and touching.load[1] > 0


def test_order_of_the_points_does_not_matter(case):
    _, model, separations, _ = case
    order = np.array([3, 0, 5, 1, 4, 2])
    shuffled = quiet(model.at_separation, separations[order])
    ordered = quiet(model.at_separation, separations)
    np.testing.assert_allclose(shuffled.load, ordered.load[order], rtol=1e-7)


@pytest.mark.parametrize("method, value, name", [
    ("at_load", np.nan, "load"), ("at_load", -1.0, "load"), ("at_load", np.inf, "load"),
    ("at_separation", np.nan, "separation"), ("at_separation", -np.inf, "separation"),
    ("at_load", "heavy", "load"),
])
def test_bad_points_name_the_parameter(case, method, value, name):
    _, model, _, _ = case
    with pytest.raises(ValueError, match=name):
        getattr(model, method)([0.01, value])


def test_unknown_quantity_names_the_parameter(case):
    _, model, separations, _ = case
    with pytest.raises(ValueError, match="quantities"):
        model.at_separation(separations[:1], quantities=("pressure_field",))


def test_models_pickle_for_process_pools(case):
    _, model, separations, _ = case
    clone = pickle.loads(pickle.dumps(model))
    np.testing.assert_array_equal(quiet(clone.at_separation, separations[2]).load,
                                  quiet(model.at_separation, separations[2]).load)


def test_registry_names_every_model_once_and_rejects_unknown_names():
    assert len(set(models.names())) == len(models.names())
    assert set(models.default_names()) <= set(models.names())
    assert models.reference_names() == ("bem", "bem_interface", "bem_nominal")
    assert {models.frame_of(name) for name in models.reference_names()} == set(models.FRAMES)
    with pytest.raises(ValueError, match="unknown model"):
        models.entry("persson_typo")
    with pytest.raises(ValueError, match="already registered"):
        models.register("gw", lambda inputs: None, label="again")


def test_a_registered_model_is_one_call_and_must_satisfy_the_contract(surface):
    inputs = surface[0]
    models.register("test_bare_gw", lambda inputs: models.build("gw", inputs),
                    label="GW (test copy)")
    models.register("test_not_a_model", lambda inputs: object(), label="broken", default=False)
    try:
        assert "test_bare_gw" in models.names() and models.labels()["test_bare_gw"]
        curve = models.build("test_bare_gw", inputs).at_load(1e-3)
        assert curve.load.shape == ()
        with pytest.raises(TypeError, match="ContactModel"):
            models.build("test_not_a_model", inputs)
    finally:
        models.unregister("test_bare_gw")
        models.unregister("test_not_a_model")
    assert "test_bare_gw" not in models.names()


def test_the_old_fixed_model_list_warns():
    from validation.run import runner

    with pytest.warns(DeprecationWarning, match="registry|needs_summits"):
        names = runner.ASPERITY_MODELS
    assert "gw" in names and "bem" not in names


def test_the_shared_path_stepper_visits_light_to_heavy_and_answers_in_order():
    from bem.common.continuation import follow_path

    visited = []

    def step(previous, target):
        visited.append(target)
        return (previous[0] + 1, target)

    loads = np.array([3.0, 1.0, 2.0])
    states = follow_path(loads, (0, None), step, control="load")
    assert visited == [1.0, 2.0, 3.0] and [s[1] for s in states] == [3.0, 1.0, 2.0]
    assert [s[0] for s in states] == [3, 1, 2]            # each warm-started from the last
    visited.clear()
    follow_path(loads, (0, None), step, control="separation")
    assert visited == [3.0, 2.0, 1.0]
    with pytest.raises(ValueError, match="control"):
        follow_path(loads, (0, None), step, control="area")
