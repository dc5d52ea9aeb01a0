"""The faces of the Reynolds flow system and the viscous dissipation over them (:mod:`bem.leakage.flow`).

A face joins two neighbouring cells of the system (eq. T43): along either axis, with the
harmonic-mean conductance ``T = 2 k_a k_b / (k_a + k_b)`` of their conductivities, open where
both cells are unknowns of the system and ``T > 0``; a periodic grid also joins its opposite
edges, and along the flow (axis 1) a periodic face carries the mean gradient's drop. The
dissipation ``sum T (p_tail - p_head + drop)^2`` over them is what the flow is read from and what
the multigrid's stopping rule follows, evaluated once per iteration.

The faces are not listed: :func:`face_dissipation` walks the grid's cells and their two
forward neighbours, recomputing each face's conductance (compiled, releasing the GIL, no
temporaries). Listed as tail, head and conductance per face they took 128 MB at 2048^2 for the
whole solve, and the gathers of one evaluation as much again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

__all__ = ["Faces", "face_dissipation"]


@dataclass(frozen=True)
class Faces:
    """The open faces of a flow system (module docstring): the cells' ``conductivity`` (the
    grid's, oriented along the flow), the ``index`` of each cell's unknown (int32, -1 off the
    system), whether the grid is ``periodic``, and the ``drop`` a face along axis 1 carries
    (the mean gradient's share of one face when periodic, else 0)."""

    conductivity: np.ndarray
    index: np.ndarray
    periodic: bool
    drop: float

    def dissipation(self, pressure: np.ndarray, scale: np.ndarray | None = None) -> float:
        """``sum T (p_tail - p_head + drop)^2`` over the open faces for the unknowns'
        ``pressure`` (times ``scale`` per unknown, when given: the pressure of a
        Jacobi-scaled iterate)."""
        return face_dissipation(self.conductivity, self.index, pressure,
                                _NO_SCALE if scale is None else scale, self.periodic,
                                float(self.drop))


_NO_SCALE = np.empty(0)


@numba.njit(nogil=True, cache=True)
def face_dissipation(conductivity, index, pressure, scale, periodic,
                     drop):   # pragma: no cover (compiled)
    """``sum T (p_tail - p_head + drop)^2`` over the open faces (:class:`Faces`), the head
    one cell further along axis 1 (with ``drop``) or axis 0; ``pressure`` per unknown,
    multiplied by ``scale`` where ``scale`` is not empty."""
    rows, columns = conductivity.shape
    scaled = scale.size > 0
    total = 0.0
    for j in range(rows):
        below = j + 1
        if below == rows:
            below = 0 if periodic else -1
        for i in range(columns):
            tail = index[j, i]
            if tail < 0:
                continue
            k_tail = conductivity[j, i]
            p_tail = pressure[tail] * scale[tail] if scaled else pressure[tail]
            right = i + 1
            if right == columns:
                right = 0 if periodic else -1
            for axis in range(2):
                if axis == 0:
                    if right < 0:
                        continue
                    head, k_head, face_drop = index[j, right], conductivity[j, right], drop
                else:
                    if below < 0:
                        continue
                    head, k_head, face_drop = index[below, i], conductivity[below, i], 0.0
                if head < 0 or k_tail + k_head <= 0.0:
                    continue
                t = 2.0 * k_tail * k_head / (k_tail + k_head)
                if t > 0.0:
                    p_head = pressure[head] * scale[head] if scaled else pressure[head]
                    difference = p_tail - p_head + face_drop
                    total += t * difference * difference
    return total
