"""The discrete asperity model with first-order interaction (docs/theory.md, "The discrete asperity
model"): Hertz limits, independent dense solves, incremental stiffness, exact interaction sums,
random summit sets, warnings and bad input."""

import math
import warnings

import numpy as np
import pytest
import scipy.optimize
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity import DiscreteAsperityModel, PointForceInteraction, Summits, ValidityWarning
from asperity import find_summits
from bem.common.warnings import ConvergenceWarning


def hertz_force(e_star, radius, approach):
    """P = 4 E* a^3 / (3 R) with a = sqrt(R delta)."""
    a = np.sqrt(radius * np.maximum(approach, 0.0))
    return 4.0 * e_star * a**3 / (3.0 * radius)


def random_summits(seed, n, *, spacing=None, sigma=1e-3, radius_scale=0.05, area=1.0):
    rng = np.random.default_rng(seed)
    if spacing is None:
        x, y = rng.random(n), rng.random(n)
    else:
        cells = int(round(1 / spacing))
        index = rng.choice(cells * cells, n, replace=False)
        row, column = np.divmod(index, cells)
        x, y = column * spacing, row * spacing
    return Summits.from_points(x, y, rng.normal(0.0, sigma, n),
                               radius_scale * 10 ** rng.uniform(-0.5, 0.5, n), area=area,
                               spacing=spacing)


def pair_matrix(summits, e_star):
    """Dense 1/(pi E* r_ij), zero diagonal (the independent oracle's kernel)."""
    r = np.hypot(summits.x[:, None] - summits.x[None, :], summits.y[:, None] - summits.y[None, :])
    with np.errstate(divide="ignore"):
        matrix = 1.0 / (np.pi * e_star * r)
    np.fill_diagonal(matrix, 0.0)
    return matrix


# ------------------------------------------------------------------------------ Hertz limits

def test_one_summit_is_exactly_hertz():
    e_star, radius, height = 2.5, 0.4, 3e-3
    summits = Summits.from_points([0.3], [0.7], [height], [radius], area=1.0)
    model = DiscreteAsperityModel(summits, e_star=e_star)
    separation = height - np.array([1e-6, 1e-4, 1e-3, 5e-3])
    curve = model.at_separation(separation, quantities=(
        "contacts", "stiffness", "conductance", "holm_greenwood"))
    a = np.sqrt(radius * (height - separation))
    np.testing.assert_allclose(curve.extras["contact_radii"][:, 0], a, rtol=1e-14)
    np.testing.assert_allclose(curve.load, 4 * e_star * a**3 / (3 * radius), rtol=1e-13)
    np.testing.assert_allclose(curve.area, np.pi * a**2, rtol=1e-14)
    np.testing.assert_allclose(curve.stiffness, 2 * e_star * a, rtol=1e-13)
    np.testing.assert_allclose(curve.conductance, 4 * a, rtol=1e-13)
    # Holm's single spot R/rho = 1/(2a): in conductance units 2/(R/rho) = 4a, Barber's value.
    np.testing.assert_allclose(curve.extras["holm_greenwood_conductance"], 4 * a, rtol=1e-13)
    np.testing.assert_array_equal(curve.contacts, 1)
    assert curve.extras["converged"].all() and curve.mean_pressure == pytest.approx(curve.load)
    # docs/theory.md, eq. T27: R = E* = P = 1 gives a = 0.908560, delta = 0.825482.
    unit = DiscreteAsperityModel(Summits.from_points([0.0], [0.0], [1.0], [1.0], area=1.0))
    by_load = unit.at_load(1.0)
    assert by_load.load.shape == () and by_load.extras["contact_radii"].shape == (1,)
    assert by_load.extras["contact_radii"][0] == pytest.approx(0.908560, abs=5e-7)
    assert 1.0 - by_load.separation == pytest.approx(0.825482, abs=5e-7)
    assert by_load.stiffness == pytest.approx(2 * 0.908560, abs=1e-6)


def test_no_contact_above_the_highest_summit():
    summits = random_summits(1, 30)
    curve = DiscreteAsperityModel(summits).at_separation(summits.height.max() + [0.0, 1e-3])
    np.testing.assert_array_equal(curve.load, 0.0)
    np.testing.assert_array_equal(curve.stiffness, 0.0)
    np.testing.assert_array_equal(curve.contacts, 0)
    zero = DiscreteAsperityModel(summits).at_load(0.0)
    assert zero.separation == summits.height.max() and zero.load == 0.0


def test_without_interaction_equals_the_direct_hertz_sum():
    e_star = 1.7
    summits = random_summits(2, 300)
    model = DiscreteAsperityModel(summits, e_star=e_star, interaction=False)
    separation = np.linspace(3e-3, -3e-3, 13)
    curve = model.at_separation(separation)
    approach = np.maximum(summits.height[None, :] - separation[:, None], 0.0)
    a = np.sqrt(summits.radius * approach)
    np.testing.assert_allclose(curve.load, hertz_force(e_star, summits.radius, approach).sum(1),
                               rtol=1e-13, atol=0)
    np.testing.assert_allclose(curve.area, np.pi * (a**2).sum(1), rtol=1e-13)
    np.testing.assert_allclose(curve.stiffness, 2 * e_star * a.sum(1), rtol=1e-13)
    np.testing.assert_array_equal(curve.contacts, (approach > 0).sum(1))
    by_load = model.at_load(curve.load[curve.load > 0])
    np.testing.assert_allclose(by_load.separation, separation[curve.load > 0], rtol=0,
                               atol=1e-12)


def test_uniform_interaction_m_lowers_every_summit_by_m_w_over_e_sqrt_a():
    e_star, m = 1.3, 0.95
    summits = random_summits(3, 200, area=0.25)
    model = DiscreteAsperityModel(summits, e_star=e_star, interaction=False, m=m)
    separation = np.array([1e-3, 0.0, -2e-3])
    curve = model.at_separation(separation)
    lowering = m * curve.load / (e_star * math.sqrt(0.25))
    approach = np.maximum(summits.height[None, :] - separation[:, None] - lowering[:, None], 0)
    # The residual of every approach is <= tol = 1e-10 of the largest interference; the load
    # error it causes moves the uniform lowering by less than that again.
    scale = (summits.height.max() - separation)[:, None]
    assert np.all(np.abs(curve.extras["contact_radii"]**2 / summits.radius - approach) <= 1e-9 * scale)
    plain = DiscreteAsperityModel(summits, e_star=e_star, interaction=False)
    assert np.all(curve.load < plain.at_separation(separation).load)


# ------------------------------------------------------------------------------ interaction

def test_interaction_lowers_the_load():
    summits = random_summits(4, 200, radius_scale=0.01)
    separation = np.linspace(2e-3, -2e-3, 9)
    with_ = DiscreteAsperityModel(summits).at_separation(separation)
    without = DiscreteAsperityModel(summits, interaction=False).at_separation(separation)
    several = with_.contacts >= 2
    assert several.sum() >= 5
    assert np.all(with_.load[several] < without.load[several])
    assert np.all(with_.area <= without.area) and np.all(with_.contacts <= without.contacts)


@pytest.mark.parametrize("distance", [0.05, 0.2, 1.0])
def test_two_equal_asperities_satisfy_both_compatibility_equations(distance):
    e_star, radius, height, separation = 1.0, 0.3, 2e-3, 0.0
    summits = Summits.from_points([0.0, distance], [0.0, 0.0], [height] * 2, [radius] * 2,
                                  area=1.0)
    curve = DiscreteAsperityModel(summits, e_star=e_star).at_separation([separation])
    a = curve.extras["contact_radii"][0]
    forces = curve.extras["forces"][0]
    for i, j in ((0, 1), (1, 0)):
        mismatch = height - separation - a[i] ** 2 / radius - forces[j] / (np.pi * e_star *
                                                                            distance)
        assert abs(mismatch) <= 1e-10 * (height - separation)   # the solver tolerance
    # Independent scalar root of delta + k delta^1.5 / (pi E* s) = z - d by bisection.
    k = 4 / 3 * e_star * math.sqrt(radius)
    delta = scipy.optimize.brentq(
        lambda v: v + k * v**1.5 / (np.pi * e_star * distance) - (height - separation),
        0.0, height - separation, xtol=1e-18, rtol=1e-15)
    np.testing.assert_allclose(forces, k * delta**1.5, rtol=1e-9)


def dense_active_set_solution(summits, e_star, separation):
    """Independent oracle: guess the contact set, solve the smooth compatibility system on it
    with scipy.optimize.root (dense Jacobian), update the set, repeat until it is stable."""
    G = pair_matrix(summits, e_star)
    k = 4 / 3 * e_star * np.sqrt(summits.radius)
    target = summits.height - separation
    active = target > 0
    for _ in range(30):
        idx = np.flatnonzero(active)
        block = G[np.ix_(idx, idx)]

        def equations(delta):
            forces = k[idx] * np.sign(delta) * np.abs(delta) ** 1.5
            return delta + block @ forces - target[idx]

        def jacobian(delta):
            return np.eye(idx.size) + block * (1.5 * k[idx] * np.sqrt(np.abs(delta)))[None, :]

        result = scipy.optimize.root(equations, 0.5 * np.maximum(target[idx], 0), jac=jacobian,
                                     method="hybr", tol=1e-14)
        # MINPACK may stop with "no further improvement": judge by the residual itself.
        assert np.abs(equations(result.x)).max() <= 1e-13 * target.max()
        delta = np.zeros(summits.count)
        delta[idx] = np.maximum(result.x, 0.0)
        forces = k * delta**1.5
        gap = target - G @ forces
        updated = np.zeros_like(active)
        updated[idx] = result.x > 0
        updated |= ~active & (gap > 0)
        if np.array_equal(updated, active):
            return forces
        active = updated
    raise AssertionError("the oracle's contact set did not settle")


@pytest.mark.parametrize("seed, separation", [(5, 1e-3), (6, 0.0), (7, -1.5e-3)])
def test_independent_dense_root_solve_agrees_to_1e_8(seed, separation):
    e_star = 1.0
    summits = random_summits(seed, 50, radius_scale=0.02)
    expected = dense_active_set_solution(summits, e_star, separation)
    curve = DiscreteAsperityModel(summits, e_star=e_star).at_separation([separation])
    assert curve.extras["converged"][0] and (expected > 0).sum() >= 5
    assert curve.load[0] == pytest.approx(expected.sum(), rel=1e-8)
    np.testing.assert_allclose(curve.extras["forces"][0], expected, rtol=0, atol=1e-8 * expected.max())
    np.testing.assert_array_equal(curve.extras["forces"][0] > 0, expected > 0)


@pytest.mark.parametrize("interaction", [True, False])
def test_stiffness_is_the_incremental_stiffness(interaction):
    summits = random_summits(8, 400, spacing=1 / 64)
    model = DiscreteAsperityModel(summits, interaction=interaction, tol=1e-13)
    separation = np.array([1.5e-3, 0.0, -1e-3])
    curve = model.at_separation(separation)
    # Central difference with step h: truncation O(h^2 S''/S) ~ 1e-8 here, plus residual noise
    # tol * interference / h ~ 1e-10; skip points where the contact set changes within +-h.
    h = 2e-7
    up = model.at_separation(separation + h, quantities=())
    down = model.at_separation(separation - h, quantities=())
    same_set = np.all((up.extras["forces"] > 0) == (down.extras["forces"] > 0), axis=1)
    assert same_set.sum() >= 2
    finite_difference = -(up.load - down.load) / (2 * h)
    np.testing.assert_allclose(curve.stiffness[same_set], finite_difference[same_set], rtol=1e-6)
    np.testing.assert_allclose(curve.conductance, 2 * curve.stiffness / model.e_star, rtol=1e-15)
    # Under load control the same points return the same separations and stiffness.
    by_load = model.at_load(curve.load)
    np.testing.assert_allclose(by_load.separation, separation, rtol=0, atol=1e-12)
    np.testing.assert_allclose(by_load.stiffness, curve.stiffness, rtol=1e-8)


def test_results_come_back_in_caller_order():
    summits = random_summits(9, 100)
    model = DiscreteAsperityModel(summits)
    separation = np.array([0.0, 2e-3, -1e-3, 1e-3])
    together = model.at_separation(separation)
    for k, value in enumerate(separation):
        alone = model.at_separation(value)
        assert alone.load.shape == ()
        assert together.load[k] == pytest.approx(alone.load, rel=1e-9)
    loads = together.load[[2, 0, 3]]
    by_load = model.at_load(loads)
    np.testing.assert_allclose(by_load.separation, separation[[2, 0, 3]], rtol=0, atol=1e-12)


# ------------------------------------------------------------------------------ fast sums

@pytest.mark.parametrize("periodic", [False, True])
def test_lattice_fft_sum_equals_the_direct_sum(periodic):
    rng = np.random.default_rng(10)
    shape, spacing = (37, 50), 0.02
    index = rng.choice(shape[0] * shape[1], 400, replace=False)
    row, column = np.divmod(index, shape[1])
    operator = PointForceInteraction(column * spacing, row * spacing, e_star=1.3,
                                     spacing=spacing, row=row, column=column, shape=shape,
                                     periodic=periodic)
    forces = rng.random(150)
    sources, targets = np.arange(150), np.arange(100, 400)
    fft = operator.displacement(forces, sources=sources, targets=targets, method="fft")
    direct = operator.displacement(forces, sources=sources, targets=targets, method="direct")
    # Naive sum written here (minimum image when periodic).
    dx = (column[targets, None] - column[None, sources]) * spacing
    dy = (row[targets, None] - row[None, sources]) * spacing
    if periodic:
        dx -= shape[1] * spacing * np.rint(dx / (shape[1] * spacing))
        dy -= shape[0] * spacing * np.rint(dy / (shape[0] * spacing))
    r = np.hypot(dx, dy)
    with np.errstate(divide="ignore"):
        kernel = np.where(r > 0, 1.0 / (np.pi * 1.3 * r), 0.0)
    naive = kernel @ forces
    # FFT convolution: rounding ~ eps * log2(grid) * (sum |terms|) / |sum|; measured ~1e-15.
    np.testing.assert_allclose(fft, naive, rtol=1e-12)
    np.testing.assert_allclose(direct, naive, rtol=1e-13)


def test_fft_and_direct_models_agree_on_a_wm_surface():
    from validation import wm_surface

    z = wm_surface(128, D=2.3, rms_slope=0.1, seed=2)
    summits = find_summits(z, 1 / 128)
    separation = np.mean(summits.height) + np.std(summits.height) * np.array([1.0, -1.0])
    fft = DiscreteAsperityModel(summits, method="fft").at_separation(separation)
    direct = DiscreteAsperityModel(summits, method="direct").at_separation(separation)
    np.testing.assert_allclose(fft.load, direct.load, rtol=1e-9)
    np.testing.assert_allclose(fft.stiffness, direct.stiffness, rtol=1e-8)


def test_periodic_summits_use_the_minimum_image():
    j, i = np.mgrid[0:64, 0:64] / 64
    z = 1e-3 * np.cos(2 * np.pi * 4 * i) * np.cos(2 * np.pi * 2 * j)
    summits = find_summits(z, 1 / 64, periodic=True)
    assert summits.count == 16 and summits.periodic
    separation = 0.5e-3
    fft = DiscreteAsperityModel(summits, method="fft").at_separation([separation])
    direct = DiscreteAsperityModel(summits, method="direct").at_separation([separation])
    np.testing.assert_allclose(fft.extras["forces"], direct.extras["forces"], rtol=1e-9)
    # The summits form a lattice of the periodic cell: with the minimum image every summit sees
    # the same neighbourhood, so all carry the same force.
    np.testing.assert_allclose(fft.extras["forces"][0], fft.extras["forces"][0].mean(), rtol=1e-9)
    # Minimum image: more neighbours at short range than the aperiodic copy of the same summits.
    aperiodic = Summits.from_points(summits.x, summits.y, summits.height, summits.radius,
                                    area=1.0)
    assert DiscreteAsperityModel(aperiodic).at_separation([separation]).load[0] > fft.load[0]


# ------------------------------------------------------------------------------ properties

def gershgorin_safe_depth(summits):
    """Largest approach for which the scaled Hessian I + S^1/2 G S^1/2 is diagonally dominant
    for any contact set: with a_i <= a_max, row sums <= (2 a_max / pi) sum_j 1/r_ij; a margin of
    4 also keeps a_i + a_j < r_ij (no overlapping spots)."""
    if summits.count == 1:
        return np.inf
    r = np.hypot(summits.x[:, None] - summits.x[None, :], summits.y[:, None] - summits.y[None, :])
    np.fill_diagonal(r, np.inf)
    a_max = np.pi / (8.0 * np.max(np.sum(1.0 / r, axis=1)))
    return a_max**2 / summits.radius.max()


@st.composite
def summit_sets(draw):
    n = draw(st.integers(1, 40))
    cells = draw(st.sampled_from([16, 64, 1000]))
    index = draw(st.lists(st.integers(0, cells * cells - 1), min_size=n, max_size=n, unique=True))
    row, column = np.divmod(np.array(index), cells)
    length = draw(st.floats(1e-3, 1e3))
    sigma = length * draw(st.floats(1e-6, 1e-1))
    heights = sigma * np.array(draw(st.lists(st.floats(-3, 3), min_size=n, max_size=n)))
    radii = length * 10.0 ** np.array(draw(st.lists(st.floats(-4, 2), min_size=n, max_size=n)))
    spacing = length / cells
    lattice = draw(st.booleans())
    return Summits.from_points(column * spacing, row * spacing, heights, radii,
                               area=length**2, spacing=spacing if lattice else None)


@settings(deadline=None)
@given(summits=summit_sets(), e_star=st.floats(1e-3, 1e3))
def test_random_summit_sets_converge_with_monotone_load(summits, e_star):
    top = summits.height.max()
    depth = min(gershgorin_safe_depth(summits), 3 * (np.ptp(summits.height) + 1e-3 * top)
                if top > 0 else np.inf, 10 * summits.radius.min() + np.ptp(summits.height))
    separation = top - depth * np.linspace(0.0, 1.0, 9) ** 2
    model = DiscreteAsperityModel(summits, e_star=e_star)
    with warnings.catch_warnings():
        warnings.simplefilter("error")        # no ConvergenceWarning / ValidityWarning here
        curve = model.at_separation(separation)
    assert curve.extras["converged"].all() and curve.extras["stable"].all()
    assert np.all(curve.extras["residual"] <= model.tol)
    assert np.all(curve.extras["forces"] >= 0) and np.all(curve.extras["contact_radii"] >= 0)
    assert np.all(np.isfinite(curve.load)) and np.all(curve.stiffness >= 0)
    np.testing.assert_array_equal(curve.extras["overlapping_spots"], 0)
    # Load decreases with separation (separations are decreasing here): allow the solver
    # tolerance, about 1.5 tol relative to the load.
    assert np.all(np.diff(curve.load) >= -1e-9 * curve.load[1:])
    # Load control returns to the same separations (the solution is unique in this regime).
    loaded = curve.load > 0
    if loaded.any():
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            by_load = model.at_load(curve.load[loaded])
        assert by_load.extras["converged"].all()
        np.testing.assert_allclose(by_load.separation, separation[loaded], rtol=0,
                                   atol=1e-8 * (top - separation.min()) + 1e-12 * abs(top))


@settings(deadline=None, max_examples=30)
@given(summits=summit_sets(), depth=st.floats(0.1, 30.0), e_star=st.floats(1e-2, 1e2))
def test_deep_loads_are_solved_or_flagged(summits, depth, e_star):
    """Far beyond the model's validity (spots overlapping, several equilibria) the solver still
    ends, every point it calls converged satisfies the compatibility equations (checked here
    with a dense kernel), and every other outcome is reported and warned."""
    spread = np.ptp(summits.height) + 1e-3 * summits.radius.min()
    separation = summits.height.max() - depth * spread * np.array([0.1, 0.5, 1.0])
    model = DiscreteAsperityModel(summits, e_star=e_star, max_iter=30)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        curve = model.at_separation(separation)
    categories = {w.category for w in caught}
    assert (ConvergenceWarning in categories) == (not curve.extras["converged"].all())
    assert (ValidityWarning in categories) == (not curve.extras["stable"].all())
    assert np.all(curve.extras["residual"][~curve.extras["converged"]] > model.tol)
    assert np.all(curve.extras["forces"] >= 0) and np.all(np.isfinite(curve.extras["forces"]))
    G = pair_matrix(summits, e_star)
    for k in np.flatnonzero(curve.extras["converged"]):
        approach = curve.extras["contact_radii"][k] ** 2 / summits.radius
        free = np.maximum(summits.height - separation[k] - G @ curve.extras["forces"][k], 0.0)
        scale = max(summits.height.max() - separation[k], approach.max())
        # Relative residual <= tol = 1e-10; allow rounding of the dense sum on top.
        assert np.abs(approach - free).max() <= 1e-9 * scale


# ------------------------------------------------------------------------------ reporting

def test_loss_of_uniqueness_is_detected_and_warned():
    # Two equal asperities s apart: the scaled Hessian [[1, c], [c, 1]], c = 2a/(pi s), is
    # indefinite exactly when a > pi s / 2. Contact spots overlap earlier, when a > s / 2.
    distance, radius = 0.01, 1.0
    summits = Summits.from_points([0.0, distance], [0.0, 0.0], [1e-3] * 2, [radius] * 2,
                                  area=1.0)
    model = DiscreteAsperityModel(summits)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        valid = model.at_separation([9.99e-4, 9e-4])
    assert valid.extras["stable"].all() and valid.extras["converged"].all()
    np.testing.assert_array_equal(valid.extras["overlapping_spots"], [0, 2])
    assert 0.5 * distance < valid.extras["contact_radii"][1, 0] < 0.5 * np.pi * distance
    with pytest.warns(ValidityWarning, match="not positive definite"):
        heavy = model.at_separation([5e-4, -1e-3])
    assert np.all(heavy.extras["contact_radii"][:, 0] > 0.5 * np.pi * distance)
    assert not heavy.extras["stable"].any() and heavy.extras["converged"].all()


def test_non_convergence_is_reported_and_warned():
    summits = random_summits(11, 200)
    model = DiscreteAsperityModel(summits, max_iter=1, tol=1e-15)
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        curve = model.at_separation([-1e-3], quantities=())
    assert not curve.extras["converged"][0] and curve.extras["residual"][0] > 1e-15 and curve.extras["iterations"][0] >= 1


def test_holm_greenwood_conductance_of_two_spots():
    e_star, radius, height, distance = 1.0, 0.3, 2e-3, 0.1
    summits = Summits.from_points([0.0, distance], [0.0, 0.0], [height] * 2, [radius] * 2,
                                  area=1.0)
    curve = DiscreteAsperityModel(summits, e_star=e_star).at_separation(
        [0.0], quantities=("holm_greenwood",))
    a = curve.extras["contact_radii"][0, 0]
    resistance = 1 / (4 * a) + (2 / np.pi) * (a * a / distance) / (2 * a) ** 2   # eq. (6)
    assert curve.extras["holm_greenwood_conductance"][0] == pytest.approx(2 / resistance, rel=1e-12)
    assert curve.stiffness is None and curve.conductance is None


# ------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("kwargs, match", [
    (dict(e_star=0.0), "e_star"),
    (dict(e_star=np.nan), "e_star"),
    (dict(m=1.0), "interaction=False"),
    (dict(interaction=False, m=-1.0), "m must"),
    (dict(tol=0.0), "tol"),
    (dict(max_iter=0), "max_iter"),
    (dict(method="tree"), "method"),
])
def test_model_bad_parameters(kwargs, match):
    summits = random_summits(12, 5)
    with pytest.raises(ValueError, match=match):
        DiscreteAsperityModel(summits, **kwargs)


def test_model_bad_arguments():
    model = DiscreteAsperityModel(random_summits(13, 5))
    with pytest.raises(ValueError, match="finite"):
        model.at_separation([0.0, np.nan])
    with pytest.raises(ValueError, match=">= 0"):
        model.at_load([-1.0])
    with pytest.raises(ValueError, match="quantities"):
        model.at_separation(0.0, quantities=("pressure_field",))
    with pytest.raises(ValueError, match="Summits"):
        DiscreteAsperityModel(np.zeros((4, 4)))
    with pytest.raises(ValueError, match="at least one"):
        DiscreteAsperityModel(find_summits(np.zeros((5, 5)), 1.0))


def test_dense_random_lattice_set_converges_from_far_to_deep():
    # Regression (stress campaign): a dense random lattice set driven from 40 sigma above to
    # 10 sigma below the mean summit height once stalled without converging; asperities that
    # enter contact now get a secant stiffness in the Newton step.
    rng = np.random.default_rng(100_000)
    count, side = 2_000, 90
    cells = rng.choice(side * side, size=count, replace=False)
    spacing = 1.0 / side
    summits = Summits.from_points((cells % side) * spacing, (cells // side) * spacing,
                                  rng.normal(0, 1e-3, count), rng.uniform(0.01, 0.1, count),
                                  area=1.0, spacing=spacing)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        curve = DiscreteAsperityModel(summits).at_separation(np.linspace(40e-3, -10e-3, 12))
    assert np.all(curve.extras["converged"])
    assert np.all(np.isfinite(curve.load)) and np.all(np.diff(curve.load) >= 0)


def test_interaction_operator_rejects_duplicate_positions():
    with pytest.raises(ValueError, match="distinct"):
        PointForceInteraction([0.0, 1.0, 0.0], [0.0, 0.0, 0.0])


def test_stiffness_solve_status_is_reported():
    rng = np.random.default_rng(3)
    summits = Summits.from_points(rng.uniform(0, 1, 40), rng.uniform(0, 1, 40),
                                  rng.normal(0, 1e-3, 40), np.full(40, 0.05), area=1.0)
    curve = DiscreteAsperityModel(summits).at_separation([2e-3, 0.0])
    assert curve.extras["stiffness_converged"].dtype == bool and np.all(curve.extras["stiffness_converged"])


# ------------------------------------------------------------------------------ regressions
def wm_summits(D, seed, n=64):
    from validation.surfaces.wm import wm_surface
    return find_summits(wm_surface(n, D=D, rms_slope=0.1, seed=seed), 1.0 / n)


def test_very_light_loads_converge_and_match_the_load():
    # Approaches of 1e-17 under separations of 1e-2: compatibility is resolved to the rounding
    # of d, so a purely relative test used to flag every point although the load matched.
    model = DiscreteAsperityModel(wm_summits(2.3, 1))
    loads = np.logspace(-14, -25, 12)
    curve = model.at_load(loads)
    assert curve.extras["converged"].all()
    np.testing.assert_allclose(curve.load, loads, rtol=1e-12)
    assert np.all(np.diff(curve.separation) > 0)            # lighter load, larger separation


@pytest.mark.parametrize("D, seed", [(2.05, 3), pytest.param(2.95, 2, marks=pytest.mark.slow)])
def test_a_point_on_a_load_path_is_never_worse_than_alone(D, seed):
    # The heaviest point of [0.01, 1, 1000] used to come back with load 0, unconverged, while
    # solved alone it converges.
    model = DiscreteAsperityModel(wm_summits(D, seed))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        path = model.at_load([0.01, 1.0, 1000.0])
        alone = model.at_load(1000.0)
    assert alone.extras["converged"] and path.extras["converged"].all()
    assert path.load[2] == pytest.approx(1000.0, rel=1e-9)
    assert path.separation[2] == pytest.approx(float(alone.separation), rel=1e-7, abs=1e-12)


def test_the_model_keeps_no_state_between_calls():
    model = DiscreteAsperityModel(random_summits(21, 80))
    first = model.at_separation([1e-3, 0.0, -1e-3])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        model.at_load([5.0, 1e-6])                           # an unrelated path in between
    again = model.at_separation([1e-3, 0.0, -1e-3])
    np.testing.assert_array_equal(first.load, again.load)
    np.testing.assert_array_equal(first.extras["iterations"], again.extras["iterations"])


def test_conjugate_gradients_from_a_start_reach_the_same_solution():
    from asperity.discrete.complementarity import _cg

    rng = np.random.default_rng(3)
    factor = rng.standard_normal((40, 40))
    matrix = factor @ factor.T + 40 * np.eye(40)
    rhs = rng.standard_normal(40)
    exact = np.linalg.solve(matrix, rhs)
    products = []

    def apply(values):
        products.append(1)
        return matrix @ values

    cold, converged, definite = _cg(apply, rhs, rtol=1e-12, max_iter=200)
    assert converged and definite
    cold_products = len(products)
    products.clear()
    start = exact + 1e-6 * rng.standard_normal(40)
    warm, converged, definite = _cg(apply, rhs, rtol=1e-12, max_iter=200, start=start)
    assert converged and definite and len(products) < cold_products
    np.testing.assert_allclose(cold, exact, rtol=0, atol=1e-10 * np.abs(exact).max())
    np.testing.assert_allclose(warm, exact, rtol=0, atol=1e-10 * np.abs(exact).max())
    products.clear()
    same, converged, _ = _cg(apply, rhs, rtol=1e-6, max_iter=200, start=exact)
    assert converged and len(products) == 1 and np.array_equal(same, exact)


def test_a_load_path_agrees_with_the_dense_oracle_at_its_separations():
    # under load control every Newton step's second solve starts from the previous one's
    # solution (the approach rate): the answers must still be those of the oracle
    e_star = 1.0
    summits = random_summits(11, 60, radius_scale=0.02)
    model = DiscreteAsperityModel(summits, e_star=e_star)
    first = model.at_separation([-1.5e-3]).load[0]
    curve = model.at_load(first * np.array([0.05, 0.2, 0.5, 1.0]), quantities=("area",))
    assert np.all(curve.extras["converged"])
    for separation, forces in zip(curve.separation, curve.extras["forces"]):
        expected = dense_active_set_solution(summits, e_star, separation)
        np.testing.assert_allclose(forces, expected, rtol=0, atol=1e-7 * expected.max())
