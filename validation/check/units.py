"""Physical quantities on the command line: ``115GPa``, ``1MPa:100MPa:12``, ``20nm``.

A quantity is a number followed by a unit, with or without a space between them (``115 GPa``,
``115GPa``, ``1.15e11 Pa``); a bare number is taken in the unit the caller names as the
default (e.g. a pressure in units of E*). Pressures take the SI prefixes of the pascal and
the common engineering units; lengths are read as every length of a measured map is
(:func:`validation.surfaces.units.parse_length`: m, mm, um/µm, nm, Å, pm, ...). Everything is
converted to SI (Pa, m).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from validation.surfaces.units import LENGTH_UNITS, PRESSURE_UNITS, format_length, \
    format_pressure, length_unit_for
from validation.surfaces.units import parse_length as _length

__all__ = ["PRESSURE_UNITS", "PressureRange", "format_length", "format_pressure",
           "length_unit_for", "parse_length", "parse_pressure", "parse_pressure_range",
           "parse_size", "unitless"]

_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S*)\s*")


def _parse(name: str, text: str | float, units: dict[str, float], what: str,
           example: str) -> tuple[float, str | None]:
    """(value in SI, the unit written or None for a bare number); the value finite and > 0."""
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise TypeError(f"{name} must be a {what} like {example!r}, got {type(text).__name__}")
    if isinstance(text, str):
        match = _QUANTITY.fullmatch(text)
        if match is None:
            raise ValueError(f"{name} must be a {what} like {example!r}, got {text!r}")
        number, unit = float(match.group(1)), match.group(2) or None
        if unit is not None and unit not in units:
            raise ValueError(f"{name}: unknown unit {unit!r} in {text!r}; use one of "
                             f"{', '.join(sorted(units, key=units.get))}")
    else:
        number, unit = float(text), None
    value = number * (units[unit] if unit is not None else 1.0)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a positive finite {what}, got {text!r}")
    return value, unit


def parse_pressure(name: str, text: str | float) -> tuple[float, bool]:
    """A pressure: ``(value, has_unit)``, the value in Pa when a unit is written (``"115GPa"``),
    else the bare number as given (a pressure in units of E*).

    Raises
    ------
    ValueError
        Naming ``name``: not a number with a pressure unit, not positive, or not finite.
    """
    value, unit = _parse(name, text, PRESSURE_UNITS, "pressure", "115GPa")
    return value, unit is not None


def parse_length(name: str, text: str | float) -> tuple[float, bool]:
    """A length: ``(value, has_unit)``, in metres when a unit is written (``"20nm"``), else the
    bare number as given.

    Raises
    ------
    ValueError
        Naming ``name``: not a number with a length unit, not positive, or not finite.
    """
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise TypeError(f"{name} must be a length like '20nm', got {type(text).__name__}")
    number, unit = _length(name, text)
    if not math.isfinite(number):
        raise ValueError(f"{name} must be a finite length, got {text!r}")
    return (number * LENGTH_UNITS[unit.strip()], True) if unit else (number, False)


def unitless(name: str, text: str, kind: str = "length") -> ValueError:
    """The error for a number written as text without its unit (``spacing="10"``,
    ``--e-star 115``): it names the units the number could mean, since a bare string is more
    often a unit left out than metres or pascals meant."""
    units, plain = (("nm", "um", "mm"), "metres") if kind == "length" else \
        (("MPa", "GPa"), "pascals")
    examples = [repr(f"{str(text).strip()}{unit}") for unit in units]
    return ValueError(f"{name} needs a unit, e.g. {', '.join(examples[:-1])} or {examples[-1]}, "
                      f"got {text!r} (in Python a number, not text, is read in {plain})")


#: Between a width and a height: x, × or *; a comma after a unit ("10um,7.8um"; "1,5 nm" is a
#: decimal comma); or a space before the next number ("10um 7.8um").
_SIZE_SEPARATOR = re.compile(r"\s*[x\u00d7*]\s*|(?<=[^\d\s.,]),\s*|\s+(?=[-+.\d])")


def parse_size(name: str, value) -> tuple[float, float]:
    """A map's physical size as (width, height) [m]: one length for a square map
    (``"10um"``, ``1e-5``), or its width and height as a pair (``("10um", "7.8um")``,
    ``(1e-5, 7.8e-6)``) or one string (``"10um x 7.8um"``, ``"10um,7.8um"``,
    ``"10 x 7.8 um"``: a unit written once, after the height, is the width's too). Numbers
    are metres; a string needs its unit.

    Raises
    ------
    ValueError, TypeError
        Naming ``name``: not one or two positive lengths, or a string without a unit.
    """
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError(f"{name} must be a length or (width, height), got {value!r}")
        parts = list(value)
    elif isinstance(value, str):
        parts = [p for p in _SIZE_SEPARATOR.split(value.strip()) if p]
        if len(parts) not in (1, 2):
            raise ValueError(f"{name} must be a length ('10um') or width and height ('10um x "
                             f"7.8um'), got {value!r}")
        if len(parts) == 2:
            units = [_length(name, part)[1] for part in parts]
            if units[0] is None and units[1] is not None:   # "10 x 7.8 um": one unit for both
                parts[0] = parts[0] + units[1]
    else:
        parts = [value, value]
    sizes = []
    for part in parts:
        metres, has_unit = parse_length(name, part)
        if isinstance(part, str) and not has_unit:
            raise unitless(name, value if isinstance(value, str) else part)
        sizes.append(metres)
    return (sizes[0], sizes[-1])


@dataclass(frozen=True)
class PressureRange:
    """Nominal pressures from ``low`` to ``high`` (``count`` points, logarithmic), in Pa when
    ``physical`` else in units of E*."""

    low: float
    high: float
    count: int
    physical: bool

    def dimensionless(self, e_star: float | None) -> tuple[float, float]:
        """(low, high) as p / E* (the scene's ``Load = W / (E* A)``).

        Raises
        ------
        ValueError
            For pressures in Pa without ``e_star``, or p / E* outside (0, 1).
        """
        if self.physical and e_star is None:
            raise ValueError("--pressure with a unit needs --e-star (the effective modulus E*, "
                             "e.g. --e-star 115GPa), or give pressures in units of E* "
                             "(bare numbers, e.g. --pressure 1e-5:1e-3)")
        scale = e_star if self.physical else 1.0
        low, high = self.low / scale, self.high / scale
        if high >= 1.0:
            raise ValueError(f"--pressure: the highest nominal pressure is {high:.3g} E*; a "
                             f"rough contact is fully closed long before p = E* (use a range "
                             f"below E*)")
        return low, high


#: Most nominal pressures a check solves.
MAX_PRESSURES = 100


def parse_pressure_range(text: str, *, default_count: int = 12) -> PressureRange:
    """``LOW:HIGH[:COUNT]``, e.g. ``1MPa:100MPa`` or ``1e-5:1e-3:16`` (units of E*).

    Raises
    ------
    ValueError
        Naming ``--pressure`` and what is allowed.
    """
    if not isinstance(text, str):
        raise TypeError(f"--pressure must be a string LOW:HIGH[:COUNT], got {type(text).__name__}")
    parts = text.split(":")
    if len(parts) not in (2, 3):
        raise ValueError(f"--pressure must be LOW:HIGH or LOW:HIGH:COUNT (e.g. 1MPa:100MPa:12), "
                         f"got {text!r}")
    (low, low_unit), (high, high_unit) = (parse_pressure("--pressure", p) for p in parts[:2])
    if low_unit != high_unit:
        raise ValueError(f"--pressure: give both ends with a unit or both without, got {text!r}")
    count = default_count
    if len(parts) == 3:
        if not parts[2].strip().isdigit() or int(parts[2]) < 1:
            raise ValueError(f"--pressure: COUNT must be a whole number >= 1, got {parts[2]!r}")
        count = int(parts[2])
        if count > MAX_PRESSURES:
            raise ValueError(f"--pressure: COUNT must be at most {MAX_PRESSURES} (each pressure "
                             f"is a whole boundary-element solve, and a smooth curve needs far "
                             f"fewer), got {count}")
    if not high > low and not (count == 1 and high == low):
        raise ValueError(f"--pressure: HIGH must be greater than LOW, got {text!r}")
    if count == 1 and high != low:
        raise ValueError(f"--pressure: one pressure cannot span {parts[0]} to {parts[1]}; COUNT "
                         f"must be at least 2 for a range (one pressure alone: LOW:LOW:1), got "
                         f"{text!r}")
    return PressureRange(low, high, count, low_unit)
