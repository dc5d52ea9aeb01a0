"""The model registry: the one place that maps a scene's model names to model factories.

Scene parsing (which names are allowed), the runner (what to build and cache), the report
(labels and plot styles) and the benchmark look models up here and nowhere else. A model is
added by one module that implements the :class:`bem.ContactModel` contract and one call::

    register("persson", _persson, label="Persson", needs_summits=False, contacts="none",
             reference_fields={"separation": "mean_gap"})

The registry's machinery (:class:`ModelInputs`, :class:`ModelEntry`, :func:`register`, the
look-ups) lives in :mod:`validation.common.registry` and is re-exported here; this module
registers the project's models. The contract test catalogue (``tests/test_contract.py``) runs
over every registered model.
"""

from __future__ import annotations

from validation.common.registry import (FRAME_LABELS, FRAMES, ModelEntry, ModelInputs, build,
                                        default_names, entry, frame_of, frames_of, labels, names,
                                        reference_among, reference_fields, reference_for,
                                        reference_names, register, styles, unregister)

__all__ = ["FRAMES", "FRAME_LABELS", "PERSSON_WINDOW", "ModelInputs", "ModelEntry", "register",
           "unregister", "entry", "names", "default_names", "build", "labels", "styles",
           "reference_names", "reference_among", "reference_for", "reference_fields", "frame_of",
           "frames_of"]


#: Window of the height map's PSD for Persson's theory (:func:`asperity.spectral.spectrum.power_spectrum_2d`).
#: "mirror" keeps h_rms and h'_rms of the map (Hann loses up to a third of h_rms at D = 2.05) and
#: its mean gap agrees better with the BEM's on WM surfaces (docs/theory.md, section 7).
PERSSON_WINDOW = "mirror"

def _gw(inputs: ModelInputs):
    return inputs.summits().greenwood_williamson(inputs.nominal_area, e_star=inputs.e_star)


def _improved_gw(inputs: ModelInputs, one_iteration: bool = False):
    from asperity import ImprovedGreenwoodWilliamson

    exact = inputs.summits().improved_greenwood_williamson(
        inputs.nominal_area, e_star=inputs.e_star, m=inputs.interaction_m)
    if not one_iteration:
        return exact
    return ImprovedGreenwoodWilliamson(exact.density, exact.radius, exact.sigma, mean=exact.mean,
                                       e_star=exact.e_star, area=exact.area, m=exact.m,
                                       one_iteration=True)


def _discrete(inputs: ModelInputs, interaction: bool = True, local: bool = False):
    from asperity import DiscreteAsperityModel

    # the scene's [bem] device serves the interaction's FFT sums too (not part of the cache
    # key: the sums are the CPU's to rounding)
    return DiscreteAsperityModel(inputs.summits(), e_star=inputs.e_star, interaction=interaction,
                                 local=local, device=inputs.bem_options.get("device", "cpu"))


def _persson(inputs: ModelInputs):
    # cached although cheap: a cached run then makes no surface at all (the heights are its
    # only input, and the WM synthesis costs more than the theory)
    from asperity import Persson

    return Persson.from_heights(inputs.heights(), inputs.spacing, e_star=inputs.e_star,
                                window=PERSSON_WINDOW)


def _bem(inputs: ModelInputs):
    from bem import BoundaryElementModel

    return BoundaryElementModel(inputs.heights(), inputs.spacing, e_star=inputs.e_star,
                                **inputs.bem_options)


def _extension(inputs: ModelInputs) -> str:
    """How the interface reference makes a period of the heights (:class:`bem.InterfaceModel`)."""
    return "periodic" if inputs.periodic_surface else "mirror"


def _cached_options(options: dict) -> dict:
    """The options that determine a reference's result (its cache key): all but the device,
    whose results are the same (tests/test_device.py), and a callback, which only watches."""
    return {k: v for k, v in options.items() if k not in ("device", "callback")}


def _interface_options(inputs: ModelInputs) -> dict:
    return {k: v for k, v in inputs.bem_options.items() if k != "periodic"}


def _bem_nominal(inputs: ModelInputs):
    from bem import NominalContactModel

    if inputs.nominal_size is None:
        raise ValueError("the reference bem_nominal needs a nominal size ([models] nominal_size)")
    return NominalContactModel(inputs.heights(), inputs.spacing, e_star=inputs.e_star,
                               nominal_size=inputs.nominal_size, extension=_extension(inputs),
                               **_interface_options(inputs))


def _bem_interface(inputs: ModelInputs):
    from bem import InterfaceModel

    return InterfaceModel(inputs.heights(), inputs.spacing, e_star=inputs.e_star,
                          extension=_extension(inputs), **_interface_options(inputs))


# GW and improved GW are cached although closed-form: inverting them at given loads (a root per
# point, at every sampling) was the largest part of a warm report's computing (5.1 -> 3.9 s for
# the quick default report read from the cache, the best of five runs)
register("gw", _gw, label="original GW", style=dict(color="tab:blue", linestyle="--"),
         cached=True, closed_form=True)
register("improved_gw", _improved_gw, label="improved GW",
         style=dict(color="tab:orange", linestyle="-"), frame="finite", cached=True,
         closed_form=True, settings=lambda inputs: {"m": inputs.interaction_m})
register("improved_gw_one_iteration", lambda inputs: _improved_gw(inputs, one_iteration=True),
         label="improved GW (one iteration)", style=dict(color="tab:red", linestyle="-."),
         inverse_consistent=False, default=False, frame="finite",
         settings=lambda inputs: {"m": inputs.interaction_m})
register("discrete_no_interaction", lambda inputs: _discrete(inputs, interaction=False),
         label="discrete (no interaction)", style=dict(color="tab:olive", linestyle=":"),
         cached=True)
register("discrete", _discrete, label="discrete (interaction)",
         style=dict(color="tab:green", linestyle="-"), cached=True, frame="finite")
# the same pairwise interaction without its uniform part (the window's m p L / E*): local
# interactions alone, judged in the interface frame (docs/theory.md 8.10); not a default model
register("discrete_local", lambda inputs: _discrete(inputs, local=True),
         label="discrete (local interaction)", style=dict(color="tab:green", linestyle="--"),
         cached=True, frame="interface", default=False)
register("persson", _persson, label="Persson", style=dict(color="tab:purple", linestyle="-."),
         needs_summits=False, contacts="none", reference_fields={"separation": "mean_gap"},
         cached=True, settings=lambda inputs: {"window": PERSSON_WINDOW})
register("bem", _bem, label="BEM (exact)", style=dict(color="black", linestyle="-", linewidth=2.0),
         needs_summits=False, cached=True, reference=True, contacts="patches", frame="finite",
         settings=lambda inputs: {"options": _cached_options(inputs.bem_options)})
register("bem_interface", _bem_interface, label="BEM interface (exact)",
         style=dict(color="dimgray", linestyle="--", linewidth=2.0), needs_summits=False,
         cached=True, reference=True, contacts="patches", frame="interface",
         settings=lambda inputs: {"options": _cached_options(_interface_options(inputs)),
                                  "extension": _extension(inputs)})
register("bem_nominal", _bem_nominal, label="BEM nominal contact (exact)",
         style=dict(color="black", linestyle=":", linewidth=2.0), needs_summits=False,
         cached=True, reference=True, contacts="patches", frame="finite", default=False,
         settings=lambda inputs: {"options": _cached_options(_interface_options(inputs)),
                                  "extension": _extension(inputs),
                                  "nominal_size": inputs.nominal_size})


# Theories from the spectral moments m0, m2, m4 of the heights (Nayak, McCool; Bush, Gibson &
# Thomas), as users apply them to a measured profile: no summit is counted on the map.
def _spectral_moments(inputs: ModelInputs):
    from asperity import spectral_moments

    return spectral_moments(inputs.heights(), inputs.spacing,
                            periodic=bool(inputs.bem_options.get("periodic", False)))


def _gw_spectral(inputs: ModelInputs, improved: bool = False):
    summits = _spectral_moments(inputs).summits()
    if improved:
        return summits.improved_greenwood_williamson(inputs.nominal_area, inputs.interaction_m,
                                                     e_star=inputs.e_star)
    return summits.greenwood_williamson(inputs.nominal_area, e_star=inputs.e_star)


def _bgt(inputs: ModelInputs):
    from asperity import BushGibsonThomas

    moments = _spectral_moments(inputs)
    return BushGibsonThomas(moments.m0, moments.m2, moments.m4, e_star=inputs.e_star,
                            area=inputs.nominal_area)


def _spectral_settings(inputs: ModelInputs) -> dict:
    return {"moments": "finite differences", "periodic": bool(inputs.bem_options.get("periodic", False))}


# cached although cheap, like Persson: a cached run then makes no surface at all
register("gw_spectral", _gw_spectral, label="GW from the spectrum",
         style=dict(color="tab:cyan", linestyle="--"), needs_summits=False, cached=True,
         settings=_spectral_settings)
register("improved_gw_spectral", lambda inputs: _gw_spectral(inputs, improved=True),
         label="improved GW from the spectrum", style=dict(color="tab:brown", linestyle="-"),
         needs_summits=False, cached=True, frame="finite",
         settings=lambda inputs: {**_spectral_settings(inputs), "m": inputs.interaction_m})
register("bgt", _bgt, label="Bush-Gibson-Thomas", style=dict(color="tab:pink", linestyle="-."),
         needs_summits=False, cached=True, settings=_spectral_settings)
