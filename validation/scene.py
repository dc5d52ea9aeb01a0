"""Scenes: declarative descriptions of what to compute and compare.

A scene names a surface family and its parameters, realizations, material, a load path, the
models and quantities to compute, the boundary-element settings and the error tolerances at
which a model is said to hold. Scenes are data: the built-in ones are TOML files shipped in
``validation/scenes/``, and any user file path works the same way (:mod:`validation.scene_file`
reads them).

The dataclasses below are the single source of the rules and the defaults: each validates
itself in ``__post_init__`` (so ``dataclasses.replace(scene, realizations=-2)`` raises too) and
its field defaults are the defaults of the file format. A file's tables and keys map onto them::

    name, title, description, kind      -> Scene (kind "surface", or "theory" for Figs. 1-3)
    [surface]  family D rms_slope G gamma M n_max L n      -> SurfaceSpec
    [realizations]  count seed          -> Scene.realizations, Scene.seed
    [material]  e_star                  -> Scene.e_star
    [loads]  quantity min max count spacing                -> LoadPath
    [models]  use m                     -> Scene.models (registered names), Scene.m
    [quantities]  use                   -> Scene.quantities
    [bem]  periodic tol max_iter reference_error           -> BemSettings
    [tolerances]  levels                -> Scene.tolerances
    [quick]  realizations n count       -> QuickSettings
    [theory]  C m separation_min separation_max count      -> TheorySpec (kind "theory")

Every key is optional except the surface's ``D`` and one of ``rms_slope``/``G``. Invalid
values raise :class:`SceneError` (a ``ValueError``) naming the key (and, from a file, the
file).
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field, fields, replace

from validation import models as _models

__all__ = [
    "Scene", "SurfaceSpec", "LoadPath", "BemSettings", "TheorySpec", "QuickSettings",
    "SceneError", "MODELS", "QUANTITIES", "KINDS", "load_scene", "builtin_scenes", "parse_scene",
    "defaults",
]

#: Models a scene uses unless it lists its own (any registered name may be listed:
#: :func:`validation.models.names`).
MODELS = _models.default_names()
#: Quantities a scene may ask for.
QUANTITIES = ("area", "load", "separation", "conductance", "contacts", "stiffness")
#: Kinds of scene.
KINDS = ("surface", "theory")


class SceneError(ValueError):
    """A scene file or value is invalid; the message names the key (and the file).

    ``key`` is the offending field and ``detail`` what is wrong with it, when known.
    """

    def __init__(self, message: str, *, key: str | None = None, detail: str | None = None):
        super().__init__(message)
        self.key, self.detail = key, detail


def _fail(owner: object, key: str, detail: str) -> None:
    raise SceneError(f"{type(owner).__name__}: key '{key}' {detail}", key=key, detail=detail)


def _number(owner, key: str, *, above: float | None = None, at_least: float | None = None,
            below: float | None = None, optional: bool = False) -> None:
    """Check (and store as float) a finite real field within the bounds."""
    value = getattr(owner, key)
    if value is None and optional:
        return
    bounds = [f"> {above:g}" if above is not None else "",
              f">= {at_least:g}" if at_least is not None else "",
              f"< {below:g}" if below is not None else ""]
    allowed = "a finite number" + "".join(f" {b}" for b in bounds if b)
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or (above is not None and value <= above) \
            or (at_least is not None and value < at_least) \
            or (below is not None and value >= below):
        _fail(owner, key, f"must be {allowed}, got {value!r}")
    object.__setattr__(owner, key, float(value))


def _integer(owner, key: str, minimum: int) -> None:
    value = getattr(owner, key)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        _fail(owner, key, f"must be an integer >= {minimum}, got {value!r}")


def _flag(owner, key: str) -> None:
    if not isinstance(getattr(owner, key), bool):
        _fail(owner, key, f"must be true or false, got {getattr(owner, key)!r}")


def _numbers(owner, key: str, *, above: float, below: float | None = None) -> None:
    """A non-empty tuple of finite numbers in (above, below)."""
    values = getattr(owner, key)
    values = tuple(values) if isinstance(values, (list, tuple)) else (values,)
    bound = f"in ({above:g}, {below:g})" if below is not None else f"> {above:g}"
    if not values:
        _fail(owner, key, "must not be empty")
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v <= above or (below is not None and v >= below):
            _fail(owner, key, f"must hold finite numbers {bound}, got {v!r}")
    object.__setattr__(owner, key, tuple(float(v) for v in values))


def _names(owner, key: str, allowed: tuple[str, ...]) -> None:
    """A non-empty tuple of distinct names, each in ``allowed``."""
    value = getattr(owner, key)
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value \
            or not all(isinstance(v, str) for v in value):
        _fail(owner, key, f"must be a non-empty list of strings, got {value!r}")
    unknown = [v for v in value if v not in allowed]
    if unknown:
        _fail(owner, key, f"has unknown entries {unknown}; allowed: {', '.join(allowed)}")
    if len(set(value)) != len(value):
        _fail(owner, key, f"lists an entry twice: {list(value)!r}")
    object.__setattr__(owner, key, tuple(value))


def _choice(owner, key: str, allowed: tuple[str, ...]) -> None:
    if getattr(owner, key) not in allowed:
        _fail(owner, key, f"must be one of {', '.join(allowed)}; got {getattr(owner, key)!r}")


@dataclass(frozen=True)
class SurfaceSpec:
    """A Weierstrass-Mandelbrot surface family (arguments of :func:`validation.wm_surface`;
    docs/theory.md eqs. (11)-(12)). Give exactly one of ``rms_slope`` and ``G``."""

    D: tuple[float, ...]
    rms_slope: float | None = 0.1
    G: float | None = None
    gamma: float = 1.5
    M: int = 10
    n_max: int = 8
    L: float = 1.0
    n: int = 256
    family: str = "wm"

    def __post_init__(self) -> None:
        _choice(self, "family", ("wm",))
        _numbers(self, "D", above=2.0, below=3.0)
        if (self.rms_slope is None) == (self.G is None):
            _fail(self, "rms_slope", "or 'G': give exactly one of the two")
        _number(self, "rms_slope", above=0.0, optional=True)
        _number(self, "G", above=0.0, optional=True)
        _number(self, "gamma", above=1.0)
        _integer(self, "M", 1)
        _integer(self, "n_max", 0)
        _number(self, "L", above=0.0)
        _integer(self, "n", 16)

    @property
    def spacing(self) -> float:
        """Grid spacing L / n [length]."""
        return self.L / self.n


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
        _choice(self, "quantity", tuple(_PATH_DEFAULTS))
        for key, default in _PATH_DEFAULTS[self.quantity].items():
            if getattr(self, key) is None:
                object.__setattr__(self, key, default)
        _choice(self, "spacing", ("log", "linear"))
        _number(self, "min", above=0.0 if self.quantity == "load" else None)
        _number(self, "max")
        _integer(self, "count", 1)
        if self.max <= self.min:
            _fail(self, "max", f"must be greater than min = {self.min:g}")
        if self.spacing == "log" and self.min <= 0:
            _fail(self, "min", "must be > 0 with logarithmic spacing")

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

    def __post_init__(self) -> None:
        _flag(self, "periodic")
        _number(self, "tol", above=0.0)
        if self.tol > 0.1:
            _fail(self, "tol", f"must be <= 0.1, got {self.tol!r}")
        _integer(self, "max_iter", 1)
        _flag(self, "reference_error")


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
        _numbers(self, "C", above=0.0)
        _number(self, "m", at_least=0.0)
        _number(self, "separation_min")
        _number(self, "separation_max")
        _integer(self, "count", 2)
        if self.separation_max <= self.separation_min:
            _fail(self, "separation_max", "must be greater than separation_min")


@dataclass(frozen=True)
class QuickSettings:
    """What quick mode changes: fewer realizations, a coarser grid, fewer load points."""

    realizations: int = 3
    n: int = 128
    count: int = 10

    def __post_init__(self) -> None:
        _integer(self, "realizations", 1)
        _integer(self, "n", 16)
        _integer(self, "count", 1)


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
    e_star: float = 1.0
    loads: LoadPath = field(default_factory=LoadPath)
    models: tuple[str, ...] = MODELS
    m: float = 1.0
    quantities: tuple[str, ...] = ("area", "load", "separation", "conductance", "contacts")
    bem: BemSettings = field(default_factory=BemSettings)
    tolerances: tuple[float, ...] = (0.05, 0.2)
    quick: QuickSettings = field(default_factory=QuickSettings)
    theory: TheorySpec | None = None
    source: str = "<memory>"

    def __post_init__(self) -> None:
        _choice(self, "kind", KINDS)
        for key in ("name", "title", "description", "source"):
            if not isinstance(getattr(self, key), str):
                _fail(self, key, f"must be a string, got {getattr(self, key)!r}")
        _integer(self, "realizations", 1)
        _integer(self, "seed", 0)
        _number(self, "e_star", above=0.0)
        _number(self, "m", at_least=0.0)
        _names(self, "models", _models.names())
        _names(self, "quantities", QUANTITIES)
        _numbers(self, "tolerances", above=0.0)
        self._check_parts()

    def _check_parts(self) -> None:
        parts = dict(surface=SurfaceSpec, loads=LoadPath, bem=BemSettings, quick=QuickSettings,
                     theory=TheorySpec)
        for key, kind in parts.items():
            value = getattr(self, key)
            if value is not None and not isinstance(value, kind):
                _fail(self, key, f"must be a {kind.__name__}, got {type(value).__name__}")
        if self.kind == "surface" and self.surface is None:
            _fail(self, "surface", "is required in a surface scene")
        if self.kind == "theory" and self.theory is None:
            _fail(self, "theory", "is required in a theory scene")
        if self.kind == "surface" and self.theory is not None:
            _fail(self, "theory", "belongs only in a scene with kind = \"theory\"")

    def quick_version(self) -> "Scene":
        """The scene as the quick default report runs it."""
        if self.kind == "theory":
            return self
        surface = replace(self.surface, n=min(self.surface.n, self.quick.n))
        loads = replace(self.loads, count=min(self.loads.count, self.quick.count))
        return replace(self, surface=surface, loads=loads,
                       realizations=min(self.realizations, self.quick.realizations))


def defaults(kind: type) -> dict:
    """Field defaults of a scene dataclass (the format's defaults), by field name."""
    out = {}
    for f in fields(kind):
        if f.default_factory is not MISSING:
            out[f.name] = f.default_factory()
        elif f.default is not MISSING:
            out[f.name] = f.default
    return out


def parse_scene(*args, **kwargs) -> Scene:
    """Validate a scene given as a dictionary (:func:`validation.scene_file.parse_scene`)."""
    from validation.scene_file import parse_scene as parse

    return parse(*args, **kwargs)


def load_scene(*args, **kwargs) -> Scene:
    """Load a built-in scene by name, or a scene file (:func:`validation.scene_file.load_scene`)."""
    from validation.scene_file import load_scene as load

    return load(*args, **kwargs)


def builtin_scenes() -> tuple[str, ...]:
    """Names of the scenes shipped with the package, sorted."""
    from validation.scene_file import builtin_scenes as names

    return names()
