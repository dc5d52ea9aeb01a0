"""``python -m validation predict SCAN``: each theory's error on a scan predicted by the error
atlas, no boundary-element solve (:func:`validation.predict_errors`); and ``python -m
validation atlas``: the atlas computed (cached, resumable) and its error model fitted."""

from __future__ import annotations

import argparse
import pathlib
import sys
import time
import warnings

from validation.check.command import add_scan_options
from validation.check.plausible import PlausibilityWarning

__all__ = ["add_parsers", "atlas_section", "prediction_after", "prediction_before", "run_atlas",
           "run_predict"]


def run_predict(args: argparse.Namespace) -> int:
    """The ``predict`` command: ``predicted.csv`` and ``report.md`` in ``--out``."""
    from validation.atlas.predict import predict_errors

    path = pathlib.Path(args.scan)
    try:
        if not path.is_file():
            raise ValueError(f"SCAN {args.scan!r} names no file")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PlausibilityWarning)
            prediction = predict_errors(path, e_star=args.e_star, pressures=args.pressure,
                                        short_cutoff=args.short_cutoff, fill=args.fill,
                                        resample=args.resample,
                                        physical_size=args.physical_size,
                                        file_unit=args.file_unit, model_file=args.model)
        for warning in caught:
            print(f"warning: {warning.message}", file=sys.stderr)
    except (ValueError, TypeError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    out = args.out or f"predict-{path.stem}"
    report = prediction.write(out)
    for line in prediction.outside:
        print(f"outside the atlas: {line}", file=sys.stderr)
    print(f"prediction written to {report} ({prediction.seconds:.2g} s, no solve)")
    return 0


def atlas_section() -> tuple[list[str], list]:
    """The report's section on the error atlas and its figure's job
    (:func:`validation.atlas.report.report_section`); none, said on stderr, where the stored
    error model cannot be read (a report never fails for it)."""
    from validation.atlas.report import report_section

    try:
        return report_section()
    except (OSError, ValueError, KeyError, TypeError) as error:
        print(f"note: no error atlas section ({type(error).__name__}: {error})", file=sys.stderr)
        return [], []


def prediction_before(request, quiet: bool):
    """The check's prediction before its solve (:func:`validation.check.command.run_check`):
    the atlas' prediction of the scan, printed unless ``quiet``; None, said on stderr, where it
    cannot be made (a check never fails for its prediction)."""
    from validation.atlas.predict import predict_request
    from validation.atlas.report import terminal_lines

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)   # the check says them once
            prediction = predict_request(request)
    except Exception as error:   # noqa: BLE001 -- the check goes on without its prediction
        print(f"note: no prediction before the solve ({type(error).__name__}: {error})",
              file=sys.stderr)
        return None
    if not quiet:
        print("\n".join(terminal_lines(prediction)), flush=True)
    return prediction


def prediction_after(prediction, result, folder, quiet: bool) -> None:
    """``predicted.csv`` and ``prediction.md`` beside the check's report, with the prediction
    set against the solve (:func:`validation.atlas.predict.against_check`)."""
    from validation.atlas.predict import against_check

    try:
        sentence = against_check(prediction, result).sentence()
        prediction.write(folder, report="prediction.md", extra=("", sentence))
    except Exception as error:   # noqa: BLE001 -- the check's report is written: keep it
        print(f"note: the prediction was not set against the solve ({type(error).__name__}: "
              f"{error})", file=sys.stderr)
        return
    if not quiet:
        print(sentence)


def run_atlas(args: argparse.Namespace, executor_of, interrupted) -> int:
    """The ``atlas`` command: every design point run (cached), the error model fitted and
    written; ``executor_of(args)`` and ``interrupted(cache_dir)`` are the command line's
    (:mod:`validation.cli`)."""
    from validation.atlas.build import build_atlas
    from validation.atlas.fit import fit_atlas
    from validation.atlas.model import MODEL_FILE
    from validation.run.cache import check_directory, default_cache_dir

    cache_dir = None if args.no_cache else str(args.cache or default_cache_dir())
    try:
        check_directory(args.out, "--out")
        if cache_dir is not None:
            check_directory(cache_dir, "--cache")
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    executor, close, abort = executor_of(args)
    try:
        build_atlas(args.out, cache_dir=cache_dir, executor=executor, progress=not args.quiet)
    except KeyboardInterrupt:
        abort()
        return interrupted(cache_dir)
    close()
    model = fit_atlas(args.out, out=args.model or MODEL_FILE)
    summary = model["validation"]["all"]
    print(f"atlas in {args.out} ({time.perf_counter() - start:.0f} s); error model written to "
          f"{args.model or MODEL_FILE}: left-out coverage of the 90 % interval "
          f"{summary['coverage']:.2f}, verdict agreement {summary['agreement']:.2f}")
    return 0


def add_parsers(sub) -> tuple[argparse.ArgumentParser, argparse.ArgumentParser]:
    """The ``predict`` and ``atlas`` sub-commands' parsers (``atlas``'s handler is the
    command line's: it runs scenes on its workers)."""
    predict = sub.add_parser(
        "predict", help="each theory's error on a scan predicted from its descriptors, no solve",
        description="Predict, from the scan's descriptors (Hurst exponent, Nayak's alpha, "
                    "skewness) and the error atlas, each theory's error at the check's load "
                    "points with a 90 % prediction interval, in seconds and without a "
                    "boundary-element solve. Writes predicted.csv and report.md.")
    add_scan_options(predict)
    predict.add_argument("--model", default=None, metavar="FILE",
                         help="an error model file (default: the package's error_model.json)")
    predict.add_argument("--out", default=None,
                         help="output folder (default: ./predict-<scan name>)")
    predict.set_defaults(handler=run_predict)
    atlas = sub.add_parser(
        "atlas", help="compute the error atlas (cached, resumable) and fit its error model",
        description="Run every design point of the error atlas (periodic self-affine, "
                    "plateau-honed and WM surfaces; validation.atlas.design) as a scene, write "
                    "atlas.csv and atlas.json into --out, fit the error model and write it "
                    "(default: the package's error_model.json). Interrupted, the same command "
                    "resumes from the cache.")
    atlas.add_argument("--out", default="atlas-out", help="output folder (default: ./atlas-out)")
    atlas.add_argument("--model", default=None, metavar="FILE",
                       help="where to write the error model (default: the package's "
                            "error_model.json)")
    return predict, atlas
