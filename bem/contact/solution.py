"""The record of one solved contact problem (:func:`bem.solve_contact`): pressures,
displacements, gaps and the scalar results, all arrays read-only."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bem.common import checks

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
        Real contact area [length^2] by the default estimator of :mod:`bem.contact.area` (the pixel
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
        is of the order of the perimeter times h, see :mod:`bem.contact.area`). Default: that count
        times ``nominal_area / contact.size``.

    Raises
    ------
    ValueError
        A field of the wrong type or out of its range (negative loads or areas, NaN or inf
        in the fields, maps of different shapes); a :class:`TypeError` for strings, None or
        objects where numbers are due. The message names the field.
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
    pixel_area: float | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        checks.record_arrays(self, ("pressure", "displacement", "gap"), ndim=2)
        contact = checks.boolean_map("contact", self.contact)
        if contact.shape != self.pressure.shape:
            raise ValueError(f"contact must have the shape of pressure, {self.pressure.shape}, "
                             f"got {contact.shape}")
        set_(self, "contact", contact if not contact.flags.writeable
             else checks.frozen_array(contact, dtype=bool))
        for name in ("load", "mean_pressure", "area"):
            set_(self, name, checks.non_negative(name, getattr(self, name)))
        for name in ("separation", "mean_gap"):
            set_(self, name, checks.real_number(name, getattr(self, name)))
        set_(self, "converged", checks.flag("converged", self.converged))
        set_(self, "iterations", checks.integer("iterations", self.iterations, minimum=0))
        set_(self, "residual", checks.non_negative_or_infinite("residual", self.residual))
        if not isinstance(self.message, str):
            raise checks.InputTypeError(f"message must be a str, got "
                                        f"{type(self.message).__name__}")
        if self.stiffness is not None:
            set_(self, "stiffness", checks.non_negative_or_infinite("stiffness", self.stiffness))
        for name in ("nominal_area", "e_star"):
            set_(self, name, checks.positive(name, getattr(self, name)))
        if self.pixel_area is None:
            set_(self, "pixel_area", self.nominal_area * np.count_nonzero(contact) / contact.size)
        else:
            set_(self, "pixel_area", checks.non_negative("pixel_area", self.pixel_area))

    @property
    def conductance(self) -> float | None:
        """``2 S / E*`` [length]: constriction conductance times resistivity (Barber's analogy)."""
        if self.stiffness is None:
            return None
        return 2.0 * self.stiffness / self.e_star

    @property
    def fluid_gap(self) -> np.ndarray:
        """The gap the fluid flows through [length]: ``gap`` with the contact set closed (0) and
        the solver's round-off below zero clipped (the input of :func:`bem.leakage.flow.leakage_aperture`)."""
        return np.where(self.contact, 0.0, np.maximum(self.gap, 0.0))

    @property
    def area_fraction(self) -> float:
        """Real over nominal contact area [-]."""
        return self.area / self.nominal_area
