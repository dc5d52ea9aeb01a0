"""Holm-Greenwood constriction resistance of a set of circular contact spots.

Paper Section 3, eq. (6) (Greenwood 1966), docs/theory.md "Holm-Greenwood":

    R / rho = 1 / (2 sum_i a_i) + (1/pi) sum_{i != j} (a_i a_j / s_ij) / (sum_i a_i)^2

for spots of radii a_i whose centres are s_ij apart, between two bodies of resistivity rho
each (for unequal bodies rho = (rho_1 + rho_2)/2). The first term is the parallel resistance
of the isolated spots (a single spot gives rho/(2a)); the second is their interaction, the
point-source potential rho/(pi s) of each spot's current (proportional to its radius) at the
others. Barber's analogy links it to the stiffness: ``R/rho = E*/S = 2/conductance`` with the
``conductance = 2S/E*`` of a :class:`bem.ContactCurve`.

The double sum is a quadratic form with a 1/r kernel. It is evaluated exactly, in square
blocks of 256 x 256 spot pairs (memory independent of the number of spots beyond the inputs),
over the pairs i < j only: 10,000 spots take about 0.2 s (benchmarks/bench_asperity_theory.py),
500 spots about 1 ms.
"""

from __future__ import annotations

import math

import numpy as np

from bem.common import checks
from numpy.typing import ArrayLike
from scipy.spatial.distance import cdist

__all__ = ["holm_greenwood"]

_BLOCK = 256                 # 256 x 256 doubles = 0.5 MB: the block stays in L2 cache


def _coordinates(name: str, values: ArrayLike) -> np.ndarray:
    return checks.real_array(name, values).ravel()


def _pair_sum(points: np.ndarray, radii: np.ndarray) -> float:
    """sum_{i<j} a_i a_j / s_ij by blocks; ValueError if two centres coincide."""
    n = radii.size
    below_or_on_diagonal = np.tri(_BLOCK, dtype=bool)
    total = 0.0
    for i0 in range(0, n, _BLOCK):
        i1 = min(i0 + _BLOCK, n)
        rows = points[i0:i1]
        for j0 in range(i0, n, _BLOCK):
            j1 = min(j0 + _BLOCK, n)
            distance = cdist(rows, points[j0:j1])
            if j0 == i0:
                mask = below_or_on_diagonal[: i1 - i0, : j1 - j0]
                distance[mask] = np.inf                  # keep the pairs i < j only
            if distance.min() == 0.0:
                raise ValueError("x, y: two spots with radius > 0 have the same centre "
                                 "(the interaction term is infinite)")
            with np.errstate(over="ignore"):            # subnormal distances: 1/s = inf
                np.reciprocal(distance, out=distance)
            total += float(radii[i0:i1] @ distance @ radii[j0:j1])
    return total


def holm_greenwood(x: ArrayLike, y: ArrayLike, radii: ArrayLike) -> float:
    """Constriction resistance over resistivity, R/rho, of circular spots (paper eq. 6).

    Parameters
    ----------
    x, y : array_like
        Spot centres [length]; any shape, flattened; equal sizes.
    radii : array_like
        Spot radii a_i >= 0 [length], same size. Spots of radius 0 carry no current and are
        ignored (so a contact-radius array with non-contacting asperities can be passed as is).

    Returns
    -------
    float
        R/rho [1/length], for two bodies of resistivity rho each (see the module docstring).
        ``inf`` when no spot has a positive radius: without contact the resistance is
        infinite.

    Raises
    ------
    ValueError
        Mismatched sizes, NaN or inf, a negative radius, or two spots of positive radius at the
        same centre (the interaction term 1/s_ij would be infinite).

    Notes
    -----
    Exact O(N^2) evaluation, vectorised in blocks (memory O(N)); see the module docstring.
    For a uniform cluster of n spots of radius a spread over a circle of radius alpha the
    interaction term tends to 16/(3 pi^2 alpha) = 0.54/alpha, close to Holm's 1/(2 alpha) of
    eq. (5).
    """
    xs, ys, a = (_coordinates(name, v) for name, v in (("x", x), ("y", y), ("radii", radii)))
    if not (xs.size == ys.size == a.size):
        raise ValueError(f"x, y and radii must have the same size, got {xs.size}, {ys.size} "
                         f"and {a.size}")
    if (a < 0).any():
        raise ValueError("radii must be >= 0")
    conducting = a > 0
    if not conducting.any():
        return math.inf
    a = a[conducting]
    points = np.column_stack([xs[conducting], ys[conducting]])
    total_radius = float(a.sum())
    # With weights w_i = a_i / sum(a): sum_{i != j} a_i a_j / s_ij / (sum a)^2 = sum w_i w_j / s_ij,
    # so neither (sum a)^2 nor the products a_i a_j over- or underflow.
    weights = a / total_radius
    interaction = 2.0 * _pair_sum(points, weights) if a.size > 1 else 0.0
    return 1.0 / (2.0 * total_radius) + interaction / math.pi
