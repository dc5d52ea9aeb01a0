"""The record of one solved contact problem (:func:`bem.solve_contact`): pressures,
displacements, gaps and the scalar results, all arrays read-only."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ContactSolution"]


def _frozen(array: np.ndarray) -> np.ndarray:
    """``array`` made read-only in place: the solver hands out arrays it made and owns."""
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class ContactSolution:
    """The converged (or last) state of a contact problem; all arrays are fresh and read-only.

    Attributes
    ----------
    pressure : numpy.ndarray
        Pixel pressures p >= 0 [pressure], indexed like the heights.
    displacement : numpy.ndarray
        Surface displacement u = K * p [length], positive into the body.
    gap : numpy.ndarray
        ``d - z + u`` [length]: >= 0 outside the contact set and zero on it, both to the
        solver's tolerance (the computed values are reported, not clipped).
    contact : numpy.ndarray of bool
        Contact set, ``pressure > 0``.
    load : float
        Total force W = h^2 sum p [force].
    mean_pressure : float
        W / A with A = (n h)^2 the nominal area [pressure].
    area : float
        Real contact area [length^2] by the default estimator of :mod:`bem.area` (the pixel
        count corrected for the staircase perimeter; ``pixel_area`` is the plain count).
    separation : float
        d [length] (module docstring for the reference plane). Given in separation control,
        ``mean over the contact set of (z - u)`` in load control; for zero load, ``max(z)``
        (first contact) unless a larger separation was given.
    mean_gap : float
        Mean of ``gap`` over the grid [length].
    converged : bool
        Whether the stopping rule of :func:`solve_contact` was met.
    iterations : int
        Conjugate-gradient iterations done.
    residual : float
        The last relative pressure change (the stopping rule's left-hand side).
    message : str
        How the iteration ended.
    stiffness : float or None
        Incremental normal stiffness S = -dW/dd [force/length] on the contact set, when asked for
        (``inf`` for full periodic contact).
    nominal_area : float
        A = (n h)^2 [length^2].
    e_star : float
        Composite modulus E* [pressure].
    pixel_area : float
        h^2 times the number of contact pixels [length^2] (what most codes report; its error
        is of the order of the perimeter times h, see :mod:`bem.area`).
    """

    pressure: np.ndarray
    displacement: np.ndarray
    gap: np.ndarray
    contact: np.ndarray
    load: float
    mean_pressure: float
    area: float
    separation: float
    mean_gap: float
    converged: bool
    iterations: int
    residual: float
    message: str
    stiffness: float | None = None
    nominal_area: float = 1.0
    e_star: float = 1.0
    pixel_area: float = math.nan

    @property
    def conductance(self) -> float | None:
        """``2 S / E*`` [length]: constriction conductance times resistivity (Barber's analogy)."""
        if self.stiffness is None:
            return None
        return 2.0 * self.stiffness / self.e_star

    @property
    def area_fraction(self) -> float:
        """Real over nominal contact area [-]."""
        return self.area / self.nominal_area
