"""The result of the discrete asperity model: from solved points to a :class:`bem.ContactCurve`.

Per point: load W = sum P_i, real area ``pi sum a_i^2``, contacts (asperities with a_i > 0),
stiffness S = -dW/dd (the exact incremental stiffness of the converged discrete system,
:func:`asperity.discrete.complementarity.tangent`) and conductance ``2 S / E*`` (Barber's analogy);
extras ``contact_radii`` and ``forces`` (points x asperities), ``converged``, ``iterations``,
``residual``, ``stable``, ``overlapping_spots``, ``stiffness_converged`` (when stiffness or
conductance is asked for) and ``holm_greenwood_conductance`` (when asked for). Non-convergence
is warned (:class:`bem.ConvergenceWarning`), loss of uniqueness too
(:class:`asperity.ValidityWarning`; :func:`is_stable` says whether a point is a strict energy
minimum).
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg

from bem.common.curve import ContactCurve
from bem.common.warnings import ConvergenceWarning

from asperity.discrete.complementarity import PointSolution, evaluate, tangent
from asperity.discrete.assembly import DiscreteProblem
from asperity.gw.summits import Summits

__all__ = ["ValidityWarning", "build_curve", "neighbours", "overlapping_spots",
           "holm_greenwood_conductance", "is_stable"]


class ValidityWarning(UserWarning):
    """The linearised first-order interaction system lost positive definiteness at some points:
    the solution may not be unique (contact radii comparable to the distance between loaded
    asperities). Overlapping contact spots, an earlier sign of the same limit, are only counted
    in the ``overlapping_spots`` extra, not warned about."""


def neighbours(summits: Summits, spots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distances and indices (into ``spots``) of each spot's 8 nearest other spots (minimum
    image when periodic), shapes (n, k)."""
    from scipy.spatial import cKDTree

    box = None
    if summits.periodic:
        box = (summits.shape[1] * summits.spacing, summits.shape[0] * summits.spacing)
    positions = np.column_stack((summits.x[spots], summits.y[spots]))
    distance, neighbour = cKDTree(positions, boxsize=box).query(positions, k=min(9, spots.size))
    return distance[:, 1:], neighbour[:, 1:]


def overlapping_spots(summits: Summits, radius: np.ndarray) -> np.ndarray:
    """Per point, the number of contact spots that overlap one of their 8 nearest spots
    (``a_i + a_j > r_ij``; minimum image when periodic)."""
    out = np.zeros(radius.shape[0], dtype=int)
    for k, radii in enumerate(radius):
        spots = np.flatnonzero(radii > 0)
        if spots.size < 2:
            continue
        distance, neighbour = neighbours(summits, spots)
        a = radii[spots]
        out[k] = int(np.count_nonzero((distance < a[:, None] + a[neighbour]).any(axis=1)))
    return out


def holm_greenwood_conductance(summits: Summits, radius: np.ndarray) -> np.ndarray:
    """Conductance [length] of eq. (6) over the contact spots of each point.

    In the units of the curve's ``conductance`` (C (rho_1 + rho_2), Barber's analogy
    ``2 S / E*``): ``2 / (R/rho)`` with R/rho of eq. (6) for bodies of resistivity rho each;
    a single spot gives 4a, exactly Barber's 2 (2 E* a) / E*.
    """
    from asperity.common.holm_greenwood import holm_greenwood

    out = np.zeros(radius.shape[0])
    for k, radii in enumerate(radius):
        spots = np.flatnonzero(radii > 0)
        if spots.size:
            out[k] = 2.0 / float(holm_greenwood(summits.x[spots], summits.y[spots], radii[spots]))
    return out


def _stiffness(problem, solutions, extras):
    """Stiffness per point (computing the tangents still missing) and its solve flags."""
    solutions = [s if s.stiffness is not None
                 else tangent(problem, s, evaluate(problem, s.delta, s.separation))
                 for s in solutions]
    solved = np.array([s.stiffness_converged for s in solutions], dtype=bool)
    extras["stiffness_converged"] = solved
    if not solved.all():
        warnings.warn(
            f"discrete asperity model: the stiffness solve did not converge at "
            f"{int(np.count_nonzero(~solved))} of {solved.size} points; see the "
            "'stiffness_converged' extra", ConvergenceWarning, stacklevel=4)
    return solutions, np.array([s.stiffness for s in solutions])


def _warn(extras: dict, tol: float) -> None:
    converged, stable = extras["converged"], extras["stable"]
    count = converged.size
    if not converged.all():
        bad = np.flatnonzero(~converged)
        warnings.warn(
            f"discrete asperity model: {bad.size} of {count} points did not converge to "
            f"tol={tol:g} (worst relative residual {extras['residual'][bad].max():.3g}); see "
            "the 'converged' and 'residual' extras", ConvergenceWarning, stacklevel=4)
    if not stable.all():
        warnings.warn(
            f"discrete asperity model: at {int(np.count_nonzero(~stable))} of {count} points "
            "the linearised first-order interaction system is not positive definite, so the "
            "solution may not be unique: contact radii are comparable to the distance "
            "between loaded asperities and the point-force model is outside its validity; "
            "see the 'stable' and 'overlapping_spots' extras", ValidityWarning, stacklevel=4)


def build_curve(problem: DiscreteProblem, solutions: list[PointSolution], want: frozenset,
                tol: float) -> ContactCurve:
    """The contact curve of solved points (a 1-D path; see the module docstring)."""
    count = len(solutions)
    delta = np.array([s.delta for s in solutions]).reshape(count, -1)
    radius = np.sqrt(delta * problem.radius[None, :])
    forces = problem.hertz[None, :] * delta ** 1.5
    load = forces.sum(axis=1)
    extras = {
        "contact_radii": radius, "forces": forces,
        "converged": np.array([s.converged for s in solutions], dtype=bool),
        "iterations": np.array([s.iterations for s in solutions], dtype=int),
        "residual": np.array([s.residual for s in solutions]),
    }
    stiffness = None
    if "stiffness" in want or "conductance" in want:
        solutions, stiffness = _stiffness(problem, solutions, extras)
    extras["stable"] = np.array([is_stable(problem, s.delta) if s.stable is None else s.stable
                                 for s in solutions], dtype=bool)
    if "holm_greenwood" in want:
        extras["holm_greenwood_conductance"] = holm_greenwood_conductance(problem.summits, radius)
    extras["overlapping_spots"] = overlapping_spots(problem.summits, radius)
    _warn(extras, tol)
    area = problem.summits.area
    return ContactCurve(
        separation=np.array([s.separation for s in solutions]), load=load,
        area=np.pi * np.sum(radius ** 2, axis=1), mean_pressure=load / area, nominal_area=area,
        e_star=problem.e_star,
        contacts=(np.count_nonzero(delta > 0, axis=1).astype(float) if "contacts" in want
                  else None),
        stiffness=stiffness if "stiffness" in want else None,
        conductance=2.0 * stiffness / problem.e_star if "conductance" in want else None,
        extras=extras)


def is_stable(problem: DiscreteProblem, delta: np.ndarray) -> bool:
    """Whether a converged point is a strict energy minimum (as far as can be detected).

    On the loaded asperities, with s_i = sqrt(2 E* a_i) and C = S^1/2 G S^1/2 (entries
    ``2 sqrt(a_i a_j) / (pi r_ij)``), the scaled Hessian is ``I + C``:

    * positive definite for certain when diagonally dominant (every row sum of C < 1);
    * indefinite for certain when a 2 x 2 principal block is, i.e. ``C_ij > 1`` for a pair
      (checked over each spot's 8 nearest loaded neighbours);
    * otherwise 20 Lanczos steps (full reorthogonalisation; start vector weighted by the
      excess row sums, fixed pseudo-random signs) look for a negative Rayleigh quotient, which
      proves indefiniteness. A negative eigenvalue those steps do not resolve can go
      undetected.
    """
    if problem.operator is None:
        return True                         # independent Hertz (+ uniform term): convex
    loaded = np.flatnonzero(delta > 0)
    if loaded.size < 2:
        return True
    s_half = np.sqrt(problem.contact_stiffness(delta, loaded))
    kernel = problem.operator.linear_map(loaded, products=21)
    row_sums = s_half * kernel(s_half)
    if float(np.max(row_sums)) < 1.0:
        return True
    distance, neighbour = neighbours(problem.summits, loaded)
    radii = np.sqrt(problem.radius[loaded] * delta[loaded])
    coupling = 2.0 * np.sqrt(radii[:, None] * radii[neighbour]) / (np.pi * distance)
    if float(np.max(coupling)) > 1.0:
        return False
    return _lanczos_minimum(lambda v: v + s_half * kernel(s_half * v), row_sums) > 0.0


def _lanczos_minimum(apply, row_sums: np.ndarray) -> float:
    """Smallest Ritz value of 20 Lanczos steps (see :func:`is_stable`)."""
    size = row_sums.size
    steps = min(20, size)
    basis = np.empty((steps, size))
    rng = np.random.default_rng(20080101)
    vector = (np.maximum(row_sums - 1.0, 0.0) + 1e-3) * rng.choice((-1.0, 1.0), size)
    vector /= np.linalg.norm(vector)
    alpha, beta = [], []
    for k in range(steps):
        basis[k] = vector
        w = apply(vector)
        alpha.append(float(vector @ w))
        w -= basis[:k + 1].T @ (basis[:k + 1] @ w)      # full reorthogonalisation
        w -= basis[:k + 1].T @ (basis[:k + 1] @ w)
        norm = float(np.linalg.norm(w))
        if k == steps - 1 or norm <= 1e-12 * max(1.0, abs(alpha[-1])):
            break
        beta.append(norm)
        vector = w / norm
    ritz = scipy.linalg.eigvalsh_tridiagonal(np.array(alpha), np.array(beta[:len(alpha) - 1]))
    return float(ritz.min())
