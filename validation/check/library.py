"""The check as a library call: :func:`check_scan` answers, on one measured scan, which theory
to trust, and returns a :class:`validation.check.result.CheckResult`.

``python -m validation check`` is a thin wrapper of the same steps (:mod:`validation.check.command`): the
arguments become a :class:`validation.check.request.CheckRequest` (numbers in SI units or
strings with units, parsed as on the command line), the request becomes a scene
(:func:`validation.check.request.scene_text`), and the scene runs as any report's does: first
the scan as sampled (its half-grid band), then with the finer reference where the band keeps a
verdict open. A scene written by a check (``check.toml``) is recognised by
:func:`is_check_scene`, so ``python -m validation report check.toml`` gives the same report.
"""

from __future__ import annotations

import contextlib
import math
import os
import pathlib
import re
import time
import tomllib
from dataclasses import replace

import numpy as np

from bem.elastic.device import array_module
from validation.check.plausible import plausibility
from validation.check.request import CheckRequest, scene_text
from validation.check.result import CheckResult
from validation.check.scan_input import SCRATCH_NAME, scan_source, size_text
from validation.check.units import parse_length, parse_pressure, parse_pressure_range, \
    parse_size, unitless
from validation.common import models as registry
from validation.scenes.reader import parse_scene
from validation.surfaces.spec import MIN_TILE
from validation.surfaces.units import LENGTH_UNITS

__all__ = ["check_scan", "check_scenes", "is_check_scene", "make_request", "request_of_scene",
           "run_request"]

#: The command line's option for each keyword of :func:`check_scan` (messages name the one
#: the user wrote).
OPTIONS = {"e_star": "--e-star", "pressures": "--pressure", "short_cutoff": "--short-cutoff",
           "fill": "--fill", "resample": "--resample", "physical_size": "--physical-size",
           "file_unit": "--file-unit", "tiles": "--tiles", "nominal_size": "--nominal-size",
           "models": "--models", "device": "--device", "scan": "SCAN"}


def _keywords(message: str) -> str:
    """A message of the command line's parsers with its options named as keywords."""
    for keyword, option in OPTIONS.items():
        if option.startswith("--"):
            message = re.sub(rf"{re.escape(option)}(?![\w-])", keyword, message)
    return message


def _pressure_text(pressures) -> str | None:
    """``pressures`` as the command line writes them: ``"LOW:HIGH[:COUNT]"`` (numbers in a
    tuple are pascals, SI; a count is the third entry)."""
    if pressures is None or isinstance(pressures, str):
        return pressures
    if isinstance(pressures, (tuple, list)) and len(pressures) in (2, 3):
        ends = [f"{p:.17g}Pa" if isinstance(p, (int, float)) and not isinstance(p, bool)
                else str(p) for p in pressures[:2]]
        return ":".join(ends + [str(c) for c in pressures[2:]])
    raise TypeError(f"pressures must be (low, high) or (low, high, count), or 'LOW:HIGH:COUNT', "
                    f"got {pressures!r}")


def make_request(scan, *, e_star=None, pressures=None, short_cutoff=None, fill=None,
                 resample=None, physical_size=None, file_unit=None, spacing=None,
                 tiles: int = 1, nominal_size=None, models=None, device: str = "cpu",
                 cache_dir: str | None = None) -> CheckRequest:
    """The :class:`CheckRequest` of :func:`check_scan`'s arguments (units parsed, the scan
    read once to check it).

    Raises
    ------
    ValueError, TypeError
        Naming the argument and what it allows (the command line's option names are used
        by the command, :mod:`validation.check.command`).
    """
    array_module(device, "--device")   # a GPU asked for where there is none: said first
    path, physical_size, file_unit, scratch = scan_source(scan, spacing, file_unit,
                                                          physical_size, fill, cache_dir)
    if not scratch and not path.is_file():
        raise ValueError(f"scan {str(path)!r} names no file")
    if e_star is not None:
        pascals, has_unit = parse_pressure("--e-star", e_star)
        if not has_unit and isinstance(e_star, str):
            raise unitless("--e-star", e_star, "pressure")
        e_star = pascals
    pressure_range = None if pressures is None else parse_pressure_range(_pressure_text(pressures))
    if pressure_range is not None:
        pressure_range.dimensionless(e_star)   # pressures in Pa need E*: said now
    if physical_size is not None and not scratch:
        physical_size = size_text(*parse_size("--physical-size", physical_size))
    if isinstance(tiles, bool) or not isinstance(tiles, (int, np.integer)) or tiles < 1 \
            or round(tiles ** 0.5) ** 2 != tiles:
        raise ValueError(f"--tiles must be a square number >= 1 (1, 4, 9, ...), got {tiles!r}")
    if models is not None:
        if isinstance(models, str):
            models = (models,)
        unknown = [m for m in models if m not in registry.names()]
        if unknown or not models:
            raise ValueError(f"--models must name registered models ({', '.join(registry.names())})"
                             f", got {list(models)!r}")
        models = tuple(models)
    request = CheckRequest(path, e_star, pressure_range, None, fill, physical_size, file_unit,
                           int(tiles), resample, None, models, scratch, device)
    if tiles > 1:
        rows, columns = request.read("m").heights.shape
        side = min(rows, columns) // math.isqrt(tiles)
        if side < MIN_TILE:
            raise ValueError(f"--tiles {tiles} cuts the {rows} x {columns}-pixel scan into tiles "
                             f"of {side} pixels per side; at least {MIN_TILE} are needed: use "
                             f"at most {(min(rows, columns) // MIN_TILE) ** 2} tiles")
    if short_cutoff is not None:
        request = replace(request, short_cutoff=_cutoff(short_cutoff, request))
    if nominal_size is not None:
        request = replace(request, nominal_size=_nominal_size(nominal_size, request))
    _plausible(request)
    return request


def _plausible(request: CheckRequest) -> None:
    """The scan and the pressures checked for their units before any solve
    (:mod:`validation.check.plausible`); a flat scan is said first."""
    scan = request.read("m")
    slope = request.rms_slope(scan)
    loads = None if request.pressures is None else request.pressures.dimensionless(request.e_star)
    plausibility("the height array" if request.scratch else request.name, scan.heights,
                 scan.spacing, scan.physical_size, slope, loads, request.e_star)


def _user_words(message: str) -> str:
    """A message as the user reads it: the command line's options named as keywords, and a
    height array's copy in the cache named as the array."""
    return SCRATCH_NAME.sub("the height array", _keywords(message))


def _cutoff(value, request: CheckRequest) -> str:
    """The short cutoff as the scene key writes it: a length (``20nm``, metres as a number) or
    pixels (``8px``) of the scan."""
    text = str(value) if not isinstance(value, str) else value
    match = re.fullmatch(r"\s*([0-9.]+(?:[eE][-+]?\d+)?)\s*px\s*", text)
    if match is None:
        metres, has_unit = parse_length("--short-cutoff", value)
        if not has_unit and isinstance(value, str):
            raise ValueError(f"{unitless('--short-cutoff', value)}; or pixels: '{value}px'")
        return f"{metres:.6g} m"
    return f"{float(match.group(1)) * request.read('m').spacing:.6g} m"


def _nominal_size(value, request: CheckRequest) -> float:
    """The nominal contact's side in metres: a length, at least the scan's side."""
    metres, has_unit = parse_length("--nominal-size", value)
    if not has_unit and isinstance(value, str):
        raise unitless("--nominal-size", value)
    if not metres > 0:
        raise ValueError(f"--nominal-size must be a positive length, got {value!r}")
    scan = request.read("m")
    side = max(scan.physical_size)
    if metres < side * (1 - 1e-9):
        raise ValueError(f"--nominal-size must be at least the scan's longer side "
                         f"({side:.4g} m): the scan is a sample of the interface inside the "
                         f"nominal contact; got {value!r}")
    return metres


def check_scenes(request: CheckRequest, source: str = "check.toml"):
    """The scenes of a request (the whole scan, then its tiles when asked) and the text of the
    first (``check.toml``)."""
    stem = re.sub(r"[^A-Za-z0-9_-]+", "-", request.path.stem).strip("-") or "scan"
    if request.scratch:
        stem = "array"
    scenes, first_text = [], None
    for tiles in dict.fromkeys((1, request.tiles)):
        name = f"check-{stem}" + (f"-tiles{tiles}" if tiles > 1 else "")
        text = scene_text(request, name, tiles=tiles)
        scenes.append(parse_scene(tomllib.loads(text),
                                  source=source if tiles == 1 else f"{name}.toml"))
        first_text = first_text or text
    return scenes, first_text


def is_check_scene(scene) -> bool:
    """Whether a scene is one scan as one surface (a measured map's scene with one tile): the
    scene a check writes, reported with the check's sections."""
    return (scene.kind == "surface" and scene.surface is not None
            and scene.surface.family == "file" and scene.surface.tiles == 1)


def request_of_scene(scene) -> CheckRequest:
    """The request a one-scan scene answers (:func:`is_check_scene`): its file, how to read it,
    its physical E* and nominal size."""
    s = scene.surface
    options = dict(s.read_options)
    nominal = None if scene.nominal_size is None else scene.nominal_size * LENGTH_UNITS[s.unit]
    cutoff = s.short_cutoff
    if cutoff is not None and not isinstance(cutoff, str):
        cutoff = f"{cutoff * LENGTH_UNITS[s.unit]:.6g} m"
    size = s.physical_size
    if isinstance(size, (int, float)):
        size = f"{size * LENGTH_UNITS[s.unit]:.17g} m"
    elif isinstance(size, (tuple, list)):
        size = tuple(f"{v * LENGTH_UNITS[s.unit]:.17g} m" if isinstance(v, (int, float)) else v
                     for v in size)
    return CheckRequest(pathlib.Path(s.path), scene.physical_e_star, None, cutoff,
                        options.get("fill"), size, s.file_unit, 1,
                        None if s.resample == "none" else s.resample, nominal, scene.models,
                        device=scene.bem.device)


def run_request(request: CheckRequest, scenes, scene_text_: str, *, executor=None,
                cache_dir: str | None = None, progress: bool = False) -> CheckResult:
    """Run a check's scenes (with the finer reference where the band decides, then the scan
    as sampled, its paths from the cache) and return its result. The scenes with their grid
    limit run first, so that their references keep the pressures a finer path starts from
    (:mod:`validation.run.starts`)."""
    from validation.judge.decide import run_scenes

    start = time.perf_counter()
    scene = scenes[0]
    sampled = replace(scene, bem=replace(scene.bem, max_grid=None))
    runs = run_scenes(scenes, executor=executor, cache_dir=cache_dir, progress=progress)
    first = run_scenes([sampled], executor=executor, cache_dir=cache_dir, progress=progress)[0]
    return CheckResult.of(request, runs, first, scene_text=scene_text_,
                          seconds=time.perf_counter() - start)


@contextlib.contextmanager
def _wisdom(cache_dir: str | None):
    """FFTW wisdom kept with the cache for the run (bem.elastic.wisdom), as the command does."""
    from bem.elastic.wisdom import WISDOM_VARIABLE

    before = os.environ.get(WISDOM_VARIABLE)
    os.environ[WISDOM_VARIABLE] = cache_dir or ""
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(WISDOM_VARIABLE, None)
        else:
            os.environ[WISDOM_VARIABLE] = before


def check_scan(scan, *, e_star=None, pressures=None, short_cutoff=None, fill=None,
               resample=None, physical_size=None, file_unit=None, spacing=None, tiles: int = 1,
               nominal_size=None, models=None, device: str = "cpu",
               cache: str | os.PathLike | bool | None = None,
               progress: bool = False) -> CheckResult:
    """Which theory to trust on one measured scan: every model against the boundary-element
    reference of that very surface, at nominal pressures in physical units.

    Parameters
    ----------
    scan : path, Topography or numpy.ndarray
        A height file (any format :func:`validation.read_topography` reads), a
        :class:`validation.Topography`, or a 2-D array of heights [m] (``file_unit`` for
        another unit) with its ``spacing``.
    e_star : float [Pa] or str, optional
        Effective modulus E*, e.g. ``115e9`` or ``"115GPa"``; None: pressures and stiffness
        in units of E*.
    pressures : (low, high[, count]) or str, optional
        Nominal pressures, logarithmic: ``("1MPa", "100MPa", 12)`` or ``(1e6, 1e8, 12)``
        [Pa; both need ``e_star``], or as the command line writes them, ``"1MPa:100MPa:12"``,
        or in units of E* without a unit, ``"1e-5:1e-3"``; None: twelve pressures from light
        to heavy contact.
    short_cutoff : float [m] or str, optional
        Low-pass the scan at this wavelength: ``"20nm"``, ``"8px"``, ``2e-8``.
    fill, resample : str, optional
        ``"mean"``/``"interpolate"`` for missing points; ``"finer"``/``"coarser"`` for pixels
        that are not square.
    physical_size, file_unit : str, optional
        The scan's width and its heights' unit when the file states neither (``"10um"``,
        ``"nm"``); ``file_unit`` is the unit of an array's heights.
    spacing : float [m] or str, optional
        The pixel size of a height array (``1e-9`` or ``"1nm"``).
    tiles : int
        1: the whole scan; k²: also the scan cut into k x k tiles.
    nominal_size : float [m] or str, optional
        Side of your square nominal contact (``"10mm"``): adds the finite frame.
    models : sequence of str, optional
        Registered model names (each frame's reference is added).
    device : {"cpu", "gpu"}
        Where the reference's contact problems are solved: ``"gpu"`` needs CuPy and a CUDA
        device (the ``gpu`` extra). A single solve gives the CPU's numbers to rounding; the
        finer reference runs its loads as one path on a GPU and as one sub-path per core on
        the CPU, whose starts differ, so its points agree within the solver's tolerance.
    cache : path, True/None or False
        The run cache folder; None or True: the command's default folder; False: none.
    progress : bool
        Show progress bars.

    Returns
    -------
    CheckResult

    Raises
    ------
    ValueError, TypeError
        Naming the argument and what it allows.
    """
    from validation.run.cache import default_cache_dir

    cache_dir = None if cache is False else str(default_cache_dir() if cache in (None, True)
                                                else cache)
    try:
        request = make_request(scan, e_star=e_star, pressures=pressures,
                               short_cutoff=short_cutoff, fill=fill, resample=resample,
                               physical_size=physical_size, file_unit=file_unit, spacing=spacing,
                               tiles=tiles, nominal_size=nominal_size, models=models,
                               device=device, cache_dir=cache_dir)
        scenes, text = check_scenes(request)
    except (ValueError, TypeError) as error:
        raise type(error)(_user_words(str(error))) from None
    with _wisdom(cache_dir):
        return run_request(request, scenes, text, cache_dir=cache_dir, progress=progress)
