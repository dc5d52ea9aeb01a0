"""The discrete asperity model with first-order elastic interaction.

THEORY.md, "The discrete asperity model" (paper Section 4; Ciavarella et al. 2006). Every summit
i (height z_i above the mean plane, radius R_i) is a Hertzian asperity::

    approach  delta_i = a_i^2 / R_i
    force     P_i = 4 E* a_i^3 / (3 R_i) = (4/3) E* R_i^1/2 delta_i^3/2
    contact stiffness dP_i/d delta_i = 2 E* a_i

and every force lowers every other asperity by ``P_j / (pi E* r_ij)``. At separation d the
approaches satisfy displacement compatibility at every summit centre::

    delta_i = max(0, z_i - d - sum_{j != i} P_j / (pi E* r_ij))                        (*)

(contact where the right side is positive; no contact where z_i - d is below the interaction).

Solver
------
(*) is solved for the approaches delta (not the forces or radii: in delta the Jacobian is
``I + G diag(2 E* a)``, regular even at first contact) by a projected semi-smooth Newton method:

* residual ``Phi(delta) = delta - max(0, z - d - G P(delta))``; the active set is where the max
  is positive; relative residual ``||Phi||_inf / max_i(z_i - d, delta_i)`` (and, under load
  control, also ``|sum P - W| / W``). Converged when it is <= ``tol``.
* Newton step on the active set A: ``(I + G_AA S) x = b`` with S = diag(2 E* a_A), solved in the
  symmetric form ``(I + S^1/2 G_AA S^1/2) y = S^1/2 b`` by matrix-free conjugate gradients
  (products by :class:`asperity.interaction.PointForceInteraction`: exact lattice FFT or blocked
  sums, never a dense N x N matrix); under load control the separation is a further unknown and
  a second solve with the right side 1 eliminates it (bordered system).
* globalisation: Armijo backtracking on ``||Phi||`` with projection onto delta >= 0; along a path
  the previous solution (plus the tangent ``d delta / d d``) is the warm start, a step that
  does not converge is split in two, recursively (depth <= 8), and the last resorts are a cold
  start from the mean-field estimate and a continuation in the interaction strength from
  independent Hertz contacts (they find the other branch after a snap-through, e.g. one very
  large summit suddenly pressing its neighbours out of contact). Splitting may use 6 max_iter
  Newton iterations per requested point and the fallbacks 2 max_iter more, so a point far
  outside the model's validity costs bounded time.
* Newton's derivative dP/d delta = 2 E* a vanishes at delta = 0, which would hide the force of
  an asperity entering contact from the step; entering asperities get the secant stiffness
  P(t)/t of their trial approach t instead (the last steps, on a settled contact set, are exact
  Newton steps).

The symmetric matrix ``I + S^1/2 G S^1/2`` is the Hessian of the energy
``sum_i int delta_i dP_i + P^T G P / 2 - sum_i (z_i - d) P_i`` (in the scaled variables). The
point-force kernel has a zero diagonal and is indefinite, so when neighbouring asperities are
heavily loaded (contact radii comparable to their distance; for two equal asperities a distance
s apart exactly when ``a > pi s / 2``) the Hessian loses positive definiteness: the first-order
model then no longer has a unique, stable solution. Each converged point is checked (diagonal
dominance certifies definiteness, an indefinite 2 x 2 block of neighbours certifies the
opposite, otherwise 20 Lanczos steps search for negative curvature, as do the
conjugate-gradient solves, which then fall back to MINRES); a point found indefinite is
flagged ``stable = False`` and a :class:`ValidityWarning` is issued. Overlapping contact spots
(``a_i + a_j > r_ij``, an earlier sign of the same limit) are counted per point in the
``overlapping_spots`` extra. The solver never loops without bound: every (sub-)step stops after
``max_iter`` Newton iterations, on stagnation, or when the line search fails, and reports
``converged = False`` with a :class:`bem.warnings.ConvergenceWarning`.

Stiffness is the exact incremental stiffness of the converged discrete system,
``S = -dW/dd = s^T (I + S^1/2 G_AA S^1/2)^{-1} s`` with ``s = S^1/2 1`` (the linearisation of (*)
on the active set), and the conductance follows by Barber's analogy, ``C rho = 2 S / E*``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.sparse.linalg

from bem.curve import CURVE_QUANTITIES, ContactCurve
from bem.model import check_points, check_quantities, empty_curve
from bem.warnings import ConvergenceWarning

from asperity.interaction import PointForceInteraction
from asperity.summits import Summits

__all__ = ["DiscreteAsperityModel", "ValidityWarning", "DISCRETE_QUANTITIES"]

#: Quantities :meth:`DiscreteAsperityModel.at_separation` / ``at_load`` can compute.
DISCRETE_QUANTITIES = ("separation", "load", "area", "contacts", "mean_pressure", "stiffness",
                       "conductance", "holm_greenwood")
_DEFAULT_QUANTITIES = CURVE_QUANTITIES
_MAX_SPLIT_DEPTH = 8
_WORK_PER_POINT = 6         # Newton iterations per requested point, in units of max_iter
_WORK_RESERVE = 2           # ... plus this much for the cold-start fallbacks
_ARMIJO = 1e-4
_MIN_STEP = 2.0 ** -12


class ValidityWarning(UserWarning):
    """The linearised first-order interaction system lost positive definiteness at some points:
    the solution may not be unique (contact radii comparable to the distance between loaded
    asperities). Overlapping contact spots, an earlier sign of the same limit, are only counted
    in the ``overlapping_spots`` extra, not warned about."""


@dataclass
class _State:
    """One evaluation of the compatibility residual at (delta, d)."""

    delta: np.ndarray
    separation: float
    loaded: np.ndarray       # indices with delta > 0
    forces: np.ndarray       # P at loaded
    load: float
    trial: np.ndarray        # max(0, z - d - u), all asperities
    phi: np.ndarray          # delta - trial
    scale: float             # length scale of the relative residual
    residual: float          # relative residual (incl. load residual under load control)
    load_residual: float     # |sum P - W| / W under load control, else 0


@dataclass
class _Solution:
    delta: np.ndarray
    separation: float
    converged: bool
    iterations: int
    residual: float
    stable: bool | None      # None until checked (see DiscreteAsperityModel._is_stable)
    tangent: np.ndarray | None = None   # -d delta / d d on the active set (full length)
    stiffness: float | None = None
    stiffness_converged: bool = True    # the linear solve behind the stiffness met its tolerance

    def load_carried(self) -> float:
        """Largest approach (> 0 when any asperity is in contact)."""
        return float(self.delta.max(initial=0.0))


def _cg(apply, rhs, *, rtol, max_iter):
    """Conjugate gradients for a symmetric operator; stops on non-positive curvature.

    Returns (solution, converged, iterations, positive_definite_so_far).
    """
    x = np.zeros_like(rhs)
    r = rhs.copy()
    rr = float(r @ r)
    target = (rtol * math.sqrt(rr)) ** 2
    if rr == 0.0:
        return x, True, 0, True
    p = r.copy()
    for k in range(max_iter):
        q = apply(p)
        curvature = float(p @ q)
        if not curvature > 0.0:
            return x, False, k, False
        alpha = rr / curvature
        x += alpha * p
        r -= alpha * q
        rr_new = float(r @ r)
        if rr_new <= target:
            return x, True, k + 1, True
        p *= rr_new / rr
        p += r
        rr = rr_new
    return x, False, max_iter, True


class DiscreteAsperityModel:
    """Hertzian summits with first-order elastic interaction (THEORY.md, discrete model).

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
        Relative residual at which a point is converged (see the module docstring), in (0, 1).
    max_iter : int
        Newton iterations per (sub-)step, >= 1.
    method : {"auto", "fft", "direct"}
        How interaction sums are evaluated (:class:`asperity.interaction.PointForceInteraction`).

    Notes
    -----
    Units: lengths in any unit, E* and pressures in one pressure unit, forces = pressure x
    length^2. The separation d is measured from the rigid plane to the mean plane of the heights
    (the reference of ``summits.height``), in the far field.

    A model keeps work buffers (FFT plans, path state): use one model per thread. Results are
    fresh arrays, never views of those buffers.
    """

    def __init__(self, summits: Summits, *, e_star: float = 1.0, interaction: bool = True,
                 m: float | None = None, tol: float = 1e-10, max_iter: int = 50,
                 method: str = "auto") -> None:
        if not isinstance(summits, Summits):
            raise ValueError(f"summits must be an asperity.Summits record, got "
                             f"{type(summits).__name__}")
        if summits.count == 0:
            raise ValueError("summits must contain at least one summit")
        e_star = float(e_star)
        if not (math.isfinite(e_star) and e_star > 0):
            raise ValueError(f"e_star must be finite and > 0, got {e_star!r}")
        if not isinstance(interaction, (bool, np.bool_)):
            raise ValueError(f"interaction must be True or False, got {interaction!r}")
        if m is not None:
            m = float(m)
            if not (math.isfinite(m) and m >= 0):
                raise ValueError(f"m must be finite and >= 0 (or None), got {m!r}")
            if interaction:
                raise ValueError("m (uniform interaction) replaces the pairwise interaction: "
                                 "use it with interaction=False")
        tol = float(tol)
        if not (0 < tol < 1):
            raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
        if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) \
                or max_iter < 1:
            raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
        self.summits = summits
        self.e_star = e_star
        self.interaction = bool(interaction)
        self.m = m
        self.tol = tol
        self.max_iter = int(max_iter)
        self._z = summits.height
        self._radius = summits.radius
        self._hertz = (4.0 / 3.0) * e_star * np.sqrt(self._radius)   # P = hertz * delta^1.5
        self._uniform = 0.0 if m is None else m / (e_star * math.sqrt(summits.area))
        self.operator = (PointForceInteraction.from_summits(summits, e_star=e_star, method=method)
                         if self.interaction else None)
        self._coupling = 1.0      # < 1 only inside the interaction-strength homotopy
        self._work_left = math.inf   # Newton iterations left for the current point

    # ------------------------------------------------------------------ public API
    def at_separation(self, separation, *, quantities=_DEFAULT_QUANTITIES) -> ContactCurve:
        """Solve the discrete model at given separations.

        Parameters
        ----------
        separation : float or array_like
            Separations d [length] (finite). Solved as a warm-started path from large to small
            d; results are returned in the caller's order.
        quantities : sequence of str
            Which of :data:`DISCRETE_QUANTITIES` to compute. Separation, load, area, contacts
            and mean pressure are always returned; "stiffness"/"conductance" cost one more
            Krylov solve per point; "holm_greenwood" evaluates eq. (6) over the contact spots.

        Returns
        -------
        bem.ContactCurve
            With extras ``contact_radii`` and ``forces`` (points x asperities, [length] and
            [force]), ``holm_greenwood_conductance`` (1 / (R/rho) of eq. 6 [length], if asked),
            ``converged``, ``iterations`` (Newton iterations, all sub-steps included),
            ``residual`` (relative, see the module docstring), ``stable`` (False where the
            solution was found not to be a unique energy minimum) and ``overlapping_spots``
            (contact spots overlapping a neighbouring spot: the point-force model is then
            outside its assumptions), all per point.

        Notes
        -----
        Cost: each Newton iteration needs one interaction product per conjugate-gradient step
        (typically 5 to 40) plus one per line-search trial; along a path 3 to 6 iterations per
        point. See ``benchmarks/bench_discrete.py`` for measured times.
        """
        points = check_points("separation", separation)
        want = check_quantities(quantities, DISCRETE_QUANTITIES)
        if points.size == 0:
            return self._empty_curve(want)
        values = points.ravel()
        order = np.argsort(-values, kind="stable")
        solutions: list[_Solution | None] = [None] * values.size
        state = self._first_contact()
        for index in order:
            self._work_left = _WORK_PER_POINT * self.max_iter
            state = self._path_step_separation(state, float(values[index]), 0,
                                               want_tangent="stiffness" in want or
                                               "conductance" in want)
            solutions[index] = state
        return self._curve(solutions, want).reshaped(points.shape)

    def at_load(self, load, *, quantities=_DEFAULT_QUANTITIES) -> ContactCurve:
        """Solve the discrete model at given total loads W [force] (>= 0).

        The separation is an unknown solved together with the approaches (bordered Newton
        system). W = 0 gives the separation of first contact (the highest summit). Loads are
        solved as a warm-started path in increasing order and returned in the caller's order.
        See :meth:`at_separation` for ``quantities`` and the returned fields.
        """
        points = check_points("load", load, non_negative=True)
        want = check_quantities(quantities, DISCRETE_QUANTITIES)
        if points.size == 0:
            return self._empty_curve(want)
        values = points.ravel()
        order = np.argsort(values, kind="stable")
        solutions: list[_Solution | None] = [None] * values.size
        state = self._first_contact()
        previous_load = 0.0
        for index in order:
            target = float(values[index])
            self._work_left = _WORK_PER_POINT * self.max_iter
            state = self._path_step_load(state, previous_load, target, 0)
            previous_load = target
            solutions[index] = state
        return self._curve(solutions, want).reshaped(points.shape)

    @property
    def name(self) -> str:
        """``"discrete"`` (pairwise interaction), ``"discrete_uniform"`` (the mean-field term
        m) or ``"discrete_no_interaction"``."""
        if self.interaction:
            return "discrete"
        return "discrete_no_interaction" if self.m is None else "discrete_uniform"

    def _empty_curve(self, want: frozenset) -> ContactCurve:
        return empty_curve(self.summits.area, self.e_star, want & set(CURVE_QUANTITIES),
                           extras=("iterations", "residual", "stable", "overlapping_spots"))

    # ------------------------------------------------------------------ mechanics
    def _interaction(self, forces, sources, targets, total) -> np.ndarray:
        """Displacement [length] at targets from forces at sources (pairwise + uniform)."""
        u = np.zeros(targets.size)
        if self.operator is not None and sources.size and targets.size:
            u += self.operator.displacement(forces, sources=sources, targets=targets)
            if self._coupling != 1.0:
                u *= self._coupling
        if self._uniform:
            u += self._uniform * total
        return u

    def _evaluate(self, delta, separation, target_load=None) -> _State:
        loaded = np.flatnonzero(delta > 0)
        forces = self._hertz[loaded] * delta[loaded] ** 1.5
        total = float(forces.sum())
        interference = self._z - separation
        candidates = np.flatnonzero(interference > 0)
        trial = np.zeros_like(delta)
        if candidates.size:
            u = self._interaction(forces, loaded, candidates, total)
            trial[candidates] = np.maximum(interference[candidates] - u, 0.0)
        phi = delta - trial
        length = max(float(interference.max()), float(delta.max(initial=0.0)))
        residual = float(np.abs(phi).max()) / length if length > 0 else 0.0
        load_residual = 0.0
        if target_load is not None:
            load_residual = abs(total - target_load) / target_load
            residual = max(residual, load_residual)
        return _State(delta, separation, loaded, forces, total, trial, phi, length, residual,
                      load_residual)

    @staticmethod
    def _merit(state: _State, scale: float) -> float:
        """Armijo merit: 2-norm of the residual on a fixed length scale (plus load residual)."""
        merit = float(np.sqrt(state.phi @ state.phi)) / scale if scale > 0 else 0.0
        return math.hypot(merit, state.load_residual)

    def _contact_stiffness(self, delta, indices):
        """dP/d delta = 2 E* a = 2 E* sqrt(R delta) [force/length]."""
        return 2.0 * self.e_star * np.sqrt(self._radius[indices] * delta[indices])

    def _solve_active(self, active, s_half, rhs, rtol, *, scaled=False):
        """Solve (I + H S) x = rhs on the active set, H = G_AA + c 1 1^T, S = s_half^2.

        Through the symmetric system (I + S^1/2 H S^1/2) y = S^1/2 rhs, x = rhs - H S^1/2 y.
        Returns (x, positive_definite), or (x, positive_definite, y) when ``scaled``.
        """
        if self.operator is None and not self._uniform:
            return (rhs.copy(), True, s_half * rhs, True) if scaled else (rhs.copy(), True)
        kernel = self.operator.linear_map(active) if self.operator is not None else None
        uniform = self._uniform

        coupling = self._coupling

        def apply_h(values):
            out = kernel(values) if kernel is not None else np.zeros_like(values)
            if coupling != 1.0:
                out *= coupling
            if uniform:
                out = out + uniform * values.sum()
            return out

        def apply(values):
            return values + s_half * apply_h(s_half * values)

        b = s_half * rhs
        max_iter = min(max(50, 2 * active.size), 2000)
        y, solved, _, definite = _cg(apply, b, rtol=rtol, max_iter=max_iter)
        if not definite:
            operator = scipy.sparse.linalg.LinearOperator((active.size, active.size),
                                                          matvec=apply, dtype=float)
            y, info = scipy.sparse.linalg.minres(operator, b, rtol=rtol, maxiter=10 * max_iter)
            solved = info == 0
        x = rhs - apply_h(s_half * y)
        return (x, definite, y, bool(solved)) if scaled else (x, definite)

    def _newton(self, delta, separation, target_load=None):
        """Projected semi-smooth Newton from (delta, separation).

        Returns (_Solution, state). Under load control the separation is an unknown.
        """
        delta = np.maximum(delta, 0.0)
        state = self._evaluate(delta, separation, target_load)
        iterations = 0
        history = [state.residual]
        while (state.residual > self.tol and iterations < self.max_iter
               and self._work_left > 0):
            if iterations >= 10 and state.residual > 0.1 * history[-6]:
                break        # stagnating (e.g. outside the model's validity): split the step
            iterations += 1
            self._work_left -= 1
            trial = state.trial
            active = np.flatnonzero(trial > 0)
            step = -state.phi                                  # inactive: go to delta = 0
            leaving = np.flatnonzero((trial <= 0) & (state.delta > 0))
            rhs = -state.phi[active]
            if leaving.size and active.size:
                change = self._contact_stiffness(state.delta, leaving) * step[leaving]
                rhs -= self._interaction(change, leaving, active, float(change.sum()))
            else:
                change = np.zeros(0)
            # Asperities entering contact (delta = 0, where dP/d delta = 0 would hide their
            # force from the linearisation) get the secant stiffness P(t)/t of their trial
            # approach t: near the solution the contact set is fixed and the step is Newton's.
            stiffness = self._contact_stiffness(state.delta, active)
            entering = state.delta[active] == 0.0
            stiffness[entering] = (2.0 / 3.0) * self._contact_stiffness(trial, active[entering])
            s_half = np.sqrt(stiffness)
            rtol = min(1e-2, max(0.1 * state.residual, 1e-3 * self.tol))
            step_separation = 0.0
            if active.size:
                x, _ = self._solve_active(active, s_half, rhs, rtol)
                if target_load is not None:
                    v, _ = self._solve_active(active, s_half, np.ones(active.size), rtol)
                    stiffness = float(s_half ** 2 @ v)
                    if not stiffness > 0:
                        break        # no loaded asperity to carry the load: restart upstream
                    mismatch = float(s_half ** 2 @ x) + float(change.sum()) \
                        - (target_load - state.load)
                    step_separation = mismatch / stiffness
                    x = x - step_separation * v
                step[active] = x
            # Armijo backtracking on the merit, with projection onto delta >= 0.
            t = 1.0
            merit = self._merit(state, state.scale)
            while True:
                candidate = self._evaluate(np.maximum(state.delta + t * step, 0.0),
                                           state.separation + t * step_separation, target_load)
                if self._merit(candidate, state.scale) <= (1.0 - _ARMIJO * t) * merit:
                    break
                t *= 0.5
                if t < _MIN_STEP:
                    candidate = None
                    break
            if candidate is None:
                break
            state = candidate
            history.append(state.residual)
        solution = _Solution(state.delta, state.separation, state.residual <= self.tol,
                             iterations, state.residual, None)
        return solution, state

    def _tangent(self, solution: _Solution, state: _State, rtol=1e-8) -> None:
        """Stiffness -dW/dd and tangent -d delta/dd of a converged point (in place).

        With s = S^1/2 1 and (I + S^1/2 H S^1/2) y = s, the stiffness is s^T y: the conjugate
        gradient estimate of this quadratic form has an error of order rtol^2 times the
        condition number (about 1e-14 relative here), far below the solver tolerance.
        """
        active = np.flatnonzero(state.trial > 0)
        tangent = np.zeros_like(solution.delta)
        if active.size == 0:
            solution.stiffness, solution.tangent = 0.0, tangent
            solution.stiffness_converged = True
            return
        s_half = np.sqrt(self._contact_stiffness(solution.delta, active))
        v, definite, y, solved = self._solve_active(active, s_half, np.ones(active.size), rtol,
                                                    scaled=True)
        tangent[active] = v
        if not definite:                    # negative curvature met at the solution itself
            solution.stable = False
        solution.tangent = tangent
        solution.stiffness = float(s_half @ y)
        solution.stiffness_converged = solved

    def _first_contact(self) -> _Solution:
        """Exact solution at the separation of first contact (highest summit): no force."""
        return _Solution(np.zeros(self._z.size), float(self._z.max()), True, 0, 0.0, True,
                         np.zeros(self._z.size), 0.0)

    def _path_step_separation(self, previous: _Solution, separation: float, depth: int,
                              want_tangent: bool) -> _Solution:
        """Solve at ``separation`` from the solution ``previous`` on the path.

        Warm start (previous approaches plus the tangent); if Newton's method fails, split the
        step in two recursively; at the top level, as last resorts, start cold from the
        mean-field estimate, then continue in the interaction strength (:meth:`_homotopy`):
        this finds a solution on another branch when the path went through a fold, e.g. one
        very large summit suddenly pressing its neighbours out of contact. The work per point
        is bounded.
        """
        if separation >= self._z.max():
            result = self._first_contact()
            result.separation = separation
            return result
        if previous.load_carried() > 0:
            guess = previous.delta
            if previous.tangent is not None:
                guess = previous.delta + previous.tangent * (previous.separation - separation)
        else:
            guess = self._mean_field_guess(separation)
        solution, state = self._newton(guess, separation)
        spent = solution.iterations
        if not solution.converged and depth < _MAX_SPLIT_DEPTH and self._work_left > 0:
            middle = 0.5 * (previous.separation + separation)
            half = self._path_step_separation(previous, middle, depth + 1, True)
            spent += half.iterations
            if half.converged:
                retry = self._path_step_separation(half, separation, depth + 1, want_tangent)
                spent += retry.iterations
                if retry.converged:
                    retry.iterations = spent
                    return retry
        if not solution.converged and depth == 0:
            self._work_left = max(self._work_left, 0) + _WORK_RESERVE * self.max_iter
            cold, cold_state = self._newton(self._mean_field_guess(separation), separation)
            spent += cold.iterations
            if not cold.converged:
                cold, cold_state = self._homotopy(separation, None)
                spent += cold.iterations
            if cold.converged:
                solution, state = cold, cold_state
        solution.iterations = spent
        if want_tangent or depth > 0:
            self._tangent(solution, state)
        return solution

    def _mean_field_coefficient(self) -> float:
        """Uniform displacement per unit load [length/force] of the cold-start estimate.

        The pairwise sum averaged over asperities spread uniformly on a square of area A is
        about ``0.95 W / (E* sqrt(A))`` (the m of the improved GW theory); used only to start
        Newton's method far from first contact, never in the solution.
        """
        if self.operator is None:
            return self._uniform
        return 0.95 / (self.e_star * math.sqrt(self.summits.area))

    def _mean_field_guess(self, separation: float) -> np.ndarray:
        """Approaches of the mean-field (uniform interaction) model at ``separation``."""
        interference = self._z - separation
        coefficient = self._mean_field_coefficient()

        def excess(load):
            lowered = np.maximum(interference - coefficient * load, 0.0)
            return float(np.sum(self._hertz * lowered ** 1.5)) - load
        upper = excess(0.0)
        if coefficient == 0.0 or upper <= 0.0:
            return np.maximum(interference, 0.0)
        load = scipy.optimize.brentq(excess, 0.0, upper, xtol=max(1e-9 * upper,
                                                                  np.finfo(float).tiny),
                                     rtol=1e-6)
        return np.maximum(interference - coefficient * load, 0.0)

    def _hertz_separation(self, load: float) -> float:
        """Separation at which independent Hertz contacts carry ``load`` (no interaction)."""
        top = float(self._z.max())
        k_top = float(self._hertz[np.argmax(self._z)])
        lower = top - (load / k_top) ** (2.0 / 3.0)    # the top asperity alone carries >= load

        def excess(d):
            return float(np.sum(self._hertz * np.maximum(self._z - d, 0.0) ** 1.5)) - load
        if excess(lower) <= 0:
            return lower
        return scipy.optimize.brentq(excess, lower, top,
                                     xtol=max(1e-14 * (top - lower), np.finfo(float).tiny),
                                     rtol=4 * np.finfo(float).eps)

    def _path_step_load(self, previous: _Solution, previous_load: float, load: float,
                        depth: int) -> _Solution:
        """Load-control counterpart of :meth:`_path_step_separation` (same fallbacks)."""
        if load == 0.0:
            return self._first_contact()
        if previous_load > 0 and previous.stiffness:
            # Tangent predictor: d(W) ~ d_prev - (W - W_prev) / S, delta along -d delta/dd.
            separation = previous.separation - (load - previous_load) / previous.stiffness
            delta = np.maximum(previous.delta + previous.tangent
                               * (previous.separation - separation), 0.0)
        else:
            delta, separation = self._mean_field_start(load)
        solution, state = self._newton(delta, separation, target_load=load)
        spent = solution.iterations
        if not solution.converged and depth < _MAX_SPLIT_DEPTH and self._work_left > 0:
            middle = (math.sqrt(previous_load * load) if previous_load > 0 else 0.25 * load)
            half = self._path_step_load(previous, previous_load, middle, depth + 1)
            spent += half.iterations
            if half.converged:
                retry = self._path_step_load(half, middle, load, depth + 1)
                spent += retry.iterations
                if retry.converged:
                    retry.iterations = spent
                    return retry
        if not solution.converged and depth == 0:
            self._work_left = max(self._work_left, 0) + _WORK_RESERVE * self.max_iter
            cold, cold_state = self._newton(*self._mean_field_start(load), target_load=load)
            spent += cold.iterations
            if not cold.converged:
                cold, cold_state = self._homotopy(self._hertz_separation(load), load)
                spent += cold.iterations
            if cold.converged:
                solution, state = cold, cold_state
        solution.iterations = spent
        self._tangent(solution, state)
        return solution

    def _homotopy(self, separation: float, target_load: float | None):
        """Continuation in the interaction strength: the pairwise kernel scaled by lambda from 0
        (independent Hertz contacts, solved exactly) to 1, with adaptive steps. Last resort
        when the path in separation or load went through a fold (within the point's Newton
        budget)."""
        delta = np.maximum(self._z - separation, 0.0)
        reached, step, spent = 0.0, 0.25, 0
        solution = state = None
        try:
            while self._work_left > 0 and step >= 2.0 ** -10:
                self._coupling = min(1.0, reached + step)
                trial, trial_state = self._newton(delta, separation, target_load)
                spent += trial.iterations
                if trial.converged:
                    reached = self._coupling
                    delta, separation = trial.delta, trial.separation
                    solution, state = trial, trial_state
                    if reached == 1.0:
                        break
                    step *= 1.5
                else:
                    step *= 0.5
        finally:
            self._coupling = 1.0
        if solution is None or reached < 1.0:
            solution, state = self._newton(delta, separation, target_load)
            spent += solution.iterations
        solution.iterations = spent
        return solution, state

    def _mean_field_start(self, load: float) -> tuple[np.ndarray, float]:
        """Independent Hertz contacts carrying ``load``, all lowered by the mean-field estimate."""
        separation = self._hertz_separation(load)
        delta = np.maximum(self._z - separation, 0.0)
        return delta, separation - self._mean_field_coefficient() * load

    # ------------------------------------------------------------------ output
    def _curve(self, solutions: list[_Solution], want: frozenset) -> ContactCurve:
        count = len(solutions)
        delta = np.array([s.delta for s in solutions]).reshape(count, -1)
        radius = np.sqrt(delta * self._radius[None, :])
        forces = self._hertz[None, :] * delta ** 1.5
        load = forces.sum(axis=1)
        separation = np.array([s.separation for s in solutions])
        converged = np.array([s.converged for s in solutions], dtype=bool)
        extras = {
            "contact_radii": radius,
            "forces": forces,
            "converged": converged,
            "iterations": np.array([s.iterations for s in solutions], dtype=int),
            "residual": np.array([s.residual for s in solutions]),
        }
        stiffness = conductance = None
        if "stiffness" in want or "conductance" in want:
            for s in solutions:
                if s.stiffness is None:
                    self._tangent(s, self._evaluate(s.delta, s.separation))
            stiffness = np.array([s.stiffness for s in solutions])
            solved = np.array([s.stiffness_converged for s in solutions], dtype=bool)
            extras["stiffness_converged"] = solved
            if not solved.all():
                warnings.warn(
                    f"discrete asperity model: the stiffness solve did not converge at "
                    f"{int(np.count_nonzero(~solved))} of {count} points; see the "
                    "'stiffness_converged' extra", ConvergenceWarning, stacklevel=3)
            if "conductance" in want:
                conductance = 2.0 * stiffness / self.e_star
            if "stiffness" not in want:
                stiffness = None
        for s in solutions:
            if s.stable is None:
                s.stable = self._is_stable(s.delta)
        stable = np.array([s.stable for s in solutions], dtype=bool)
        extras["stable"] = stable
        if "holm_greenwood" in want:
            extras["holm_greenwood_conductance"] = self._holm_greenwood(radius)
        if not converged.all():
            bad = np.flatnonzero(~converged)
            warnings.warn(
                f"discrete asperity model: {bad.size} of {count} points did not converge to "
                f"tol={self.tol:g} (worst relative residual "
                f"{extras['residual'][bad].max():.3g}); see the 'converged' and 'residual' "
                f"extras", ConvergenceWarning, stacklevel=3)
        overlapping = self._overlapping_spots(radius)
        extras["overlapping_spots"] = overlapping
        if not stable.all():
            warnings.warn(
                f"discrete asperity model: at {int(np.count_nonzero(~stable))} of {count} points "
                "the linearised first-order interaction system is not positive definite, so the "
                "solution may not be unique: contact radii are comparable to the distance "
                "between loaded asperities and the point-force model is outside its validity; "
                "see the 'stable' and 'overlapping_spots' extras", ValidityWarning, stacklevel=3)
        return ContactCurve(
            separation=separation, load=load, area=np.pi * np.sum(radius ** 2, axis=1),
            mean_pressure=load / self.summits.area, nominal_area=self.summits.area,
            e_star=self.e_star,
            contacts=(np.count_nonzero(delta > 0, axis=1).astype(float) if "contacts" in want
                      else None),
            stiffness=stiffness, conductance=conductance, extras=extras)

    def _neighbours(self, spots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distances and indices (into ``spots``) of each spot's 8 nearest other spots
        (minimum image when periodic), shapes (n, k)."""
        from scipy.spatial import cKDTree
        summits = self.summits
        box = None
        if summits.periodic:
            box = (summits.shape[1] * summits.spacing, summits.shape[0] * summits.spacing)
        positions = np.column_stack((summits.x[spots], summits.y[spots]))
        distance, neighbour = cKDTree(positions, boxsize=box).query(
            positions, k=min(9, spots.size))
        return distance[:, 1:], neighbour[:, 1:]

    def _is_stable(self, delta: np.ndarray) -> bool:
        """Whether the converged point is a strict energy minimum (as far as can be detected).

        On the loaded asperities, with s_i = sqrt(2 E* a_i) and C = S^1/2 G S^1/2 (entries
        ``2 sqrt(a_i a_j) / (pi r_ij)``), the scaled Hessian is ``I + C``:

        * positive definite for certain when diagonally dominant (every row sum of C < 1);
        * indefinite for certain when a 2 x 2 principal block is, i.e. ``C_ij > 1`` for a pair
          (checked over each spot's 8 nearest loaded neighbours);
        * otherwise 20 Lanczos steps (full reorthogonalisation; start vector weighted by the
          excess row sums, fixed pseudo-random signs) look for a negative Rayleigh quotient,
          which proves indefiniteness. A negative eigenvalue those steps do not resolve can go
          undetected.
        """
        if self.operator is None:
            return True                         # independent Hertz (+ uniform term): convex
        loaded = np.flatnonzero(delta > 0)
        if loaded.size < 2:
            return True
        s_half = np.sqrt(self._contact_stiffness(delta, loaded))
        kernel = self.operator.linear_map(loaded, products=21)
        row_sums = s_half * kernel(s_half)
        if float(np.max(row_sums)) < 1.0:
            return True
        distance, neighbour = self._neighbours(loaded)
        radii = np.sqrt(self._radius[loaded] * delta[loaded])
        coupling = 2.0 * np.sqrt(radii[:, None] * radii[neighbour]) / (np.pi * distance)
        if float(np.max(coupling)) > 1.0:
            return False
        steps = min(20, loaded.size)
        basis = np.empty((steps, loaded.size))
        rng = np.random.default_rng(20080101)
        vector = (np.maximum(row_sums - 1.0, 0.0) + 1e-3) * rng.choice((-1.0, 1.0), loaded.size)
        vector /= np.linalg.norm(vector)
        alpha, beta = [], []
        for k in range(steps):
            basis[k] = vector
            w = vector + s_half * kernel(s_half * vector)
            alpha.append(float(vector @ w))
            w -= basis[:k + 1].T @ (basis[:k + 1] @ w)      # full reorthogonalisation
            w -= basis[:k + 1].T @ (basis[:k + 1] @ w)
            norm = float(np.linalg.norm(w))
            if k == steps - 1 or norm <= 1e-12 * max(1.0, abs(alpha[-1])):
                break
            beta.append(norm)
            vector = w / norm
        ritz = scipy.linalg.eigvalsh_tridiagonal(np.array(alpha), np.array(beta[:len(alpha) - 1]))
        return bool(ritz.min() > 0.0)

    def _overlapping_spots(self, radius: np.ndarray) -> np.ndarray:
        """Per point, the number of contact spots that overlap one of their 8 nearest spots
        (``a_i + a_j > r_ij``; minimum image when periodic)."""
        out = np.zeros(radius.shape[0], dtype=int)
        for k, radii in enumerate(radius):
            spots = np.flatnonzero(radii > 0)
            if spots.size < 2:
                continue
            distance, neighbour = self._neighbours(spots)
            a = radii[spots]
            overlap = distance < a[:, None] + a[neighbour]
            out[k] = int(np.count_nonzero(overlap.any(axis=1)))
        return out

    def _holm_greenwood(self, radius: np.ndarray) -> np.ndarray:
        """Conductance [length] of eq. (6) over the contact spots of each point.

        In the units of the curve's ``conductance`` (C (rho_1 + rho_2), Barber's analogy
        ``2 S / E*``): ``2 / (R/rho)`` with R/rho of eq. (6) for bodies of resistivity rho each;
        a single spot gives 4a, exactly Barber's 2 (2 E* a) / E*.
        """
        from asperity.holm_greenwood import holm_greenwood
        out = np.zeros(radius.shape[0])
        for k, radii in enumerate(radius):
            spots = np.flatnonzero(radii > 0)
            if spots.size:
                out[k] = 2.0 / float(holm_greenwood(self.summits.x[spots], self.summits.y[spots],
                                                    radii[spots]))
        return out
