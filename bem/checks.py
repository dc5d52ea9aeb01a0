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
"""

from __future__ import annotations

import math
import numbers
import os
import pathlib
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

__all__ = [
    "InputTypeError",
    "boolean_map",
    "choice",
    "file_path",
    "flag",
    "frozen_array",
    "height_map",
    "instances",
    "integer",
    "non_negative",
    "points",
    "positive",
    "random_generator",
    "real_array",
    "real_number",
]


class InputTypeError(TypeError, ValueError):
    """A parameter of the wrong type (a string, ``None``, a bool or a complex number where a real
    number is needed). A :class:`TypeError`; also a :class:`ValueError`, so that code written
    when these were reported as ``ValueError`` keeps catching them."""


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _bounds(minimum, maximum, exclusive, exclusive_maximum) -> str:
    parts = []
    if minimum is not None:
        parts.append(f"{'>' if exclusive else '>='} {minimum:g}")
    if maximum is not None:
        parts.append(f"{'<' if exclusive_maximum else '<='} {maximum:g}")
    return (" " + " and ".join(parts)) if parts else ""


def real_number(name: str, value: Any, *, minimum: float | None = None,
                exclusive: bool = False, maximum: float | None = None,
                exclusive_maximum: bool = False) -> float:
    """``float(value)`` if it is a finite real number within the bounds.

    Raises
    ------
    InputTypeError
        A :class:`TypeError`: ``value`` is not a real number (a string, ``None``, a bool,
        a complex number, ...).
    ValueError
        NaN, +-inf or outside ``[minimum, maximum]`` (open ends with ``exclusive`` /
        ``exclusive_maximum``); the message names ``name``, the value and the allowed range.
    """
    allowed = f"a finite real number{_bounds(minimum, maximum, exclusive, exclusive_maximum)}"
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if (isinstance(value, (bool, np.bool_))
            or not isinstance(value, (numbers.Real, np.integer, np.floating))):
        raise InputTypeError(f"{name} must be {allowed}, got {type(value).__name__} "
                        f"{_describe(value)}")
    try:
        number = float(value)
    except (OverflowError, ValueError):   # an int too large for a double
        raise ValueError(f"{name} must be {allowed}, got {_describe(value)}") from None
    if (not math.isfinite(number)
            or (minimum is not None and (number <= minimum if exclusive else number < minimum))
            or (maximum is not None
                and (number >= maximum if exclusive_maximum else number > maximum))):
        raise ValueError(f"{name} must be {allowed}, got {_describe(value)}")
    return number


def positive(name: str, value: Any) -> float:
    """A finite real number > 0."""
    return real_number(name, value, minimum=0.0, exclusive=True)


def non_negative(name: str, value: Any) -> float:
    """A finite real number >= 0."""
    return real_number(name, value, minimum=0.0)


def integer(name: str, value: Any, *, minimum: int | None = None,
            maximum: int | None = None) -> int:
    """``int(value)`` if it is an integer (not a bool) within the bounds."""
    allowed = "an integer" + _bounds(minimum, maximum, False, False)
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral,
                                                                    np.integer)):
        raise InputTypeError(f"{name} must be {allowed}, got {type(value).__name__} "
                        f"{_describe(value)}")
    number = int(value)
    if (minimum is not None and number < minimum) or (maximum is not None and number > maximum):
        raise ValueError(f"{name} must be {allowed}, got {number!r}")
    return number


def flag(name: str, value: Any) -> bool:
    """A bool (Python or numpy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be True or False, got {type(value).__name__} "
                        f"{_describe(value)}")
    return bool(value)


def choice(name: str, value: Any, allowed: Iterable[Any]) -> Any:
    """``value`` if it is one of ``allowed`` (compared by equality, bools never match ints)."""
    allowed = tuple(allowed)
    if isinstance(value, (bool, np.bool_)) or not _hashable(value) or value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {_describe(value)}")
    return allowed[allowed.index(value)]


def _hashable(value: Any) -> bool:
    try:
        hash(value)
    except TypeError:
        return False
    return True


def optional_integer(name: str, value: Any, *, minimum: int | None = None) -> int | None:
    """``None``, or :func:`integer` (e.g. a thread count whose default is chosen later)."""
    return None if value is None else integer(name, value, minimum=minimum)


def random_generator(name: str, seed: Any) -> np.random.Generator:
    """``numpy.random.default_rng(seed)`` for a seed that is ``None`` (fresh entropy), an
    integer >= 0, a :class:`numpy.random.Generator` (used as is) or a
    :class:`numpy.random.SeedSequence`; anything else (strings, floats, bools, arrays) is a
    :class:`TypeError` naming ``name``."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, np.random.SeedSequence):
        return np.random.default_rng(seed)
    if isinstance(seed, np.ndarray) and seed.ndim == 0:
        seed = seed[()]
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (numbers.Integral, np.integer)):
        raise InputTypeError(f"{name} must be None, an integer >= 0 or a numpy.random.Generator,"
                             f" got {type(seed).__name__} {_describe(seed)}")
    if seed < 0:
        raise ValueError(f"{name} must be None, an integer >= 0 or a numpy.random.Generator, "
                         f"got {int(seed)!r}")
    return np.random.default_rng(int(seed))


def file_path(name: str, value: Any) -> pathlib.Path:
    """``value`` as a :class:`pathlib.Path` if it is a ``str`` or an ``os.PathLike`` (not
    bytes); whether the file exists is the caller's question."""
    if isinstance(value, (bytes, bytearray)) or not isinstance(value, (str, os.PathLike)):
        raise InputTypeError(f"{name} must be a path (a str or os.PathLike), got "
                             f"{type(value).__name__} {_describe(value)}")
    try:
        return pathlib.Path(value)
    except TypeError:   # an os.PathLike whose __fspath__ returns bytes
        raise InputTypeError(f"{name} must be a path (a str or os.PathLike), got "
                             f"{_describe(value)}") from None


def instances(name: str, values: Any, kind: type | tuple[type, ...] | Callable[[Any], bool],
              *, min_size: int = 0, described: str | None = None) -> tuple:
    """The items of an iterable (not a string or a mapping) as a tuple, each an instance of
    ``kind`` (or accepted by it, when it is a predicate, described by ``described``): entry
    points taking collections of the project's own objects (scenes, realization results)
    refuse anything else with a :class:`TypeError` naming ``name``."""
    if isinstance(kind, (type, tuple)):
        kinds = kind if isinstance(kind, tuple) else (kind,)
        described = described or " or ".join(k.__name__ for k in kinds)
        accept = lambda item: isinstance(item, kinds)  # noqa: E731
    else:
        accept = kind
    if isinstance(values, (str, bytes, dict)) or not isinstance(values, Iterable):
        raise InputTypeError(f"{name} must be a sequence of {described}, got "
                             f"{type(values).__name__} {_describe(values)}")
    items = tuple(values)
    wrong = [item for item in items if not accept(item)]
    if wrong:
        raise InputTypeError(f"{name} must be a sequence of {described}, got an item of type "
                             f"{type(wrong[0]).__name__} ({_describe(wrong[0])})")
    if len(items) < min_size:
        raise ValueError(f"{name} must hold at least {min_size} {described}, got {len(items)}")
    return items


def _as_array(name: str, values: Any, allowed: str) -> np.ndarray:
    """``numpy.asarray(values)``, refusing None, strings and ragged sequences."""
    if values is None or isinstance(values, (str, bytes)):
        raise InputTypeError(f"{name} must be {allowed}, got {type(values).__name__} "
                             f"{_describe(values)}")
    try:
        return np.asarray(values)
    except (ValueError, TypeError):
        raise ValueError(f"{name} must be {allowed}, rectangular (got a ragged "
                         "sequence)") from None


def boolean_map(name: str, values: Any) -> np.ndarray:
    """A 2-D map of booleans (a contact set) as a bool array: a bool array, or real numbers
    that are all 0 or 1. NaN, +-inf and other numbers are a :class:`ValueError`; strings,
    complex numbers and objects a :class:`TypeError`, naming ``name``."""
    raw = _as_array(name, values, "a 2-D array of booleans")
    if raw.dtype.kind != "b":
        array = real_array(name, raw, finite=False)
        if not np.all((array == 0.0) | (array == 1.0)):
            raise ValueError(f"{name} must be booleans (or the numbers 0 and 1), got other "
                             "values (NaN, inf or numbers other than 0 and 1)")
        raw = array.astype(bool)
    if raw.ndim != 2:
        raise ValueError(f"{name} must be a 2-D array of booleans, got {raw.ndim} dimension(s)")
    return raw


def real_array(name: str, values: Any, *, ndim: int | None = None, finite: bool = True,
               min_size: int = 0, minimum: float | None = None,
               exclusive: bool = False) -> np.ndarray:
    """``values`` as a float64 array (a view when it already is one; read-only input is fine).

    Raises
    ------
    TypeError
        ``None``, strings, booleans, complex or object values.
    ValueError
        Ragged input, wrong number of dimensions, fewer than ``min_size`` entries, NaN/inf (when
        ``finite``) or entries below ``minimum``.
    """
    raw = _as_array(name, values, "real numbers (an array)")
    if raw.dtype.kind not in "iuf":
        kind = {"b": "booleans", "c": "complex numbers", "U": "strings", "S": "bytes",
                "O": "objects"}.get(raw.dtype.kind, f"dtype {raw.dtype}")
        raise InputTypeError(f"{name} must be real numbers (an array), got {kind}")
    array = raw.astype(float, copy=False)
    if ndim is not None and array.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got {array.ndim} dimension(s) "
                         f"(shape {array.shape})")
    if array.size < min_size:
        raise ValueError(f"{name} must have at least {min_size} entries, got {array.size}")
    if finite and not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    if minimum is not None and array.size:
        low = np.nanmin(array)
        if low <= minimum if exclusive else low < minimum:
            raise ValueError(f"{name} must be {'>' if exclusive else '>='} {minimum:g} "
                             f"everywhere, got a minimum of {low!r}")
    return array


def integer_array(name: str, values: Any, *, minimum: int | None = None) -> np.ndarray:
    """``values`` as a 1-D ``intp`` array: integer entries (or floats with no fraction), each
    >= ``minimum``."""
    array = real_array(name, values).ravel()
    if np.asarray(values).dtype.kind == "f" and np.any(array != np.rint(array)):
        raise ValueError(f"{name} must be integers, got fractional entries")
    if np.any(np.abs(array) > np.iinfo(np.intp).max // 2):
        raise ValueError(f"{name} entries are too large for an index")
    if minimum is not None and array.size and array.min() < minimum:
        raise ValueError(f"{name} must be integers >= {minimum}, got {array.min():g}")
    return array.astype(np.intp)


def points(name: str, values: Any, *, non_negative: bool = False,
           allow_infinity: bool = False) -> np.ndarray:
    """Loads or separations of a contact model as a float array of any shape (0-d for a scalar).

    Raises
    ------
    ValueError
        Naming ``name``: not real numbers, NaN, infinite (``+inf`` is allowed only with
        ``allow_infinity``, meaning out of contact; ``-inf`` never), or negative when
        ``non_negative``.
    """
    array = real_array(name, values, finite=False)
    allowed = "finite or +inf" if allow_infinity else "finite"
    if np.isnan(array).any():
        raise ValueError(f"{name} must be {allowed}, got NaN")
    infinite = np.isinf(array)
    if infinite.any() and not (allow_infinity and np.all(array[infinite] > 0)):
        raise ValueError(f"{name} must be {allowed}, got {array[infinite][0]!r}")
    if non_negative and (array < 0).any():
        raise ValueError(f"{name} must be >= 0, got minimum {float(array.min())!r}")
    return array


def separations(name: str, values: Any) -> np.ndarray:
    """Separations [length] of a closed-form model: real, no NaN, no -inf (+inf means out of
    contact)."""
    return points(name, values, allow_infinity=True)


def no_overflow(name: str, values: np.ndarray, what: str) -> np.ndarray:
    """``values`` if none is +-inf; a ValueError naming ``name`` and ``what`` overflowed."""
    if np.isinf(values).any():
        raise ValueError(f"{name} is outside the supported range: {what} overflows")
    return values


def names(name: str, values: Any, allowed: Iterable[str]) -> tuple[str, ...]:
    """A tuple of names, each one of ``allowed`` (a lone string is a mistake, not a name
    list)."""
    allowed = tuple(allowed)
    if isinstance(values, str) or not isinstance(values, (tuple, list)):
        raise InputTypeError(f"{name} must be a tuple of names from {allowed}, got "
                             f"{type(values).__name__} {_describe(values)}")
    unknown = [value for value in values if not isinstance(value, str) or value not in allowed]
    if unknown:
        raise ValueError(f"{name} must be among {allowed}, got unknown {unknown}")
    return tuple(values)


def curve_error_arguments(sigma: Any, quantities: Any, allowed: Iterable[str]
                          ) -> tuple[float, tuple[str, ...]]:
    """Checked ``(sigma, quantities)`` of a comparison of two contact curves: sigma > 0 [length]
    in the supported range, quantities known by name."""
    sigma = supported_magnitude("sigma", positive("sigma", sigma))
    return sigma, names("quantities", quantities, allowed)


def height_map(name: str, values: Any, *, minimum: int = 3, square: bool = False) -> np.ndarray:
    """A 2-D, finite, real height map of at least ``minimum`` x ``minimum`` points."""
    array = real_array(name, values, ndim=2, finite=False)
    if min(array.shape) < minimum:
        raise ValueError(f"{name} must be at least {minimum} x {minimum}, got shape "
                         f"{array.shape}")
    if square and array.shape[0] != array.shape[1]:
        raise ValueError(f"{name} must be a square grid (n x n), got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return array


def frozen_array(values: Any, dtype=float) -> np.ndarray | None:
    """A read-only copy of ``values`` as an array (``None`` stays ``None``); ``dtype=None``
    keeps the input's type."""
    if values is None:
        return None
    array = np.array(values, dtype=dtype, copy=True)
    array.setflags(write=False)
    return array


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


def contact_number(name: str, value: Any, *, minimum: float | None = None,
                   exclusive: bool = False) -> float:
    """A finite real number (bounded below) of a contact problem, in the supported range."""
    return supported_magnitude(name, real_number(name, value, minimum=minimum,
                                                 exclusive=exclusive))


def contact_heights(name: str, values: Any, *, minimum: int) -> np.ndarray:
    """A finite, real height map of at least ``minimum`` x ``minimum`` points (N x M: square
    pixels, any number of rows and columns) whose largest magnitude lies in the supported range
    (a fresh float64 copy)."""
    z = np.array(height_map(name, values, minimum=minimum), dtype=float, copy=True)
    supported_magnitude(f"max |{name}|", float(np.max(np.abs(z))))
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
