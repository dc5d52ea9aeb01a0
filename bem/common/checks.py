"""Input checks shared by every module of the project: one wording for one kind of mistake.

The rules, written once:

* a *number* is a finite real scalar: a Python ``int``/``float``, a numpy integer or floating
  scalar, or a 0-d real array. Strings (even ``'0.5'``), bytes, ``None``, booleans and complex
  numbers are a :class:`TypeError`; NaN, +-inf and values outside the allowed range are a
  :class:`ValueError`.
* an *integer* is an ``int`` or numpy integer (not a bool, not a float with no fraction).
* an *array* is anything numpy turns into a real numeric array (lists, tuples, read-only arrays,
  memory maps); strings, objects, booleans and complex values are a :class:`TypeError`, NaN/inf
  and wrong shapes a :class:`ValueError`.

Every message names the parameter, what was given and what is allowed; no check lets an
exception from inside numpy or the standard library escape.

The checks live in :mod:`bem.common.scalar_checks` (numbers, names, objects) and
:mod:`bem.common.array_checks` (arrays); this module gathers them under one name
(``from bem.common import checks``) and adds those of a contact problem: magnitudes in the range the
boundary-element solver supports.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from bem.common.array_checks import (boolean_map, frozen_array, height_map, integer_array, no_overflow,
                              point_mask, points, real_array, record_array, record_arrays,
                              separations)
from bem.common.scalar_checks import (InputTypeError, choice, file_path, flag, instances, integer, names,
                               non_negative, non_negative_or_infinite, optional_callable,
                               optional_integer, positive, random_generator, real_number)

__all__ = [
    "InputTypeError",
    "SUPPORTED_MAGNITUDE",
    "below_supported_magnitude",
    "boolean_map",
    "choice",
    "contact_heights",
    "contact_number",
    "contact_path",
    "contact_problem",
    "curve_error_arguments",
    "file_path",
    "flag",
    "frozen_array",
    "height_map",
    "instances",
    "integer",
    "integer_array",
    "names",
    "no_overflow",
    "non_negative",
    "non_negative_or_infinite",
    "optional_callable",
    "optional_integer",
    "point_mask",
    "points",
    "positive",
    "random_generator",
    "real_array",
    "real_number",
    "record_array",
    "record_arrays",
    "separations",
    "supported_magnitude",
]


def curve_error_arguments(sigma: Any, quantities: Any, allowed: Iterable[str]
                          ) -> tuple[float, tuple[str, ...]]:
    """Checked ``(sigma, quantities)`` of a comparison of two contact curves: sigma > 0 [length]
    in the supported range, quantities known by name."""
    sigma = supported_magnitude("sigma", positive("sigma", sigma))
    return sigma, names("quantities", quantities, allowed)


#: Magnitudes the boundary-element solver supports for lengths, moduli, loads and heights: any
#: physical unit system fits (SI: E* ~ 1e11 Pa, spacings ~ 1e-9 m, loads 1e-12..1e6 N), and
#: products of powers of them (pressures^2 in the CG dot products) stay far from over/underflow.
SUPPORTED_MAGNITUDE = (1e-30, 1e30)


def supported_magnitude(name: str, value: float) -> float:
    """``value`` if it is 0 or its magnitude lies in :data:`SUPPORTED_MAGNITUDE`."""
    low, high = SUPPORTED_MAGNITUDE
    size = abs(value)
    if size != 0.0 and not low <= size <= high:
        raise ValueError(f"{name} = {value!r} is outside the supported range: its magnitude "
                         f"must be 0 or between {low:g} and {high:g} (rescale the units)")
    return value


def below_supported_magnitude(name: str, values: np.ndarray) -> np.ndarray:
    """``values`` if no magnitude exceeds the upper end of :data:`SUPPORTED_MAGNITUDE` (loads
    and separations of a model: small ones are fine, huge ones overflow its forces)."""
    if values.size and float(np.max(np.abs(values))) > SUPPORTED_MAGNITUDE[1]:
        supported_magnitude(f"max |{name}|", float(np.max(np.abs(values))))
    return values


def contact_number(name: str, value: Any, *, minimum: float | None = None,
                   exclusive: bool = False) -> float:
    """A finite real number (bounded below) of a contact problem, in the supported range."""
    return supported_magnitude(name, real_number(name, value, minimum=minimum,
                                                 exclusive=exclusive))


def contact_heights(name: str, values: Any, *, minimum: int) -> np.ndarray:
    """A finite, real height map of at least ``minimum`` x ``minimum`` points (N x M: square
    pixels, any number of rows and columns) whose largest magnitude lies in the supported range
    (a fresh float64 copy; a read-only float64 array that owns its data, which nothing changes,
    as it is: a model's frozen heights, not copied again for each of its paths, 34 MB at
    2048^2)."""
    frozen = (isinstance(values, np.ndarray) and values.dtype == np.float64
              and not values.flags.writeable and values.flags.owndata)
    z = height_map(name, values, minimum=minimum)
    if not frozen:
        z = np.array(z, dtype=float, copy=True)
    supported_magnitude(f"max |{name}|", max(float(z.max()), -float(z.min())))
    return z


def contact_problem(heights: Any, spacing: Any, e_star: Any, tol: Any, max_iter: Any,
                    periodic: Any, *, minimum_grid: int):
    """Checked ``(heights, spacing, e_star, tol, max_iter, periodic)`` of a contact problem."""
    z = contact_heights("heights", heights, minimum=minimum_grid)
    spacing = contact_number("spacing", spacing, minimum=0.0, exclusive=True)
    e_star = contact_number("e_star", e_star, minimum=0.0, exclusive=True)
    tol = contact_number("tol", tol, minimum=0.0, exclusive=True)
    return z, spacing, e_star, tol, integer("max_iter", max_iter, minimum=1), flag("periodic",
                                                                                 periodic)


def contact_path(name: str, values: Any, *, non_negative: bool) -> np.ndarray:
    """A non-empty 1-D sequence of loads or separations (a scalar is one point), finite, in the
    supported range (a fresh float64 copy)."""
    array = np.array(real_array(name, values, finite=True, minimum=0.0 if non_negative
                                else None), dtype=float, copy=True)
    if array.ndim == 0:
        array = array.reshape(1)
    if array.ndim != 1 or array.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D sequence, got shape {array.shape}")
    supported_magnitude(f"max |{name}|", float(np.max(np.abs(array))))
    nonzero = np.abs(array[array != 0])
    if nonzero.size:
        supported_magnitude(f"min nonzero |{name}|", float(nonzero.min()))
    return array
