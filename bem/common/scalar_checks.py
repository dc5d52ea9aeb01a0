"""Checks of scalar parameters, names and collections of objects (the rules: :mod:`bem.common.checks`).

Numbers, integers, flags, choices among names, seeds, paths and sequences of the project's own
objects; each message names the parameter, what was given and what is allowed.
"""

from __future__ import annotations

import math
import numbers
import os
import pathlib
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

__all__ = ["InputTypeError", "choice", "file_path", "flag", "instances", "integer", "names",
           "non_negative", "non_negative_or_infinite", "optional_callable", "optional_integer", "positive",
           "random_generator", "real_number"]


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


def non_negative_or_infinite(name: str, value: Any) -> float:
    """A real number >= 0, or +inf (an unbounded stiffness, a ratio whose denominator is 0)."""
    if isinstance(value, (float, np.floating)) and value == math.inf:
        return math.inf
    try:
        return real_number(name, value, minimum=0.0)
    except ValueError as error:
        error.args = (str(error).replace("a finite real number >= 0",
                                         "a real number >= 0 or +inf"),)
        raise


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


def optional_callable(name: str, value: Any) -> Callable | None:
    """``None``, or a callable (a callback); anything else is a :class:`TypeError` naming
    ``name``, raised before any work rather than at the first call."""
    if value is not None and not callable(value):
        raise InputTypeError(f"{name} must be a callable or None, got {type(value).__name__} "
                             f"{_describe(value)}")
    return value


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
