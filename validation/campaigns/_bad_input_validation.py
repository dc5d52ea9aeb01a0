"""Rows of the bad-input campaign for the names :mod:`validation` exports (see
:mod:`validation.campaigns._bad_input_table`)."""

from __future__ import annotations

import functools
import tempfile

import numpy as np

from validation.campaigns._bad_input_fixtures import (EXAMPLE, N, SPACING, EntryPoint, curve,
                                                      realizations, surface,
                                                      validity_range_call)

__all__ = ["rows"]


@functools.lru_cache(maxsize=1)
def _scratch() -> tempfile.TemporaryDirectory:
    """One scratch folder for every call of ``write_report`` (each replaces the last report),
    removed when the process ends."""
    return tempfile.TemporaryDirectory(prefix="bad-input-report-")


def _theory_scene():
    from validation import parse_scene

    return parse_scene({"kind": "theory", "theory": {"C": [5.0]}})


def _statistics() -> dict:
    return dict(rms_height=0.01, rms_gradient=0.1, rms_curvature=3.0, m0=1e-4, m2=5e-3,
                m4=4.5, nayak=18.0)


def rows() -> tuple[EntryPoint, ...]:
    """One row per name :mod:`validation` exports, and per public method with arguments."""
    import validation

    z = surface
    return (
        # ---------------------------------------------------------------- validation
        EntryPoint("validation.wm_surface", validation.wm_surface,
                   lambda: dict(n=N, D=2.3, rms_slope=0.1, seed=1),
                   scalars=dict(n="integer", D="real", rms_slope="positive", L="positive",
                                gamma="real", M="integer", n_max="integer",
                                seed="integer optional")),
        EntryPoint("validation.self_affine_surface", validation.self_affine_surface,
                   lambda: dict(n=N, hurst=0.8, rms_height=1.0, seed=1),
                   scalars=dict(n="integer", hurst="positive", rms_height="positive",
                                L="positive", window="integer optional",
                                seed="integer optional")),
        EntryPoint("validation.wm_surface(G)", validation.wm_surface,
                   lambda: dict(n=N, D=2.3, G=1e-3, seed=1), scalars=dict(G="positive")),
        EntryPoint("validation.wm_amplitude", validation.wm_amplitude,
                   lambda: dict(G=1e-3, D=2.3),
                   scalars=dict(G="positive", D="real", L="positive", gamma="real",
                                M="integer")),
        EntryPoint("validation.surface_statistics", validation.surface_statistics,
                   lambda: dict(heights=z(), spacing=SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("validation.surface_descriptors", validation.surface_descriptors,
                   lambda: dict(heights=z(), spacing=SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("validation.curve_errors", validation.curve_errors,
                   lambda: dict(model=curve(), reference=curve(), sigma=0.01,
                                quantities=("separation", "area")),
                   scalars=dict(sigma="positive")),
        EntryPoint("validation.validity_range", validity_range_call,
                   lambda: dict(loads=np.array([1.0, 2.0, 3.0]),
                                errors=np.array([0.01, 0.5, 0.02]), tolerance=0.1,
                                area_fraction=np.array([0.01, 0.02, 0.03])),
                   scalars=dict(tolerance="positive"),
                   arrays=dict(loads="", errors="nan inf", area_fraction="optional")),
        EntryPoint("validation.compare_realizations", validation.compare_realizations,
                   lambda: dict(results=realizations(), tolerances=(0.05, 0.2)),
                   scalars=dict(results="object", reference_model="choice optional"),
                   arrays=dict(tolerances="")),
        EntryPoint("validation.run_scenes", validation.run_scenes,
                   lambda: dict(scenes=(), progress=False), scalars=dict(scenes="object")),
        EntryPoint("validation.load_scene", validation.load_scene,
                   lambda: dict(name_or_path="paper-theory"),
                   scalars=dict(name_or_path="object")),
        EntryPoint("validation.parse_scene", validation.parse_scene,
                   lambda: dict(data={"kind": "theory", "theory": {"C": [5.0]}}),
                   scalars=dict(data="object")),
        EntryPoint("validation.read_topography", validation.read_topography,
                   lambda: dict(path=EXAMPLE, height_unit="um"),
                   scalars=dict(path="object", height_unit="choice", detrend="choice optional",
                                fill="choice optional", square="choice", reader="choice",
                                channel="integer optional")),
        EntryPoint("validation.SurfaceStatistics", validation.SurfaceStatistics, _statistics,
                   scalars={name: "non_negative" for name in _statistics() if name != "nayak"}),
        EntryPoint("validation.Scene", validation.Scene,
                   lambda: dict(name="demo", kind="theory", theory=_theory_scene().theory,
                                realizations=3, seed=0, e_star=1.0, m=1.0),
                   scalars=dict(name="text", kind="choice", theory="object optional",
                                realizations="integer", seed="integer", e_star="positive",
                                m="non_negative", surface="object optional",
                                loads="object", bem="object", quick="object")),
        EntryPoint("validation.builtin_scenes", validation.builtin_scenes, dict),
        EntryPoint("validation.parse_scene(source, name, folder)", validation.parse_scene,
                   lambda: dict(data={"kind": "theory", "theory": {"C": [5.0]}},
                                source="<memory>", name="demo", folder="."),
                   scalars=dict(source="text", name="text optional", folder="path optional")),
        EntryPoint("validation.run_scenes(options)", validation.run_scenes,
                   lambda: dict(scenes=(), progress=False, executor=None, cache_dir=None,
                                stream=None),
                   scalars=dict(executor="object optional", cache_dir="path optional",
                                stream="object optional")),
        EntryPoint("validation.write_report", validation.write_report,
                   lambda: dict(results=[], folder=_scratch().name, seconds=1.0, mode="quick",
                                command="python -m validation report"),
                   scalars=dict(results="object", folder="path", seconds="non_negative optional",
                                mode="text", command="text optional",
                                cache_dir="path optional", figure_jobs="object optional")),
        EntryPoint("validation.radial_power_spectrum", validation.radial_power_spectrum,
                   lambda: dict(heights=z(), spacing=SPACING, bins=8),
                   scalars=dict(spacing="positive", bins="integer"), arrays=dict(heights="")),
        EntryPoint("validation.short_wavelength_cutoff", validation.short_wavelength_cutoff,
                   lambda: dict(heights=z(), spacing=SPACING, cutoff=4 * SPACING),
                   scalars=dict(spacing="positive", cutoff="positive"), arrays=dict(heights="")),
        EntryPoint("validation.Topography", validation.Topography,
                   lambda: dict(heights=z(), spacing=SPACING, physical_size=(1.0, 1.0), unit="m",
                                source="memory"),
                   scalars=dict(spacing="positive", physical_size="object size", unit="choice",
                                source="text"),
                   arrays=dict(heights="")),
        EntryPoint("validation.curve_errors(options)", validation.curve_errors,
                   lambda: dict(model=curve(), reference=curve(), sigma=0.01,
                                quantities=("separation", "area"), load_rtol=1e-6),
                   scalars=dict(model="object", reference="object", quantities="object",
                                load_rtol="non_negative")),
        EntryPoint("validation.compare_realizations(options)", validation.compare_realizations,
                   lambda: dict(results=realizations(), tolerances=(0.05, 0.2), confidence=0.95),
                   scalars=dict(confidence="positive")),
    )
