"""Start pressures of a finer reference: the contact pressures solved one grid below, kept.

A finer reference (:mod:`validation.run.refine`) solves a realization's load points on the grid
of ``2 n`` points per side. Its nested iteration starts every point from the same load solved
on every other grid point (:func:`bem.contact_curve`), and that problem is exactly the one the
grid below has solved: the finer sample reproduces the scene's heights at every second point
(:func:`validation.run.finer_sample.refined_heights`), with the same loads, modulus and extension.
The path one grid below therefore keeps its pressures in the cache, and the finer path starts
from them instead of solving each coarse problem again: on the check's 512^2 benchmark scan the
1024^2 path of 12 points took 24 s instead of 32 s (one thread), the fine iterations the same
(365 against 357). Any pressure is a valid start: without them (evicted, or a cache turned off)
the finer path solves its coarse problems itself, and its result agrees to the solver's
tolerance.

Only the contact pixels are kept (flat index, pressure): at 2048^2 the twelve pressures of a
default path take about 25 MB, against 400 MB dense.
"""

from __future__ import annotations

import numpy as np

from bem.contact.nested_grid import _nestable
from validation.run.cache import Cache, cache_key, source_version
from validation.surfaces.families import surface_identity

__all__ = ["SMALLEST_KEPT_GRID", "KeptPressures", "keeps_starts", "load_starts", "starts_key"]


#: Smallest grid (points per side) whose path keeps its pressures. Below, a finer path's coarse
#: solves take seconds, while a report of hundreds of realizations would keep about a
#: megabyte of pressures per realization (256^2) to save them.
SMALLEST_KEPT_GRID = 512


def keeps_starts(task, grid: int) -> bool:
    """Whether the path of ``task`` solved on ``grid`` points per side keeps its pressures: a
    finer grid, within ``[bem] max_grid``, may refine it (load paths only), and the grid has
    at least :data:`SMALLEST_KEPT_GRID` points per side (and the finer grid one the nested
    iteration halves)."""
    max_grid = task.bem.max_grid
    return (max_grid is not None and SMALLEST_KEPT_GRID <= grid and 2 * grid <= max_grid
            and _nestable((2 * grid, 2 * grid)) and task.loads.quantity == "load"
            and bool(task.bem.reference_error))


def starts_key(task, grid: int, extension: str | None) -> str:
    """The cache key of the pressures of ``task``'s reference solved on ``grid`` points per
    side: the window's (``extension`` None) or the interface's (``"mirror"``, ``"periodic"``),
    at the task's loads (all of them; a finer level keeps those it solved)."""
    s = task.surface
    loads = np.array(task.loads.values()) * task.e_star * s.L**2
    return cache_key("bem-starts", source_version(), surface=surface_identity(s, task.seed),
                     grid=grid, loads=loads, e_star=task.e_star, extension=extension,
                     periodic=task.bem.periodic)


class KeptPressures:
    """The pressures of a path's points as they are solved (:meth:`add`, e.g. from a
    :func:`bem.contact_curve` callback, any thread), their contact pixels only, to be stored
    under a key (:meth:`store`)."""

    def __init__(self) -> None:
        self._points: dict[int, tuple[tuple[int, int], np.ndarray, np.ndarray]] = {}

    def add(self, point: int, pressure) -> None:
        """Keep the pressure field of load point ``point``."""
        field = np.asarray(pressure, dtype=float)
        flat = np.flatnonzero(field)
        self._points[int(point)] = (field.shape, flat, field.ravel()[flat])

    def __len__(self) -> int:
        return len(self._points)

    def store(self, cache: Cache, key: str) -> None:
        """Write the kept pressures under ``key`` (nothing when none are kept)."""
        if not self._points or not cache.enabled:
            return
        points = sorted(self._points)
        kept = [self._points[k] for k in points]
        cache.store(key, {
            "points": np.array(points, dtype=np.int64),
            "shape": np.array(kept[0][0], dtype=np.int64),
            "counts": np.array([flat.size for _, flat, _ in kept], dtype=np.int64),
            "index": np.concatenate([flat for _, flat, _ in kept]),
            "pressure": np.concatenate([values for _, _, values in kept])})


def _fields(arrays: dict[str, np.ndarray]) -> dict[int, np.ndarray]:
    """The kept pressure fields by load point index (a malformed entry raises, and the cache
    discards it)."""
    shape = tuple(int(v) for v in arrays["shape"])
    counts = arrays["counts"]
    if len(shape) != 2 or counts.size != arrays["points"].size \
            or not int(counts.sum()) == arrays["index"].size == arrays["pressure"].size:
        raise ValueError("a malformed entry of start pressures")
    fields, end = {}, 0
    for point, count in zip(arrays["points"], counts):
        field = np.zeros(shape[0] * shape[1])
        field[arrays["index"][end:end + count]] = arrays["pressure"][end:end + count]
        fields[int(point)] = field.reshape(shape)
        end += count
    return fields


def load_starts(cache: Cache, key: str, points) -> dict[int, np.ndarray]:
    """The kept pressures under ``key`` at the load point indices ``points``, by position in
    ``points`` (the indexing of a path through those points); empty when none are kept."""
    fields = cache.load(key, decode=_fields) or {}
    return {position: fields[int(point)] for position, point in enumerate(points)
            if int(point) in fields}
