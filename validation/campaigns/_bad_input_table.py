"""The entry-point table of the bad-input campaign (:mod:`validation.campaigns.bad_input`).

Each row is a valid call of one public function or constructor on small inputs (an 8 x 8 WM
surface, a few summits), fast enough to be called hundreds of times in the test suite.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, Callable
import pathlib

import numpy as np

__all__ = ["EntryPoint", "table"]


@dataclass(frozen=True)
class EntryPoint:
    """One public callable and a valid call of it.

    ``call(**arguments())`` must succeed. ``scalars`` maps a parameter to its domain:
    ``"real"``, ``"positive"``, ``"non_negative"`` or ``"integer"`` (a seed is an
    ``"integer"``), ``"choice"`` (a name such as an FFT backend) or ``"object"`` (one of the
    project's objects, or a path): no value of :data:`validation.campaigns.bad_input.BAD_SCALARS` is valid for these two; plus
    the word ``"optional"`` when ``None`` is a valid value. ``arrays`` maps an array parameter
    to ``""`` or to words among ``"optional"`` (None is valid), ``"inf"`` (+inf entries are
    valid, e.g. a separation out of contact), ``"nan"`` (NaN entries are valid, e.g. an error
    not computed) and ``"mask"`` (booleans are valid: a contact map).
    """

    name: str
    call: Callable[..., Any]
    arguments: Callable[[], dict]
    scalars: dict = field(default_factory=dict)
    arrays: dict = field(default_factory=dict)


_N = 8
_SPACING = 1.0 / _N
#: The shipped example map (a Gwyddion ASCII export that states its size and unit).
_EXAMPLE = str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "example_topography.txt")


@functools.lru_cache(maxsize=1)
def _surface() -> np.ndarray:
    from validation.surfaces.wm import wm_surface

    heights = wm_surface(_N, D=2.3, rms_slope=0.1, seed=1)
    heights.setflags(write=False)
    return heights


def _points():
    return dict(x=np.array([0.0, 1.0, 2.0]), y=np.array([0.0, 0.0, 1.0]))


def _gw(**extra):
    return dict(density=50.0, radius=0.05, sigma=0.01, **extra)


def _curve():
    from asperity import GreenwoodWilliamson

    return GreenwoodWilliamson(**_gw()).at_load(np.array([1e-4, 1e-3]))


@functools.lru_cache(maxsize=1)
def _summits():
    from asperity import find_summits

    return find_summits(_surface(), _SPACING)


def _realizations() -> list:
    """Three duck-typed realization results (a BEM-labelled reference and a GW curve); the
    reference carries its own per-point error estimates, as a BEM run with
    ``error_estimate=True`` does (without them its band is NaN, "not estimated", by design).
    Three, the fewest with a per-surface tolerance interval (fewer leave it NaN, by design)."""
    from dataclasses import replace
    from types import SimpleNamespace

    curve = _curve()
    estimates = {f"{name}_error": 0.01 * np.abs(getattr(curve, name))
                 for name in ("area", "separation", "load")}
    reference = replace(curve, extras={**curve.extras, **estimates})
    task = SimpleNamespace(seed=0, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                           quantities=("area", "separation"), sweep_value=2.3)
    return [SimpleNamespace(task=task, curves={"bem": reference, "gw": curve}, sigma=0.01)] * 3


def _theories(model, load=(1e-4, 1e-3), separation=(0.0, 0.01)):
    """A GW-type theory evaluated along both paths (the parameters meet at the evaluation)."""
    def call(**parameters):
        theory = model(**parameters)
        return theory.at_load(np.array(load)), theory.at_separation(np.array(separation))
    return call


def _range(**arguments):
    from validation import validity_range

    found = validity_range(**arguments)   # NaN bounds mean "holds nowhere", by design
    return found.points, found.total


def table() -> tuple[EntryPoint, ...]:
    import asperity
    import bem
    import validation

    z = _surface
    bem_fast = dict(tol=1e-6, max_iter=50)
    hertz_load = float(np.max(z()) - np.mean(z())) * 0.05
    return (
        # ---------------------------------------------------------------- bem
        EntryPoint("bem.solve_contact", bem.solve_contact,
                   lambda: dict(heights=z(), spacing=_SPACING, load=hertz_load, **bem_fast),
                   scalars=dict(spacing="positive", load="non_negative", e_star="positive",
                                tol="positive", max_iter="integer"),
                   arrays=dict(heights="")),
        EntryPoint("bem.solve_contact(separation)", bem.solve_contact,
                   lambda: dict(heights=z(), spacing=_SPACING, separation=float(z().max()) * 0.5,
                                **bem_fast),
                   scalars=dict(separation="real")),
        EntryPoint("bem.contact_curve", bem.contact_curve,
                   lambda: dict(heights=z(), spacing=_SPACING, loads=[hertz_load], **bem_fast),
                   scalars=dict(spacing="positive", e_star="positive", tol="positive",
                                max_iter="integer", area_estimator="choice"),
                   arrays=dict(heights="", loads="")),
        EntryPoint("bem.HalfSpace", bem.HalfSpace,
                   lambda: dict(shape=(_N, _N), spacing=_SPACING),
                   scalars=dict(spacing="positive", e_star="positive",
                                threads="integer optional", backend="choice",
                                planner_effort="choice optional")),
        EntryPoint("bem.HalfSpace.displacement",
                   lambda pressure: bem.HalfSpace((_N, _N), _SPACING).displacement(pressure),
                   lambda: dict(pressure=np.full((_N, _N), 1e-3)), arrays=dict(pressure="")),
        EntryPoint("bem.ContactCurve", bem.ContactCurve,
                   lambda: dict(separation=[1.0, 0.5], load=[0.0, 1.0], area=[0.0, 0.1],
                                mean_pressure=[0.0, 1.0], nominal_area=1.0, e_star=1.0),
                   scalars=dict(nominal_area="positive", e_star="positive")),
        EntryPoint("bem.count_contacts", bem.count_contacts,
                   lambda: dict(contact=z() > 0), arrays=dict(contact="mask")),
        EntryPoint("ContactCurve.quantity", lambda name: _curve().quantity(name),
                   lambda: dict(name="area"), scalars=dict(name="choice")),
        # ---------------------------------------------------------------- GW functions
        EntryPoint("asperity.gw_integral", asperity.gw_integral,
                   lambda: dict(n=1.5, h=np.array([-1.0, 0.0, 2.0])), scalars=dict(n="real"),
                   arrays=dict(h="inf")),
        EntryPoint("asperity.log_gw_integral", asperity.log_gw_integral,
                   lambda: dict(n=1.0, h=np.array([-1.0, 0.0, 2.0])), scalars=dict(n="real"),
                   arrays=dict(h="inf")),
        EntryPoint("asperity.GreenwoodWilliamson", asperity.GreenwoodWilliamson, _gw,
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive")),
        EntryPoint("GreenwoodWilliamson.at_separation",
                   lambda separation: asperity.GreenwoodWilliamson(**_gw()).at_separation(
                       separation),
                   lambda: dict(separation=np.array([0.0, 0.01, 0.03])),
                   arrays=dict(separation="inf")),
        EntryPoint("GreenwoodWilliamson.at_load",
                   lambda load: asperity.GreenwoodWilliamson(**_gw()).at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("GreenwoodWilliamson curves", _theories(asperity.GreenwoodWilliamson),
                   lambda: _gw(mean=0.0, e_star=1.0, area=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive")),
        EntryPoint("ImprovedGreenwoodWilliamson curves",
                   _theories(asperity.ImprovedGreenwoodWilliamson),
                   lambda: _gw(mean=0.0, e_star=1.0, area=1.0, m=1.0),
                   scalars=dict(density="positive", radius="positive", sigma="positive",
                                mean="real", e_star="positive", area="positive",
                                m="non_negative")),
        EntryPoint("asperity.ImprovedGreenwoodWilliamson", asperity.ImprovedGreenwoodWilliamson,
                   lambda: _gw(m=1.0), scalars=dict(m="non_negative", sigma="positive")),
        EntryPoint("ImprovedGreenwoodWilliamson.at_separation",
                   lambda separation: asperity.ImprovedGreenwoodWilliamson(
                       **_gw()).at_separation(separation),
                   lambda: dict(separation=np.array([0.0, 0.01, 0.03])),
                   arrays=dict(separation="inf")),
        EntryPoint("ImprovedGreenwoodWilliamson.at_load",
                   lambda load: asperity.ImprovedGreenwoodWilliamson(**_gw()).at_load(load),
                   lambda: dict(load=np.array([1e-4, 1e-3])), arrays=dict(load="")),
        EntryPoint("ImprovedGreenwoodWilliamson.effective_reduced_separation",
                   lambda h: asperity.ImprovedGreenwoodWilliamson(
                       **_gw()).effective_reduced_separation(h),
                   lambda: dict(h=np.array([-1.0, 0.0, 2.0])), arrays=dict(h="inf")),
        # ---------------------------------------------------------------- other asperity
        EntryPoint("asperity.holm_greenwood", asperity.holm_greenwood,
                   lambda: dict(**_points(), radii=np.array([0.1, 0.2, 0.1])),
                   arrays=dict(x="", y="", radii="")),
        EntryPoint("asperity.dimensionless", asperity.dimensionless,
                   lambda: dict(curve=_curve(), sigma=0.01, length=1.0),
                   scalars=dict(sigma="positive", length="positive")),
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
                   lambda: dict(summits=_summits(), tol=1e-8, max_iter=20, e_star=1.0),
                   scalars=dict(tol="positive", max_iter="integer", e_star="positive",
                                m="non_negative optional", method="choice")),
        EntryPoint("asperity.radial_power_spectrum", asperity.radial_power_spectrum,
                   lambda: dict(heights=z(), spacing=_SPACING, window="hann"),
                   scalars=dict(spacing="positive", window="choice"), arrays=dict(heights="")),
        EntryPoint("IsotropicSpectrum.moment",
                   lambda order: asperity.radial_power_spectrum(z(), _SPACING).moment(order),
                   lambda: dict(order=2), scalars=dict(order="real")),
        EntryPoint("asperity.separation_kernel", asperity.separation_kernel,
                   lambda: dict(x=np.array([0.1, 1.0, 3.0]), gamma=0.42),
                   scalars=dict(gamma="positive"), arrays=dict(x="inf")),
        EntryPoint("asperity.find_summits", asperity.find_summits,
                   lambda: dict(heights=z(), spacing=_SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("asperity.Summits.from_points", asperity.Summits.from_points,
                   lambda: dict(**_points(), height=np.array([0.1, 0.2, 0.3]),
                                radius=np.array([0.1, 0.1, 0.2]), area=4.0),
                   scalars=dict(area="positive"),
                   arrays=dict(x="", y="", height="", radius="")),
        EntryPoint("Summits.greenwood_williamson",
                   lambda area, e_star: asperity.find_summits(z(), _SPACING).greenwood_williamson(
                       area, e_star=e_star),
                   lambda: dict(area=1.0, e_star=1.0),
                   scalars=dict(area="positive optional", e_star="positive")),
        EntryPoint("asperity.PointForceInteraction", asperity.PointForceInteraction,
                   lambda: dict(**_points(), e_star=1.0, spacing=1.0, row=np.array([0, 0, 1]),
                                column=np.array([0, 1, 2])),
                   scalars=dict(e_star="positive", spacing="positive optional", threads="integer",
                                method="choice", fft_backend="choice"),
                   arrays=dict(x="", y="")),
        EntryPoint("PointForceInteraction.displacement",
                   lambda forces: asperity.PointForceInteraction(**_points()).displacement(
                       forces),
                   lambda: dict(forces=np.array([1.0, 2.0, 3.0])), arrays=dict(forces="")),
        # ---------------------------------------------------------------- validation
        EntryPoint("validation.wm_surface", validation.wm_surface,
                   lambda: dict(n=_N, D=2.3, rms_slope=0.1, seed=1),
                   scalars=dict(n="integer", D="real", rms_slope="positive", L="positive",
                                gamma="real", M="integer", n_max="integer",
                                seed="integer optional")),
        EntryPoint("validation.self_affine_surface", validation.self_affine_surface,
                   lambda: dict(n=_N, hurst=0.8, rms_height=1.0, seed=1),
                   scalars=dict(n="integer", hurst="positive", rms_height="positive",
                                L="positive", window="integer optional",
                                seed="integer optional")),
        EntryPoint("validation.wm_surface(G)", validation.wm_surface,
                   lambda: dict(n=_N, D=2.3, G=1e-3, seed=1), scalars=dict(G="positive")),
        EntryPoint("validation.wm_amplitude", validation.wm_amplitude,
                   lambda: dict(G=1e-3, D=2.3),
                   scalars=dict(G="positive", D="real", L="positive", gamma="real",
                                M="integer")),
        EntryPoint("validation.surface_statistics", validation.surface_statistics,
                   lambda: dict(heights=z(), spacing=_SPACING),
                   scalars=dict(spacing="positive"), arrays=dict(heights="")),
        EntryPoint("validation.curve_errors", validation.curve_errors,
                   lambda: dict(model=_curve(), reference=_curve(), sigma=0.01,
                                quantities=("separation", "area")),
                   scalars=dict(sigma="positive")),
        EntryPoint("validation.validity_range", _range,
                   lambda: dict(loads=np.array([1.0, 2.0, 3.0]),
                                errors=np.array([0.01, 0.5, 0.02]), tolerance=0.1,
                                area_fraction=np.array([0.01, 0.02, 0.03])),
                   scalars=dict(tolerance="positive"),
                   arrays=dict(loads="", errors="nan inf", area_fraction="optional")),
        EntryPoint("validation.compare_realizations", validation.compare_realizations,
                   lambda: dict(results=_realizations(), tolerances=(0.05, 0.2)),
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
                   lambda: dict(path=_EXAMPLE, height_unit="um"),
                   scalars=dict(path="object", height_unit="choice", detrend="choice optional",
                                fill="choice optional", square="choice", reader="choice",
                                channel="integer optional")),
    )
