"""The same surface sampled at coarser intervals: the summit-fitted models on every k-th point.

A scene's ``[sampling] factors = [1, 2, 4]`` asks, for every realization, for the models fitted
to counted summits (registry entries with ``needs_summits``: original and improved GW, the
discrete models) once more on the height map sampled at the interval k h (h the scene's grid
step)::

    z_k = z[::k, ::k]        (no re-centring)

so that every sampling keeps the fine map's mean plane, hence the separation d of the one
boundary-element solution, which is solved on the finest grid only (docs/theory.md, eq. S13,
"Sampling interval"). For a WM surface z_k *is* the surface generated on the coarse grid, eq.
(11) sampled at x = i k h, less the constant its own mean removal would subtract, when the
amplitude is fixed on the fine grid (``wm_surface(n // k, ..., slope_grid=n)``); for a
self-affine surface and a measured map it is what an instrument with k times the sampling
interval records (no anti-aliasing filter). The coarser samplings follow the reference's loads
(or the scene's separations), their summits are cached like the finest ones, and each
variant's curve is cached under the model's name with ``@<k>h`` appended and the factor among
its settings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from bem.common.curve import ContactCurve
from validation.common import models
from validation.run.cache import cache_key
from validation.common.models import ModelInputs
from validation.surfaces.families import surface_identity

__all__ = ["SummitStatistics", "Sampled", "subsample", "variant_name", "variant",
           "sampled_models", "sample_realization"]


@dataclass(frozen=True)
class SummitStatistics:
    """What the GW fit takes from a sampling's summits (:meth:`asperity.Summits.greenwood_williamson`)."""

    count: int        # summits N
    density: float    # N / A [1/length^2]
    radius: float     # mean summit radius [length]
    sigma: float      # standard deviation of the summit heights [length]
    mean: float       # mean summit height above the finest map's mean plane [length]

    @classmethod
    def of(cls, summits) -> "SummitStatistics":
        """The statistics of an :class:`asperity.Summits` (NaN where it has no summit)."""
        count = int(summits.count)
        if count == 0:
            return cls(0, 0.0, math.nan, math.nan, math.nan)
        return cls(count, float(summits.density), float(np.mean(summits.radius)),
                   float(np.std(summits.height)), float(np.mean(summits.height)))


@dataclass(frozen=True)
class Sampled:
    """One sampling interval ``factor`` x h of one realization: its summits and the curves of
    the summit-fitted models (by model name; for factor 1 the realization's own curves)."""

    factor: int
    summits: SummitStatistics
    curves: dict[str, ContactCurve]


def subsample(heights: np.ndarray, factor: int) -> np.ndarray:
    """Every ``factor``-th point of a height map in both directions, heights unchanged.

    The mean is *not* removed again: the sampled map keeps the mean plane of ``heights``.
    """
    return heights[::factor, ::factor]


def variant_name(name: str, factor: int) -> str:
    """The name of model ``name`` at the sampling interval ``factor`` h: ``"gw@2h"``."""
    return f"{name}@{factor}h"


def variant(name: str, factor: int) -> models.ModelEntry:
    """Registry entry ``name`` renamed for a coarser sampling, the factor among its settings
    (so that its cache key differs from the finest sampling's)."""
    item = models.entry(name)
    settings = item.settings
    return replace(item, name=variant_name(name, factor),
                   settings=lambda inputs: {**settings(inputs), "sampling": factor})


def sampled_models(names) -> tuple[str, ...]:
    """The models among ``names`` that a coarser sampling changes: those fitted to summits."""
    return tuple(name for name in names if models.entry(name).needs_summits)


def _summits(task, heights: Callable[[], np.ndarray], factor: int, cache, log, version: str):
    """The summits of the map sampled at ``factor`` h, from the cache or found and stored."""
    import asperity

    key = cache_key("summits", version, surface=surface_identity(task.surface, task.seed),
                    sampling=factor)
    found = cache.load(key, decode=asperity.summits_from_arrays)
    if found is None:
        found = asperity.find_summits(subsample(heights(), factor), factor * task.surface.spacing)
        cache.store(key, asperity.summits_to_arrays(found))
        log.did(f"summits@{factor}h")
    return found


def sample_realization(task, heights: Callable[[], np.ndarray], summits, inputs: ModelInputs,
                       curves: dict[str, ContactCurve], cache, log, *, version: str,
                       curve: Callable[[models.ModelEntry, ModelInputs], ContactCurve]
                       ) -> tuple[Sampled, ...]:
    """Every sampling interval of ``task.sampling`` of one realization (none when the task
    samples only its own grid or no model is fitted to summits).

    Parameters
    ----------
    task : validation.run.realization.RealizationTask
    heights : callable
        Makes (once) the finest height map [length].
    summits : asperity.Summits or None
        The finest map's summits.
    inputs : ModelInputs
        The finest map's model inputs; a coarser sampling changes the spacing, the heights
        and the summits only.
    curves : dict
        The realization's curves on the finest grid (the factor-1 entry reuses them).
    cache, log
        The runner's cache and computation log (``log.did(what)``).
    version : str
        Code version in the cache keys.
    curve : callable
        ``curve(entry, inputs) -> ContactCurve``: one model's curve along the realization's
        path, from or into the cache (the runner's).
    """
    names = sampled_models(task.models)
    if len(task.sampling) < 2 or summits is None or not names:
        return ()
    out = []
    for factor in task.sampling:
        if factor == 1:
            out.append(Sampled(1, SummitStatistics.of(summits),
                               {name: curves[name] for name in names}))
            continue
        found = _summits(task, heights, factor, cache, log, version)
        at = ModelInputs(spacing=factor * inputs.spacing, nominal_area=inputs.nominal_area,
                         heights=lambda factor=factor: subsample(heights(), factor),
                         summits=found, e_star=inputs.e_star, m=inputs.m,
                         bem_options=inputs.bem_options, periodic_surface=inputs.periodic_surface,
                         nominal_size=inputs.nominal_size)
        out.append(Sampled(factor, SummitStatistics.of(found),
                           {name: curve(variant(name, factor), at) for name in names}))
    return tuple(out)
