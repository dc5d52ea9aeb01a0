"""Rows of the bad-input campaign for the names :mod:`asperity` exports (see
:mod:`validation.campaigns._bad_input_table`)."""

from __future__ import annotations

import dataclasses

import numpy as np

from validation.campaigns._bad_input_fixtures import (SPACING, EntryPoint, curve, gw, points,
                                                      summits, surface, theories)

__all__ = ["rows"]

_MOMENTS = dict(m0=1.0, m2=1.0, m4=3.0)


def _spectrum():
    import asperity

    return asperity.radial_power_spectrum(surface(), SPACING)


def _persson():
    import asperity

    return asperity.Persson(_spectrum(), 1.0)


def _interaction_curves() -> dict:
    import asperity

    found = asperity.interaction_curves(5.0, separation=np.array([-1.0, 0.0, 2.0]))
    return {item.name: getattr(found, item.name) for item in dataclasses.fields(found)}


def _discrete():
    import asperity

    return asperity.DiscreteAsperityModel(summits(), tol=1e-8, max_iter=20)


def rows() -> tuple[EntryPoint, ...]:
    """One row per name :mod:`asperity` exports, and per public method with arguments."""
    import asperity

    z = surface
    bgt = asperity.BushGibsonThomas
    return (
        # ---------------------------------------------------------------- GW functions
        EntryPoint("asperity.gw_integral", asperity.gw_integral,
                   lambda: dict(n=1.5, h=np.array([-1.0, 0.0, 2.0])), scalars=dict(n="real"),
                   arrays=dict(h="inf")),
        EntryPoint("asperity.log_gw_integral", asperity.log_gw_integral,
                   lambda: dict(n=1.0, h=np.array([-1.0, 0.0, 2.0])), scalars=dict(n="real"),
                   arrays=dict(h="inf")),
        EntryPoint("asperity.GreenwoodWilliamson", asperity.GreenwoodWilliamson, gw,
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive",
                                distribution="choice", height_rms="positive optional")),
        EntryPoint("GreenwoodWilliamson.at_separation",
                   lambda separation: asperity.GreenwoodWilliamson(**gw()).at_separation(
                       separation),
                   lambda: dict(separation=np.array([0.0, 0.01, 0.03])),
                   arrays=dict(separation="inf")),
        EntryPoint("GreenwoodWilliamson.at_load",
                   lambda load: asperity.GreenwoodWilliamson(**gw()).at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("GreenwoodWilliamson curves", theories(asperity.GreenwoodWilliamson),
                   lambda: gw(mean=0.0, e_star=1.0, area=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive",
                                distribution="choice", height_rms="positive optional")),
        EntryPoint("ImprovedGreenwoodWilliamson curves",
                   theories(asperity.ImprovedGreenwoodWilliamson),
                   lambda: gw(mean=0.0, e_star=1.0, area=1.0, m=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive",
                                m="non_negative")),
        EntryPoint("asperity.ImprovedGreenwoodWilliamson", asperity.ImprovedGreenwoodWilliamson,
                   lambda: gw(m=1.0), scalars=dict(m="non_negative", sigma="positive")),
        EntryPoint("ImprovedGreenwoodWilliamson.at_separation",
                   lambda separation: asperity.ImprovedGreenwoodWilliamson(
                       **gw()).at_separation(separation),
                   lambda: dict(separation=np.array([0.0, 0.01, 0.03])),
                   arrays=dict(separation="inf")),
        EntryPoint("ImprovedGreenwoodWilliamson.at_load",
                   lambda load: asperity.ImprovedGreenwoodWilliamson(**gw()).at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("ImprovedGreenwoodWilliamson.effective_reduced_separation",
                   lambda h: asperity.ImprovedGreenwoodWilliamson(
                       **gw()).effective_reduced_separation(h),
                   lambda: dict(h=np.array([-1.0, 0.0, 2.0])), arrays=dict(h="inf")),
        # ---------------------------------------------------------------- other asperity
        EntryPoint("asperity.holm_greenwood", asperity.holm_greenwood,
                   lambda: dict(**points(), radii=np.array([0.1, 0.2, 0.1])),
                   arrays=dict(x="", y="", radii="")),
        EntryPoint("asperity.dimensionless", asperity.dimensionless,
                   lambda: dict(curve=curve(), sigma=0.01, length=1.0),
                   scalars=dict(curve="object", sigma="positive", length="positive")),
        EntryPoint("asperity.dimensionless_pressure", asperity.dimensionless_pressure,
                   lambda: dict(mean_pressure=np.array([1e-3, 1e-2]), density=50.0, radius=0.05,
                                sigma=0.01, e_star=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                e_star="positive"),
                   arrays=dict(mean_pressure="")),
        EntryPoint("asperity.interaction_parameter", asperity.interaction_parameter,
                   lambda: dict(density=50.0, radius=0.05, sigma=0.01, area=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                area="positive")),
        EntryPoint("asperity.interaction_curves", asperity.interaction_curves,
                   lambda: dict(interaction_parameter=5.0, m=1.0,
                                separation=np.array([-1.0, 0.0, 2.0])),
                   scalars=dict(interaction_parameter="non_negative", m="non_negative"),
                   arrays=dict(separation="optional inf")),
        EntryPoint("asperity.DiscreteAsperityModel", asperity.DiscreteAsperityModel,
                   lambda: dict(summits=summits(), tol=1e-8, max_iter=20, e_star=1.0),
                   scalars=dict(summits="object", tol="positive", max_iter="integer", e_star="positive",
                                m="non_negative optional", method="choice")),
        EntryPoint("asperity.radial_power_spectrum", asperity.radial_power_spectrum,
                   lambda: dict(heights=z(), spacing=SPACING, window="hann"),
                   scalars=dict(spacing="positive", window="choice"), arrays=dict(heights="")),
        EntryPoint("IsotropicSpectrum.moment",
                   lambda order: asperity.radial_power_spectrum(z(), SPACING).moment(order),
                   lambda: dict(order=2), scalars=dict(order="real")),
        EntryPoint("asperity.separation_kernel", asperity.separation_kernel,
                   lambda: dict(x=np.array([0.1, 1.0, 3.0]), gamma=0.42),
                   scalars=dict(gamma="positive"), arrays=dict(x="inf")),
        EntryPoint("asperity.find_summits", asperity.find_summits,
                   lambda: dict(heights=z(), spacing=SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("Summits.from_points", asperity.Summits.from_points,
                   lambda: dict(**points(), height=np.array([0.1, 0.2, 0.3]),
                                radius=np.array([0.1, 0.1, 0.2]), area=4.0),
                   scalars=dict(area="positive"),
                   arrays=dict(x="", y="", height="", radius="")),
        EntryPoint("Summits.greenwood_williamson",
                   lambda area, e_star: asperity.find_summits(z(), SPACING).greenwood_williamson(
                       area, e_star=e_star),
                   lambda: dict(area=1.0, e_star=1.0),
                   scalars=dict(area="positive optional", e_star="positive")),
        EntryPoint("asperity.PointForceInteraction", asperity.PointForceInteraction,
                   lambda: dict(**points(), e_star=1.0, spacing=1.0, row=np.array([0, 0, 1]),
                                column=np.array([0, 1, 2])),
                   scalars=dict(e_star="positive", spacing="positive optional", threads="integer",
                                method="choice", fft_backend="choice"),
                   arrays=dict(x="", y="")),
        EntryPoint("PointForceInteraction.displacement",
                   lambda forces: asperity.PointForceInteraction(**points()).displacement(
                       forces),
                   lambda: dict(forces=np.array([1.0, 2.0, 3.0])), arrays=dict(forces="")),
        EntryPoint("asperity.DimensionlessCurve", asperity.DimensionlessCurve,
                   lambda: dict(separation=np.array([0.0, 1.0]), load=np.array([1e-3, 1e-4]),
                                area=np.array([0.1, 0.01]), conductance=np.array([1.0, 0.1])),
                   arrays=dict(separation="inf", load="inf", area="inf",
                               conductance="optional inf")),
        EntryPoint("asperity.InteractionCurves", asperity.InteractionCurves, _interaction_curves,
                   scalars=dict(interaction_parameter="non_negative", m="non_negative"),
                   arrays={name: "inf" for name in (
                       "separation", "effective_separation", "gw_pressure", "improved_pressure",
                       "effective_stiffness", "improved_stiffness", "gw_stiffness")}),
        EntryPoint("asperity.Summits", asperity.Summits,
                   lambda: dict(**points(), height=np.array([0.1, 0.2, 0.3]),
                                radius=np.array([0.1, 0.1, 0.2]), area=4.0),
                   scalars=dict(area="positive", spacing="positive optional",
                                curvature="choice"),
                   arrays=dict(x="", y="", height="", radius="")),
        EntryPoint("asperity.summits_to_arrays", asperity.summits_to_arrays,
                   lambda: dict(summits=summits()), scalars=dict(summits="object")),
        EntryPoint("asperity.summits_from_arrays", asperity.summits_from_arrays,
                   lambda: dict(arrays=summits().to_arrays()), scalars=dict(arrays="object")),
        EntryPoint("Summits.from_arrays", asperity.Summits.from_arrays,
                   lambda: dict(arrays=summits().to_arrays()), scalars=dict(arrays="object")),
        EntryPoint("Summits.improved_greenwood_williamson",
                   lambda area, m, e_star: summits().improved_greenwood_williamson(
                       area, m, e_star=e_star),
                   lambda: dict(area=1.0, m=1.0, e_star=1.0),
                   scalars=dict(area="positive optional", m="non_negative", e_star="positive")),
        EntryPoint("DiscreteAsperityModel.at_separation",
                   lambda separation: _discrete().at_separation(separation),
                   lambda: dict(separation=np.array([0.0, 0.01])),
                   arrays=dict(separation="")),
        EntryPoint("DiscreteAsperityModel.at_load", lambda load: _discrete().at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("PointForceInteraction.from_summits",
                   asperity.PointForceInteraction.from_summits,
                   lambda: dict(summits=summits(), e_star=1.0, method="auto"),
                   scalars=dict(summits="object", e_star="positive", method="choice")),
        EntryPoint("PointForceInteraction.linear_map",
                   lambda indices, products: asperity.PointForceInteraction(
                       **points()).linear_map(indices, products=products)(np.ones(2)),
                   lambda: dict(indices=np.array([0, 2]), products=20),
                   scalars=dict(products="integer"), arrays=dict(indices="")),
        EntryPoint("asperity.Persson", asperity.Persson,
                   lambda: dict(spectrum=_spectrum(), nominal_area=1.0, e_star=1.0, gamma=0.42),
                   scalars=dict(spectrum="object", nominal_area="positive", e_star="positive",
                                gamma="positive")),
        EntryPoint("Persson.from_spectrum", asperity.Persson.from_spectrum,
                   lambda: dict(wavevector=np.array([1.0, 100.0]), psd=np.array([1e-6, 1e-14]),
                                nominal_area=1.0, samples=65),
                   scalars=dict(nominal_area="positive", e_star="positive", gamma="positive",
                                samples="integer"),
                   arrays=dict(wavevector="", psd="")),
        EntryPoint("Persson.from_heights", asperity.Persson.from_heights,
                   lambda: dict(heights=z(), spacing=SPACING),
                   scalars=dict(spacing="positive", e_star="positive", gamma="positive",
                                window="choice"),
                   arrays=dict(heights="")),
        EntryPoint("Persson.mean_gap", lambda pressure: _persson().mean_gap(pressure),
                   lambda: dict(pressure=np.array([1e-4, 1e-3])), arrays=dict(pressure="inf")),
        EntryPoint("Persson.at_load", lambda load: _persson().at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("Persson.at_separation", lambda separation: _persson().at_separation(separation),
                   lambda: dict(separation=np.array([0.01, 0.02])),
                   arrays=dict(separation="inf")),
        EntryPoint("asperity.IsotropicSpectrum", asperity.IsotropicSpectrum,
                   lambda: dict(wavevector=np.array([1.0, 10.0, 100.0]),
                                psd=np.array([1e-6, 1e-10, 1e-14])),
                   arrays=dict(wavevector="", psd="")),
        EntryPoint("IsotropicSpectrum.cumulative_moment",
                   lambda order, wavevector: _spectrum().cumulative_moment(order, wavevector),
                   lambda: dict(order=3, wavevector=np.array([10.0, 20.0])),
                   scalars=dict(order="real"), arrays=dict(wavevector="inf")),
        EntryPoint("IsotropicSpectrum.wavevector_at_fourth_moment",
                   lambda m: _spectrum().wavevector_at_fourth_moment(m),
                   lambda: dict(m=np.array([0.1, 0.5]) * _spectrum().moment(5)),
                   arrays=dict(m="inf")),
        EntryPoint("asperity.SpectralMoments", asperity.SpectralMoments, lambda: dict(_MOMENTS),
                   scalars=dict(m0="positive", m2="positive", m4="positive")),
        EntryPoint("SpectralMoments.from_spectrum", asperity.SpectralMoments.from_spectrum,
                   lambda: dict(spectrum=_spectrum()), scalars=dict(spectrum="object")),
        EntryPoint("asperity.SpectralSummits", asperity.SpectralSummits, lambda: dict(_MOMENTS),
                   scalars=dict(m0="positive", m2="positive", m4="positive")),
        EntryPoint("asperity.spectral_summits", asperity.spectral_summits,
                   lambda: dict(_MOMENTS),
                   scalars=dict(m0="positive", m2="positive", m4="positive")),
        EntryPoint("SpectralSummits.greenwood_williamson",
                   lambda area, e_star: asperity.spectral_summits(
                       **_MOMENTS).greenwood_williamson(area, e_star=e_star),
                   lambda: dict(area=1.0, e_star=1.0),
                   scalars=dict(area="positive", e_star="positive")),
        EntryPoint("SpectralSummits.improved_greenwood_williamson",
                   lambda area, m, e_star: asperity.spectral_summits(
                       **_MOMENTS).improved_greenwood_williamson(area, m, e_star=e_star),
                   lambda: dict(area=1.0, m=1.0, e_star=1.0),
                   scalars=dict(area="positive", m="non_negative", e_star="positive")),
        EntryPoint("asperity.spectral_moments", asperity.spectral_moments,
                   lambda: dict(heights=z(), spacing=SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("asperity.hertz_elliptic_factors", asperity.hertz_elliptic_factors,
                   lambda: dict(ratio=np.array([0.25, 0.5, 1.0])), arrays=dict(ratio="")),
        EntryPoint("asperity.BushGibsonThomas", bgt, lambda: dict(_MOMENTS, e_star=1.0, area=1.0),
                   scalars=dict(m0="positive", m2="positive", m4="positive", e_star="positive",
                                area="positive")),
        EntryPoint("BushGibsonThomas.at_separation",
                   lambda separation: bgt(**_MOMENTS).at_separation(separation),
                   lambda: dict(separation=np.array([0.5, 1.0, 2.0])),
                   arrays=dict(separation="inf")),
        EntryPoint("BushGibsonThomas.at_load", lambda load: bgt(**_MOMENTS).at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
    )
