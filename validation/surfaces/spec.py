"""The surface of a scene: its family (Weierstrass-Mandelbrot, self-affine, measured map), the
family's parameters and their validation (:class:`SurfaceSpec`, the ``[surface]`` table of a
scene file, :mod:`validation.scenes.scene`).
"""

from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass, fields, replace

from validation.common import checks as check

__all__ = ["SurfaceSpec", "SWEEPS", "SIDES_SWEEP", "FAMILIES", "FAMILY_KEYS", "MIN_TILE",
           "READ_FIELDS", "read_keywords"]

#: Surface families and the parameter each sweeps (a list of values gives a validity map): its
#: key in the scene file and its symbol in the report. A measured map sweeps nothing. A WM
#: surface with ``sides`` sweeps its nominal side instead (:data:`SIDES_SWEEP`).
SWEEPS: dict[str, tuple[str, str] | None] = {"wm": ("D", "D"), "self-affine": ("hurst", "H"),
                                             "file": None}
#: The sweep of a WM surface with ``sides``: nested windows of one surface, nominal side L.
SIDES_SWEEP = ("sides", "L")
FAMILIES = tuple(SWEEPS)
#: Keys of ``[surface]`` by family (besides ``family``).
FAMILY_KEYS = {
    "wm": ("D", "rms_slope", "G", "gamma", "M", "n_max", "L", "n", "wavelength", "sides",
           "periodic"),
    "self-affine": ("hurst", "rms_slope", "rms_height", "long_cutoff", "rolloff", "short_cutoff",
                    "window", "plateau", "L", "n"),
    "file": ("path", "physical_size", "file_unit", "unit", "detrend", "resample", "square",
             "short_cutoff", "tiles", "n"),
}
#: Keywords of :func:`validation.read_topography` with a field of their own in a file scene
#: (``height_unit`` is the scene's ``unit``); every other keyword of it is passed through as
#: it is (``read_options``: fill, channel, reader, ...), so a scene accepts whatever the
#: reader does, including what its error messages recommend.
READ_FIELDS = {"path": "path", "physical_size": "physical_size", "file_unit": "file_unit",
               "detrend": "detrend", "height_unit": "unit", "resample": "resample",
               "square": "square", "short_cutoff": "short_cutoff"}
#: Why ``periodic`` is no key of a family other than WM (the scene reader says it too).
NOT_PERIODIC = {
    "self-affine": "is not a key of family 'self-affine': its surface is periodic with "
                   "window = 1 (the L x L map is then one period of the generated surface)",
    "file": "is not a key of family 'file': a measured map is not periodic (its interface "
            "reference is its mirror extension's)",
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
    ``rms_slope`` and ``G`` (default rms slope 0.1); ``wavelength``, the longest wavelength
    of eq. (11) [length] (default L: the paper's surface); ``periodic`` (default False): every
    wave vector of eq. (11) on the nearest point of the period's lattice 2 pi (i, j) / L
    (:func:`validation.surfaces.wm.wm_lattice`, docs/theory.md eq. T52), so that the L x L map
    is one period of its surface (:attr:`one_period`; not with ``sides`` or another
    ``wavelength``). ``sides`` (a tuple of nominal sides
    [length], with one ``D``) sweeps the size instead: realization k of side s is the window
    ``[0, s)^2`` of the same surface (seed), with the wavelengths of ``wavelength`` (default
    the first side) and the grid spacing of the first side (``n`` points on it, ``n s /
    sides[0]`` on side s, which must be a whole number); ``L`` is then the first side (leave
    it out), and each side in turn in the realizations' specs (:meth:`at`).

    ``"self-affine"``: Gaussian self-affine (:func:`validation.self_affine_surface`); ``hurst``
    H in (0, 1] required (a tuple sweeps it); at most one of ``rms_slope`` and ``rms_height``
    (default rms slope 0.1); cut-off wavelengths ``long_cutoff`` (default L), ``rolloff``
    (default long_cutoff) and ``short_cutoff`` (default 2 L/n) [length]; the L x L window is
    cut from a periodic surface ``window`` times larger per side (default 2; 1: periodic);
    ``plateau``, a quantile q in (0, 1): the heights above their q-quantile are cut flat before
    the amplitude is fixed (a plateau-honed finish, non-Gaussian heights; default none).

    ``"file"``: a measured height map (:func:`validation.read_topography`); ``path`` (read when
    the spec is made), ``physical_size`` and ``file_unit`` when the file does not state them,
    ``unit`` of every length (default m), ``detrend`` ("plane", "mean" or "none"),
    ``resample`` ("none", or "finer"/"coarser": non-square pixels onto square ones of the finer
    or coarser spacing, :func:`validation.read_topography`), ``square`` ("crop": a rectangular
    map is cropped to its largest centred square; "keep": it is used whole),
    ``short_cutoff`` (a length with its unit like ``physical_size``, ``"20 nm"``, or a number
    in ``unit``: every wavelength shorter than it is removed from the map, before it is cut
    into tiles and before every model and the BEM see it,
    :func:`validation.surfaces.cutoff.short_wavelength_cutoff`; default none),
    ``read_options`` (a dict, stored as sorted ``(key, value)`` pairs) the other keywords of
    :func:`validation.read_topography` (:func:`read_keywords`: ``fill``, ``channel``,
    ``reader``, ...), passed to it unchanged;
    ``tiles = k^2`` non-overlapping tiles as realizations, k x k of the map (each at least
    :data:`MIN_TILE` pixels per side, and an even number of rows and of columns: an odd cell
    drops its last row or column, so that the reference's error estimate on every second
    pixel covers the same window). ``shape`` (rows, columns of a tile), ``n`` (its rows)
    and ``L`` (the square root of its area [unit]: its side when square, so that the nominal
    area is ``L^2`` for every family) follow from the file: an explicit ``n`` or ``L`` must
    agree.

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
    short_cutoff: float | str | None = None
    window: int = 2
    plateau: float | None = None
    path: str | None = None
    physical_size: float | str | tuple[float, float] | None = None
    file_unit: str | None = None
    unit: str = "m"
    detrend: str = "plane"
    resample: str = "none"
    square: str = "crop"
    tiles: int = 1
    wavelength: float | None = None
    sides: tuple[float, ...] | None = None
    periodic: bool = False
    read_options: tuple[tuple[str, object], ...] | dict = ()
    shape: tuple[int, int] | None = None      # derived: (rows, columns) of a measured tile

    def __post_init__(self) -> None:
        check.choice(self, "family", FAMILIES)
        base = {f.name: f.default for f in fields(self)}
        derived = ("n", "L", "shape", "read_options") if self.family == "file" else ()
        if self.family in NOT_PERIODIC and self.periodic is not False:
            check.fail(self, "periodic", NOT_PERIODIC[self.family])
        for key, default in base.items():
            if key not in FAMILY_KEYS[self.family] + ("family",) + derived \
                    and getattr(self, key) != default:
                check.fail(self, key, f"is not a parameter of family {self.family!r} (its keys: "
                           f"{', '.join(FAMILY_KEYS[self.family])})")
        if self.family == "file":
            self._check_file()
        else:
            self._check_generated()
        check.integer(self, "n", 16)

    def _check_generated(self) -> None:
        amplitude = ("rms_slope", "G") if self.family == "wm" else ("rms_slope", "rms_height")
        if all(getattr(self, key) is None for key in amplitude):
            object.__setattr__(self, "rms_slope", _GENERATED_DEFAULTS["rms_slope"])
        if all(getattr(self, key) is not None for key in amplitude):
            check.fail(self, amplitude[0], f"or '{amplitude[1]}': give at most one of the two")
        if self.sides is not None:
            check.numbers(self, "sides", above=0.0)
            if self.L is None:
                object.__setattr__(self, "L", self.sides[0])
        for key in ("L", "n"):
            if getattr(self, key) is None:
                object.__setattr__(self, key, _GENERATED_DEFAULTS[key])
        check.number(self, "L", above=0.0)
        check.integer(self, "n", 16)
        for key in amplitude:
            check.number(self, key, above=0.0, optional=True)
        if self.family == "wm":
            check.numbers(self, "D", above=2.0, below=3.0)
            check.number(self, "gamma", above=1.0)
            check.integer(self, "M", 1)
            check.integer(self, "n_max", 0)
            check.number(self, "wavelength", above=0.0, optional=True)
            check.flag(self, "periodic")
            self._check_sides()
            self._check_periodic()
            return
        check.numbers(self, "hurst", above=0.0, at_most=1.0)
        for key in ("long_cutoff", "rolloff", "short_cutoff"):
            check.number(self, key, above=0.0, optional=True)
        check.integer(self, "window", 1)
        check.number(self, "plateau", above=0.0, below=1.0, optional=True)
        long_cutoff = self.L if self.long_cutoff is None else self.long_cutoff
        rolloff = long_cutoff if self.rolloff is None else self.rolloff
        short_cutoff = 2 * self.spacing if self.short_cutoff is None else self.short_cutoff
        if long_cutoff > self.window * self.L * (1 + 1e-12):
            check.fail(self, "long_cutoff", f"must be <= window * L = {self.window * self.L:g}")
        if rolloff > long_cutoff * (1 + 1e-12):
            check.fail(self, "rolloff", f"must be <= long_cutoff = {long_cutoff:g}")
        if short_cutoff < 2 * self.spacing * (1 - 1e-12) or short_cutoff >= rolloff:
            check.fail(self, "short_cutoff", f"must lie in [2 L/n, rolloff) = "
                       f"[{2 * self.spacing:g}, {rolloff:g}), got {short_cutoff:g}")

    def _check_sides(self) -> None:
        """``sides`` of a WM size sweep: one D, L the first side, whole grids on every side."""
        if self.sides is None:
            return
        first = self.sides[0]
        if len(self.D) > 1:
            check.fail(self, "sides", "sweeps the size: give one D with it, got "
                       f"{len(self.D)}")
        if len(set(self.sides)) != len(self.sides):
            check.fail(self, "sides", f"lists a side twice: {list(self.sides)!r}")
        if not math.isclose(self.L, first, rel_tol=1e-12):
            check.fail(self, "L", f"= {self.L!r} conflicts with the first of the sides "
                       f"({first:g}); leave it out")
        for side in self.sides:
            points = self.n * side / first
            if not math.isclose(points, round(points), rel_tol=1e-9):
                check.fail(self, "sides", f"must keep the grid spacing L/n = {first / self.n:g}"
                           f" on every side: side {side:g} gives {points:g} points, not a "
                           f"whole number")

    def _check_periodic(self) -> None:
        """A periodic WM surface is one period of side L: no nested windows, no other longest
        wavelength."""
        if not self.periodic:
            return
        if self.sides is not None:
            check.fail(self, "periodic", "cannot be true with 'sides': the size sweep's nested "
                       "windows of one surface cannot each be periodic (leave periodic out)")
        if self.wavelength is not None and not math.isclose(self.wavelength, self.L,
                                                            rel_tol=1e-12):
            check.fail(self, "periodic", f"needs the longest wavelength equal to the period L = "
                       f"{self.L:g}, got wavelength = {self.wavelength:g} (leave wavelength out)")

    def _check_file(self) -> None:
        from validation.surfaces.families import read_map, tile_side
        from validation.surfaces.topography import LENGTH_UNITS

        if not isinstance(self.path, str) or not self.path:
            check.fail(self, "path", f"must name a height file, got {self.path!r}")
        self._check_read_options()
        if isinstance(self.physical_size, list):
            object.__setattr__(self, "physical_size", tuple(self.physical_size))
        check.choice(self, "unit", tuple(LENGTH_UNITS))
        check.choice(self, "detrend", ("plane", "mean", "none"))
        check.choice(self, "resample", ("none", "finer", "coarser"))
        check.choice(self, "square", ("crop", "keep"))
        self._check_short_cutoff()
        check.integer(self, "tiles", 1)
        per_side = math.isqrt(self.tiles)
        if per_side**2 != self.tiles:
            check.fail(self, "tiles", f"must be a square number (k x k tiles: 1, 4, 9, ...), "
                       f"got {self.tiles}")
        if not pathlib.Path(self.path).is_file():
            check.fail(self, "path", f"names no file: {self.path!r}")
        try:
            scan = read_map(self)
        except (ValueError, ImportError) as error:
            _refuse_map(self, error)
        rows, columns = (tile_side(side, self.tiles) for side in scan.heights.shape)
        if min(rows, columns) < MIN_TILE:
            map_shape = " x ".join(map(str, scan.heights.shape))
            check.fail(self, "tiles", f"= {self.tiles} cuts the {map_shape}-pixel map into tiles "
                       f"of {rows} x {columns} pixels; at least {MIN_TILE} per side are needed")
        object.__setattr__(self, "shape", (rows, columns))
        for key, value in (("n", rows), ("L", math.sqrt(rows * columns) * scan.spacing)):
            given = getattr(self, key)
            if given is not None and not math.isclose(given, value, rel_tol=1e-9):
                check.fail(self, key, f"= {given!r} conflicts with the tile of the file "
                           f"({value:g}); leave it out")
            object.__setattr__(self, key, value if key == "L" else int(value))

    def _check_short_cutoff(self) -> None:
        """A measured map's cutoff: a positive number (in ``unit``) or a length string; its
        range (two pixels up to the map's side) is the reader's to check."""
        from validation.surfaces.units import length_in

        if self.short_cutoff is None:
            return
        try:
            length_in("short_cutoff", self.short_cutoff, self.unit)
        except (TypeError, ValueError):
            check.fail(self, "short_cutoff", f"must be a length: a number in the scene's unit "
                       f"({self.unit}) or a string with its unit like '20 nm', got "
                       f"{self.short_cutoff!r}")

    @property
    def short_cutoff_length(self) -> float | None:
        """A measured map's ``short_cutoff`` in ``unit`` (None when there is none)."""
        from validation.surfaces.units import length_in

        if self.family != "file" or self.short_cutoff is None:
            return None
        return length_in("short_cutoff", self.short_cutoff, self.unit)

    def _check_read_options(self) -> None:
        options = self.read_options
        if isinstance(options, dict):
            options = options.items()
        try:
            pairs = sorted((str(k), tuple(v) if isinstance(v, list) else v) for k, v in options)
        except (TypeError, ValueError):
            check.fail(self, "read_options", f"must be a dict of keywords of read_topography, "
                       f"got {self.read_options!r}")
        for key, _ in pairs:
            if key not in read_keywords():
                check.fail(self, key, f"is not a keyword of read_topography that a file scene "
                           f"passes on (those are: {', '.join(read_keywords())})")
        object.__setattr__(self, "read_options", tuple(pairs))

    @property
    def one_period(self) -> bool:
        """Whether a realization is one period of a periodic surface (a self-affine surface
        generated with ``window = 1``, a WM surface with ``periodic``): its interface
        reference is then the periodic BEM of the map itself, not of its mirror extension
        (:class:`bem.InterfaceModel`)."""
        return (self.family == "self-affine" and self.window == 1
                or self.family == "wm" and self.periodic)

    @property
    def grid(self) -> tuple[int, int]:
        """(rows, columns) of a realization: ``(n, n)``, or a measured tile's shape."""
        return (self.n, self.n) if self.shape is None else self.shape

    @property
    def spacing(self) -> float:
        """Grid spacing [length]: L / n, L / sqrt(rows columns) for a rectangular tile."""
        rows, columns = self.grid
        return self.L / (self.n if rows == columns else math.sqrt(rows * columns))

    @property
    def _sweep(self) -> tuple[str, str] | None:
        return SIDES_SWEEP if self.sides is not None else SWEEPS[self.family]

    @property
    def sweep_name(self) -> str:
        """Symbol of the swept parameter in the report ("D", "H", "L" for the sides of a size
        sweep), "" for a measured map."""
        sweep = self._sweep
        return sweep[1] if sweep else ""

    @property
    def sweep_values(self) -> tuple[float, ...]:
        """Values of the swept parameter; ``(0.0,)`` for a measured map (one family)."""
        sweep = self._sweep
        return getattr(self, sweep[0]) if sweep else (0.0,)

    def at(self, value: float) -> "SurfaceSpec":
        """The family at one value of its swept parameter (for a size sweep: the window of
        side ``value``, its grid of the same spacing, and the wavelengths of the sweep)."""
        if self.sides is not None:
            return replace(self, sides=(value,), L=value, n=round(self.n * value / self.L),
                           wavelength=self.wavelength if self.wavelength else self.L)
        sweep = SWEEPS[self.family]
        return replace(self, **{sweep[0]: (value,)}) if sweep else self



def read_keywords() -> tuple[str, ...]:
    """Keywords of :func:`validation.read_topography` a file scene passes on unchanged: every
    keyword-only parameter without a field of its own (:data:`READ_FIELDS`) in
    :class:`SurfaceSpec`, read from its signature, so that a new option of the reader is a
    scene key at once."""
    import inspect

    from validation.surfaces.topography import read_topography

    own = set(READ_FIELDS) | {f.name for f in fields(SurfaceSpec)}
    return tuple(p.name for p in inspect.signature(read_topography).parameters.values()
                 if p.kind is p.KEYWORD_ONLY and p.name not in own)


#: Scene keys of a measured map: its own fields, then the reader's other keywords.
FAMILY_KEYS["file"] = FAMILY_KEYS["file"] + read_keywords()


def _refuse_map(spec: SurfaceSpec, error: Exception) -> None:
    """A :class:`SceneError` for a map the reader refused, naming the scene key at fault and
    giving the reader's advice in the scene's own words (``fill = "mean"`` in [surface], not
    ``fill='mean'``); settings the file lacks are listed together, with an example."""
    import re

    message = str(error)
    options = ("resample", "square", "short_cutoff") + read_keywords()
    keys = [k for k in ("file_unit", "physical_size") if re.search(rf"\b{k}\b", message)] + [
        k for k in options if re.search(rf"\b{k}(=| must)", message)]
    advice = re.sub(r"\b(\w+)='([^']*)'", r'\1 = "\2"', message).replace("pass ", "set ")
    advice = re.sub(r'(= "[^"]*" or )\'([^\']*)\'', r'\1"\2"', advice)
    missing = [k for k in ("file_unit", "physical_size") if f"set {k}" in advice
               or f"and {k}" in advice]
    if missing:
        examples = {"file_unit": 'file_unit = "nm"        # unit of the numbers in the file',
                    "physical_size": 'physical_size = "10 um"  # width of the whole map'}
        advice += " in [surface], e.g.\n    " + "\n    ".join(examples[k] for k in missing)
    elif keys and keys[0] in options:
        advice += " in [surface]"
    check.fail(spec, keys[0] if keys else "path",
               f"does not give a readable height map: {advice}")
