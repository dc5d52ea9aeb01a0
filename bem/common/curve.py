"""The contact curve: the one record every model returns.

Every model of the project (Greenwood-Williamson, improved GW, the discrete asperity model and
the boundary-element reference) answers the same question, "what happens at these separations
or loads?", with a :class:`ContactCurve`. The validation package compares curves field by field
without adapters.

Units and conventions (docs/theory.md, "Conventions used everywhere")
-----------------------------------------------------------------------
* ``separation`` d [length]: rigid plane to the mean plane of the surface heights, in the far
  field.
* ``load`` W [force]: total normal force on the nominal area.
* ``area`` [length^2]: real contact area.
* ``contacts`` [-]: number of contact spots (asperities in contact, or connected contact patches
  for the boundary-element solver).
* ``stiffness`` S = -dW/dd [force/length].
* ``conductance`` = 2 S / E* [length]: the constriction conductance times the resistivity rho
  (C rho, Barber's analogy).
* ``mean_pressure`` = W / A_nominal [pressure].
* ``leakage`` h_eff [length]: effective hydraulic aperture of the gap, the uniform gap that
  leaks as much, ``Q = W h_eff^3 dp / (12 mu L)``; for the BEM the exact Reynolds flow through
  its gap (:func:`bem.leakage.flow.leakage_aperture`: mean leak rate of flow along x and along y), 0
  once the contact seals.

Fields a model did not compute (not asked for) are ``None``; separation, load, area and
mean_pressure are always filled. Every field has the shape of the separations or loads asked for
(numpy's rule: a scalar gives 0-d arrays, an array of shape s gives arrays of shape s).

Extras
------
Model-specific results live in the read-only mapping ``extras`` and are read as
``curve.extras["name"]`` (attribute access, ``curve.effective_separation``, still works but is
deprecated). Per-point extras have the curve's shape; per-asperity extras (``forces``,
``contact_radii``) have the curve's shape followed by the number of asperities. Names in use:

* ``converged`` (bool, every model): the point met its model's stopping rule; all True for
  closed forms (GW theory at a separation).
* ``residual`` [-]: relative residual of the model's own equations at the returned point, the
  number compared with the model's ``tol`` (see :mod:`bem.model`, "Residual").
* ``iterations`` (int): solver iterations spent on the point (all sub-steps included).
* ``mean_gap`` [length] (BEM): mean gap between the surfaces over the nominal area.
* ``effective_separation`` d1 [length], ``gw_stiffness`` S1 [force/length] (improved GW).
* ``forces`` [force], ``contact_radii`` [length], ``stable``, ``overlapping_spots``,
  ``stiffness_converged``, ``holm_greenwood_conductance`` [length] (discrete model).
* ``<quantity>_error`` (BEM, when asked for): absolute estimate of the discretisation error of
  that quantity, same units and shape.

This module lives in ``bem`` because ``bem`` imports nothing else of the project, while both
``asperity`` and ``validation`` may import ``bem``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import Any, Iterable, Mapping

import numpy as np

from bem.common.checks import InputTypeError
from bem.common.checks import integer as _integer
from bem.common.checks import frozen_array as _frozen_array
from bem.common.checks import positive as _positive
from bem.common.checks import real_array as _real_array

__all__ = ["ContactCurve", "CURVE_QUANTITIES", "check_quantities"]

#: The quantities a contact curve may carry, in the order they are tabulated.
CURVE_QUANTITIES = ("separation", "load", "area", "contacts", "stiffness", "conductance",
                    "mean_pressure", "leakage")


def check_quantities(quantities: Iterable[str] | str,
                     allowed: tuple[str, ...] = CURVE_QUANTITIES) -> frozenset[str]:
    """The set of quantities asked for; ``ValueError`` naming ``quantities`` if one is unknown."""
    if isinstance(quantities, str):
        quantities = (quantities,)
    if isinstance(quantities, (bytes, bytearray, memoryview)):   # iterates as integers
        raise TypeError(f"quantities must be strings among {allowed}, got {quantities!r}")
    try:
        want = frozenset(quantities)
    except TypeError:
        raise ValueError(f"quantities must be strings among {allowed}, got {quantities!r}") \
            from None
    unknown = sorted(str(q) for q in want - set(allowed))
    if unknown:
        raise ValueError(f"quantities must be among {allowed}, got unknown {unknown}")
    return want


@dataclass(frozen=True, eq=False)
class ContactCurve:
    """Contact quantities along a path of separations or loads (one entry per point).

    Parameters
    ----------
    separation, load, area, mean_pressure : array_like
        See the module docstring for units. All arrays share one shape.
    contacts, stiffness, conductance, leakage : array_like or None
        ``None`` when the model was not asked for them.
    nominal_area : float
        Nominal contact area A = L^2 [length^2].
    e_star : float
        Composite modulus E* [pressure].
    extras : mapping of str to array_like
        Model-specific results (see the module docstring), read as ``extras["name"]``.
    """

    separation: np.ndarray
    load: np.ndarray
    area: np.ndarray
    mean_pressure: np.ndarray
    nominal_area: float
    e_star: float
    contacts: np.ndarray | None = None
    stiffness: np.ndarray | None = None
    conductance: np.ndarray | None = None
    leakage: np.ndarray | None = None
    extras: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        shape = None
        for f in fields(self):
            if f.name in ("nominal_area", "e_star", "extras"):
                continue
            value = getattr(self, f.name)
            # real numbers, NaN and inf allowed (unreached points, infinite stiffness); a
            # string, complex or ragged field is refused naming it
            array = None if value is None else _frozen_array(
                _real_array(f"ContactCurve field {f.name!r}", value, finite=False))
            if array is not None:
                if shape is None:
                    shape = array.shape
                elif array.shape != shape:
                    raise ValueError(
                        f"ContactCurve field {f.name!r} has shape {array.shape}, expected {shape}"
                    )
            object.__setattr__(self, f.name, array)
        for name in ("nominal_area", "e_star"):
            object.__setattr__(self, name, _positive(name, getattr(self, name)))
        extras = {}
        for key, value in dict(self.extras).items():
            if isinstance(value, np.ndarray):
                value = value.copy()
                value.setflags(write=False)
            extras[key] = value
        object.__setattr__(self, "extras", MappingProxyType(extras))

    def __reduce__(self):
        # The extras mapping is a read-only proxy, which pickle cannot store: rebuild from a dict
        # (curves travel between processes when realizations fan out over an executor).
        state = {f.name: getattr(self, f.name) for f in fields(self)}
        state["extras"] = dict(self.extras)
        return (_rebuild_curve, (state,))

    def __getattr__(self, name: str) -> Any:
        # Only called when normal lookup fails: the deprecated attribute access to extras.
        extras = self.__dict__.get("extras")
        if extras is not None and name in extras:
            warnings.warn(f"curve.{name} is deprecated: read curve.extras[{name!r}]",
                          DeprecationWarning, stacklevel=2)
            return extras[name]
        raise AttributeError(f"{type(self).__name__!s} has no field or extra {name!r}")

    def __len__(self) -> int:
        return int(np.size(self.load))

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the separations or loads the curve was computed at (``()`` for a scalar)."""
        return self.load.shape

    def reshaped(self, shape: tuple[int, ...]) -> "ContactCurve":
        """The same curve with every field, and the leading axis of every per-point extra,
        reshaped to ``shape`` (same number of points)."""
        count = len(self)
        if isinstance(shape, (str, bytes)) or not isinstance(shape, (tuple, list)):
            raise InputTypeError(f"shape must be a tuple of integers >= 0, got "
                                 f"{type(shape).__name__} {shape!r}")
        shape = tuple(_integer(f"shape[{index}]", value, minimum=0)
                      for index, value in enumerate(shape))
        if int(np.prod(shape, dtype=int)) != count:
            raise ValueError(f"shape {shape} does not hold the curve's {count} points")
        state = {f.name: getattr(self, f.name) for f in fields(self)}
        for name in CURVE_QUANTITIES:
            if state[name] is not None:
                state[name] = state[name].reshape(shape)
        extras = {}
        for key, value in self.extras.items():
            array = np.asarray(value)
            if array.ndim >= 1 and array.shape[:self.load.ndim] == self.load.shape:
                value = array.reshape(shape + array.shape[self.load.ndim:])
            extras[key] = value
        state["extras"] = extras
        return ContactCurve(**state)

    @property
    def area_fraction(self) -> np.ndarray:
        """Real contact area over nominal area, A_real / A [-]."""
        return self.area / self.nominal_area

    def _computed(self) -> list[str]:
        fields_ = [n for n in CURVE_QUANTITIES if getattr(self, n, None) is not None]
        return fields_ + ["area_fraction", *self.extras]

    def quantity(self, name: str) -> np.ndarray:
        """Return a field or an extra by name; raise ``ValueError`` if it was not computed."""
        if not isinstance(name, str):
            raise InputTypeError(f"name must be a quantity name (a str), got "
                                 f"{type(name).__name__} {name!r}")
        if name in self.extras:
            return self.extras[name]
        readable = name in CURVE_QUANTITIES or name == "area_fraction"
        value = getattr(self, name) if readable else None
        if value is None:
            raise ValueError(f"quantity {name!r} was not computed for this curve (name must be "
                             f"a computed field or an extra: {', '.join(self._computed())})")
        return value


def _rebuild_curve(state: dict) -> ContactCurve:
    return ContactCurve(**state)
