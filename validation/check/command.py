"""``python -m validation check SCAN``: which theory to trust on one measured scan.

A thin wrapper of the library call :func:`validation.check_scan`
(:mod:`validation.check.library`): the options become a
:class:`~validation.check.request.CheckRequest`, the request a scene, the scene runs as any
report does (the same cache, workers and report folder: ``report.md``, ``errors.csv``,
``verdicts.csv``, ...), and the report opens with what only one surface has: every theory
against the reference at the user's pressures in physical units (``physical.csv``,
:mod:`.physical`) and whether the reference is converged on the scan as sampled, with the
remedy when the contact area is not (:mod:`.resolution`). The scene is kept as ``check.toml``
in the folder: ``python -m validation report DIR/check.toml`` writes the same report.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import shlex
import sys
import time
import warnings

from validation.check.library import check_scenes, make_request, run_request
from validation.check.plausible import PlausibilityWarning
from validation.check.request import CheckRequest

__all__ = ["add_parser", "add_scan_options", "check_request", "run_check"]


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
    return make_request(path, e_star=args.e_star, pressures=args.pressure,
                        short_cutoff=args.short_cutoff, fill=args.fill, resample=args.resample,
                        physical_size=args.physical_size, file_unit=args.file_unit,
                        tiles=args.tiles, nominal_size=getattr(args, "nominal_size", None),
                        device=getattr(args, "device", None) or "cpu")


#: The reader's keywords a message may recommend, and the check's option for each.
_OPTIONS = {"file_unit": "--file-unit", "physical_size": "--physical-size", "fill": "--fill",
            "resample": "--resample", "short_cutoff": "--short-cutoff"}


def _options_hint(message: str) -> str:
    """Where a reader's message recommends its keywords, the check's options that set them."""
    named = [option for keyword, option in _OPTIONS.items() if re.search(rf"\b{keyword}\b", message)]
    return f" (on the command line: {', '.join(named)})" if named else ""


def run_check(args: argparse.Namespace, run_pipeline, prediction=None) -> int:
    """The ``check`` command (see the module docstring); ``run_pipeline`` is the command
    line's way of running a report (:func:`validation.cli.run_pipeline`). ``prediction``:
    ``(before, after)``, ``before(request, quiet)`` called before the solve (it may print, and
    returns what ``after(that, result, folder, quiet)`` gets once the report is written; the
    command line passes :func:`validation.atlas.command.prediction_before` and
    :func:`validation.atlas.command.prediction_after`), or None: no prediction."""
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PlausibilityWarning)
            request = check_request(args)
        for warning in caught:
            if issubclass(warning.category, PlausibilityWarning):
                print(f"warning: {warning.message}{_options_hint(str(warning.message))}",
                      file=sys.stderr)
            else:
                warnings.warn_explicit(warning.message, warning.category, warning.filename,
                                       warning.lineno)
        args.out = args.out or f"check-{request.path.stem}"
        if args.jobs == 0:
            args.jobs = 1 if request.tiles == 1 else (os.cpu_count() or 1)
        scenes, text = check_scenes(request)
    except (ValueError, TypeError, ImportError) as error:
        print(f"error: {error}{_options_hint(str(error))}", file=sys.stderr)
        return 2
    command = "python -m validation " + shlex.join(args.argv)
    before, after = prediction or (None, None)
    predicted = before(request, args.quiet) if before is not None else None

    def work(executor, cache_dir):
        result = run_request(request, scenes, text, executor=executor, cache_dir=cache_dir,
                             progress=not args.quiet)
        start = time.perf_counter()
        path = result.write_report(args.out, command=command, executor=executor,
                                   cache_dir=cache_dir)
        if predicted is not None:
            after(predicted, result, args.out, args.quiet)
        return path, result.seconds, time.perf_counter() - start

    return run_pipeline(args, work)


def add_parser(sub) -> argparse.ArgumentParser:
    """The ``check`` sub-command's parser."""
    check = sub.add_parser(
        "check", help="which theory to trust on one measured scan, in physical units",
        description="Run every model and the boundary-element reference on one height file "
                    "(any format read_topography reads) and say, pressure by pressure, where "
                    "each theory holds on this surface, in physical units.")
    add_scan_options(check)
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


def add_scan_options(check: argparse.ArgumentParser) -> None:
    """The options that say how to read a scan and which pressures to put on it (the check's,
    shared by ``predict``)."""
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
    check.add_argument("--physical-size", default=None, metavar="SIZE",
                       help="the scan's size if the file does not state it: its width for a "
                            "square map ('10um'), or width and height ('10um x 7.8um', "
                            "'10um,7.8um' or two values: --physical-size 10um 7.8um)")
    check.add_argument("--file-unit", default=None, metavar="UNIT",
                       help="the unit of the file's heights (nm, um, ...) if it does not state it")
