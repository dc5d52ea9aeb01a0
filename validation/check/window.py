"""The scan's window as a loaded patch: how much of the reference's separation and stiffness is
the size of the scan rather than the interface.

The reference solves the scan's window (side ``L = sqrt(A0)``) pressed into an elastic
half-space, not an unbounded interface. Under a nominal pressure p the whole window therefore
also sinks as a loaded patch: by ``m p L / E*`` on average for a uniform pressure (``m`` =
:data:`bem.reference.UNIFORM_SQUARE_MEAN_DEFLECTION` = 0.946 for a square, the uniform
interaction of the improved GW theory), and the stiffness per unit area ``K = -dp/dd`` can never
exceed that of the window in full contact, a rigid square punch, ``K_max =``
:data:`FULL_CONTACT_STIFFNESS` ``E* / L``. Both scale with the scan's size: a larger scan of the
same surface sinks more and has a lower ceiling. The improved GW theory and the discrete model
with interaction contain this term (their summits interact across the window); original GW,
the discrete model without interaction and Persson's theory describe an unbounded interface
without it. Taken out in series (the interface and the window as two springs), the interface's
own stiffness is ``K_i = 1 / (1/K - m L / E*)``, well conditioned while K is well below the
ceiling (docs/theory.md, section 11.5, eqs. T47 and T48).
"""

from __future__ import annotations

import math

import numpy as np

from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION
from validation.surfaces.units import LENGTH_UNITS

__all__ = ["FULL_CONTACT_STIFFNESS", "WINDOW_MATTERS", "window_lines"]

#: ``K L / E*`` of a square window in full contact (a rigid flat square punch on a half-space):
#: 1.1462, 1.1492 and 1.1507 from the boundary-element reference on 64², 128² and 256² grids
#: (tests/test_check.py checks the 64² value against it).
FULL_CONTACT_STIFFNESS = 1.15
#: The report speaks of the window when its sink exceeds this share of sigma, or the
#: reference's stiffness this share of the ceiling, at the highest pressure.
WINDOW_MATTERS = 0.1


def window_lines(tables, *, side: float, sigma: float, unit: str,
                 e_star: float | None) -> list[str]:
    """The report's paragraph on the window's own compliance, or nothing where it is small.

    Parameters
    ----------
    tables : list of validation.check.physical.PhysicalTable
        The check's tables (the ``conductance`` one gives the reference's stiffness K).
    side : float
        ``sqrt(A0)`` [unit], the side of the scan's (square) window.
    sigma : float
        Standard deviation of the summit heights [unit].
    unit : str
        The scan's length unit.
    e_star : float or None
        E* [Pa]; None: stiffness in units of E* per ``unit``.
    """
    if not tables:
        return []
    load = float(np.max(tables[0].load))                    # highest p / E*
    sink = UNIFORM_SQUARE_MEAN_DEFLECTION * load * side      # [unit]
    stiffness = next((t for t in tables if t.field == "conductance"), None)
    # the ceiling and the window's compliance in the tables' stiffness unit
    per_unit = 1.0 if e_star is None else e_star / LENGTH_UNITS[unit]
    ceiling = FULL_CONTACT_STIFFNESS * per_unit / side
    window = UNIFORM_SQUARE_MEAN_DEFLECTION * side / per_unit      # 1 / stiffness
    top = (float(stiffness.reference[int(np.argmax(stiffness.load))])
           if stiffness is not None else math.nan)
    share = top / ceiling if math.isfinite(top) else 0.0
    if sink <= WINDOW_MATTERS * sigma and share <= WINDOW_MATTERS:
        return []
    k_unit = stiffness.unit if stiffness is not None else ("N/m³" if e_star else f"E*/{unit}")
    text = (f"**Part of the separation and the stiffness is the size of the scan, not the "
            f"interface.** The reference presses the scan's window (side {side:.3g} {unit}) into "
            f"a half-space, so under the mean pressure the whole window also sinks, by "
            f"m p L/E* (m = {UNIFORM_SQUARE_MEAN_DEFLECTION:.3f} for a square): {sink:.3g} "
            f"{unit} = {sink / sigma:.3g} σ at the highest pressure. Its stiffness per unit area "
            f"can never exceed that of the window in full contact, "
            f"{FULL_CONTACT_STIFFNESS:g} E*/L = {ceiling:.3g} {k_unit}")
    if math.isfinite(top):
        text += f"; the reference reaches {100 * share:.0f} % of it"
    text += (". A larger scan of the same surface sinks more and has a lower ceiling. The "
             "improved GW theory and the discrete model with interaction contain this term (the "
             "paper's uniform interaction); original GW, the discrete model without interaction "
             "and Persson's theory describe an unbounded interface without it, so at the "
             "highest pressures part of their separation and stiffness errors is this term.")
    if math.isfinite(top) and share <= 0.5:
        own = 1.0 / (1.0 / top - window)
        text += (f" The interface's own stiffness, the window's compliance taken out in series "
                 f"(K_i = 1/(1/K − m L/E*)), is {own:.3g} {k_unit} at the highest pressure.")
    elif math.isfinite(top):
        text += (" This close to the ceiling the interface's own stiffness cannot be told "
                 "from the window's on this scan.")
    return [text + "\n"]
