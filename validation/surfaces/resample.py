"""Non-square pixels onto square ones: a measured map resampled along one axis
(docs/theory.md, "7.6 Measured maps: non-square pixels and rectangular maps").

A map of ``rows x columns`` pixels of ``dx x dy`` covers ``columns dx`` along x and ``rows dy``
along y (each sample is the centre of its pixel). The square spacing ``h`` is the finer or the
coarser of the two, so one axis keeps its samples exactly and only the other is resampled, with
a cubic interpolating spline (:func:`scipy.interpolate.make_interp_spline`, not-a-knot) along
that axis:

* ``"finer"``: the spline at the new pixel centres (eq. T33): no new information, a spectrum
  that ends at the old Nyquist wavevector pi/dy of that axis and is attenuated just below it;
* ``"coarser"``: the spline's mean over each new pixel (its antiderivative at the pixel edges,
  eq. T34): the height a coarser pixel records, a box filter that damps, but does not remove,
  the folding back (aliasing) of wavevectors above the new Nyquist wavevector pi/h.

The new pixel count along the resampled axis is ``round(old size / h)``, centred on the old
extent, so the physical size is kept to within half a new pixel; new centres (and pixel edges)
beyond the outermost old centres take the value at those centres (no extrapolation: a cubic
could invent a summit at the edge).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import make_interp_spline

from bem.common import checks

__all__ = ["RESAMPLE", "resample_square"]

#: What ``resample`` may ask for: square pixels of the finer or of the coarser spacing.
RESAMPLE = ("finer", "coarser")


def resample_square(heights: np.ndarray, spacing_x: float, spacing_y: float, to: str
                    ) -> tuple[np.ndarray, float]:
    """Heights [length] on square pixels of the finer or coarser of ``spacing_x`` (columns)
    and ``spacing_y`` (rows), and that spacing [length].

    Parameters
    ----------
    heights : array_like
        Finite heights z[j, i] (row j = y, column i = x), at least 4 x 4.
    spacing_x, spacing_y : float
        Pixel sizes along x and y [length].
    to : {"finer", "coarser"}
        Which of the two becomes the square spacing (module docstring).

    Returns
    -------
    (numpy.ndarray, float)
        The resampled heights (a new array) and the square spacing h. Square pixels (equal
        spacings to 1e-6) are returned unchanged (copied).
    """
    z = checks.height_map("heights", heights, minimum=4)
    dx = checks.positive("spacing_x", spacing_x)
    dy = checks.positive("spacing_y", spacing_y)
    to = checks.choice("to", to, RESAMPLE)
    h = min(dx, dy) if to == "finer" else max(dx, dy)
    if math.isclose(dx, dy, rel_tol=1e-6):
        return np.array(z, dtype=float), dx
    axis, old = (0, dy) if not math.isclose(dy, h) else (1, dx)
    resampled = _along(np.moveaxis(z, axis, 0), old, h, average=to == "coarser")
    return np.ascontiguousarray(np.moveaxis(resampled, 0, axis)), h


def _along(z: np.ndarray, old: float, new: float, *, average: bool) -> np.ndarray:
    """``z`` resampled along axis 0 from spacing ``old`` to ``new``: the cubic spline at the
    new centres, or (``average``) its mean over each new pixel."""
    count = z.shape[0]
    centres = (np.arange(count) + 0.5) * old
    new_count = max(2, round(count * old / new))
    offset = 0.5 * (count * old - new_count * new)      # centre the new grid on the extent
    spline = make_interp_spline(centres, z, k=3, axis=0)
    if not average:
        at = np.clip(offset + (np.arange(new_count) + 0.5) * new, centres[0], centres[-1])
        return spline(at)
    edges = offset + np.arange(new_count + 1) * new
    inside = np.clip(edges, centres[0], centres[-1])
    integral = spline.antiderivative()(inside)
    # beyond the outermost centres the surface is held at its value there (no extrapolation)
    below = (inside[:-1] - edges[:-1])[:, None] * z[:1]
    above = (edges[1:] - inside[1:])[:, None] * z[-1:]
    return (np.diff(integral, axis=0) + below + above) / new
