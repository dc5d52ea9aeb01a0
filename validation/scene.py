"""Scenes: declarative descriptions of what to compute and compare, parsed from TOML.

A scene names a surface family and its parameters, realizations, material, a load path, the
models and quantities to compute, the boundary-element settings and the error tolerances at
which a model is said to hold. Scenes are data: the built-in ones are TOML files shipped in
``validation/scenes/``, and any user file path works the same way. Unknown keys and bad values
raise :class:`SceneError` (a ``ValueError``) naming the key and the file.

File format (every key, with its default)::

    name = "wm-d205"                # default: the file name without .toml
    title = "..."                   # one line for the report
    description = "..."             # a paragraph for the report
    kind = "surface"                # "surface" (surfaces, models, BEM) or "theory" (Figs. 1-3)

    [surface]                       # kind = "surface" only
    family = "wm"                   # Weierstrass-Mandelbrot, THEORY.md eqs. (11)-(12)
    D = 2.05                        # a number, or a list of numbers for a sweep (validity map)
    rms_slope = 0.1                 # exactly one of rms_slope and G
    gamma = 1.5
    M = 10
    n_max = 8
    L = 1.0                         # sample length, the nominal area is L^2
    n = 256                         # grid points per side

    [realizations]
    count = 25
    seed = 0                        # realization k uses seed + k

    [material]
    e_star = 1.0

    [loads]                         # the load path, in the paper's dimensionless units
    quantity = "load"               # "load": Load = W/(E* L^2); "separation": d/sigma
    min = 1e-5
    max = 1e-2
    count = 16
    spacing = "log"                 # "log" or "linear"

    [models]
    use = ["gw", "improved_gw", "discrete", "discrete_no_interaction", "bem"]
    m = 1.0                         # interaction factor of the improved GW theory

    [quantities]
    use = ["area", "load", "separation", "conductance", "contacts"]   # or "stiffness"

    [bem]
    periodic = false
    tol = 1e-8
    max_iter = 2000
    reference_error = true          # per-point error estimate of every BEM curve (grid n/2 vs n)

    [tolerances]
    levels = [0.05, 0.2]            # relative error (and separation error in units of sigma)

    [quick]                         # what the default quick report changes
    realizations = 3
    n = 128
    count = 10

    [theory]                        # kind = "theory" only: GW vs improved GW, Figs. 1-3
    C = [5.0, 50.0]                 # interaction parameter C = eta sqrt(A R sigma), eq. (4)
    m = 1.0
    separation_min = -2.0           # (d - mu_s)/sigma of the GW curve
    separation_max = 4.0
    count = 200
"""

from __future__ import annotations

import math
import pathlib
import tomllib
from dataclasses import dataclass, field, replace
from importlib import resources
from typing import Any

__all__ = [
    "Scene", "SurfaceSpec", "LoadPath", "BemSettings", "TheorySpec", "SceneError",
    "MODELS", "QUANTITIES", "load_scene", "builtin_scenes", "parse_scene",
]

#: Models a scene may ask for.
MODELS = ("gw", "improved_gw", "discrete", "discrete_no_interaction", "bem")
#: Quantities a scene may ask for.
QUANTITIES = ("area", "load", "separation", "conductance", "contacts", "stiffness")


class SceneError(ValueError):
    """A scene file or value is invalid; the message names the key and the file."""


@dataclass(frozen=True)
class SurfaceSpec:
    """A Weierstrass-Mandelbrot surface family (arguments of :func:`validation.wm_surface`)."""

    D: tuple[float, ...]
    rms_slope: float | None = 0.1
    G: float | None = None
    gamma: float = 1.5
    M: int = 10
    n_max: int = 8
    L: float = 1.0
    n: int = 256
    family: str = "wm"

    @property
    def spacing(self) -> float:
        """Grid spacing L / n [length]."""
        return self.L / self.n


@dataclass(frozen=True)
class LoadPath:
    """The load path, dimensionless: ``Load = W/(E* L^2)`` or ``Separation = d/sigma``."""

    quantity: str = "load"
    min: float = 1e-5
    max: float = 1e-2
    count: int = 16
    spacing: str = "log"

    def values(self) -> tuple[float, ...]:
        """The points of the path, increasing."""
        if self.count == 1:
            return (self.min,)
        if self.spacing == "log":
            ratio = math.log(self.max / self.min)
            return tuple(self.min * math.exp(ratio * k / (self.count - 1)) for k in range(self.count))
        step = (self.max - self.min) / (self.count - 1)
        return tuple(self.min + step * k for k in range(self.count))


@dataclass(frozen=True)
class BemSettings:
    """Boundary-element settings of a scene."""

    periodic: bool = False
    tol: float = 1e-8
    max_iter: int = 2000
    reference_error: bool = True


@dataclass(frozen=True)
class TheorySpec:
    """GW vs improved GW in dimensionless form (the paper's Figs. 1-3)."""

    C: tuple[float, ...] = (5.0, 50.0)
    m: float = 1.0
    separation_min: float = -2.0
    separation_max: float = 4.0
    count: int = 200


@dataclass(frozen=True)
class QuickSettings:
    """What quick mode changes: fewer realizations, a coarser grid, fewer load points."""

    realizations: int = 3
    n: int = 128
    count: int = 10


@dataclass(frozen=True)
class Scene:
    """A validated scene. Build it with :func:`load_scene` or :func:`parse_scene`."""

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

    def quick_version(self) -> "Scene":
        """The scene as the quick default report runs it."""
        if self.kind == "theory":
            return self
        surface = replace(self.surface, n=min(self.surface.n, self.quick.n))
        loads = replace(self.loads, count=min(self.loads.count, self.quick.count))
        return replace(self, surface=surface, loads=loads,
                       realizations=min(self.realizations, self.quick.realizations))


# --------------------------------------------------------------------------------------------
# parsing

_TOP_KEYS = {"name", "title", "description", "kind", "surface", "realizations", "material", "loads",
             "models", "quantities", "bem", "tolerances", "quick", "theory"}


class _Reader:
    """Reads one table of a scene file, remembering the key path for error messages."""

    def __init__(self, table: dict, path: str, source: str) -> None:
        if not isinstance(table, dict):
            raise SceneError(f"{source}: [{path}] must be a table")
        self.table, self.path, self.source = table, path, source
        self.used: set[str] = set()

    def _key(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, message: str) -> None:
        raise SceneError(f"{self.source}: key '{self._key(key)}' {message}")

    def get(self, key: str, default: Any = None) -> Any:
        self.used.add(key)
        return self.table.get(key, default)

    def number(self, key: str, default: float | None, *, minimum: float | None = None,
               exclusive: bool = False, maximum: float | None = None, required: bool = False
               ) -> float | None:
        value = self.get(key, default)
        if value is None:
            if required:
                self.fail(key, "is required")
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(key, f"must be a finite number, got {value!r}")
        if minimum is not None and (value <= minimum if exclusive else value < minimum):
            self.fail(key, f"must be {'>' if exclusive else '>='} {minimum}, got {value!r}")
        if maximum is not None and value > maximum:
            self.fail(key, f"must be <= {maximum}, got {value!r}")
        return float(value)

    def integer(self, key: str, default: int, *, minimum: int) -> int:
        value = self.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            self.fail(key, f"must be an integer >= {minimum}, got {value!r}")
        return int(value)

    def boolean(self, key: str, default: bool) -> bool:
        value = self.get(key, default)
        if not isinstance(value, bool):
            self.fail(key, f"must be true or false, got {value!r}")
        return value

    def string(self, key: str, default: str, choices: tuple[str, ...] | None = None) -> str:
        value = self.get(key, default)
        if not isinstance(value, str):
            self.fail(key, f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            self.fail(key, f"must be one of {', '.join(choices)}; got {value!r}")
        return value

    def choices(self, key: str, default: tuple[str, ...], allowed: tuple[str, ...]) -> tuple[str, ...]:
        value = self.get(key, list(default))
        if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
            self.fail(key, f"must be a non-empty list of strings, got {value!r}")
        unknown = [v for v in value if v not in allowed]
        if unknown:
            self.fail(key, f"has unknown entries {unknown}; allowed: {', '.join(allowed)}")
        if len(set(value)) != len(value):
            self.fail(key, f"lists an entry twice: {value!r}")
        return tuple(value)

    def numbers(self, key: str, default: tuple[float, ...], *, lower: float, upper: float | None
                ) -> tuple[float, ...]:
        value = self.get(key, list(default))
        values = value if isinstance(value, list) else [value]
        if not values:
            self.fail(key, "must not be empty")
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                    or v <= lower or (upper is not None and v >= upper):
                bound = f"in ({lower}, {upper})" if upper is not None else f"> {lower}"
                self.fail(key, f"must hold finite numbers {bound}, got {v!r}")
        return tuple(float(v) for v in values)

    def sub(self, key: str) -> "_Reader":
        self.used.add(key)
        return _Reader(self.table.get(key, {}), self._key(key), self.source)

    def finish(self) -> None:
        unknown = sorted(set(self.table) - self.used)
        if unknown:
            where = f"[{self.path}]" if self.path else "the top level"
            self.fail(unknown[0], f"is not a known key of {where}"
                      + (f" (also unknown: {', '.join(unknown[1:])})" if len(unknown) > 1 else ""))


def parse_scene(data: dict, *, source: str = "<memory>", name: str | None = None) -> Scene:
    """Validate a scene given as a dictionary (the parsed TOML) and build a :class:`Scene`."""
    top = _Reader(data, "", source)
    scene_name = top.string("name", name or "scene")
    kind = top.string("kind", "surface", ("surface", "theory"))
    title = top.string("title", scene_name)
    description = top.string("description", "")
    tolerances_table = top.sub("tolerances")
    tolerances = tolerances_table.numbers("levels", (0.05, 0.2), lower=0.0, upper=None)
    tolerances_table.finish()

    if kind == "theory":
        for key in ("surface", "realizations", "loads", "models", "quantities", "bem", "quick",
                    "material"):
            if key in data:
                top.fail(key, "does not belong in a theory scene (it needs no surface)")
        th = top.sub("theory")
        theory = TheorySpec(
            C=th.numbers("C", (5.0, 50.0), lower=0.0, upper=None),
            m=th.number("m", 1.0, minimum=0.0),
            separation_min=th.number("separation_min", -2.0),
            separation_max=th.number("separation_max", 4.0),
            count=th.integer("count", 200, minimum=2),
        )
        if theory.separation_max <= theory.separation_min:
            th.fail("separation_max", "must be greater than separation_min")
        th.finish()
        top.finish()
        return Scene(name=scene_name, kind=kind, title=title, description=description,
                     tolerances=tolerances, theory=theory, source=source, models=("gw", "improved_gw"),
                     quantities=("load", "separation", "stiffness"))

    if "theory" in data:
        top.fail("theory", "belongs only in a scene with kind = \"theory\"")
    s = top.sub("surface")
    s.string("family", "wm", ("wm",))
    rms_slope = s.number("rms_slope", None, minimum=0.0, exclusive=True)
    G = s.number("G", None, minimum=0.0, exclusive=True)
    if (rms_slope is None) == (G is None):
        s.fail("rms_slope", "or 'G': give exactly one of the two")
    surface = SurfaceSpec(
        D=s.numbers("D", (2.5,), lower=2.0, upper=3.0),
        rms_slope=rms_slope, G=G,
        gamma=s.number("gamma", 1.5, minimum=1.0, exclusive=True),
        M=s.integer("M", 10, minimum=1),
        n_max=s.integer("n_max", 8, minimum=0),
        L=s.number("L", 1.0, minimum=0.0, exclusive=True),
        n=s.integer("n", 256, minimum=16),
    )
    s.finish()

    r = top.sub("realizations")
    realizations = r.integer("count", 25, minimum=1)
    seed = r.integer("seed", 0, minimum=0)
    r.finish()

    mat = top.sub("material")
    e_star = mat.number("e_star", 1.0, minimum=0.0, exclusive=True)
    mat.finish()

    lo = top.sub("loads")
    quantity = lo.string("quantity", "load", ("load", "separation"))
    spacing = lo.string("spacing", "log" if quantity == "load" else "linear", ("log", "linear"))
    low = lo.number("min", 1e-5 if quantity == "load" else 0.0,
                    minimum=0.0 if quantity == "load" else None, exclusive=True)
    high = lo.number("max", 1e-2 if quantity == "load" else 3.0)
    if high <= low:
        lo.fail("max", f"must be greater than loads.min = {low}")
    if spacing == "log" and low <= 0:
        lo.fail("min", "must be > 0 with logarithmic spacing")
    loads = LoadPath(quantity=quantity, min=low, max=high, count=lo.integer("count", 16, minimum=1),
                     spacing=spacing)
    lo.finish()

    mo = top.sub("models")
    models = mo.choices("use", MODELS, MODELS)
    m = mo.number("m", 1.0, minimum=0.0)
    mo.finish()

    qu = top.sub("quantities")
    quantities = qu.choices("use", ("area", "load", "separation", "conductance", "contacts"),
                            QUANTITIES)
    qu.finish()

    b = top.sub("bem")
    bem = BemSettings(
        periodic=b.boolean("periodic", False),
        tol=b.number("tol", 1e-8, minimum=0.0, exclusive=True, maximum=0.1),
        max_iter=b.integer("max_iter", 2000, minimum=1),
        reference_error=b.boolean("reference_error", True),
    )
    b.finish()

    q = top.sub("quick")
    quick = QuickSettings(
        realizations=q.integer("realizations", 3, minimum=1),
        n=q.integer("n", 128, minimum=16),
        count=q.integer("count", 10, minimum=1),
    )
    q.finish()
    top.finish()
    return Scene(name=scene_name, kind=kind, title=title, description=description, surface=surface,
                 realizations=realizations, seed=seed, e_star=e_star, loads=loads, models=models,
                 m=m, quantities=quantities, bem=bem, tolerances=tolerances, quick=quick,
                 source=source)


def load_scene(name_or_path: str | pathlib.Path) -> Scene:
    """Load a built-in scene by name, or a scene file by path.

    Raises
    ------
    SceneError
        When the file does not exist, is not valid TOML, or holds an invalid scene.
    """
    text, source, stem = None, str(name_or_path), None
    builtin = builtin_scenes()
    if isinstance(name_or_path, str) and name_or_path in builtin:
        resource = resources.files("validation") / "scenes" / f"{name_or_path}.toml"
        text, source, stem = resource.read_text(encoding="utf-8"), f"built-in scene {name_or_path}", name_or_path
    else:
        path = pathlib.Path(name_or_path)
        if not path.is_file():
            raise SceneError(f"{source}: no such scene file, and not a built-in scene "
                             f"(built-in: {', '.join(builtin)})")
        text, stem = path.read_text(encoding="utf-8"), path.stem
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SceneError(f"{source}: not valid TOML: {error}") from None
    return parse_scene(data, source=source, name=stem)


def builtin_scenes() -> tuple[str, ...]:
    """Names of the scenes shipped with the package, sorted."""
    folder = resources.files("validation") / "scenes"
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml")))
