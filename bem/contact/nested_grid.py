"""The coarse grid of the nested iteration (:func:`bem.contact.solver._coarse_start`, the load path's
starts in :mod:`bem.contact.path`): which grids have one, and a coarse pressure carried to the fine grid.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

#: Nested iteration: coarse solves down to grids of this side.
_COARSEST_GRID = 64


def _nestable(shape: tuple[int, int]) -> bool:
    """Whether a grid has a coarse level for the nested iteration (even, half >= 64)."""
    rows, columns = shape
    return rows % 2 == 0 and columns % 2 == 0 and min(rows, columns) // 2 >= _COARSEST_GRID


def _prolonged(coarse, operator):
    """A coarse pressure on the grid of ``operator`` (twice as fine): the coarse values at the
    even points (the samples the coarse grid shares with the fine one, ``z[::2, ::2]``) and
    their linear interpolation between them, along each axis in turn; past the last sample the
    neighbour across the period (a periodic operator) or the last sample itself (a window, or a
    mirror extension's even image). Against each coarse value repeated on 2 x 2 pixels, which
    shifts every contact spot by half a fine pixel, this start saved 13 % of the fine grid's
    products on a 12-point 1024^2 path of the check's benchmark scan (829 -> 720; iterations
    410 -> 357)."""
    wraps = operator.periodic and not operator.mirror
    return _doubled(_doubled(coarse, 0, wraps), 1, wraps)


def _doubled(values, axis: int, wraps: bool):
    """``values`` with a sample between every two along ``axis``, their mean (past the last:
    its mean with the first when ``wraps``, else the last itself), written into the output
    without temporaries (the interleaving by stacking held three times the fine grid's
    memory at 2048^2). Works on a device's arrays (numpy's functions dispatch to its module)."""
    def along(part):
        index = [slice(None)] * 2
        index[axis] = part
        return tuple(index)

    shape = list(values.shape)
    shape[axis] *= 2
    out = np.empty_like(values, shape=tuple(shape))
    out[along(slice(0, None, 2))] = values
    between = out[along(slice(1, None, 2))]
    np.add(values[along(slice(None, -1))], values[along(slice(1, None))],
           out=between[along(slice(None, -1))])
    np.add(values[along(slice(-1, None))], values[along(slice(0, 1) if wraps else slice(-1, None))],
           out=between[along(slice(-1, None))])
    between *= 0.5
    return out


def checked_coarse_pressures(pressures, shape: tuple[int, int], points: int,
                             preconditioned: bool) -> dict[int, np.ndarray]:
    """``pressures`` (point index -> pressure on every other grid point of a grid of
    ``shape``, as :func:`bem.contact_curve` takes them) as a dict of float arrays, checked:
    a mapping, indices among the ``points`` of the path, each array of the half grid's shape,
    finite and non-negative, on a grid the nested iteration can halve."""
    if pressures is None:
        return {}
    if not isinstance(pressures, Mapping):
        raise TypeError(f"coarse_pressures must be a mapping of point indices to pressures, "
                        f"got {type(pressures).__name__}")
    if pressures and not (preconditioned and _nestable(shape)):
        raise ValueError(f"coarse_pressures need the nested iteration: the preconditioned "
                         f"solver on an even grid of at least {2 * _COARSEST_GRID} points per "
                         f"side, got {shape}")
    half = (shape[0] // 2, shape[1] // 2)
    out = {}
    for index, pressure in pressures.items():
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)) \
                or not 0 <= index < points:
            raise ValueError(f"coarse_pressures: keys must be point indices 0..{points - 1}, "
                             f"got {index!r}")
        pressure = np.asarray(pressure, dtype=float)
        if pressure.shape != half:
            raise ValueError(f"coarse_pressures[{index}] must have the half grid's shape {half}, "
                             f"got {pressure.shape}")
        if not np.all(np.isfinite(pressure)) or np.any(pressure < 0.0):
            raise ValueError(f"coarse_pressures[{index}] must be finite and non-negative")
        out[int(index)] = pressure
    return out
