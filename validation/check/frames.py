"""The frames of a check: the answer for the interface, and for the user's nominal contact.

A scan samples an interface larger than itself, so the check judges every theory by default
against the scan solved as an unbounded interface (:class:`bem.InterfaceModel`: its mirror
extension on the periodic half-space), per unit nominal area, with no bulk term. A finite
nominal contact of side ``L`` (``--nominal-size``) pressed as a whole also sinks as a loaded
patch: by ``m p L / E*`` on average for a uniform pressure (``m`` =
:data:`bem.reference.UNIFORM_SQUARE_MEAN_DEFLECTION` = 0.946 for a square, the uniform
interaction of the improved GW theory), and the stiffness per unit area ``K = -dp/dd`` can never
exceed that of the square in full contact, a rigid square punch, ``K_max =``
:data:`FULL_CONTACT_STIFFNESS` ``E* / L``. With ``--nominal-size`` the check adds that finite
frame: the interface's answer with the rigid plane lowered by the sink, the stiffness in series
(:class:`bem.NominalContactModel`), and improved GW, whose uniform term is the sink
(docs/theory.md, eqs. T47-T49).
"""

from __future__ import annotations

import numpy as np

from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION
from validation.check.units import format_length
from validation.surfaces.units import LENGTH_UNITS

__all__ = ["FULL_CONTACT_STIFFNESS", "frame_lines"]

#: ``K L / E*`` of a square window in full contact (a rigid flat square punch on a half-space):
#: 1.1462, 1.1492 and 1.1507 from the boundary-element reference on 64², 128² and 256² grids
#: (tests/test_check.py checks the 64² value against it).
FULL_CONTACT_STIFFNESS = 1.15


def _plain(value: float) -> str:
    """A number to three figures without an exponent below a million (``3,790``)."""
    return f"{value:,.0f}" if 1e3 <= abs(value) < 1e6 else f"{value:.3g}"


def frame_lines(tables, *, sigma: float, unit: str, e_star: float | None,
                nominal_size: float | None) -> list[str]:
    """The report's paragraph on the frames of the answer (module docstring).

    Parameters
    ----------
    tables : list of validation.check.physical.PhysicalTable
        The check's tables (their loads are the pressures p / E*).
    sigma : float
        Standard deviation of the summit heights [unit].
    unit : str
        The scan's length unit.
    e_star : float or None
        E* [Pa]; None: stiffness in units of E* per ``unit``.
    nominal_size : float or None
        The nominal contact's side [unit], or None (the interface frame alone).
    """
    if not tables:
        return []
    load = float(np.max(tables[0].load))                    # highest p / E*
    m = UNIFORM_SQUARE_MEAN_DEFLECTION
    text = ("**Frames.** Every theory is judged in the frame of the problem it describes. "
            "*Interface*: the scan solved as a sample of an unbounded interface (its mirror "
            "image, periodic boundary elements), per unit nominal area, with no bulk "
            "deformation; its separation d is the mean gap ū. Original GW, GW and "
            "Bush-Gibson-Thomas from the spectrum, the discrete model without interaction and "
            "Persson's theory are judged there.")
    if nominal_size is None:
        return [text + (" A finite nominal contact of side L pressed as a whole also sinks by "
                        f"m p L/E* (m = {m:.3f}, a square) and its stiffness per unit area "
                        f"stays below about {FULL_CONTACT_STIFFNESS:g} E*/L: give "
                        "`--nominal-size` (e.g. a seal's width) for the answer of that contact, "
                        "with improved GW, whose uniform term is that sink.") + "\n"]
    sink = m * load * nominal_size
    per_unit = 1.0 if e_star is None else e_star / LENGTH_UNITS[unit]
    ceiling = FULL_CONTACT_STIFFNESS * per_unit / nominal_size
    k_unit = "N/m³" if e_star is not None else f"E*/{unit}"
    side = format_length(nominal_size * LENGTH_UNITS[unit])
    return [text + (f" *Finite nominal contact* of side {side} "
                    "(`--nominal-size`): the interface's answer with the separation lowered by the bulk sink of that "
                    f"square under the mean pressure, m p L/E* = "
                    f"{format_length(sink * LENGTH_UNITS[unit])} = "
                    f"{_plain(sink / sigma)} σ at the highest pressure, and its compliance "
                    "m L/E* in series with the interface's stiffness (1/K = 1/K_i + m L/E*, "
                    f"which stays below about {FULL_CONTACT_STIFFNESS:g} E*/L = {ceiling:.3g} "
                    f"{k_unit}); improved GW, with that square's uniform term, is judged "
                    "there. Its separation is negative once the sink exceeds the interface's "
                    "mean gap: the rigid plane is then below the surface's mean plane.") + "\n"]
