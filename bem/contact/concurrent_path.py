"""A load path solved as interleaved sub-paths at once, one thread and one FFT thread each.

Two FFT threads on one path gain less than two paths on one thread each: FFTW's threads
synchronise at every transform and the conjugate-gradient steps between the transforms run on
one core. Measured on a 1024² path of 12 loads (a 512² scan interpolated to twice its grid,
tolerance 1e-4, two cores): one path with two FFT threads 58.1 s wall and 106 s of process time,
two interleaved paths of six loads each 44.4 s and 81 s, with the same iterations per point
within their scatter (each point starts from its own load solved on every other grid point, so
it hardly depends on its neighbours along the path).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from bem.common import checks
from bem.common.background import BackgroundCall, running
from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.elastic.fft_threads import default_threads
from bem.contact.nested_grid import checked_coarse_pressures
from bem.contact.path import contact_curve
from bem.contact.solver import ContactSolution

__all__ = ["CONCURRENT_LIMIT", "concurrent_curve", "dealt", "path_parts"]

#: Largest grid side split into concurrent sub-paths: each holds its own operator (about 150 n²
#: bytes, 630 MB at 2048²).
CONCURRENT_LIMIT = 2048


def path_parts(points: int, shape: tuple[int, int]) -> int:
    """How many sub-paths a path of ``points`` loads on a grid of ``shape`` is split into: the
    CPUs this process may use less its running background calls, at most one per point, one
    above :data:`CONCURRENT_LIMIT`."""
    if max(shape) > CONCURRENT_LIMIT:
        return 1
    return max(1, min(points, default_threads() - running()))


def concurrent_curve(heights, spacing: float, *, loads, parts: int | None = None,
                     callback: Callable[[int, ContactSolution], None] | None = None,
                     **options) -> ContactCurve:
    """:func:`bem.contact_curve` along ``loads``, the loads dealt to ``parts`` sub-paths
    solved at once, each in its own thread with one FFT thread; the curve in the order of
    ``loads``. The loads are dealt by increasing load to the sub-paths 0, 1, ..., p-1, then
    p-1, ..., 0, and so on (:func:`dealt`), so that each gets a like share of the heavy loads,
    whose solves take the most iterations.

    Parameters
    ----------
    heights, spacing, loads
        As for :func:`bem.contact_curve` (load control only).
    parts : int, optional
        Number of sub-paths (default :func:`path_parts`); 1 is :func:`bem.contact_curve`.
    callback : callable, optional
        ``callback(index, solution)`` with ``index`` into ``loads``; called from the
        sub-paths' threads.
    **options
        Any other keyword of :func:`bem.contact_curve` but ``error_estimate`` and ``operator``.

    Raises
    ------
    ValueError
        For bad arguments (as :func:`bem.contact_curve`), ``parts`` below 1, or
        ``error_estimate`` / ``operator`` among the options.
    """
    loads = checks.contact_path("loads", loads, non_negative=True)
    callback = checks.optional_callable("callback", callback)
    for name in ("error_estimate", "operator", "separations"):
        if name in options:
            raise ValueError(f"concurrent_curve does not take {name!r} (each sub-path builds "
                             f"its own operator; load control only)")
    if parts is None:   # (the heights are checked by contact_curve, in every sub-path)
        parts = path_parts(loads.size, np.shape(heights)) if np.ndim(heights) == 2 else 1
    else:
        parts = checks.integer("parts", parts, minimum=1)
    parts = min(parts, max(loads.size, 1))
    if parts == 1:
        return contact_curve(heights, spacing, loads=loads, callback=callback, **options)
    positions = dealt(loads, parts)

    # checked here as a single path would (the sub-paths see only the points they solve)
    coarse = checked_coarse_pressures(options.pop("coarse_pressures", None), np.shape(heights),
                                      loads.size, options.get("preconditioned", True))
    stiff = checks.point_mask("stiffness_at", options.pop("stiffness_at", None), loads.size)

    def solve(where: np.ndarray) -> ContactCurve:
        report = (None if callback is None
                  else lambda index, solution: callback(int(where[index]), solution))
        starts = {k: coarse[point] for k, point in enumerate(where.tolist()) if point in coarse}
        return contact_curve(heights, spacing, loads=loads[where], callback=report,
                             coarse_pressures=starts, stiffness_at=np.flatnonzero(stiff[where]),
                             **options)

    # the other sub-paths start first, so that each operator sees the others running and takes
    # one FFT thread (bem.elastic.fft_threads.fft_threads)
    others = [BackgroundCall(solve, where, name=f"sub-path-{k}")
              for k, where in enumerate(positions[1:], start=1)]
    curves = [solve(positions[0])] + [call.result() for call in others]
    return _interleaved(curves, positions, loads.size)


def dealt(loads: np.ndarray, parts: int) -> list[np.ndarray]:
    """Indices into ``loads`` of each of ``parts`` sub-paths: by increasing load, dealt
    0, 1, ..., p-1, p-1, ..., 0, 0, 1, ... (each sub-path's in increasing order). The
    iterations of a point grow with its load (14 to 63 from the lightest to the heaviest of
    12 points of a 1024^2 path), so dealing them in turn gave the second of two sub-paths
    the heavier of every pair: 202 iterations against 163, 184 against 181 dealt this way."""
    order = np.argsort(loads, kind="stable")
    turn = np.arange(order.size) % (2 * parts)
    part = np.where(turn < parts, turn, 2 * parts - 1 - turn)
    return [np.sort(order[part == k]) for k in range(parts)]


def _interleaved(curves: list[ContactCurve], positions: list[np.ndarray],
                 size: int) -> ContactCurve:
    """One curve of ``size`` points from sub-path curves at ``positions``."""
    first = curves[0]
    fields = {}
    for name in CURVE_QUANTITIES:
        if getattr(first, name) is not None:
            fields[name] = np.empty(size)
            for curve, where in zip(curves, positions):
                fields[name][where] = getattr(curve, name)
    extras = {}
    for key, value in first.extras.items():
        value = np.asarray(value)
        if value.ndim == 1 and value.size == np.size(first.load):
            merged = np.empty(size, dtype=value.dtype)
            for curve, where in zip(curves, positions):
                merged[where] = curve.extras[key]
            extras[key] = merged
    return ContactCurve(nominal_area=first.nominal_area, e_star=first.e_star, extras=extras,
                        **fields)
