"""Vector operations of the conjugate-gradient solvers (the contact iteration of
:mod:`bem.contact.constrained_cg`, the stiffness solve of :mod:`bem.contact.stiffness`, the Reynolds
solve of :mod:`bem.leakage.flow_solver`): an inner product without BLAS and a fused step of the
Reynolds solve's iteration.
"""

from __future__ import annotations

import numba
import numpy as np

_DOT_SUBSCRIPTS = {1: "i,i->", 2: "ij,ij->"}


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Inner product of two arrays of one shape without BLAS (``@`` on vectors is BLAS).

    OpenBLAS worker threads keep spinning after a call and then compete with the FFT threads
    for the cores (a 60x slowdown of the next FFT measured here on 2 cores), so the iteration
    uses numpy's own reductions.
    """
    return float(np.einsum(_DOT_SUBSCRIPTS[a.ndim], a, b))


@numba.njit(nogil=True, cache=True)
def _step(x: np.ndarray, p: np.ndarray, r: np.ndarray, q: np.ndarray,
          alpha: float) -> float:   # pragma: no cover (compiled)
    """A conjugate-gradient step in place, ``x += alpha p`` and ``r -= alpha q`` (vectors of
    one size), in one pass without temporaries (two 32 MB arrays per iteration at 2048^2);
    returns the new ``r.r``."""
    squares = 0.0
    for i in range(x.size):
        x[i] += alpha * p[i]
        value = r[i] - alpha * q[i]
        r[i] = value
        squares += value * value
    return squares
