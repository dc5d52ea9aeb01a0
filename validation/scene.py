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
    [surface]  family, and the keys of the family (FAMILY_KEYS)   -> SurfaceSpec
               wm: D rms_slope G gamma M n_max L n
               self-affine: hurst rms_slope rms_height long_cutoff rolloff short_cutoff
                            window L n
               file: path physical_size file_unit unit detrend tiles
    [realizations]  count seed          -> Scene.realizations, Scene.seed
    [material]  e_star                  -> Scene.e_star
    [loads]  quantity min max count spacing                -> LoadPath
    [models]  use m                     -> Scene.models (registered names), Scene.m
    [quantities]  use                   -> Scene.quantities
    [bem]  periodic tol max_iter reference_error           -> BemSettings
    [tolerances]  levels                -> Scene.tolerances
    [quick]  realizations n count       -> QuickSettings
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
import pathlib
from dataclasses import MISSING, dataclass, field, fields, replace

from validation import models as _models

__all__ = [
    "Scene", "SurfaceSpec", "LoadPath", "BemSettings", "TheorySpec", "QuickSettings",
    "SceneError", "MODELS", "QUANTITIES", "KINDS", "FAMILIES", "FAMILY_KEYS", "SWEEPS",
    "load_scene", "builtin_scenes", "parse_scene", "defaults",
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


def _numbers(owner, key: str, *, above: float, below: float | None = None,
             at_most: float | None = None) -> None:
    """A non-empty tuple of finite numbers in (above, below) or (above, at_most]."""
    values = getattr(owner, key)
    if values is None:
        _fail(owner, key, "is required")
    values = tuple(values) if isinstance(values, (list, tuple)) else (values,)
    bound = (f"in ({above:g}, {below:g})" if below is not None else
             f"in ({above:g}, {at_most:g}]" if at_most is not None else f"> {above:g}")
    if not values:
        _fail(owner, key, "must not be empty")
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v <= above or (below is not None and v >= below) \
                or (at_most is not None and v > at_most):
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


#: Surface families and the parameter each sweeps (a list of values gives a validity map): its
#: key in the scene file and its symbol in the report. A measured map sweeps nothing.
SWEEPS: dict[str, tuple[str, str] | None] = {"wm": ("D", "D"), "self-affine": ("hurst", "H"),
                                             "file": None}
FAMILIES = tuple(SWEEPS)
#: Keys of ``[surface]`` by family (besides ``family``).
FAMILY_KEYS = {
    "wm": ("D", "rms_slope", "G", "gamma", "M", "n_max", "L", "n"),
    "self-affine": ("hurst", "rms_slope", "rms_height", "long_cutoff", "rolloff", "short_cutoff",
                    "window", "L", "n"),
    "file": ("path", "physical_size", "file_unit", "unit", "detrend", "tiles", "n"),
}
#: Defaults filled in by family: amplitude, side L and grid n of a generated surface.
_GENERATED_DEFAULTS = dict(rms_slope=0.1, L=1.0, n=256)
#: Smallest tile of a measured map, in pixels per side.
MIN_TILE = 32


@dataclass(frozen=True)
class SurfaceSpec:
    """A surface family and its parameters; ``family`` is one of :data:`FAMILIES`.

    ``"wm"`` (default): Weierstrass-Mandelbrot (arguments of :func:`validation.wm_surface`;
    docs/theory.md eqs. (11)-(12)); ``D`` required (a tuple sweeps it); at most one of
    ``rms_slope`` and ``G`` (default rms slope 0.1).

    ``"self-affine"``: Gaussian self-affine (:func:`validation.self_affine_surface`); ``hurst``
    H in (0, 1] required (a tuple sweeps it); at most one of ``rms_slope`` and ``rms_height``
    (default rms slope 0.1); cut-off wavelengths ``long_cutoff`` (default L), ``rolloff``
    (default long_cutoff) and ``short_cutoff`` (default 2 L/n) [length]; the L x L window is
    cut from a periodic surface ``window`` times larger per side (default 2; 1: periodic).

    ``"file"``: a measured height map (:func:`validation.read_topography`); ``path`` (read when
    the spec is made), ``physical_size`` and ``file_unit`` when the file does not state them,
    ``unit`` of every length (default m), ``detrend`` ("plane", "mean" or "none"),
    ``tiles = k^2`` non-overlapping k x k square tiles as realizations (each at least
    :data:`MIN_TILE` pixels). ``n`` (tile pixels) and ``L`` (tile side [unit]) follow from the
    file: an explicit value must agree. ``digest`` is the SHA-256 of the file when read.

    Other families' parameters must keep their defaults.
    """

    D: tuple[float, ...] | None = None
    rms_slope: float | None = None
    G: float | None = None
    gamma: float = 1.5
    M: int = 10
    n_max: int = 8
    L: float | None = None
    n: int | None = None
    family: str = "wm"
    hurst: tuple[float, ...] | None = None
    rms_height: float | None = None
    long_cutoff: float | None = None
    rolloff: float | None = None
    short_cutoff: float | None = None
    window: int = 2
    path: str | None = None
    physical_size: float | str | tuple[float, float] | None = None
    file_unit: str | None = None
    unit: str = "m"
    detrend: str = "plane"
    tiles: int = 1

    def __post_init__(self) -> None:
        _choice(self, "family", FAMILIES)
        base = {f.name: f.default for f in fields(self)}
        derived = ("n", "L") if self.family == "file" else ()
        for key, default in base.items():
            if key not in FAMILY_KEYS[self.family] + ("family",) + derived \
                    and getattr(self, key) != default:
                _fail(self, key, f"is not a parameter of family {self.family!r} (its keys: "
                      f"{', '.join(FAMILY_KEYS[self.family])})")
        if self.family == "file":
            self._check_file()
        else:
            self._check_generated()
        _integer(self, "n", 16)

    def _check_generated(self) -> None:
        amplitude = ("rms_slope", "G") if self.family == "wm" else ("rms_slope", "rms_height")
        if all(getattr(self, key) is None for key in amplitude):
            object.__setattr__(self, "rms_slope", _GENERATED_DEFAULTS["rms_slope"])
        if all(getattr(self, key) is not None for key in amplitude):
            _fail(self, amplitude[0], f"or '{amplitude[1]}': give at most one of the two")
        for key in ("L", "n"):
            if getattr(self, key) is None:
                object.__setattr__(self, key, _GENERATED_DEFAULTS[key])
        _number(self, "L", above=0.0)
        _integer(self, "n", 16)
        for key in amplitude:
            _number(self, key, above=0.0, optional=True)
        if self.family == "wm":
            _numbers(self, "D", above=2.0, below=3.0)
            _number(self, "gamma", above=1.0)
            _integer(self, "M", 1)
            _integer(self, "n_max", 0)
            return
        _numbers(self, "hurst", above=0.0, at_most=1.0)
        for key in ("long_cutoff", "rolloff", "short_cutoff"):
            _number(self, key, above=0.0, optional=True)
        _integer(self, "window", 1)
        long_cutoff = self.L if self.long_cutoff is None else self.long_cutoff
        rolloff = long_cutoff if self.rolloff is None else self.rolloff
        short_cutoff = 2 * self.spacing if self.short_cutoff is None else self.short_cutoff
        if long_cutoff > self.window * self.L * (1 + 1e-12):
            _fail(self, "long_cutoff", f"must be <= window * L = {self.window * self.L:g}")
        if rolloff > long_cutoff * (1 + 1e-12):
            _fail(self, "rolloff", f"must be <= long_cutoff = {long_cutoff:g}")
        if short_cutoff < 2 * self.spacing * (1 - 1e-12) or short_cutoff >= rolloff:
            _fail(self, "short_cutoff", f"must lie in [2 L/n, rolloff) = [{2 * self.spacing:g}, "
                  f"{rolloff:g}), got {short_cutoff:g}")

    def _check_file(self) -> None:
        from validation.surface_families import read_map
        from validation.topography import LENGTH_UNITS

        if not isinstance(self.path, str) or not self.path:
            _fail(self, "path", f"must name a height file, got {self.path!r}")
        if isinstance(self.physical_size, list):
            object.__setattr__(self, "physical_size", tuple(self.physical_size))
        _choice(self, "unit", tuple(LENGTH_UNITS))
        _choice(self, "detrend", ("plane", "mean", "none"))
        _integer(self, "tiles", 1)
        per_side = math.isqrt(self.tiles)
        if per_side**2 != self.tiles:
            _fail(self, "tiles", f"must be a square number (k x k tiles: 1, 4, 9, ...), "
                  f"got {self.tiles}")
        if not pathlib.Path(self.path).is_file():
            _fail(self, "path", f"names no file: {self.path!r}")
        try:
            scan = read_map(self)
        except (ValueError, ImportError) as error:
            key = next((k for k in ("physical_size", "file_unit") if k in str(error)), "path")
            _fail(self, key, f"does not give a readable height map: {error}")
        side = scan.heights.shape[0] // per_side
        if side < MIN_TILE or scan.heights.shape[0] != scan.heights.shape[1]:
            _fail(self, "tiles", f"= {self.tiles} cuts the {scan.heights.shape[0]}-pixel map "
                  f"into tiles of {side} pixels; at least {MIN_TILE} are needed")
        for key, value in (("n", side), ("L", side * scan.spacing)):
            given = getattr(self, key)
            if given is not None and not math.isclose(given, value, rel_tol=1e-9):
                _fail(self, key, f"= {given!r} conflicts with the tile of the file "
                      f"({value:g}); leave it out")
            object.__setattr__(self, key, value if key == "L" else int(value))

    @property
    def spacing(self) -> float:
        """Grid spacing L / n [length]."""
        return self.L / self.n

    @property
    def sweep_name(self) -> str:
        """Symbol of the swept parameter in the report ("D", "H"), "" for a measured map."""
        sweep = SWEEPS[self.family]
        return sweep[1] if sweep else ""

    @property
    def sweep_values(self) -> tuple[float, ...]:
        """Values of the swept parameter; ``(0.0,)`` for a measured map (one family)."""
        sweep = SWEEPS[self.family]
        return getattr(self, sweep[0]) if sweep else (0.0,)

    def at(self, value: float) -> "SurfaceSpec":
        """The family at one value of its swept parameter."""
        sweep = SWEEPS[self.family]
        return replace(self, **{sweep[0]: (value,)}) if sweep else self


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
        family = self.surface.family if self.surface is not None else "wm"
        if family != "wm" and self.bem.periodic:
            _fail(self, "bem.periodic", f"must be false for a {family} surface (its window is "
                  "not periodic)")
        if family == "file":  # the tiles of a measured map are its realizations
            object.__setattr__(self, "realizations", self.surface.tiles)

    def quick_version(self) -> "Scene":
        """The scene as the quick default report runs it."""
        if self.kind == "theory":
            return self
        surface = self.surface if self.surface.family == "file" else \
            replace(self.surface, n=min(self.surface.n, self.quick.n))
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
