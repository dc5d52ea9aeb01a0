"""Scenes: declarative descriptions of what to compute and compare.

A scene names a surface family and its parameters, realizations, material, a load path, the
models and quantities to compute, the boundary-element settings and the error tolerances at
which a model is said to hold. Scenes are data: the built-in ones are TOML files shipped in
``validation/scenes/``, and any user file path works the same way (:mod:`validation.scenes.reader`
reads them).

The dataclasses below, with :class:`SurfaceSpec` (:mod:`validation.surfaces.spec`), are the
single source of the rules and the defaults: each validates itself in ``__post_init__`` (so
``dataclasses.replace(scene, realizations=-2)`` raises too; the field checks are in
:mod:`validation.common.checks`) and its field defaults are the defaults of the file format. A
file's tables and keys map onto them::

    name, title, description, kind      -> Scene (kind "surface", or "theory" for Figs. 1-3)
    [surface]  family, and the keys of the family (FAMILY_KEYS)   -> SurfaceSpec
               wm: D rms_slope G gamma M n_max L n wavelength sides periodic
               self-affine: hurst rms_slope rms_height long_cutoff rolloff short_cutoff
                            window plateau L n
               file: path physical_size file_unit unit detrend resample square
                     short_cutoff tiles, and
                     every other keyword of read_topography (fill channel reader ...)
    [realizations]  count seed max      -> Scene.realizations, Scene.seed, Scene.max_realizations
    [material]  e_star physical_e_star  -> Scene.e_star, Scene.physical_e_star
    [loads]  quantity min max count spacing                -> LoadPath
    [models]  use m nominal_size        -> Scene.models (registered names), Scene.m,
                                           Scene.nominal_size
    [quantities]  use                   -> Scene.quantities
    [bem]  periodic tol max_iter reference_error max_grid frames device  -> BemSettings
    [tolerances]  levels                -> Scene.tolerances
    [sampling]  factors                 -> Scene.sampling (surface scenes)
    [quick]  realizations n count quantities max_grid       -> QuickSettings
    [theory]  C m separation_min separation_max count      -> TheorySpec (kind "theory")

Every key is optional except the surface's sweep parameter (``D`` of a WM surface, ``hurst``
of a self-affine one) and amplitude (``rms_slope`` or ``G``; ``rms_slope`` or ``rms_height``),
or a measured map's ``path`` (relative to the scene file's folder). A measured map's
realizations are its tiles: a file scene has no ``[realizations]`` table. Invalid
values raise :class:`SceneError` (a ``ValueError``) naming the key (and, from a file, the
file).
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields, replace

from bem.elastic.device import DEVICES
from validation.common import models as _models
from validation.common import checks as check
from validation.common.checks import SceneError, SceneWarning
from validation.surfaces.spec import FAMILIES, FAMILY_KEYS, MIN_TILE, SWEEPS, SurfaceSpec

__all__ = [
    "Scene", "SurfaceSpec", "LoadPath", "BemSettings", "TheorySpec", "QuickSettings",
    "SceneError", "SceneWarning", "scene_warnings", "MODELS", "QUANTITIES", "KINDS", "FAMILIES",
    "FAMILY_KEYS", "SWEEPS", "MIN_TILE", "defaults",
]

#: Models a scene uses unless it lists its own (any registered name may be listed:
#: :func:`validation.common.models.names`).
#: The finite frame's reference of a scene with a nominal size (``[models] nominal_size``).
NOMINAL_REFERENCE = "bem_nominal"
MODELS = tuple(sorted(_models.default_names(), key=lambda name: _models.entry(name).reference))
#: Quantities a scene may ask for. ``leakage`` (the effective hydraulic aperture h_eff of the
#: gap, docs/theory.md section 10) is computed only by scenes that list it: it costs the BEM a
#: Reynolds solve per load point.
QUANTITIES = ("area", "load", "separation", "conductance", "contacts", "stiffness", "leakage")
#: Kinds of scene.
KINDS = ("surface", "theory")
#: Fewest grid points per side of a coarser sampling (``[sampling] factors``).
MIN_SAMPLED_GRID = 16

#: Path defaults by controlled quantity (the only place they are written).
_PATH_DEFAULTS = {"load": dict(min=1e-5, max=1e-2, spacing="log"),
                  "separation": dict(min=0.0, max=3.0, spacing="linear")}


@dataclass(frozen=True)
class LoadPath:
    """The load path, dimensionless: ``Load = W/(E* L^2)`` or ``Separation = d/sigma``.

    ``min``, ``max`` and ``spacing`` left as ``None`` take the defaults of the quantity:
    Load 1e-5 to 1e-2, logarithmic; Separation 0 to 3, linear.
    """

    quantity: str = "load"
    min: float | None = None
    max: float | None = None
    count: int = 16
    spacing: str | None = None

    def __post_init__(self) -> None:
        check.choice(self, "quantity", tuple(_PATH_DEFAULTS))
        for key, default in _PATH_DEFAULTS[self.quantity].items():
            if getattr(self, key) is None:
                object.__setattr__(self, key, default)
        check.choice(self, "spacing", ("log", "linear"))
        check.number(self, "min", above=0.0 if self.quantity == "load" else None)
        check.number(self, "max")
        check.integer(self, "count", 1)
        if self.max <= self.min:
            check.fail(self, "max", f"must be greater than min = {self.min:g}")
        if self.spacing == "log" and self.min <= 0:
            check.fail(self, "min", "must be > 0 with logarithmic spacing")

    def values(self) -> tuple[float, ...]:
        """The points of the path, increasing."""
        if self.count == 1:
            return (self.min,)
        if self.spacing == "log":
            ratio = math.log(self.max / self.min)
            return tuple(self.min * math.exp(ratio * k / (self.count - 1))
                         for k in range(self.count))
        step = (self.max - self.min) / (self.count - 1)
        return tuple(self.min + step * k for k in range(self.count))


@dataclass(frozen=True)
class BemSettings:
    """Boundary-element settings of a scene (``reference_error``: every BEM curve carries a
    per-point estimate of its own discretisation error, from the same path on half the grid,
    :func:`bem.contact_curve` ``error_estimate``)."""

    periodic: bool = False
    tol: float = 1e-8
    max_iter: int = 2000
    reference_error: bool = True
    # finest grid of the refined reference where its band decides (validation.run.refine);
    # None: never refined
    max_grid: int | None = None
    # the frames whose references are computed ("interface", "finite": docs/theory.md 8.10);
    # None: those of the scene's models (Scene resolves it)
    frames: tuple[str, ...] | None = None
    # where the reference's contact problems are solved (bem.elastic.device): "cpu" or "gpu"; results
    # and cache entries are the same from either
    device: str = "cpu"

    def __post_init__(self) -> None:
        check.choice(self, "device", DEVICES)
        if self.frames is not None:
            check.names(self, "frames", _models.FRAMES)
        check.flag(self, "periodic")
        check.number(self, "tol", above=0.0)
        if self.tol > 0.1:
            check.fail(self, "tol", f"must be <= 0.1, got {self.tol!r}")
        check.integer(self, "max_iter", 1)
        check.flag(self, "reference_error")
        if self.max_grid is not None:
            check.integer(self, "max_grid", 8)


@dataclass(frozen=True)
class TheorySpec:
    """GW vs improved GW in dimensionless form (the paper's Figs. 1-3): interaction parameters
    C = eta sqrt(A R sigma) (eq. 4), factor m, reduced separations (d - mu_s)/sigma."""

    C: tuple[float, ...] = (5.0, 50.0)
    m: float = 1.0
    separation_min: float = -2.0
    separation_max: float = 4.0
    count: int = 200

    def __post_init__(self) -> None:
        check.numbers(self, "C", above=0.0)
        check.number(self, "m", at_least=0.0)
        check.number(self, "separation_min")
        check.number(self, "separation_max")
        check.integer(self, "count", 2)
        if self.separation_max <= self.separation_min:
            check.fail(self, "separation_max", "must be greater than separation_min")


@dataclass(frozen=True)
class QuickSettings:
    """What quick mode changes: fewer realizations, a coarser grid, fewer load points,
    optionally fewer quantities (``quantities``: those of the quick run, by default the
    scene's; e.g. leaving out ``leakage``, whose Reynolds solves cost the BEM several times
    its contact solves), and no finer reference unless ``max_grid`` is set (the finest grid of
    the quick run's refined reference, in place of ``[bem] max_grid``: a refined point is
    solved again on a grid of four times the points, so refining cost the quick default report
    about three times the BEM solves of its realizations)."""

    realizations: int = 3
    n: int = 128
    count: int = 10
    quantities: tuple[str, ...] | None = None
    max_grid: int | None = None

    def __post_init__(self) -> None:
        check.integer(self, "realizations", 1)
        check.integer(self, "n", 16)
        check.integer(self, "count", 1)
        if self.quantities is not None:
            check.names(self, "quantities", QUANTITIES)
        if self.max_grid is not None:
            check.integer(self, "max_grid", 8)


@dataclass(frozen=True)
class Scene:
    """A validated scene. Build it with :func:`load_scene` or :func:`parse_scene`, or directly."""

    name: str
    kind: str = "surface"
    title: str = ""
    description: str = ""
    surface: SurfaceSpec | None = None
    realizations: int = 25
    seed: int = 0
    # budget of the sequential plan (validation.run.sequential); None: the planned ones only
    max_realizations: int | None = None
    e_star: float = 1.0
    # E* [Pa] of a scene that runs in units of E* (e_star = 1) and reports in physical units: the
    # pressures and stiffness of a one-scan report (python -m validation check); None: none
    physical_e_star: float | None = None
    loads: LoadPath = field(default_factory=LoadPath)
    models: tuple[str, ...] = MODELS
    m: float = 1.0
    # side of a square nominal contact [length] that the finite frame describes instead of the
    # window: its reference is the interface's plus that square's bulk sink
    # (bem.NominalContactModel), and improved GW's uniform term is that square's
    nominal_size: float | None = None
    quantities: tuple[str, ...] = ("area", "load", "separation", "conductance", "contacts")
    bem: BemSettings = field(default_factory=BemSettings)
    tolerances: tuple[float, ...] = (0.05, 0.2)
    quick: QuickSettings = field(default_factory=QuickSettings)
    theory: TheorySpec | None = None
    sampling: tuple[int, ...] = (1,)
    source: str = "<memory>"

    def __post_init__(self) -> None:
        for key in ("kind", "name", "title", "description", "source"):
            if not isinstance(getattr(self, key), str):
                check.fail(self, key, f"must be a string, got {getattr(self, key)!r}")
        check.choice(self, "kind", KINDS)
        check.integer(self, "realizations", 1)
        check.integer(self, "seed", 0)
        check.number(self, "e_star", above=0.0)
        if self.physical_e_star is not None:
            check.number(self, "physical_e_star", above=0.0)
        check.number(self, "m", at_least=0.0)
        if self.nominal_size is not None:
            check.number(self, "nominal_size", above=0.0)
        check.names(self, "models", _models.names())
        check.names(self, "quantities", QUANTITIES)
        check.numbers(self, "tolerances", above=0.0)
        self._check_parts()
        self._resolve_frames()
        self._check_sampling()

    def _resolve_frames(self) -> None:
        """Each frame's reference among the models: ``[bem] frames``, by default the frames of
        the models it judges and of the references it lists, each model judged against the
        reference of its own frame. A scene that lists no reference model compares nothing and
        is left as it is."""
        listed = [m for m in self.models if _models.entry(m).reference]
        if self.kind != "surface" or not listed:
            return
        judged = [m for m in self.models if not _models.entry(m).reference]
        if self.nominal_size is not None:   # the finite frame is the nominal square's
            listed = [NOMINAL_REFERENCE if _models.frame_of(m) == "finite" else m
                      for m in listed]
        frames = self.bem.frames or _models.frames_of(judged + listed)
        references = tuple(dict.fromkeys(
            [m for m in listed if _models.frame_of(m) in frames]
            + [NOMINAL_REFERENCE if frame == "finite" and self.nominal_size is not None
               else _models.reference_for(frame) for frame in frames
               if not any(_models.frame_of(m) == frame for m in listed)]))
        object.__setattr__(self, "models", tuple(judged) + references)

    @property
    def frames(self) -> tuple[str, ...]:
        """The frames whose reference the scene computes (``[bem] frames`` resolved; empty for
        a scene without a reference), in the order of :data:`validation.common.models.FRAMES`."""
        return _models.frames_of([m for m in self.models if _models.entry(m).reference])

    def _check_parts(self) -> None:
        parts = dict(surface=SurfaceSpec, loads=LoadPath, bem=BemSettings, quick=QuickSettings,
                     theory=TheorySpec)
        for key, kind in parts.items():
            value = getattr(self, key)
            if value is None and key in ("loads", "bem", "quick"):   # their defaults, not None
                check.fail(self, key, f"must be a {kind.__name__}, got None")
            if value is not None and not isinstance(value, kind):
                check.fail(self, key, f"must be a {kind.__name__}, got {type(value).__name__}")
        if self.kind == "surface" and self.surface is None:
            check.fail(self, "surface", "is required in a surface scene")
        if self.kind == "theory" and self.theory is None:
            check.fail(self, "theory", "is required in a theory scene")
        if self.kind == "surface" and self.theory is not None:
            check.fail(self, "theory", "belongs only in a scene with kind = \"theory\"")
        family = self.surface.family if self.surface is not None else "wm"
        if family != "wm" and self.bem.periodic:
            check.fail(self, "bem.periodic", f"must be false for a {family} surface (its "
                       "window is not periodic)")
        if self.surface is not None and family != "file":
            quick_n = min(self.surface.n, self.quick.n)
            for key, grid, n, which in (
                    ("bem.max_grid", self.bem.max_grid, self.surface.n, "surface grid"),
                    ("quick.max_grid", self.quick.max_grid, quick_n, "quick run's grid")):
                if grid is not None and grid < n:
                    check.fail(self, key, f"must be at least the {which} n = {n}, "
                               f"got {grid!r}")
        if family == "file":  # the tiles of a measured map are its realizations
            object.__setattr__(self, "realizations", self.surface.tiles)
        elif self.kind == "surface" and self.bem.reference_error:
            # the reference band comes from the same surface on every second grid point, which
            # covers the same window only on an even grid (a measured map's tiles are made even)
            for key, n in (("surface.n", self.surface.n), ("quick.n", self.quick.n)):
                if n % 2:
                    check.fail(self, key, f"must be even when bem.reference_error = true (the "
                               f"BEM's error band is estimated on every second grid point, "
                               f"which spans the same window only on an even grid); use "
                               f"{n - 1} or {n + 1}, or set bem.reference_error = false (no "
                               f"band: every verdict then stays undecided)")
        if self.max_realizations is not None:
            if family == "file":
                check.fail(self, "max_realizations", "cannot be set for a measured map (its "
                           "realizations are its tiles; there are no more)")
            check.integer(self, "max_realizations", self.realizations)

    def _check_sampling(self) -> None:
        """``sampling``: sampling intervals as multiples k of the grid step, 1 (the grid itself,
        the one the BEM solves) among them; every coarser sampling takes every k-th point of
        the grid (:mod:`validation.run.sampling`), so k divides the grid and leaves at least
        :data:`MIN_SAMPLED_GRID` points per side, and a model fitted to summits must be listed."""
        check.integers(self, "sampling", 1)
        if 1 not in self.sampling:
            check.fail(self, "sampling", f"must list 1 (the scene's own grid, the one the BEM "
                       f"solves) beside the coarser factors, got {list(self.sampling)!r}")
        if len(self.sampling) == 1:
            return
        if self.kind == "theory":
            check.fail(self, "sampling", "belongs only in a surface scene")
        summit_models = [m for m in _models.names() if _models.entry(m).needs_summits]
        if not set(self.models) & set(summit_models):
            check.fail(self, "sampling", f"needs a model fitted to summits among the models "
                       f"(one of {', '.join(summit_models)}); the scene lists "
                       f"{', '.join(self.models)}")
        grid = self.surface.grid
        for factor in self.sampling:
            if any(side % factor for side in grid) or min(grid) // factor < MIN_SAMPLED_GRID:
                shape = " x ".join(map(str, grid))
                check.fail(self, "sampling", f"factor {factor} must divide the {shape} grid "
                           f"and leave at least {MIN_SAMPLED_GRID} points per side")

    def quick_version(self) -> "Scene":
        """The scene as the quick default report runs it."""
        if self.kind == "theory":
            return self
        surface = self.surface if self.surface.family == "file" else \
            replace(self.surface, n=min(self.surface.n, self.quick.n))
        loads = replace(self.loads, count=min(self.loads.count, self.quick.count))
        realizations = min(self.realizations, self.quick.realizations)
        # the budget shrinks in proportion: the same number of looks at the same ratios
        budget = None if self.max_realizations is None else max(realizations, math.ceil(
            self.max_realizations * realizations / self.realizations))
        # no finer reference unless [quick] max_grid asks for one: in the quick default
        # report it cost about three times the BEM solves of the realizations (the paper
        # scenes' 512^2 re-solves, the validity map's 256^2 ones); the full run refines up to
        # [bem] max_grid
        bem = replace(self.bem, max_grid=self.quick.max_grid)
        quantities = self.quantities if self.quick.quantities is None else tuple(
            q for q in self.quantities if q in self.quick.quantities)
        ran = (f"Run in quick mode: {realizations} realization(s)"
               + ("" if surface.family == "file" else f" on {surface.n} × {surface.n} grids")
               + f", {loads.count} loads, no finer reference unless [quick] max_grid asks for "
                 f"one; the description above is the scene as written.")
        return replace(self, surface=surface, loads=loads, quantities=quantities, bem=bem,
                       realizations=realizations, max_realizations=budget,
                       description=self.description if "Run in quick mode" in self.description
                       else (self.description.rstrip() + "\n\n" + ran).strip())


def scene_warnings(scene: Scene) -> list[str]:
    """What a valid scene will not give although it seems to ask for it (one message each): a
    generated surface family with one realization is judged as that one surface (by the
    reference band alone, :func:`validation.judge.verdicts.one_surface_verdicts`), not as
    surfaces of its kind. A measured map with ``tiles = 1`` is one surface by intent."""
    if scene.kind != "surface" or scene.realizations >= 2 or scene.surface.family == "file" \
            or not set(scene.models) & set(_models.reference_names()):
        return []
    return [f"scene {scene.name!r} ({scene.source}) has {scene.realizations} realization: its "
            f"verdicts are about that one surface (its error against the reference band), not "
            f"about surfaces of its kind; set [realizations] count = 2 or more for those"]


def defaults(kind: type) -> dict:
    """Field defaults of a scene dataclass (the format's defaults), by field name."""
    out = {}
    for f in fields(kind):
        if f.default_factory is not MISSING:
            out[f.name] = f.default_factory()
        elif f.default is not MISSING:
            out[f.name] = f.default
    return out
