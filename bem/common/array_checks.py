"""Checks of array parameters (the rules: :mod:`bem.common.checks`).

Real arrays, integer index arrays, contact maps, height maps, loads and separations of a model;
each message names the parameter, what was given and what is allowed.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bem.common.scalar_checks import InputTypeError, _describe

__all__ = ["boolean_map", "frozen_array", "height_map", "integer_array", "no_overflow", "points",
           "real_array", "record_array", "record_arrays", "separations"]


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


def point_mask(name: str, indices: Any, size: int) -> np.ndarray:
    """Boolean mask of ``size`` points set at ``indices`` (integers in ``[0, size)``), or set
    everywhere when ``indices`` is None.

    Raises
    ------
    ValueError
        Naming ``name``: an index outside ``[0, size)`` or not an integer.
    """
    mask = np.zeros(size, dtype=bool)
    if indices is None:
        mask[:] = True
        return mask
    if isinstance(indices, (set, frozenset)):
        indices = sorted(indices)
    where = integer_array(name, indices, minimum=0)
    if where.size and where.max() >= size:
        raise ValueError(f"{name} must be point indices below {size}, got {int(where.max())}")
    mask[where] = True
    return mask


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


def record_array(name: str, values: Any, *, ndim: int | None = None,
                 allow_infinity: bool = False) -> np.ndarray:
    """A field of a result record (a curve, a solution) as a read-only float array: real, no
    NaN, no -inf (+inf only with ``allow_infinity``: out of contact, an overflowed load), of
    ``ndim`` dimensions when given. An array that is already read-only float64 is kept as is,
    anything else copied."""
    array = points(name, values, allow_infinity=allow_infinity)
    if ndim is not None and array.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got {array.ndim} dimension(s) "
                         f"(shape {array.shape})")
    return frozen_array(array) if array.flags.writeable else array


def record_arrays(record: Any, names: tuple[str, ...], *, optional: tuple[str, ...] = (),
                  ndim: int | None = None, allow_infinity: bool = False) -> None:
    """Check the array fields ``names`` of a frozen dataclass (a result record) with
    :func:`record_array` and store them back read-only; all must have one shape. A field in
    ``optional`` may be None."""
    shapes = {}
    for name in names:
        value = getattr(record, name)
        if value is None and name in optional:
            continue
        array = record_array(name, value, ndim=ndim, allow_infinity=allow_infinity)
        object.__setattr__(record, name, array)
        shapes[name] = array.shape
    if len(set(shapes.values())) > 1:
        raise ValueError(f"{', '.join(shapes)} must have one shape, got {shapes}")
