"""Units: the accepted spellings of lengths (of measured maps) and pressures, lengths written
with their unit (``"10 um"``, ``"20 nm"``), shared by the file readers
(:mod:`validation.surfaces.formats`), :func:`validation.read_topography` and the scene keys that
take a length; and lengths and pressures written as they read best (``20 nm``, ``6.7 MPa``),
for the check and the reports.
"""

from __future__ import annotations

import math
import re

from bem.common.checks import positive

__all__ = ["LENGTH_UNITS", "PRESSURE_UNITS", "format_length", "format_pressure", "length_in",
           "length_unit_for", "parse_length", "readable", "unit_factor"]

#: Metres per unit, for every spelling accepted in files and arguments.
LENGTH_UNITS: dict[str, float] = {
    "m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "micron": 1e-6,
    "nm": 1e-9, "A": 1e-10, "\u00c5": 1e-10, "\u212b": 1e-10, "angstrom": 1e-10, "pm": 1e-12,
}


def unit_factor(name: str, unit: str) -> float:
    """Metres per ``unit``; a ValueError naming ``name`` for a spelling not in
    :data:`LENGTH_UNITS`."""
    if not isinstance(unit, str) or unit.strip() not in LENGTH_UNITS:
        raise ValueError(f"{name} must be a length unit, one of {sorted(set(LENGTH_UNITS))}, "
                         f"got {unit!r}")
    return LENGTH_UNITS[unit.strip()]


def parse_length(name: str, value: float | str) -> tuple[float, str | None]:
    """A positive length as (number, unit or None): ``2.5`` gives ``(2.5, None)``, ``"10 µm"``
    (or ``"10µm"``, ``"1,5 nm"``) gives ``(10.0, "µm")``.

    Raises
    ------
    ValueError
        Naming ``name``: not a number, not positive, or an unknown unit.
    """
    if isinstance(value, str):
        try:   # a bare number written as text ("20"): no unit (not "2" of unit "0")
            bare = float(value.replace(",", "."))
        except ValueError:
            bare = None
        if bare is not None:
            return positive(name, bare), None
        match = re.fullmatch(r"\s*([-+0-9.,eE]+)\s*(\S+)\s*", value.replace(",", "."))
        if match is None:
            raise ValueError(f"{name} must be a number or 'number unit' like '10 um', got {value!r}")
        unit = match.group(2)
        unit_factor(f"the unit of {name}", unit)
        try:
            number = float(match.group(1))
        except ValueError:
            raise ValueError(f"{name} must be a number or 'number unit' like '10 um', "
                             f"got {value!r}") from None
        return positive(name, number), unit
    return positive(name, value), None


def length_in(name: str, value: float | str, unit: str) -> float:
    """A positive length in ``unit``: a number is taken as already in ``unit``, a string with
    its own unit (``"20 nm"``) is converted."""
    number, given = parse_length(name, value)
    if given is None:
        return number
    return number * unit_factor(f"the unit of {name}", given) / unit_factor("unit", unit)


#: Pascals per unit of pressure.
PRESSURE_UNITS: dict[str, float] = {
    "Pa": 1.0, "hPa": 1e2, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "TPa": 1e12,
    "N/m2": 1.0, "N/m^2": 1.0, "N/mm2": 1e6, "N/mm^2": 1e6,
    "bar": 1e5, "mbar": 1e2, "psi": 6894.757293168361, "ksi": 6894757.293168361,
}


def readable(value: float, digits: int = 3) -> str:
    """``value`` to ``digits`` significant figures, as a reader writes it: without an exponent
    from 0.001 to a million (``1570``, not ``1.57e+03``; ``0.0123``), with one outside."""
    value = float(value)
    if not math.isfinite(value) or value == 0.0:
        return f"{value:g}"
    magnitude = math.floor(math.log10(abs(value)))
    if not -3 <= magnitude < 6:
        return f"{value:.{digits}g}"
    decimals = digits - 1 - magnitude
    rounded = round(value, decimals)
    if rounded != 0 and math.floor(math.log10(abs(rounded))) > magnitude:   # 999.7 -> 1000
        decimals -= 1
    text = f"{rounded:.{max(decimals, 0)}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def _shown(value: float) -> float:
    """``value`` as printed to three significant figures (so that 0.99999999 MPa, a pressure
    range's end after a round trip through E*, is shown in MPa, not as 1e+03 kPa)."""
    return float(f"{value:.3g}")


def length_unit_for(metres: float) -> str:
    """The length unit (nm, um or mm) in which ``metres`` reads as a number from 1 to 1000."""
    for unit in ("nm", "um", "mm"):
        if abs(_shown(metres / LENGTH_UNITS[unit])) < 1000.0:
            return unit
    return "m"


def format_pressure(pascals: float) -> str:
    """A pressure in the prefix that reads best: ``3.2 MPa``."""
    for unit in ("GPa", "MPa", "kPa"):
        if abs(_shown(pascals / PRESSURE_UNITS[unit])) >= 1.0:
            return f"{readable(pascals / PRESSURE_UNITS[unit])} {unit}"
    return f"{readable(pascals)} Pa"


def format_length(metres: float) -> str:
    """A length in the unit that reads best: ``20 nm``."""
    unit = length_unit_for(metres)
    return f"{readable(metres / LENGTH_UNITS[unit])} {unit}"
