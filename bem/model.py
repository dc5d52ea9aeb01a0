"""The contact-model contract: one question, one answer, for every model of the project.

Every model -- GW theory, improved GW, the discrete asperity model, the boundary-element
reference, and any model added later -- satisfies :class:`ContactModel`: it answers "what is the
contact at these loads, or at these separations?" with a :class:`bem.ContactCurve`.

The contract
------------
* ``model.name`` (str): a short identifier of the kind of model.
* ``model.at_load(load, *, quantities=CURVE_QUANTITIES)`` and
  ``model.at_separation(separation, *, quantities=CURVE_QUANTITIES)`` return a ContactCurve.
* Shapes follow numpy: a scalar gives 0-d fields, an array of shape s gives fields of shape s
  (empty arrays give empty curves). Points may come in any order; results are in the caller's
  order.
* ``quantities`` (any of :data:`bem.CURVE_QUANTITIES`): ``contacts``, ``stiffness``,
  ``conductance`` and ``leakage`` are computed only when asked for (otherwise ``None``);
  separation, load, area and mean pressure are always filled.
* ``curve.extras["converged"]`` is a bool array of the curve's shape for every model (all True
  for closed forms). Non-convergence is flagged there and warned
  (:class:`bem.ConvergenceWarning`), never raised.
* Bad input -- NaN, a negative load, an unknown quantity -- raises ``ValueError`` naming the
  parameter (``load``, ``separation``, ``quantities``).

Zero load
---------
``at_load(0).separation`` is the separation of first contact, ``inf{d : W(d) = 0}``: the height
of the highest summit (discrete model) or of the highest surface point (BEM), measured from the
mean plane of the heights; ``+inf`` for theories whose summit heights are unbounded (GW and
improved GW with Gaussian or exponential heights), where every finite separation carries a load.

Residual
--------
``extras["residual"]``, where a model reports it, is the dimensionless residual of that model's
own equations at the returned point -- the number its ``tol`` is compared with:

* BEM: the last relative pressure change of the (preconditioned) constrained
  conjugate-gradient iteration, the left-hand side of its stopping rule
  (:func:`bem.solve_contact`, ``ContactSolution.residual``).
* Discrete model: the largest violation of displacement compatibility over the summits, relative
  to the largest interference (:mod:`asperity.discrete.model`), and under load control also
  ``|sum P - W| / W``.
* Closed forms (GW, improved GW at a load) have no residual; improved GW at a separation solves
  one scalar equation per point and reports only ``converged``.

Residuals of different models are not comparable with each other; ``converged`` is.
"""

from __future__ import annotations

from typing import Any, Iterable, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from bem.common import checks
from bem.common.checks import points as check_points  # loads and separations of every model
from bem.common.curve import CURVE_QUANTITIES, ContactCurve, check_quantities

__all__ = ["ContactModel", "BoundaryElementModel", "check_points", "check_quantities",
           "empty_curve"]

#: Keywords of :func:`bem.contact_curve` that each call of a model sets itself.
_PER_CALL = frozenset({"heights", "spacing", "loads", "separations", "quantities"})

#: The quantities a model fills whether asked or not.
ALWAYS_FILLED = ("separation", "load", "area", "mean_pressure")


@runtime_checkable
class ContactModel(Protocol):
    """What every contact model provides (see the module docstring for the contract)."""

    @property
    def name(self) -> str:
        """A short identifier of the kind of model."""
        ...

    def at_load(self, load: ArrayLike, *,
                quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """The contact at total loads W [force] >= 0 (any shape)."""
        ...

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """The contact at separations d [length] (any shape)."""
        ...


def empty_curve(nominal_area: float, e_star: float, quantities: Iterable[str],
                extras: Iterable[str] = ()) -> ContactCurve:
    """A curve with no points (for empty input): asked-for fields are empty arrays, the
    ``converged`` extra an empty bool array and each name in ``extras`` an empty float array."""
    want = check_quantities(quantities)
    empty = np.empty(0)
    optional = {q: (empty if q in want else None)
                for q in CURVE_QUANTITIES if q not in ALWAYS_FILLED}
    values = {name: empty for name in extras}
    values["converged"] = np.empty(0, dtype=bool)
    return ContactCurve(separation=empty, load=empty, area=empty, mean_pressure=empty,
                        nominal_area=nominal_area, e_star=e_star, extras=values, **optional)


class BoundaryElementModel:
    """The boundary-element reference as a :class:`ContactModel`: heights, spacing, options.

    Parameters
    ----------
    heights : array_like
        Heights z[j, i] [length] on an N x M grid (as in :func:`bem.contact_curve`).
    spacing : float
        Grid step h [length].
    **options
        Passed unchanged to :func:`bem.contact_curve` on every call (``e_star``, ``periodic``,
        ``tol``, ``max_iter``, ...), so new options of the solver need no change here. Names
        that are not its keywords, and bad heights, spacing, ``e_star``, ``tol``, ``max_iter`` or
        ``periodic``, are refused here rather than at the first solve.

    Each call solves its points as one warm-started path (:func:`bem.contact_curve`).
    Extras: ``converged``, ``iterations``, ``residual``, ``mean_gap`` and whatever else
    :func:`bem.contact_curve` returns.
    """

    name = "bem"

    def __init__(self, heights: ArrayLike, spacing: float, **options: Any) -> None:
        import inspect

        from bem.contact.path import contact_curve
        from bem.contact.solver import MINIMUM_GRID

        keywords = inspect.signature(contact_curve).parameters
        unknown = sorted(set(options) - set(keywords) | set(options) & _PER_CALL)
        if unknown:
            raise TypeError(f"options must be keywords of bem.contact_curve other than "
                            f"{sorted(_PER_CALL)}, got {unknown}")
        given = {name: options.get(name, keywords[name].default)
                 for name in ("e_star", "tol", "max_iter", "periodic")}
        heights, spacing, *_ = checks.contact_problem(heights, spacing, **given,
                                                      minimum_grid=MINIMUM_GRID)
        if "device" in options:   # a GPU asked for where there is none: now, not at the first solve
            from bem.elastic.device import array_module

            array_module(options["device"])
        heights.setflags(write=False)
        self.heights = heights
        self.spacing = spacing
        self.options = dict(options)

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(heights of shape {self.heights.shape}, "
                f"spacing={self.spacing!r}, options={self.options!r})")

    def at_load(self, load: ArrayLike, *,
                quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact at total loads W >= 0 [force], any shape (see :func:`bem.contact_curve`)."""
        values = check_points("load", load, non_negative=True)
        return self._solve(values, "loads", quantities)

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact at separations d [length], any shape (see :func:`bem.contact_curve`)."""
        values = check_points("separation", separation)
        return self._solve(values, "separations", quantities)

    def _solve(self, values: np.ndarray, keyword: str, quantities) -> ContactCurve:
        from bem.contact.path import contact_curve

        want = check_quantities(quantities)
        if values.size == 0:
            return empty_curve(self.heights.size * self.spacing**2,
                               float(self.options.get("e_star", 1.0)), want,
                               extras=("iterations", "residual", "mean_gap"))
        ordered = tuple(q for q in CURVE_QUANTITIES if q in want)
        curve = contact_curve(self.heights, self.spacing, quantities=ordered,
                              **{keyword: values.ravel()}, **self.options)
        return curve.reshaped(values.shape)
