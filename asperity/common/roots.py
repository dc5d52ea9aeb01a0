"""Elementwise roots of monotone functions inside brackets (Newton safeguarded by bisection):
the inversion of the GW functions F_n, of the improved-GW effective separation and of
Persson's mean gap."""

from __future__ import annotations

import numpy as np

__all__ = ["monotone_root"]


def monotone_root(function, lower: np.ndarray, upper: np.ndarray, start: np.ndarray, *,
                  increasing: bool, max_iterations: int = 400
                  ) -> tuple[np.ndarray, np.ndarray, int]:
    """Elementwise root of a monotone function inside a bracket: Newton, else bisection.

    ``function(x, index)`` returns ``(value, derivative)`` at the points ``x`` for the
    elements ``index`` of the problem. The root of element i lies in ``[lower[i], upper[i]]``.
    A Newton step that does not fall strictly inside the current bracket (or is not finite)
    is replaced by the bracket midpoint, so the iteration cannot diverge, and rounding noise
    that bounces Newton between two neighbouring points ends by the bracket-width test. Give
    bounds a little outside the root's known interval, so that Newton does not land on them.
    Stopping test, elementwise:
    ``value == 0`` or ``|x_new - x| <= 4 eps max(1, |x_new|)`` or
    ``upper - lower <= 4 eps max(1, |x_new|)``.

    Returns ``(root, converged, iterations)``.
    """
    x = np.array(start, dtype=float, copy=True)
    lo = np.array(lower, dtype=float, copy=True)
    hi = np.array(upper, dtype=float, copy=True)
    converged = np.zeros(x.shape, dtype=bool)
    active = np.arange(x.size)
    x, lo, hi, converged = x.ravel(), lo.ravel(), hi.ravel(), converged.ravel()
    sign = 1.0 if increasing else -1.0
    eps4 = 4.0 * np.finfo(float).eps
    iterations = 0
    while active.size and iterations < max_iterations:
        iterations += 1
        xa = x[active]
        value, derivative = function(xa, active)
        g = sign * value
        lo_a = np.where(g < 0, xa, lo[active])
        hi_a = np.where(g > 0, xa, hi[active])
        lo[active], hi[active] = lo_a, hi_a
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            proposal = xa - value / derivative
        tolerance = eps4 * np.maximum(1.0, np.abs(xa))
        # A Newton step below the tolerance means convergence, even when rounding puts the
        # proposal on the bracket's edge (x itself): test it before falling back to bisection.
        small_step = np.abs(proposal - xa) <= tolerance
        bisect = ~small_step & (~np.isfinite(proposal) | (proposal <= lo_a) | (proposal >= hi_a))
        proposal = np.where(bisect, 0.5 * lo_a + 0.5 * hi_a, proposal)
        exact = g == 0
        done = exact | small_step | (hi_a - lo_a <= tolerance)
        x[active] = np.where(exact, xa, proposal)
        converged[active[done]] = True
        active = active[~done]
    return x, converged, iterations
