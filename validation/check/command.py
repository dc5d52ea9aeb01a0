"""``python -m validation check SCAN``: which theory to trust on one measured scan.

The command reads the scan, writes the scene that answers the question (:mod:`.request`),
runs it as any report does (the same cache, workers and report folder: ``report.md``,
``errors.csv``, ``verdicts.csv``, ...) and puts first in ``report.md`` what only one surface
has: every theory against the reference at the user's pressures in physical units
(``physical.csv``, :mod:`.physical`) and whether the reference is converged on the scan as
sampled, with the remedy when the contact area is not (:mod:`.resolution`). The scene is kept
as ``check.toml`` in the folder: ``python -m validation report DIR/check.toml`` recomputes it.
"""

from __future__ import annotations

import argparse
import math
import os
import pathlib
import re
import shlex
import sys
import time
import tomllib
from dataclasses import replace

import numpy as np

from validation.check.glance import glance_lines
from validation.check.physical import physical_tables, table_lines, write_csv
from validation.check.request import CheckRequest, scene_text
from validation.check.resolution import cutoff_text, resolution, resolution_lines
from validation.check.frames import frame_lines
from validation.check.units import format_pressure, parse_length, parse_pressure, \
    parse_pressure_range
from validation.scenes.reader import parse_scene

__all__ = ["add_parser", "check_request", "run_check"]


def check_request(args: argparse.Namespace) -> CheckRequest:
    """The request of the command line's options (units parsed, the file checked).

    Raises
    ------
    ValueError
        Naming the option and what it allows.
    """
    path = pathlib.Path(args.scan)
    if not path.is_file():
        raise ValueError(f"SCAN {args.scan!r} names no file")
    e_star = None
    if args.e_star is not None:
        e_star, has_unit = parse_pressure("--e-star", args.e_star)
        if not has_unit:
            raise ValueError(f"--e-star needs a unit, e.g. 115GPa, got {args.e_star!r}")
    pressures = None if args.pressure is None else parse_pressure_range(args.pressure)
    if pressures is not None:
        pressures.dimensionless(e_star)   # pressures in Pa need E*: said now
    cutoff = None
    if args.short_cutoff is not None:
        cutoff = _cutoff(args.short_cutoff, args)
    if args.physical_size is not None:
        _, has_unit = parse_length("--physical-size", args.physical_size)
        if not has_unit:
            raise ValueError(f"--physical-size needs a unit, e.g. '10um', got "
                             f"{args.physical_size!r}")
    tiles = args.tiles
    if tiles < 1 or round(tiles ** 0.5) ** 2 != tiles:
        raise ValueError(f"--tiles must be a square number >= 1 (1, 4, 9, ...), got {tiles}")
    request = CheckRequest(path, e_star, pressures, cutoff, args.fill, args.physical_size,
                           args.file_unit, tiles, args.resample)
    nominal_size = getattr(args, "nominal_size", None)
    if nominal_size is not None:
        request = replace(request, nominal_size=_nominal_size(nominal_size, request))
    return request


def _nominal_size(text: str, request: CheckRequest) -> float:
    """``--nominal-size`` in metres: a length with its unit, at least the scan's side."""
    metres, has_unit = parse_length("--nominal-size", text)
    if not has_unit:
        raise ValueError(f"--nominal-size needs a unit, e.g. 10mm, got {text!r}")
    if not metres > 0:
        raise ValueError(f"--nominal-size must be a positive length, got {text!r}")
    scan = request.read("m")
    side = math.sqrt(scan.heights.size) * scan.spacing
    if metres < side * (1 - 1e-9):
        raise ValueError(f"--nominal-size must be at least the scan's side ({side:.4g} m): the "
                         f"scan is a sample of the interface inside the nominal contact; got "
                         f"{text!r}")
    return metres


def _cutoff(text: str, args: argparse.Namespace) -> str:
    """``--short-cutoff`` as the scene key writes it: a length (``20nm``) or pixels (``8px``)."""
    match = re.fullmatch(r"\s*([0-9.]+(?:[eE][-+]?\d+)?)\s*px\s*", text)
    if match is None:
        metres, has_unit = parse_length("--short-cutoff", text)
        if not has_unit:
            raise ValueError(f"--short-cutoff needs a unit (20nm, 0.5um) or pixels (8px), "
                             f"got {text!r}")
        return f"{metres:.6g} m"
    pixels = float(match.group(1))
    scan = CheckRequest(pathlib.Path(args.scan), fill=args.fill, physical_size=args.physical_size,
                        file_unit=args.file_unit, resample=args.resample).read("m")
    return f"{pixels * scan.spacing:.6g} m"


def _scene(request: CheckRequest, out: pathlib.Path, tiles: int = 1):
    stem = re.sub(r"[^A-Za-z0-9_-]+", "-", request.path.stem).strip("-") or "scan"
    name = f"check-{stem}" + (f"-tiles{tiles}" if tiles > 1 else "")
    text = scene_text(request, name, tiles=tiles)
    source = str(out / (f"{name}.toml" if tiles > 1 else "check.toml"))
    return parse_scene(tomllib.loads(text), source=source), text


#: Share of filled points above which the report says so in bold.
MANY_FILLED = 0.05


def _filled_text(request: CheckRequest) -> str:
    """How many points of the scan were missing and filled (``--fill``), if any."""
    if request.fill is None:
        return ""
    scan = request.read("m")
    if not scan.filled:
        return ""
    share = scan.filled / scan.heights.size
    text = (f"{scan.filled} of {scan.heights.size} points ({100 * share:.3g} %) missing in the "
            f"file and filled (`--fill {request.fill}`)")
    if share > MANY_FILLED:
        text = (f"; **{text}: the filled points are not measured topography, yet every model "
                f"and the reference see them**")
    else:
        text = f"; {text}"
    return text


def _sections(result, sampled, request: CheckRequest, out: pathlib.Path) -> list[str]:
    """What heads a check's report: the answer in physical units, then the resolution."""
    from validation.judge.analysis import analyse

    scene = result.scene
    comparison = analyse(result).comparisons[0]
    half_grid = analyse(sampled).comparisons[0]
    realization = result.realizations[0.0][0]
    s = scene.surface
    unit = s.unit
    tables = physical_tables(realization, comparison, e_star=request.e_star, unit=unit)
    write_csv(tables, out / "physical.csv")
    from validation.check.figure import physical_figure

    physical_figure(tables, out / "check-physical.png")
    from validation.common import models

    # the interface's reference: the check's answer, and the one its finer grid refines
    reference = realization.curves[models.reference_among(realization.curves, "interface")
                                   or models.reference_among(realization.curves)]
    refined = np.asarray(reference.extras.get("grid", np.full(reference.load.shape, s.n))) > s.n
    rows, columns = s.grid
    e_star = ("E* not given: pressures and stiffness are in units of E*" if request.e_star is None
              else f"E* = {format_pressure(request.e_star)}")
    lines = [f"## Your surface: {request.path.name}\n",
             f"The whole scan as one surface: {rows} x {columns} pixels of {s.spacing:.4g} {unit}, "
             f"plane removed, σ (summit heights) = {realization.sigma:.4g} {unit}, {e_star}"
             + (f", low-pass filtered at {cutoff_text(request.short_cutoff, s.spacing, unit)}"
                if request.short_cutoff else
                ", no short-wavelength cutoff")
             + _filled_text(request)
             + ". One surface is not a population: the reference solves this very surface, so "
               "a theory **holds** where |error| + band ≤ tolerance, **fails** where |error| − "
               "band > tolerance, and stays undecided only where the reference's band straddles "
               "the tolerance.\n"]
    lines += glance_lines(tables)
    lines += ["Every model's value at each pressure, beside the reference with its band "
              "(`physical.csv` has them all):\n",
              "![Each theory against the reference in physical units](check-physical.png)\n"]
    for table in tables:
        lines += table_lines(table)
    lines += frame_lines(tables, sigma=realization.sigma, unit=unit, e_star=request.e_star,
                         nominal_size=scene.nominal_size)
    lines += resolution_lines(resolution(half_grid, comparison, refined), spacing=s.spacing,
                              unit=unit, short_cutoff=request.short_cutoff)
    return lines


#: The reader's keywords a message may recommend, and the check's option for each.
_OPTIONS = {"file_unit": "--file-unit", "physical_size": "--physical-size", "fill": "--fill",
            "resample": "--resample", "short_cutoff": "--short-cutoff"}


def _options_hint(message: str) -> str:
    """Where a reader's message recommends its keywords, the check's options that set them."""
    named = [option for keyword, option in _OPTIONS.items() if re.search(rf"\b{keyword}\b", message)]
    return f" (on the command line: {', '.join(named)})" if named else ""


def _insert(report: pathlib.Path, lines: list[str]) -> None:
    """Put ``lines`` after the report's header (before its first section)."""
    text = report.read_text(encoding="utf-8").split("\n")
    first = next((k for k, line in enumerate(text) if line.startswith("## ")), len(text))
    report.write_text("\n".join(text[:first] + lines + text[first:]), encoding="utf-8")


def run_check(args: argparse.Namespace, run_pipeline) -> int:
    """The ``check`` command (see the module docstring); ``run_pipeline`` is the command
    line's way of running a report (:func:`validation.cli.run_pipeline`)."""
    try:
        request = check_request(args)
        args.out = args.out or f"check-{request.path.stem}"
        if args.jobs == 0:
            args.jobs = 1 if request.tiles == 1 else (os.cpu_count() or 1)
        out = pathlib.Path(args.out)
        scene, text = _scene(request, out)
        scenes = [scene] + ([_scene(request, out, request.tiles)[0]] if request.tiles > 1 else [])
    except (ValueError, TypeError, ImportError) as error:
        print(f"error: {error}{_options_hint(str(error))}", file=sys.stderr)
        return 2
    command = "python -m validation " + shlex.join(args.argv)

    def work(executor, cache_dir):
        from validation.report.write import write_report
        from validation.judge.decide import run_scenes

        start = time.perf_counter()
        # the scan as sampled first (its half-grid band), then with the finer reference where
        # the band decides (the path itself comes from the cache)
        sampled = replace(scene, bem=replace(scene.bem, max_grid=None))
        first = run_scenes([sampled], executor=executor, cache_dir=cache_dir,
                           progress=not args.quiet)[0]
        results = run_scenes(scenes, executor=executor, cache_dir=cache_dir,
                             progress=not args.quiet)
        seconds = time.perf_counter() - start
        path = write_report(results, out, seconds=seconds, mode="one surface", command=command,
                            executor=executor, cache_dir=cache_dir)
        _insert(path, _sections(results[0], first, request, out))
        (out / "check.toml").write_text(text, encoding="utf-8")
        return path, seconds, time.perf_counter() - start - seconds

    return run_pipeline(args, work)


def add_parser(sub) -> argparse.ArgumentParser:
    """The ``check`` sub-command's parser."""
    check = sub.add_parser(
        "check", help="which theory to trust on one measured scan, in physical units",
        description="Run every model and the boundary-element reference on one height file "
                    "(any format read_topography reads) and say, pressure by pressure, where "
                    "each theory holds on this surface, in physical units.")
    check.add_argument("scan", metavar="SCAN", help="height file (.di, .ibw, .x3p, .opd, .plu, "
                       ".sur, .gwy, .dat, .npy, text matrix, ...)")
    check.add_argument("--e-star", default=None, metavar="VALUE",
                       help="effective modulus E* with its unit, e.g. 115GPa (default: "
                            "pressures and stiffness in units of E*)")
    check.add_argument("--pressure", default=None, metavar="LOW:HIGH[:COUNT]",
                       help="nominal pressures, logarithmic, e.g. 1MPa:100MPa:12 (needs "
                            "--e-star) or 1e-5:1e-3 in units of E* (default: 12 pressures "
                            "from light to heavy contact, 5e-4 to 0.15 times E* |grad h|_rms)")
    check.add_argument("--short-cutoff", default=None, metavar="LENGTH",
                       help="low-pass the scan at this wavelength before every model and the "
                            "reference see it: a length (20nm) or pixels (8px); default none")
    check.add_argument("--fill", choices=("mean", "interpolate"), default=None,
                       help="fill missing points of the scan (default: refuse a scan with "
                            "missing points)")
    check.add_argument("--resample", choices=("finer", "coarser"), default=None,
                       help="pixels that are not square (an optical profilometer's): resample "
                            "one axis onto the finer or the coarser spacing (default: refuse)")
    check.add_argument("--physical-size", default=None, metavar="LENGTH",
                       help="the scan's width, e.g. '10 um', if the file does not state it")
    check.add_argument("--file-unit", default=None, metavar="UNIT",
                       help="the unit of the file's heights (nm, um, ...) if it does not state it")
    check.add_argument("--nominal-size", default=None, metavar="LENGTH",
                       help="side of your square nominal contact (a seal's width), e.g. 10mm: "
                            "adds the finite frame of that contact (the interface with that "
                            "square's bulk sink) and improved GW (default: the interface frame "
                            "alone)")
    check.add_argument("--tiles", type=int, default=1,
                       help="also answer on the scan cut into k x k tiles (4, 9, ...): how much "
                            "the answer varies across the scan (default 1: the whole scan only)")
    check.add_argument("--out", default=None,
                       help="output folder (default: ./check-<scan name>)")
    return check
