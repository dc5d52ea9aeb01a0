"""Scene files: TOML tables and keys onto the scene dataclasses of :mod:`validation.scenes.scene`.

The reader checks only what TOML can get wrong (types, unknown keys, a table where a value
belongs); the value rules and the defaults are those of the dataclasses, whose errors are
re-raised here naming the file and the full key (``surface.n``, ``models.use``).
"""

from __future__ import annotations

import contextlib
import math
import pathlib
import tomllib
import warnings
from importlib import resources
from typing import Any, Iterator

from bem.common.checks import InputTypeError, file_path

from validation.scenes.scene import (FAMILIES, FAMILY_KEYS, KINDS, BemSettings, LoadPath,
                                     QuickSettings, Scene, SceneError, SceneWarning, SurfaceSpec,
                                     TheorySpec, defaults, scene_warnings)
from validation.surfaces.spec import NOT_PERIODIC, read_keywords

__all__ = ["parse_scene", "load_scene", "builtin_scenes"]

#: Scene fields read from another table than their name, as "table.key".
_SCENE_KEYS = {"realizations": "realizations.count", "seed": "realizations.seed",
               "max_realizations": "realizations.max",
               "e_star": "material.e_star",
               "physical_e_star": "material.physical_e_star", "models": "models.use", "m": "models.m",
               "nominal_size": "models.nominal_size",
               "quantities": "quantities.use", "tolerances": "tolerances.levels",
               "sampling": "sampling.factors"}
_SURFACE_TABLES = ("surface", "realizations", "loads", "models", "quantities", "bem", "quick",
                   "material", "sampling")


class _Reader:
    """One table of a scene file: typed look-ups, remembering the key path for messages."""

    def __init__(self, table: Any, path: str, source: str) -> None:
        if not isinstance(table, dict):
            raise SceneError(f"{source}: [{path}] must be a table", key=path)
        self.table, self.path, self.source = table, path, source
        self.used: set[str] = set()

    def key(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, detail: str) -> None:
        raise SceneError(f"{self.source}: key '{self.key(key)}' {detail}", key=self.key(key),
                         detail=detail)

    def get(self, key: str, default: Any = None, kind: str = "any") -> Any:
        """The value of ``key`` (``default`` if absent), checked to be of ``kind``:
        "number", "integer", "boolean", "string", "numbers" (one or a list), "strings" or
        "length" (a number, or a string with its unit: "20 nm")."""
        self.used.add(key)
        if key not in self.table:
            return default
        value = self.table[key]
        checks = {
            "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
            "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
            "boolean": lambda v: isinstance(v, bool),
            "string": lambda v: isinstance(v, str),
            "strings": lambda v: isinstance(v, list) and all(isinstance(x, str) for x in v),
            "numbers": lambda v: isinstance(v, (int, float, list)) and not isinstance(v, bool),
            "length": lambda v: isinstance(v, (int, float, str)) and not isinstance(v, bool),
            "any": lambda v: True,
        }
        if not checks[kind](value):
            article = "an" if kind[0] in "aeiou" else "a"
            self.fail(key, f"must be {article} {kind.rstrip('s')}"
                      f"{' or a list of them' if kind.endswith('s') else ''}, got {value!r}")
        if kind == "number" and not math.isfinite(value):
            self.fail(key, f"must be a finite number, got {value!r}")
        return tuple(value) if isinstance(value, list) else value

    def values(self, kinds: dict[str, str], base: dict) -> dict:
        """Every key of ``kinds`` present in the table, over the defaults ``base``."""
        out = dict(base)
        for key, kind in kinds.items():
            out[key] = self.get(key, base.get(key), kind)
        return out

    def sub(self, key: str) -> "_Reader":
        self.used.add(key)
        return _Reader(self.table.get(key, {}), self.key(key), self.source)

    def finish(self) -> None:
        unknown = sorted(set(self.table) - self.used)
        if unknown:
            where = f"[{self.path}]" if self.path else "the top level"
            also = f" (also unknown: {', '.join(unknown[1:])})" if len(unknown) > 1 else ""
            self.fail(unknown[0], f"is not a known key of {where}{also}")


@contextlib.contextmanager
def _keys(source: str, prefix: str = "", mapping: dict[str, str] | None = None) -> Iterator:
    """Re-raise a dataclass's :class:`SceneError` naming the file and the full key."""
    try:
        yield
    except SceneError as error:
        if error.detail is None:
            raise
        key = (mapping or {}).get(error.key, f"{prefix}{error.key}")
        raise SceneError(f"{source}: key '{key}' {error.detail}", key=key,
                         detail=error.detail) from None


def _build(kind: type, reader: _Reader, kinds: dict[str, str]):
    """A dataclass from one table (defaults from the dataclass), the table then closed."""
    values = reader.values(kinds, defaults(kind))
    with _keys(reader.source, f"{reader.path}."):
        built = kind(**values)
    reader.finish()
    return built


#: Value kind of every ``[surface]`` key (which keys a family takes: FAMILY_KEYS).
_SURFACE_KINDS = dict(
    D="numbers", rms_slope="number", G="number", gamma="number", M="integer", n_max="integer",
    L="number", n="integer", hurst="numbers", rms_height="number", long_cutoff="number",
    rolloff="number", short_cutoff="length", window="integer", path="string",
    physical_size="any", file_unit="string", unit="string", detrend="string", resample="string",
    square="string", tiles="integer", wavelength="number", sides="numbers",
    periodic="boolean")
#: Keys a family needs in a file: each entry is one key, or alternatives (one of them).
_SURFACE_REQUIRED = {"wm": ("D", ("rms_slope", "G")),
                     "self-affine": ("hurst", ("rms_slope", "rms_height")), "file": ("path",)}


def _surface(top: _Reader, folder: pathlib.Path | None) -> SurfaceSpec:
    reader = top.sub("surface")
    family = reader.get("family", defaults(SurfaceSpec)["family"], "string")
    if family not in FAMILIES:
        reader.fail("family", f"must be one of {', '.join(FAMILIES)}; got {family!r}")
    allowed = FAMILY_KEYS[family]
    if family == "file" and "height_unit" in reader.table:
        # read_topography's name for the scene's unit, accepted where its messages use it
        if "unit" in reader.table:
            reader.fail("height_unit", "and 'unit' are the same setting: give one of them")
        reader.table = {("unit" if k == "height_unit" else k): v for k, v in reader.table.items()}
    if "periodic" in reader.table and family in NOT_PERIODIC:
        reader.fail("periodic", NOT_PERIODIC[family])
    for key in reader.table:
        if key != "family" and key not in allowed:
            reader.fail(key, f"is not a key of family {family!r} (its keys: {', '.join(allowed)})")
    for need in _SURFACE_REQUIRED[family]:
        options = (need,) if isinstance(need, str) else need
        if not any(key in reader.table for key in options):
            reader.fail(options[0], ("or '" + "' or '".join(options[1:]) + "' " if
                                     len(options) > 1 else "") + "is required")
    values = {key: reader.get(key, None, _SURFACE_KINDS.get(key, "any")) for key in allowed
              if key in reader.table}
    if family == "file":
        # the reader's other keywords go to it as they are (it checks their values)
        options = {key: values.pop(key) for key in read_keywords() if key in values}
        if options:
            values["read_options"] = options
    if "path" in values and folder is not None:
        values["path"] = str(folder / values["path"])
    with _keys(reader.source, "surface."):
        surface = SurfaceSpec(family=family, **values)
    reader.finish()
    return surface


def _loads(top: _Reader) -> LoadPath:
    reader = top.sub("loads")
    kinds = dict(quantity="string", min="number", max="number", count="integer",
                 spacing="string")
    return _build(LoadPath, reader, kinds)


def _surface_parts(top: _Reader, base: dict, folder: pathlib.Path | None) -> dict:
    """Scene fields of a surface scene, table by table."""
    parts = dict(surface=_surface(top, folder), loads=_loads(top))
    if parts["surface"].family == "file" and "realizations" in top.table:
        top.fail("realizations", "does not belong in a scene of a measured map: its "
                 "realizations are its tiles (surface.tiles)")
    tables = dict(realizations=dict(count="integer", seed="integer", max="integer"),
                  material=dict(e_star="number", physical_e_star="number"),
                  models=dict(use="strings", m="number", nominal_size="number"),
                  quantities=dict(use="strings"), sampling=dict(factors="numbers"))
    for table, kinds in tables.items():
        reader = top.sub(table)
        for key, kind in kinds.items():
            field_name = next(f for f, k in _SCENE_KEYS.items() if k == f"{table}.{key}")
            parts[field_name] = reader.get(key, base[field_name], kind)
        reader.finish()
    parts["bem"] = _build(BemSettings, top.sub("bem"), dict(
        periodic="boolean", tol="number", max_iter="integer", reference_error="boolean",
        max_grid="integer", frames="strings", device="string"))
    parts["quick"] = _build(QuickSettings, top.sub("quick"), dict(
        realizations="integer", n="integer", count="integer", quantities="strings",
        max_grid="integer"))
    return parts


def _theory_parts(top: _Reader, data: dict) -> dict:
    """Scene fields of a theory scene (GW vs improved GW; no surface)."""
    for key in _SURFACE_TABLES:
        if key in data:
            top.fail(key, "does not belong in a theory scene (it needs no surface)")
    theory = _build(TheorySpec, top.sub("theory"), dict(
        C="numbers", m="number", separation_min="number", separation_max="number",
        count="integer"))
    # data, not dispatch: the theory scene computes exactly these two (validation.run.theory)
    return dict(theory=theory, models=("gw", "improved_gw"),
                quantities=("load", "separation", "stiffness"))


def parse_scene(data: dict, *, source: str = "<memory>", name: str | None = None,
                folder: str | pathlib.Path | None = None) -> Scene:
    """Validate a scene given as a dictionary (the parsed TOML) and build a :class:`Scene`.

    A measured map's ``surface.path`` is taken relative to ``folder`` (the scene file's
    folder; default: the working directory).

    Raises
    ------
    SceneError
        Naming the key and ``source``.

    Warns
    -----
    SceneWarning
        For a valid scene that will not give what it seems to ask for
        (:func:`validation.scenes.scene.scene_warnings`: a generated surface family of one
        realization, judged as that one surface).
    """
    if not isinstance(data, dict):
        raise InputTypeError(f"data must be a dict (a parsed TOML scene), got "
                             f"{type(data).__name__}")
    if name is not None and not isinstance(name, str):
        raise InputTypeError(f"name must be a str or None, got {type(name).__name__}")
    folder = None if folder is None else file_path("folder", folder)
    top = _Reader(data, "", source)
    base = defaults(Scene)
    scene_name = top.get("name", name or "scene", "string")
    kind = top.get("kind", base["kind"], "string")
    if kind not in KINDS:
        top.fail("kind", f"must be one of {', '.join(KINDS)}; got {kind!r}")
    tolerances = top.sub("tolerances")
    fields = dict(name=scene_name, kind=kind, source=source,
                  title=top.get("title", scene_name, "string"),
                  description=top.get("description", base["description"], "string"),
                  tolerances=tolerances.get("levels", base["tolerances"], "numbers"))
    tolerances.finish()
    if kind == "theory":
        fields.update(_theory_parts(top, data))
    else:
        if "theory" in data:
            top.fail("theory", "belongs only in a scene with kind = \"theory\"")
        fields.update(_surface_parts(top, base, folder))
    top.finish()
    with _keys(source, mapping=_SCENE_KEYS):
        scene = Scene(**fields)
    for message in scene_warnings(scene):
        warnings.warn(message, SceneWarning, stacklevel=3)
    return scene


def load_scene(name_or_path: str | pathlib.Path) -> Scene:
    """Load a built-in scene by name, or a scene file by path.

    Raises
    ------
    SceneError
        When the file does not exist, is not valid TOML, or holds an invalid scene.
    """
    if not isinstance(name_or_path, str):
        file_path("name_or_path", name_or_path)
    source, builtin = str(name_or_path), builtin_scenes()
    if isinstance(name_or_path, str) and name_or_path in builtin:
        resource = resources.files("validation") / "scenes" / f"{name_or_path}.toml"
        text, source = resource.read_text(encoding="utf-8"), f"built-in scene {name_or_path}"
        stem, folder = name_or_path, pathlib.Path(str(resource)).parent
    else:
        path = pathlib.Path(name_or_path)
        if not path.is_file():
            raise SceneError(f"{source}: no such scene file, and not a built-in scene "
                             f"(name_or_path must be a scene file or one of the built-in: "
                             f"{', '.join(builtin)})")
        text, stem, folder = path.read_text(encoding="utf-8"), path.stem, path.parent
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SceneError(f"{source}: not valid TOML: {error}") from None
    return parse_scene(data, source=source, name=stem, folder=folder)


def builtin_scenes() -> tuple[str, ...]:
    """Names of the scenes shipped with the package, sorted."""
    folder = resources.files("validation") / "scenes"
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml")))
