"""Input checks shared by every module of the project: one wording for one kind of mistake."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["real_number", "positive", "non_negative", "frozen_array"]


def real_number(name: str, value: Any, *, minimum: float | None = None,
                exclusive: bool = False) -> float:
    """``float(value)`` if it is a finite real number (not a bool) within the bound.

    Raises
    ------
    ValueError
        Naming ``name``, what was given and what is allowed.
    """
    bound = "" if minimum is None else f" {'>' if exclusive else '>='} {minimum:g}"
    message = f"{name} must be a finite real number{bound}, got {value!r}"
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(message)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(message) from None
    if not math.isfinite(number):
        raise ValueError(message)
    if minimum is not None and (number <= minimum if exclusive else number < minimum):
        raise ValueError(message)
    return number


def positive(name: str, value: Any) -> float:
    """A finite real number > 0."""
    return real_number(name, value, minimum=0.0, exclusive=True)


def non_negative(name: str, value: Any) -> float:
    """A finite real number >= 0."""
    return real_number(name, value, minimum=0.0)


def frozen_array(values: Any, dtype=float) -> np.ndarray | None:
    """A read-only copy of ``values`` as an array (``None`` stays ``None``); ``dtype=None``
    keeps the input's type."""
    if values is None:
        return None
    array = np.array(values, dtype=dtype, copy=True)
    array.setflags(write=False)
    return array
