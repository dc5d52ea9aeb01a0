"""The model registry's machinery: the inputs a model is built from (:class:`ModelInputs`),
the registry's entries (:class:`ModelEntry`), :func:`register` and the look-ups by name, label,
style and frame.

:mod:`validation.common.models` re-exports all of it and registers the project's models: import
that module (a model looked up here alone may not be registered yet).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from bem.model import ContactModel

__all__ = ["FRAMES", "FRAME_LABELS", "ModelInputs", "ModelEntry", "register", "unregister", "entry", "names",
           "default_names", "build", "labels", "styles", "reference_names", "reference_among",
           "reference_for", "reference_fields", "frame_of", "frames_of"]

#: The two problems a model may describe (docs/theory.md, section 8.10): an interface of
#: unbounded nominal extent (per unit area, periodic, zero mean displacement), or a finite
#: nominal contact, the L x L window pressed as a whole (its bulk sink in the separation).
FRAMES = ("interface", "finite")
#: How tables and reports name each frame.
FRAME_LABELS = {"interface": "interface", "finite": "finite contact"}


class ModelInputs:
    """What a factory may use to build a model for one surface (realization).

    Parameters
    ----------
    spacing : float
        Grid step of the heights [length].
    nominal_area : float
        Nominal contact area L^2 [length^2].
    heights : array or callable, optional
        The heights [length], or a function making them on first use (the runner makes a
        surface only when a result that needs it is not cached).
    summits : asperity.Summits or callable, optional
        The summits, or a function finding them; default: found on the heights.
    e_star : float
        Composite modulus E* [pressure].
    m : float
        Interaction factor of the improved GW theory (eq. 2).
    bem_options : mapping
        Options of :func:`bem.contact_curve` (``periodic``, ``tol``, ``max_iter``, ...).
    periodic_surface : bool
        The heights are one period of a periodic surface (the interface reference solves them
        as they are; otherwise their mirror extension, :class:`bem.InterfaceModel`).
    nominal_size : float, optional
        Side [length] of the square nominal contact of the finite frame, in place of the
        window (``Scene.nominal_size``): the reference ``bem_nominal`` and improved GW's
        uniform term describe that square.
    """

    def __init__(self, *, spacing: float, nominal_area: float, heights=None, summits=None,
                 e_star: float = 1.0, m: float = 1.0,
                 bem_options: Mapping[str, Any] | None = None,
                 periodic_surface: bool = False, nominal_size: float | None = None) -> None:
        self.periodic_surface = bool(periodic_surface)
        self.nominal_size = None if nominal_size is None else float(nominal_size)
        self.spacing, self.nominal_area = float(spacing), float(nominal_area)
        self.e_star, self.m = float(e_star), float(m)
        self.bem_options = dict(bem_options or {})
        self._heights, self._summits = heights, summits

    def with_bem_options(self, **options: Any) -> "ModelInputs":
        """These inputs with ``options`` added to :attr:`bem_options` (a copy)."""
        copy = object.__new__(type(self))
        copy.__dict__.update(self.__dict__)
        copy.bem_options = {**self.bem_options, **options}
        return copy

    @property
    def interaction_m(self) -> float:
        """Improved GW's m for the finite frame's nominal contact: ``m`` for the window, and
        ``m L_n / L`` for a nominal square of side L_n (the uniform term ``m p sqrt(A) / E*``
        of that square on the window's summits and loads)."""
        if self.nominal_size is None:
            return self.m
        return self.m * self.nominal_size / float(np.sqrt(self.nominal_area))

    def heights(self) -> np.ndarray:
        """The height map [length] (made on first call when given as a function)."""
        if self._heights is None:
            raise ValueError("this model needs the heights, and none were given")
        if callable(self._heights):
            self._heights = self._heights()
        return self._heights

    def summits(self):
        """The summits (found on the heights on first call unless given)."""
        if self._summits is None:
            import asperity

            self._summits = asperity.find_summits(self.heights(), self.spacing)
        elif callable(self._summits):
            self._summits = self._summits()
        return self._summits


@dataclass(frozen=True)
class ModelEntry:
    """A registered model.

    Attributes
    ----------
    name : str
        The name scenes use.
    factory : callable
        ``factory(inputs: ModelInputs) -> ContactModel``.
    label : str
        Name in tables and legends.
    style : mapping
        Matplotlib line style of its curves.
    needs_summits : bool
        Built on the summits (the runner finds them, and sigma, only when some model needs
        them).
    cached : bool
        Its load paths are cached by the runner (expensive, or, like GW's, many to invert).
    closed_form : bool
        Evaluated from closed-form expressions: cheap to compute again, so the run-time
        estimate (:mod:`validation.run.cost`) counts nothing for it, cached or not.
    reference : bool
        The exact reference of its frame, which the models of that frame are compared with;
        with a separation path, the other models follow the first reference's loads.
    frame : {"interface", "finite"}
        The problem the model describes (:data:`FRAMES`): an unbounded interface (GW, BGT,
        Persson, the discrete model without interaction) or the finite nominal contact of the
        window (improved GW with its nominal area, the discrete model with interaction).
    inverse_consistent : bool
        ``at_load`` inverts ``at_separation`` (false for an approximation whose load path is
        solved exactly, like the one-iteration improved GW).
    contacts : {"asperities", "patches", "none"}
        What its ``contacts`` counts: asperities in contact (never fewer as the separation
        falls), connected contact patches (which merge, so the count may fall), or nothing
        (the theory does not predict a count: ``contacts`` stays None even when asked for).
    reference_fields : mapping
        quantity -> the reference's field it is compared with, where that is not the field of
        the same name (Persson's separation is a mean gap: ``{"separation": "mean_gap"}``).
    default : bool
        Part of a scene that does not list its models.
    settings : callable
        ``settings(inputs) -> dict``: inputs beyond the surface, E* and the path that determine
        its results (part of its cache key).
    """

    name: str
    factory: Callable[[ModelInputs], ContactModel]
    label: str
    style: Mapping[str, Any] = field(default_factory=dict)
    needs_summits: bool = True
    cached: bool = False
    closed_form: bool = False
    reference: bool = False
    frame: str = "interface"
    inverse_consistent: bool = True
    contacts: str = "asperities"
    default: bool = True
    reference_fields: Mapping[str, str] = field(default_factory=dict)
    settings: Callable[[ModelInputs], dict] = field(default=lambda inputs: {})


_REGISTRY: dict[str, ModelEntry] = {}


def register(name: str, factory: Callable[[ModelInputs], ContactModel], *, label: str,
             **attributes: Any) -> ModelEntry:
    """Register a model under ``name`` (see :class:`ModelEntry` for the attributes)."""
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"name must be an identifier-like string, got {name!r}")
    if name in _REGISTRY:
        raise ValueError(f"a model named {name!r} is already registered")
    item = ModelEntry(name, factory, label, **attributes)
    if item.contacts not in ("asperities", "patches", "none"):
        raise ValueError(f"contacts must be 'asperities', 'patches' or 'none', got {item.contacts!r}")
    if item.frame not in FRAMES:
        raise ValueError(f"frame must be one of {FRAMES}, got {item.frame!r}")
    _REGISTRY[name] = item
    return item


def unregister(name: str) -> None:
    """Remove a registered model (for tests and interactive work)."""
    entry(name)
    del _REGISTRY[name]


def entry(name: str) -> ModelEntry:
    """The registered model ``name``; ``ValueError`` listing the known names otherwise."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ValueError(f"unknown model {name!r}; registered: {', '.join(_REGISTRY)}") from None


def names() -> tuple[str, ...]:
    """Names of all registered models, in registration order."""
    return tuple(_REGISTRY)


def default_names() -> tuple[str, ...]:
    """Names of the models a scene uses unless it lists its own."""
    return tuple(name for name, item in _REGISTRY.items() if item.default)


def reference_names() -> tuple[str, ...]:
    """Names of the reference models."""
    return tuple(name for name, item in _REGISTRY.items() if item.reference)


def reference_for(frame: str) -> str:
    """The name of the first registered reference of ``frame`` (``ValueError`` when there is
    none): the one a scene adds for that frame."""
    if frame not in FRAMES:
        raise ValueError(f"frame must be one of {FRAMES}, got {frame!r}")
    found = [name for name in reference_names() if _REGISTRY[name].frame == frame]
    if not found:
        raise ValueError(f"no reference of the {frame} frame is registered")
    return found[0]


def frame_of(name: str) -> str:
    """The frame of the registered model ``name`` (``"interface"`` or ``"finite"``)."""
    return entry(name).frame


def frames_of(names) -> tuple[str, ...]:
    """The frames of the registered models among ``names``, in the order of :data:`FRAMES`."""
    found = {_REGISTRY[name].frame for name in names if name in _REGISTRY}
    return tuple(frame for frame in FRAMES if frame in found)


def reference_among(names, frame: str | None = None) -> str | None:
    """The registered reference among ``names`` of ``frame`` (``None`` when there is none).

    Without ``frame``: the one reference among ``names``, or, where both frames' references
    are there, the finite window's (the paper's problem; callers that judge a model pass its
    frame). Raises ``ValueError`` for a frame outside :data:`FRAMES`.
    """
    if frame is not None and frame not in FRAMES:
        raise ValueError(f"frame must be one of {FRAMES} or None, got {frame!r}")
    found = [name for name in reference_names() if name in names
             and (frame is None or _REGISTRY[name].frame == frame)]
    if frame is None and len({_REGISTRY[name].frame for name in found}) > 1:
        found = [name for name in found if _REGISTRY[name].frame == "finite"]
    if len(found) > 1:
        raise ValueError(f"several reference models of one frame among the curves: "
                         f"{', '.join(found)}; a comparison needs one per frame")
    return found[0] if found else None


def build(name: str, inputs: ModelInputs) -> ContactModel:
    """The model ``name`` built from ``inputs``; ``TypeError`` if the factory's result does
    not satisfy :class:`bem.ContactModel`."""
    model = entry(name).factory(inputs)
    if not isinstance(model, ContactModel):
        raise TypeError(f"the factory of model {name!r} returned {type(model).__name__}, "
                        "which lacks name, at_load or at_separation (bem.ContactModel)")
    return model


class _Attribute(Mapping):
    """A live, read-only view name -> one attribute of every registered model."""

    def __init__(self, attribute: str) -> None:
        self._attribute = attribute

    def __getitem__(self, name: str) -> Any:
        if name not in _REGISTRY:
            raise KeyError(name)
        return getattr(_REGISTRY[name], self._attribute)

    def __iter__(self):
        return iter(list(_REGISTRY))

    def __len__(self) -> int:
        return len(_REGISTRY)


def reference_fields() -> Mapping[str, Mapping[str, str]]:
    """Model name -> {quantity: reference field it is compared with} (a live view; empty
    where every quantity is compared with the reference's field of the same name)."""
    return _Attribute("reference_fields")


def labels() -> Mapping[str, str]:
    """Model name -> label, in registration order (a live view: later registrations show)."""
    return _Attribute("label")


def styles() -> Mapping[str, Mapping[str, Any]]:
    """Model name -> matplotlib style, in registration order (a live view)."""
    return _Attribute("style")
