"""Incremental normal stiffness of a converged contact state (docs/theory.md, "8.6 Stiffness by the incremental problem").

The incremental problem on the contact set C, ``K_CC q = 1`` (unit rigid approach), solved by
conjugate gradients preconditioned like the contact iteration (:mod:`bem.contact.preconditioner`);
``S = -dW/dd = h^2 sum q`` and the conductance by Barber's analogy ``C rho = 2 S / E*``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from bem.contact.coarse_correction import CoarseCorrection
from bem.common.vectors import _dot
from bem.contact.cg_buffers import _Scatter
from bem.elastic.halfspace import HalfSpace
from bem.contact.preconditioner import InverseKernel
from bem.common.warnings import ConvergenceWarning


def _stiffness(operator: HalfSpace, contact: np.ndarray, *, tol: float, max_iter: int,
               preconditioner: InverseKernel | None = None,
               correction: CoarseCorrection | None = None) -> tuple[float, bool, int]:
    """Solve ``K_CC q = 1`` on the contact set C by (preconditioned) conjugate gradients;
    ``S = h^2 sum q``.

    With ``preconditioner`` M, the residual is preconditioned by ``P_C M P_C`` (symmetric
    positive definite on C; :mod:`bem.contact.preconditioner`), which keeps the iteration count nearly
    independent of the grid; with ``correction``, the contact iteration's coarse correction
    (:mod:`bem.contact.coarse_correction`, built where M alone converged slowly), moved to C or built
    anew on C, which takes a third to a half of the iterations away where C is many patches.
    Stops when ``||1 - (K q)_C|| <= tol sqrt(|C|)``. Returns (S, converged, iterations).

    The fields live on C only (one value per contact pixel), written into and read from the
    FFT buffers of the operator and the preconditioner at C's positions: no full-grid pass but
    the transforms. Starting from the previous load point's q, from the secant of the pressures
    of two points or from the pressure itself needed as many iterations as the uniform start
    (WM paths at 256^2, D = 2.05): the error that remains is at the contact edges.
    """
    n_contact = int(np.count_nonzero(contact))
    if n_contact == 0:
        return 0.0, True, 0
    if operator.periodic and n_contact == contact.size:
        warnings.warn("bem.solve_contact: full contact of a periodic surface: the stiffness is "
                      "infinite (no load can push the plane further)", ConvergenceWarning,
                      stacklevel=4)
        return math.inf, True, 0
    # compressed fields on C (one value per contact pixel), scattered into and gathered from
    # the FFT buffers at C's positions only
    indices = np.flatnonzero(contact)
    columns = contact.shape[1]
    op_in_flat, op_out_flat, op_stride = operator._flat_direction_buffers()
    operator_in = _Scatter(op_in_flat, op_stride, columns)
    at_in = operator_in.positions(indices)
    at_out = at_in if op_stride == columns else _Scatter(op_out_flat, op_stride,
                                                         columns).positions(indices)
    if preconditioner is not None:
        preconditioner_in = _Scatter(preconditioner.input_block.reshape(-1), columns, columns)

    def product(values: np.ndarray) -> np.ndarray:
        operator_in.write(at_in, values)
        operator._transform_direction()
        return op_out_flat[at_out]

    coarse: CoarseCorrection | None = None

    def precondition(source: np.ndarray) -> np.ndarray:
        if preconditioner is None:
            return source
        if coarse is None:
            preconditioner_in.write(indices, source)
            preconditioner.execute()
            return preconditioner.read(indices)
        without_means, sums = coarse.before(source)
        preconditioner_in.write(indices, without_means)
        preconditioner.execute()
        return coarse.after(preconditioner.read(indices), sums)

    # start: uniform on C, scaled to minimise the energy q.Kq/2 - q.1 along it (no extra
    # product: K q is needed for the residual anyway; about 10 % fewer iterations than the
    # unscaled 1 / K(0) measured on WM load paths)
    q = operator.xp.full(n_contact, 1.0 / operator.self_influence)
    kq = product(q)
    curvature = _dot(q, kq)
    if preconditioner is not None and correction is not None and curvature > 0.0:
        coarse = correction   # the contact iteration's, on (nearly) this set, or a new one
        if not correction.follow(indices):
            # (the operator's coarse data exist since the contact iteration built its
            # correction: this build writes none of the operator's buffers)
            coarse = CoarseCorrection(operator, indices, curvature / float(q[0]) ** 2)
            coarse = coarse if coarse.usable else None
    if curvature > 0.0:
        scaling = float(q.sum()) / curvature
        q *= scaling
        kq *= scaling
    residual = 1.0 - kq
    target = (tol**2) * n_contact
    direction = precondition(residual).copy()
    rz = _dot(residual, direction)
    iterations = 0
    converged = _dot(residual, residual) <= target
    while not converged and iterations < max_iter:
        iterations += 1
        kd = product(direction)
        step = rz / _dot(direction, kd)
        q += step * direction
        residual -= step * kd
        converged = _dot(residual, residual) <= target
        if converged:
            break
        preconditioned = precondition(residual)
        rz_new = _dot(residual, preconditioned)
        direction *= rz_new / rz
        direction += preconditioned
        rz = rz_new
    return float(q.sum()) * operator.spacing**2, converged, iterations
