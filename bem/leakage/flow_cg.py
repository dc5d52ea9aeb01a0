"""The conjugate gradients of the Reynolds solve (:mod:`bem.leakage.flow_solver`), stopped on
the error of the dissipation, the quantity the solve is for: its value is known along the way and
the error left is estimated from the energy the last steps removed.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from bem.common.vectors import _dot, _step   # (no BLAS: its threads spin and take the path's cores)

__all__ = ["DISSIPATION_TOLERANCE", "ESTIMATE_CONFIRMATIONS", "ESTIMATE_STEPS",
           "MULTIGRID_MAX_ITERATIONS", "RESIDUAL_LIMIT"]

#: Relative error of the dissipation (the aperture's cubed: three times its relative error) at
#: which the multigrid's conjugate gradients may stop (:func:`_conjugate_gradients`), the
#: residual permitting: an aperture error of about 3e-7, a thousandth of the smallest leakage
#: band a check's reference has shown (2.4e-4; 2e-3 to 1e-2 typically), within the share of
#: the band a refined contact solve may spend (1 %, eq. T40). The estimate follows the energy
#: the iteration removes (T43's dissipation is the energy it minimises). Against 1e-7: the four
#: gaps of a noisy 1024^2 scan at 5-24 % contact, each from the previous one's pressure, 136
#: iterations instead of 186, the apertures within 3.1e-7 of the LU instead of 8.8e-8.
DISSIPATION_TOLERANCE = 1e-6
#: Relative residual at which the multigrid's conjugate gradients stop whatever the estimate
#: (whose decrements need not fall step after step where the convergence is irregular, and at
#: the end are rounding): a floor, not a rule. The residual is relative to ``b``, whose scale is
#: the inlet's, and on a gap that barely percolates the dissipation is many decades below it:
#: at 1e-7 a 256^2 window of a gap at 28 % contact (aperture 1e-6 of its largest gap, the energy
#: 8 decades below its start) stopped 3.7 % off the LU, at 1e-9 1.4e-6 off; at 1e-10 within
#: 6e-7, for 7 % more iterations on 32 such windows and none on the gaps of a 512^2 scan's path.
RESIDUAL_LIMIT = 1e-10
#: Decrements of the energy the error estimate looks back on.
ESTIMATE_STEPS = 5
#: Consecutive iterations at which the estimate must hold before it stops the iteration. From
#: a neighbour's pressure the error can lie in one slow mode (a region hanging on thin necks)
#: behind fast ones: on the heaviest y gap of a 512^2 scan's path the decrements fell at a
#: ratio of 0.08 for six steps, the estimate held once, and a plateau followed (the aperture
#: 1.7e-5 off the LU); asked twice, it stopped after the plateau, 3e-7 off, and every gap of
#: that path took one iteration more.
ESTIMATE_CONFIRMATIONS = 2
#: Most conjugate-gradient iterations of the multigrid solve.
MULTIGRID_MAX_ITERATIONS = 1000


def _conjugate_gradients(matrix, rhs: np.ndarray, preconditioner,
                         dissipation: Callable[[np.ndarray], float] | None,
                         tolerance: float, start: np.ndarray | None = None, *,
                         most: int | None = None) -> tuple[np.ndarray, int, bool]:
    """Preconditioned conjugate gradients for ``A x = b`` from ``x = start`` (default 0; a
    float64 ``start`` is the iterate, updated in place), stopped on the error of the quantity
    the solve is for: ``dissipation(x)`` = ``x.A x - 2 b.x`` + const, the energy the iteration
    minimises. Each step lowers it by ``alpha r.z`` (Hestenes and Stiefel), so its value is
    known along the way, and the error left is estimated from the last :data:`ESTIMATE_STEPS`
    decrements as a geometric tail,
    ``d_k rho / (1 - rho)`` with ``rho`` their largest ratio (none while a decrement grows);
    the iteration stops once that is
    at most :data:`DISSIPATION_TOLERANCE` of the dissipation (evaluated at the iterate, not
    accumulated, for the check) and the relative residual at most ``tolerance``, at
    :data:`ESTIMATE_CONFIRMATIONS` consecutive iterations, or once the
    relative residual is :data:`RESIDUAL_LIMIT` (``tolerance`` if lower) whatever the
    estimate; without ``dissipation``, at the residual ``tolerance`` alone. Returns
    ``(x, iterations, settled)``, ``settled`` False after ``most`` iterations (default
    :data:`MULTIGRID_MAX_ITERATIONS`).
    """
    if start is None:
        x, r = np.zeros_like(rhs), rhs.copy()
    else:
        x = np.asarray(start, dtype=float)   # (the caller's start becomes the iterate)
        r = rhs - matrix @ x
    p = preconditioner @ r   # (the first direction is the preconditioned residual itself)
    rz = _dot(r, p)
    norm = math.sqrt(_dot(rhs, rhs))
    enough = tolerance * norm
    # stops whatever the estimate (and without one, the only rule)
    limit = enough if dissipation is None else min(RESIDUAL_LIMIT, tolerance) * norm
    if math.sqrt(_dot(r, r)) <= limit:   # (e.g. b = 0: a periodic gap uniform along the flow)
        return x, 0, True
    energy = dissipation(x) if dissipation is not None else math.nan
    decrements: list[float] = []
    confirmed = 0
    most = MULTIGRID_MAX_ITERATIONS if most is None else most
    for iteration in range(1, most + 1):
        q = matrix @ p
        alpha = rz / _dot(p, q)
        residual = math.sqrt(_step(x, p, r, q, alpha))
        del q   # (each field freed once dead: the V-cycle's peak holds x, r and p alone)
        decrements.append(alpha * rz)
        energy -= alpha * rz
        if residual <= limit:
            return x, iteration, True
        tail = _remaining(decrements) if dissipation is not None else math.inf
        if residual <= enough and tail <= DISSIPATION_TOLERANCE * abs(energy) \
                and tail <= DISSIPATION_TOLERANCE * abs(dissipation(x)):
            confirmed += 1
            if confirmed >= ESTIMATE_CONFIRMATIONS:
                return x, iteration, True
        else:
            confirmed = 0
        z = preconditioner @ r
        rz_next = _dot(r, z)
        p *= rz_next / rz
        p += z
        rz = rz_next
        del z
    return x, most, False


def _remaining(decrements: list[float]) -> float:
    """The energy still to be removed, from the last decrements as a geometric tail (inf while
    there are too few, or one grew)."""
    if len(decrements) <= ESTIMATE_STEPS:
        return math.inf
    last = np.asarray(decrements[-ESTIMATE_STEPS - 1:])
    if np.any(last <= 0.0):
        return math.inf
    rho = float(np.max(last[1:] / last[:-1]))
    return math.inf if rho >= 1.0 else float(last[-1]) * rho / (1.0 - rho)
