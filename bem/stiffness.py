"""Incremental normal stiffness of a converged contact state (docs/theory.md, "8.6 Stiffness by the incremental problem").

The incremental problem on the contact set C, ``K_CC q = 1`` (unit rigid approach), solved by
conjugate gradients preconditioned like the contact iteration (:mod:`bem.preconditioner`);
``S = -dW/dd = h^2 sum q`` and the conductance by Barber's analogy ``C rho = 2 S / E*``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from bem.constrained_cg import _dot, _Workspace
from bem.halfspace import HalfSpace
from bem.preconditioner import InverseKernel
from bem.warnings import ConvergenceWarning


def _stiffness(operator: HalfSpace, contact: np.ndarray, *, tol: float, max_iter: int,
               ws: _Workspace, preconditioner: InverseKernel | None = None
               ) -> tuple[float, bool, int]:
    """Solve ``K_CC q = 1`` on the contact set C by (preconditioned) conjugate gradients;
    ``S = h^2 sum q``.

    With ``preconditioner`` M, the residual is preconditioned by ``P_C M P_C`` (symmetric
    positive definite on C; :mod:`bem.preconditioner`), which keeps the iteration count nearly
    independent of the grid. Stops when ``||1 - (K q)_C|| <= tol sqrt(|C|)``. Returns
    (S, converged, iterations).
    """
    n_contact = int(np.count_nonzero(contact))
    if n_contact == 0:
        return 0.0, True, 0
    if operator.periodic and n_contact == contact.size:
        warnings.warn("bem.solve_contact: full contact of a periodic surface: the stiffness is "
                      "infinite (no load can push the plane further)", ConvergenceWarning,
                      stacklevel=4)
        return math.inf, True, 0
    # the workspace of the contact solve, free once it has ended, and the operator's FFT
    # buffers (direction in, product out) hold every array
    weight, q, residual = ws.contact_weight, ws.g, ws.work
    direction, product = operator._direction_buffers()
    np.copyto(weight, contact)
    np.multiply(weight, 1.0 / operator.self_influence, out=q)
    np.copyto(direction, q)
    operator._transform_direction()
    np.multiply(product, weight, out=residual)
    np.subtract(weight, residual, out=residual)
    target = (tol**2) * n_contact

    def precondition(source: np.ndarray) -> np.ndarray:
        if preconditioner is None:
            return source
        preconditioner.input_block[...] = source
        preconditioner.execute()
        np.multiply(preconditioner.output_block, weight, out=preconditioner.output_block)
        return preconditioner.output_block

    np.copyto(direction, precondition(residual))
    rz = _dot(residual, direction)
    iterations = 0
    converged = _dot(residual, residual) <= target
    while not converged and iterations < max_iter:
        iterations += 1
        operator._transform_direction()
        np.multiply(product, weight, out=product)
        step = rz / _dot(direction, product)
        direction *= step  # q += step direction and residual -= step K direction, in place
        q += direction
        product *= step
        residual -= product
        converged = _dot(residual, residual) <= target
        if converged:
            break
        preconditioned = precondition(residual)
        rz_new = _dot(residual, preconditioned)
        direction *= rz_new / (rz * step)
        direction += preconditioned
        rz = rz_new
    return float(q.sum()) * operator.spacing**2, converged, iterations
