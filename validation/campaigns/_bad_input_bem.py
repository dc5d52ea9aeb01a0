"""Rows of the bad-input campaign for the names :mod:`bem` exports (see
:mod:`validation.campaigns._bad_input_table`)."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from validation.campaigns._bad_input_fixtures import N, SPACING, EntryPoint, curve, surface

__all__ = ["rows"]


@functools.lru_cache(maxsize=1)
def _solution():
    import bem

    z = surface()
    return bem.solve_contact(z, SPACING, load=float(np.ptp(z)) * 0.05, tol=1e-6, max_iter=50)


def _solution_fields() -> dict:
    found = _solution()
    return {item.name: getattr(found, item.name) for item in dataclasses.fields(found)}


def rows() -> tuple[EntryPoint, ...]:
    """One row per name :mod:`bem` exports, and per public method with arguments."""
    import bem

    z = surface
    bem_fast = dict(tol=1e-6, max_iter=50)
    hertz_load = float(np.max(z()) - np.mean(z())) * 0.05
    model = functools.partial(bem.BoundaryElementModel, z(), SPACING, **bem_fast)
    interface = functools.partial(bem.InterfaceModel, z(), SPACING, **bem_fast)
    nominal = functools.partial(bem.NominalContactModel, z(), SPACING, nominal_size=1.0,
                                **bem_fast)
    return (
        # ---------------------------------------------------------------- bem
        EntryPoint("bem.solve_contact", bem.solve_contact,
                   lambda: dict(heights=z(), spacing=SPACING, load=hertz_load, **bem_fast),
                   scalars=dict(spacing="positive", load="non_negative", e_star="positive",
                                tol="positive", max_iter="integer"),
                   arrays=dict(heights="")),
        EntryPoint("bem.solve_contact(separation)", bem.solve_contact,
                   lambda: dict(heights=z(), spacing=SPACING, separation=float(z().max()) * 0.5,
                                **bem_fast),
                   scalars=dict(separation="real")),
        EntryPoint("bem.contact_curve", bem.contact_curve,
                   lambda: dict(heights=z(), spacing=SPACING, loads=[hertz_load], **bem_fast),
                   scalars=dict(spacing="positive", e_star="positive", tol="positive",
                                max_iter="integer", area_estimator="choice"),
                   arrays=dict(heights="", loads="")),
        EntryPoint("bem.HalfSpace", bem.HalfSpace,
                   lambda: dict(shape=(N, N), spacing=SPACING),
                   scalars=dict(spacing="positive", e_star="positive",
                                threads="integer optional", backend="choice",
                                planner_effort="choice optional")),
        EntryPoint("HalfSpace.displacement",
                   lambda pressure: bem.HalfSpace((N, N), SPACING).displacement(pressure),
                   lambda: dict(pressure=np.full((N, N), 1e-3)), arrays=dict(pressure="")),
        EntryPoint("bem.ContactCurve", bem.ContactCurve,
                   lambda: dict(separation=[1.0, 0.5], load=[0.0, 1.0], area=[0.0, 0.1],
                                mean_pressure=[0.0, 1.0], nominal_area=1.0, e_star=1.0),
                   scalars=dict(nominal_area="positive", e_star="positive")),
        EntryPoint("bem.count_contacts", bem.count_contacts,
                   lambda: dict(contact=z() > 0), arrays=dict(contact="mask")),
        EntryPoint("ContactCurve.quantity", lambda name: curve().quantity(name),
                   lambda: dict(name="area"), scalars=dict(name="choice")),
        EntryPoint("bem.contact_curve(callback, operator)", bem.contact_curve,
                   lambda: dict(heights=z(), spacing=SPACING, loads=[hertz_load],
                                callback=lambda index, solution: None,
                                operator=bem.HalfSpace((N, N), SPACING), **bem_fast),
                   scalars=dict(callback="callable optional", operator="object optional",
                                quantities="object")),
        EntryPoint("bem.solve_contact(operator, initial)", bem.solve_contact,
                   lambda: dict(heights=z(), spacing=SPACING, load=hertz_load,
                                operator=bem.HalfSpace((N, N), SPACING),
                                initial=np.full((N, N), 1e-3), **bem_fast),
                   scalars=dict(operator="object optional"), arrays=dict(initial="optional")),
        EntryPoint("ContactCurve.reshaped", lambda shape: curve().reshaped(shape),
                   lambda: dict(shape=(2, 1)), scalars=dict(shape="object")),
        EntryPoint("bem.ContactSolution", bem.ContactSolution, _solution_fields,
                   scalars=dict(load="non_negative", mean_pressure="non_negative",
                                area="non_negative", separation="real", mean_gap="real",
                                iterations="integer", message="text", nominal_area="positive",
                                e_star="positive", pixel_area="non_negative optional"),
                   arrays=dict(pressure="", displacement="", gap="", contact="mask")),
        EntryPoint("bem.BoundaryElementModel", bem.BoundaryElementModel,
                   lambda: dict(heights=z(), spacing=SPACING, **bem_fast),
                   scalars=dict(spacing="positive", tol="positive", max_iter="integer"),
                   arrays=dict(heights="")),
        EntryPoint("BoundaryElementModel.at_load", lambda load: model().at_load(load),
                   lambda: dict(load=np.array([hertz_load])), arrays=dict(load="")),
        EntryPoint("BoundaryElementModel.at_separation",
                   lambda separation: model().at_separation(separation),
                   lambda: dict(separation=np.array([float(z().max()) * 0.5])),
                   arrays=dict(separation="")),
        EntryPoint("bem.InterfaceModel", bem.InterfaceModel,
                   lambda: dict(heights=z(), spacing=SPACING, **bem_fast),
                   scalars=dict(spacing="positive", tol="positive", max_iter="integer",
                                extension="choice"),
                   arrays=dict(heights="")),
        EntryPoint("InterfaceModel.at_load", lambda load: interface().at_load(load),
                   lambda: dict(load=np.array([hertz_load])), arrays=dict(load="")),
        EntryPoint("InterfaceModel.at_separation",
                   lambda separation: interface().at_separation(separation),
                   lambda: dict(separation=np.array([float(z().max()) * 0.5])),
                   arrays=dict(separation="")),
        EntryPoint("bem.NominalContactModel", bem.NominalContactModel,
                   lambda: dict(heights=z(), spacing=SPACING, nominal_size=1.0, **bem_fast),
                   scalars=dict(spacing="positive", nominal_size="positive", tol="positive",
                                max_iter="integer"),
                   arrays=dict(heights="")),
        EntryPoint("NominalContactModel.at_load", lambda load: nominal().at_load(load),
                   lambda: dict(load=np.array([hertz_load])), arrays=dict(load="")),
        EntryPoint("NominalContactModel.at_separation",
                   lambda separation: nominal().at_separation(separation),
                   lambda: dict(separation=np.array([float(z().max()) * 0.5])),
                   arrays=dict(separation="")),
        EntryPoint("bem.hydraulic_aperture", bem.hydraulic_aperture,
                   lambda: dict(gap=np.maximum(_solution().gap, 0.0), spacing=SPACING),
                   scalars=dict(spacing="positive", direction="choice"), arrays=dict(gap="")),
    )
