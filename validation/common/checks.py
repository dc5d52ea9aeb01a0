"""Field checks shared by the scene dataclasses (:mod:`validation.scenes.scene`,
:mod:`validation.surfaces.spec`): each reads one field of a frozen dataclass in its
``__post_init__``, normalises it in place (floats, tuples) and raises :class:`SceneError` naming
the key and what is allowed. They sit at the bottom of :mod:`validation` because the surface
spec, a layer below the scenes, raises :class:`SceneError` too.
"""

from __future__ import annotations

import math

__all__ = ["SceneError", "SceneWarning", "fail", "number", "integer", "flag", "numbers", "names",
           "choice", "integers"]


class SceneError(ValueError):
    """A scene file or value is invalid; the message names the key (and the file).

    ``key`` is the offending field and ``detail`` what is wrong with it, when known.
    """

    def __init__(self, message: str, *, key: str | None = None, detail: str | None = None):
        super().__init__(message)
        self.key, self.detail = key, detail


class SceneWarning(UserWarning):
    """A valid scene that will not give what it seems to ask for (e.g. verdicts from one
    realization); the message says why and what to change."""


def fail(owner: object, key: str, detail: str) -> None:
    raise SceneError(f"{type(owner).__name__}: key '{key}' {detail}", key=key, detail=detail)


def number(owner, key: str, *, above: float | None = None, at_least: float | None = None,
           below: float | None = None, optional: bool = False) -> None:
    """Check (and store as float) a finite real field within the bounds."""
    value = getattr(owner, key)
    if value is None and optional:
        return
    bounds = [f"> {above:g}" if above is not None else "",
              f">= {at_least:g}" if at_least is not None else "",
              f"< {below:g}" if below is not None else ""]
    allowed = "a finite number" + "".join(f" {b}" for b in bounds if b)
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or (above is not None and value <= above) \
            or (at_least is not None and value < at_least) \
            or (below is not None and value >= below):
        fail(owner, key, f"must be {allowed}, got {value!r}")
    object.__setattr__(owner, key, float(value))


def integer(owner, key: str, minimum: int) -> None:
    value = getattr(owner, key)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        fail(owner, key, f"must be an integer >= {minimum}, got {value!r}")


def flag(owner, key: str) -> None:
    if not isinstance(getattr(owner, key), bool):
        fail(owner, key, f"must be true or false, got {getattr(owner, key)!r}")


def numbers(owner, key: str, *, above: float, below: float | None = None,
            at_most: float | None = None) -> None:
    """A non-empty tuple of finite numbers in (above, below) or (above, at_most]."""
    values = getattr(owner, key)
    if values is None:
        fail(owner, key, "is required")
    values = tuple(values) if isinstance(values, (list, tuple)) else (values,)
    bound = (f"in ({above:g}, {below:g})" if below is not None else
             f"in ({above:g}, {at_most:g}]" if at_most is not None else f"> {above:g}")
    if not values:
        fail(owner, key, "must not be empty")
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v <= above or (below is not None and v >= below) \
                or (at_most is not None and v > at_most):
            fail(owner, key, f"must hold finite numbers {bound}, got {v!r}")
    object.__setattr__(owner, key, tuple(float(v) for v in values))


def names(owner, key: str, allowed: tuple[str, ...]) -> None:
    """A non-empty tuple of distinct names, each in ``allowed``."""
    value = getattr(owner, key)
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value \
            or not all(isinstance(v, str) for v in value):
        fail(owner, key, f"must be a non-empty list of strings, got {value!r}")
    unknown = [v for v in value if v not in allowed]
    if unknown:
        fail(owner, key, f"has unknown entries {unknown}; allowed: {', '.join(allowed)}")
    if len(set(value)) != len(value):
        fail(owner, key, f"lists an entry twice: {list(value)!r}")
    object.__setattr__(owner, key, tuple(value))


def choice(owner, key: str, allowed: tuple[str, ...]) -> None:
    if getattr(owner, key) not in allowed:
        fail(owner, key, f"must be one of {', '.join(allowed)}; got {getattr(owner, key)!r}")



def integers(owner, key: str, minimum: int) -> None:
    """A non-empty tuple of distinct integers >= ``minimum``, stored in increasing order."""
    value = getattr(owner, key)
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)) or not value:
        fail(owner, key, f"must be a non-empty list of integers >= {minimum}, got {value!r}")
    bad = [v for v in value if isinstance(v, bool) or not isinstance(v, int) or v < minimum]
    if bad:
        fail(owner, key, f"must hold integers >= {minimum}, got {bad[0]!r}")
    if len(set(value)) != len(value):
        fail(owner, key, f"lists an entry twice: {list(value)!r}")
    object.__setattr__(owner, key, tuple(sorted(value)))
