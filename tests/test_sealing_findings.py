"""The paper's sealing claims, findings (f) and (g), on synthetic results whose verdict is
known, and the rules they apply checked against the models' own leakage."""

from types import SimpleNamespace

import numpy as np
import pytest

from asperity.common.leakage import rigid_gaussian_aperture
from bem.common.curve import ContactCurve
from validation.judge.findings import CONTRADICTED, REPRODUCED, UNDECIDED
from validation.judge.sealing import (LEVELS, d1_measures_leakage, effective_separation,
                                      sealing_size, size_collapse)

REALIZATIONS = 12
POINTS = 8
NOISE = np.random.default_rng(5).standard_normal((REALIZATIONS, POINTS))


def bem_curve(separation, load, leakage, area=1.0):
    return ContactCurve(separation=separation, load=load, area=0.1 * load, mean_pressure=load / area,
                        nominal_area=area, e_star=1.0, leakage=leakage)


def realization(seed, curve, m=1.0):
    task = SimpleNamespace(seed=seed, m=m, quantities=("area", "leakage"),
                           surface=SimpleNamespace(L=np.sqrt(curve.nominal_area), sweep_name="D"))
    return SimpleNamespace(task=task, curves={"bem": curve}, sigma=1.0)


def path_results(governed_by: str, scatter: float = 0.01):
    """A load path on which the exact leakage is the rigid gap (s = sigma = 1) at d1 = d + W
    (m = 1, A = 1, E* = 1) or at d, with a seeded 1 % scatter over realizations."""
    load = np.geomspace(0.1, 1.0, POINTS)
    separation = np.linspace(3.0, -0.5, POINTS)
    out = []
    for seed in range(REALIZATIONS):
        at = separation + load if governed_by == "d1" else separation
        exact = rigid_gaussian_aperture(at, 1.0) * np.exp(scatter * NOISE[seed])
        out.append(realization(seed, bem_curve(separation, load, exact)))
    return out


def test_effective_separation_is_the_papers_d1():
    curve = bem_curve([1.0, 0.5], np.array([0.5, 2.0]), [1.0, 0.5], area=4.0)
    # d1 = d + m W / (E* sqrt A), sqrt A = 2
    np.testing.assert_allclose(effective_separation(curve, 0.95), [1.0 + 0.95 * 0.5 / 2,
                                                                  0.5 + 0.95 * 2.0 / 2])


def test_d1_measures_the_leakage_when_the_exact_leakage_follows_d1():
    finding = d1_measures_leakage(path_results("d1"), 0.2)
    assert finding.verdict == REPRODUCED, finding.evidence
    # the rigid gap at d seals (d <= 0) where the BEM leaks: infinitely wrong there
    assert "disagrees with the BEM about sealing" in finding.evidence
    assert f"d1 closer at {POINTS}, d closer at 0" in finding.evidence


def test_d1_does_not_measure_the_leakage_when_the_exact_leakage_follows_d():
    finding = d1_measures_leakage(path_results("d"), 0.2)
    assert finding.verdict == CONTRADICTED, finding.evidence


def test_d1_finding_needs_the_leakage_and_sigma():
    plain = [realization(0, ContactCurve(separation=[1.0], load=[1.0], area=[0.1],
                                         mean_pressure=[1.0], nominal_area=1.0, e_star=1.0))]
    assert d1_measures_leakage(plain, 0.2).verdict == UNDECIDED
    no_sigma = path_results("d1")
    for r in no_sigma:
        r.sigma = float("nan")
    assert "needs σ" in d1_measures_leakage(no_sigma, 0.2).evidence


def test_the_rules_of_finding_f_are_the_models_own():
    # GW's leakage at d is the rigid gap at d with s = sigma of the summits; improved GW's at d
    # is that at its d1, and its d1 is effective_separation of its own curve
    from validation.common.models import ModelInputs, build
    from validation.surfaces.wm import wm_surface

    heights = wm_surface(64, D=2.3, rms_slope=0.1, seed=3)
    inputs = ModelInputs(spacing=1 / 64, nominal_area=1.0, heights=heights)
    sigma = float(np.std(inputs.summits().height))
    separation = np.array([2.0, 1.0, 0.5, 0.0]) * sigma
    gw = build("gw", inputs).at_separation(separation, quantities=("leakage",))
    np.testing.assert_allclose(gw.leakage, rigid_gaussian_aperture(separation, sigma), rtol=1e-12)
    improved = build("improved_gw", inputs).at_separation(separation, quantities=("leakage",))
    d1 = effective_separation(improved, inputs.m)
    np.testing.assert_allclose(d1, improved.extras["effective_separation"], rtol=1e-10)
    np.testing.assert_allclose(improved.leakage, rigid_gaussian_aperture(d1, sigma), rtol=1e-10)


def size_results(governed_by: str, m: float = 1.0, scatter: float = 0.005):
    """Nested windows of sides 1, 2, 4 at the same nominal pressures: the exact leakage is the
    rigid gap (s = 1) at d1, the same function of the pressure on every size, and d = d1 - m p L
    (W / sqrt(A) = p L); or it is the rigid gap at d, the same function of d on every size."""
    pressure = np.geomspace(0.01, 0.3, 10)
    d1 = np.linspace(3.0, 0.3, 10)
    by_side = {}
    for index, side in enumerate((1.0, 2.0, 4.0)):
        d = d1 - m * pressure * side
        at = d1 if governed_by == "d1" else d
        by_side[side] = [realization(seed, bem_curve(
            d, pressure * side**2, rigid_gaussian_aperture(at, 1.0)
            * np.exp(scatter * np.resize(NOISE[(seed + 5 * index) % REALIZATIONS], 10)),
            area=side**2), m) for seed in range(REALIZATIONS)]
    return by_side


def test_size_curves_collapse_on_d1_when_the_leakage_follows_d1():
    by_side = size_results("d1")
    finding, collapse = sealing_size(by_side, 1.0, 0.2)
    assert finding.verdict == REPRODUCED, finding.evidence
    assert collapse.d.shape == (3, REALIZATIONS, LEVELS) and collapse.sigma == 1.0
    # the spread in d at a level is m p (4 - 1) at that level's pressure (exact for d1 collapse)
    assert np.all(collapse.spread_d1.mean(axis=0) < 0.05)
    assert collapse.spread_d.mean(axis=0).max() > 0.5
    assert f"d falls with the size (a larger area needs a deeper approach) at {LEVELS}" \
        in finding.evidence


def test_size_curves_that_collapse_on_d_contradict_the_claim():
    finding, _ = sealing_size(size_results("d"), 1.0, 0.2)
    assert finding.verdict == CONTRADICTED, finding.evidence


@pytest.mark.parametrize("change", ["one size", "no leakage", "disjoint"])
def test_size_finding_not_tested_without_what_it_needs(change):
    by_side = size_results("d1")
    if change == "one size":
        by_side = {1.0: by_side[1.0]}
    elif change == "no leakage":
        for r in by_side[2.0]:
            r.curves["bem"] = ContactCurve(separation=r.curves["bem"].separation,
                                           load=r.curves["bem"].load, area=r.curves["bem"].area,
                                           mean_pressure=r.curves["bem"].mean_pressure,
                                           nominal_area=4.0, e_star=1.0)
    else:   # leakage ranges that do not overlap
        for r in by_side[4.0]:
            c = r.curves["bem"]
            r.curves["bem"] = bem_curve(c.separation, c.load, c.leakage * 100.0, area=16.0)
    assert size_collapse(by_side, 1.0) is None
    finding, collapse = sealing_size(by_side, 1.0, 0.2)
    assert finding.verdict == UNDECIDED and "not tested" in finding.evidence and collapse is None
