"""The discrete asperity model with first-order elastic interaction.

docs/theory.md, eqs. T18-T21 (paper Section 4; Ciavarella et al. 2006). Every summit
i (height z_i above the mean plane, radius R_i) is a Hertzian asperity::

    approach  delta_i = a_i^2 / R_i
    force     P_i = 4 E* a_i^3 / (3 R_i) = (4/3) E* R_i^1/2 delta_i^3/2
    contact stiffness dP_i/d delta_i = 2 E* a_i

and every force lowers every other asperity by ``P_j / (pi E* r_ij)``. At separation d the
approaches satisfy displacement compatibility at every summit centre::

    delta_i = max(0, z_i - d - sum_{j != i} P_j / (pi E* r_ij))                        (*)

(contact where the right side is positive; no contact where z_i - d is below the interaction).

The model is split by role:

* :mod:`asperity.discrete.assembly` -- summits to Hertz laws and the interaction operator;
* :mod:`asperity.discrete.complementarity` -- the projected semi-smooth Newton solver of (*), pure
  functions (the residual and its rounding floor are defined there);
* :mod:`asperity.discrete.path` -- warm starts, step splitting and fallbacks along a path,
  visited by the shared stepper :func:`bem.common.continuation.follow_path`;
* :mod:`asperity.discrete.result` -- the :class:`bem.ContactCurve`, the stability and overlap
  diagnostics and the Holm-Greenwood conductance;
* this module -- the public model.

The symmetric matrix ``I + S^1/2 G S^1/2`` (S = diag(2 E* a)) is the Hessian of the energy
``sum_i int delta_i dP_i + P^T G P / 2 - sum_i (z_i - d) P_i`` (in the scaled variables). The
point-force kernel has a zero diagonal and is indefinite, so when neighbouring asperities are
heavily loaded (contact radii comparable to their distance; for two equal asperities a distance
s apart exactly when ``a > pi s / 2``) the Hessian loses positive definiteness: the first-order
model then no longer has a unique, stable solution. Such points are flagged ``stable = False``
and a :class:`ValidityWarning` is issued; overlapping contact spots (``a_i + a_j > r_ij``) are
counted in the ``overlapping_spots`` extra. The solver never loops without bound and reports
``converged = False`` with a :class:`bem.common.warnings.ConvergenceWarning` where it fails.

Stiffness is the exact incremental stiffness of the converged discrete system,
``S = -dW/dd = s^T (I + S^1/2 G_AA S^1/2)^{-1} s`` with ``s = S^1/2 1``, and the conductance
follows by Barber's analogy, ``C rho = 2 S / E*``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike

from bem.common import checks
from bem.common.checks import points as check_points
from bem.common.checks import positive
from bem.common.continuation import follow_path
from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.model import check_quantities, empty_curve

from asperity.discrete.assembly import assemble
from asperity.discrete.path import PathSolver
from asperity.discrete.result import ValidityWarning, build_curve
from asperity.common.leakage import rigid_gaussian_aperture
from asperity.gw.summits import Summits

__all__ = ["DiscreteAsperityModel", "ValidityWarning", "DISCRETE_QUANTITIES"]

#: Quantities :meth:`DiscreteAsperityModel.at_separation` / ``at_load`` can compute.
DISCRETE_QUANTITIES = CURVE_QUANTITIES + ("holm_greenwood",)


class DiscreteAsperityModel:
    """Hertzian summits with first-order elastic interaction (docs/theory.md, discrete model).

    Parameters
    ----------
    summits : Summits
        The asperities (from :func:`asperity.find_summits` or :meth:`Summits.from_points`).
    e_star : float
        Composite modulus E* [pressure].
    interaction : bool
        Include the pairwise interaction ``P_j / (pi E* r_ij)``. ``False`` gives independent
        Hertz contacts (the discrete GW model).
    m : float, optional
        Uniform (mean-field) interaction of the improved GW theory, eq. (2), applied to the
        discrete summits: every asperity is lowered by ``m W / (E* sqrt(A))`` with W the total
        load and A = ``summits.area``. ``None`` (default) = off. It replaces the pairwise sum,
        so it needs ``interaction=False`` (using both would count the interaction twice). With
        it, the model differs from :class:`asperity.ImprovedGreenwoodWilliamson` only by using
        the actual summits instead of a Gaussian fit.
    tol : float
        Relative residual at which a point is converged (:mod:`asperity.discrete.complementarity`),
        in (0, 1).
    max_iter : int
        Newton iterations per (sub-)step, >= 1.
    method : {"auto", "fft", "direct"}
        How interaction sums are evaluated (:class:`asperity.discrete.interaction.PointForceInteraction`).
    local : bool
        With ``interaction``: the pairwise interaction without its uniform part, every
        asperity raised back by ``m W / (E* sqrt(A))`` with m = 0.946 (the mean deflection of a
        uniformly loaded square, the improved GW term): the interactions between neighbouring
        asperities alone, the first-order interaction of an unbounded interface (zero mean
        displacement; docs/theory.md 8.10) rather than of the finite window. Default False.
    height_rms : float, optional
        rms of the surface heights [length], used only by ``leakage``: the effective hydraulic
        aperture of the rigid gap ``max(d - z, 0)``, z ~ N(0, s^2), at the model's own
        separation d (docs/theory.md, eq. L5). Default: s = the standard deviation of the
        summit heights (ddof = 0, as in the GW fit), the only height spread the model carries.
    device : {"cpu", "gpu"}
        Where the interaction's FFT sums run (:class:`asperity.discrete.interaction.PointForceInteraction`,
        :mod:`bem.elastic.device`); the Newton solver and its results stay numpy.

    Notes
    -----
    Units: lengths in any unit, E* and pressures in one pressure unit, forces = pressure x
    length^2. The separation d is measured from the rigid plane to the mean plane of the heights
    (the reference of ``summits.height``), in the far field. The model holds no solver state
    between calls (one model may serve several threads, up to the FFT plans of its operator).
    """

    def __init__(self, summits: Summits, *, e_star: float = 1.0, interaction: bool = True,
                 m: float | None = None, tol: float = 1e-10, max_iter: int = 50,
                 method: str = "auto", height_rms: float | None = None,
                 local: bool = False, device: str = "cpu") -> None:
        tol = checks.real_number("tol", tol, minimum=0.0, exclusive=True, maximum=1.0,
                                 exclusive_maximum=True)
        max_iter = checks.integer("max_iter", max_iter, minimum=1)
        self.problem = assemble(summits, e_star=e_star, interaction=interaction, m=m,
                                method=method, local=local, device=device)
        self.local = bool(local)
        self.summits = summits
        self.e_star = self.problem.e_star
        self.interaction = bool(interaction)
        self.m = None if m is None else float(m)
        self.tol = tol
        self.max_iter = int(max_iter)
        self.operator = self.problem.operator
        self.height_rms = None if height_rms is None else positive("height_rms", height_rms)

    @property
    def name(self) -> str:
        """``"discrete"`` (pairwise interaction), ``"discrete_local"`` (without its uniform
        part), ``"discrete_uniform"`` (the mean-field term m) or ``"discrete_no_interaction"``."""
        if self.interaction:
            return "discrete_local" if self.local else "discrete"
        return "discrete_no_interaction" if self.m is None else "discrete_uniform"

    def _solver(self) -> PathSolver:
        return PathSolver(self.problem, self.tol, self.max_iter)

    def at_separation(self, separation: ArrayLike, *,
                      quantities=CURVE_QUANTITIES) -> ContactCurve:
        """Solve the discrete model at given separations.

        Parameters
        ----------
        separation : float or array_like
            Separations d [length] (finite, of magnitude <= 1e30,
            :data:`bem.common.checks.SUPPORTED_MAGNITUDE`; any shape, numpy's rule: a scalar gives 0-d
            fields). Solved as a warm-started path from large to small d; results are returned
            in the caller's order.
        quantities : sequence of str
            Which of :data:`DISCRETE_QUANTITIES` to compute. Separation, load, area and mean
            pressure are always returned; "contacts" counts asperities in contact;
            "stiffness"/"conductance" cost one more Krylov solve per point; "holm_greenwood"
            evaluates eq. (6) over the contact spots; "leakage" is the effective hydraulic
            aperture of the rigid gap at the solved separation (eq. L5, no interaction
            correction to the gap).

        Returns
        -------
        bem.ContactCurve
            With extras ``contact_radii`` and ``forces`` (points x asperities, [length] and
            [force]), ``holm_greenwood_conductance`` (1 / (R/rho) of eq. 6 [length], if asked),
            ``converged``, ``iterations`` (Newton iterations, all sub-steps included),
            ``residual`` (relative, :mod:`asperity.discrete.complementarity`), ``stable`` (False where
            the solution was found not to be a unique energy minimum),
            ``overlapping_spots`` (contact spots overlapping a neighbouring spot: the
            point-force model is then outside its assumptions) and, with stiffness,
            ``stiffness_converged``, all per point.

        Notes
        -----
        Cost: each Newton iteration needs one interaction product per conjugate-gradient step
        (typically 5 to 40) plus one per line-search trial; along a path 3 to 6 iterations per
        point. See ``benchmarks/bench_discrete.py`` for measured times.
        """
        points = checks.below_supported_magnitude("separation",
                                                  check_points("separation", separation))
        want = check_quantities(quantities, DISCRETE_QUANTITIES)
        if points.size == 0:
            return self._empty_curve(want)
        solver = self._solver()
        tangents = bool(want & {"stiffness", "conductance"})
        solutions = follow_path(
            points.ravel(), solver.start(),
            lambda previous, d: solver.separation_step(previous, d, want_tangent=tangents),
            control="separation")
        return self._with_leakage(build_curve(self.problem, solutions, want, self.tol),
                                  want).reshaped(points.shape)

    def at_load(self, load: ArrayLike, *, quantities=CURVE_QUANTITIES) -> ContactCurve:
        """Solve the discrete model at given total loads W [force] (>= 0 and <= 1e30, any shape).

        The separation is an unknown solved together with the approaches (bordered Newton
        system). W = 0 gives the separation of first contact (the highest summit). Loads are
        solved as a warm-started path in increasing order and returned in the caller's order;
        a point that fails on the path is solved again as if alone. See
        :meth:`at_separation` for ``quantities`` and the returned fields.
        """
        points = checks.below_supported_magnitude("load",
                                                  check_points("load", load, non_negative=True))
        want = check_quantities(quantities, DISCRETE_QUANTITIES)
        if points.size == 0:
            return self._empty_curve(want)
        solver = self._solver()
        states = follow_path(points.ravel(), (solver.start(), 0.0), solver.load_step,
                             control="load")
        solutions = [solution for solution, _ in states]
        return self._with_leakage(build_curve(self.problem, solutions, want, self.tol),
                                  want).reshaped(points.shape)

    @property
    def gap_rms(self) -> float:
        """s [length] of the rigid gap behind ``leakage``: ``height_rms``, else the standard
        deviation of the summit heights."""
        if self.height_rms is not None:
            return self.height_rms
        return float(np.std(self.summits.height))      # 0 for one summit: a flat surface

    def _with_leakage(self, curve: ContactCurve, want: frozenset) -> ContactCurve:
        if "leakage" not in want:
            return curve
        return dataclasses.replace(curve, leakage=rigid_gaussian_aperture(curve.separation,
                                                                          self.gap_rms))

    def _empty_curve(self, want: frozenset) -> ContactCurve:
        return empty_curve(self.summits.area, self.e_star, want & set(CURVE_QUANTITIES),
                           extras=("iterations", "residual", "stable", "overlapping_spots"))

    def __repr__(self) -> str:
        return (f"{type(self).__name__}({self.summits.count} summits, e_star={self.e_star!r}, "
                f"interaction={self.interaction!r}, local={self.local!r}, m={self.m!r}, "
                f"tol={self.tol!r})")
