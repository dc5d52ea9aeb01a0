"""Command line: ``python -m validation {report,check,predict,atlas,list,show,bench,stress}``.

``report`` with no scene runs the default scenes in quick mode, a preview of the published
report: 8 realizations of each paper scene on 256 x 256 grids with 12 loads, and 4 per D of the
validity map on 128 x 128 grids with 12 loads (up to 8 where cells stay undecided). Quick mode
leaves to ``--full`` the self-affine map, the size scene ``sealing-size``, the paper scenes'
leakage and the finer reference: no load point is solved again on a finer grid where the
reference band holds a cell, so the cells it holds stay undecided; the numbers to cite are the
full report's. ``--full`` and ``--publish`` run the default scenes as written (25 realizations
of each paper scene on 512 x 512 grids with 16 loads, the leakage included, 10 per D of the
validity map on 256 x 256 grids with 16 loads, 8 per H of the self-affine map on 256 x 256
grids with 12 loads, and 8 realizations of each window of ``sealing-size`` on 128 x 128 grids
with 12 loads; where cells stay undecided, the validity and self-affine maps add realizations
up to their budgets, and the reference is solved again on finer grids up to each scene's
limit, 1024 x 1024 for the paper scenes). What each run costs, measured with the command that
measures it: the Benchmarks page of the documentation (docs/guide/benchmarks.md).
Ctrl-C stops a report at once (exit status 130); what was finished stays in the cache, and the
same command resumes.
"""

from __future__ import annotations

import argparse
import functools
import os
import pathlib
import re
import shlex
import signal
import sys
import threading
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

from bem.elastic.device import DEVICES, array_module
from bem.elastic.wisdom import WISDOM_VARIABLE
from validation.run.cache import check_directory, default_cache_dir
from validation.scenes.reader import builtin_scenes, load_scene
from validation.scenes.scene import SceneError, SceneWarning, scene_warnings

#: Scenes of the default report, in report order.
DEFAULT_SCENES = ("paper-theory", "paper-wm-d205", "paper-wm-d295", "validity-map", "self-affine",
                  "sealing-size")
#: Default scenes the quick default report leaves out: the size scene's leakage (Reynolds solves
#: on windows up to 4 x 4 times the paper's) alone would make it half again as long, and the
#: self-affine map adds three more surface families' worth of BEM paths; the full and published
#: reports run them.
FULL_ONLY_SCENES = ("self-affine", "sealing-size")


#: Exit status of a run stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
INTERRUPTED = 130


def _worker_init(threads: int) -> None:
    # Each worker process gets its share of the cores for its FFTs (read at every operator
    # build, so setting it here, after the worker imported numpy, still takes effect).
    os.environ["ASPERITY_FFT_THREADS"] = str(threads)
    # Ctrl-C in a terminal reaches the whole process group: the workers leave it to the main
    # process, which ends them (no traceback per worker, no worker dying between tasks).
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _end_pool(pool: ProcessPoolExecutor) -> None:
    """Stop a process pool now: queued realizations cancelled, running workers terminated
    (a realization cut short leaves no cache entry: entries are renamed into place whole)."""
    workers = list((getattr(pool, "_processes", None) or {}).values())  # shutdown forgets them
    pool.shutdown(wait=False, cancel_futures=True)
    for process in workers:
        if process.is_alive():
            process.terminate()
    for process in workers:
        process.join(timeout=5)


def _executor(args: argparse.Namespace):
    """The executor of ``args`` and two ways to end it: ``close()`` after a finished run and
    ``abort()`` after an interruption (returns at once, nothing left running here)."""
    if args.scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise SystemExit("--scheduler needs dask.distributed: "
                             "pip install 'asperity-validation[distributed]'") from None
        client = Client(args.scheduler)
        # the runner cancels the submitted futures (on the cluster too) before the abort
        return client.get_executor(), client.close, client.close
    if args.jobs <= 1:
        return None, lambda: None, lambda: None
    cores = os.cpu_count() or 1
    pool = ProcessPoolExecutor(max_workers=args.jobs, initializer=_worker_init,
                               initargs=(max(1, cores // args.jobs),))
    return pool, pool.shutdown, lambda: _end_pool(pool)


def _interrupt_once(signum, frame) -> None:
    """SIGINT handler: the first Ctrl-C interrupts, later ones are ignored while the run shuts
    down (a second Ctrl-C must not interrupt the shutdown and leave workers behind)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    raise KeyboardInterrupt


def _interrupted(cache_dir: str | None) -> int:
    kept = ("nothing was kept (--no-cache)" if cache_dir is None else
            f"finished realizations are kept in the cache {cache_dir}: the same command "
            "resumes from there")
    print(f"\ninterrupted: {kept}", file=sys.stderr)
    return INTERRUPTED


def _load_scene(name: str):
    """:func:`load_scene` with unreadable files (binary, not UTF-8, no permission) reported as
    a :class:`SceneError`."""
    try:
        return load_scene(name)
    except UnicodeDecodeError:
        raise SceneError(f"{name}: not a text scene file (it is not UTF-8 encoded)") from None
    except (IsADirectoryError, PermissionError) as error:
        raise SceneError(f"{name}: cannot read the scene file: {error.strerror}") from None


def _report(args: argparse.Namespace) -> int:
    quick = args.quick or (not args.full and not args.scenes and not args.publish)
    names = args.scenes or [name for name in DEFAULT_SCENES
                            if not (quick and name in FULL_ONLY_SCENES)]
    with warnings.catch_warnings():
        # said once below, for the scenes as they will run (quick mode changes them)
        warnings.simplefilter("ignore", SceneWarning)
        scenes = [_load_scene(name) for name in names]
    repeated = sorted({s.name for s in scenes if [t.name for t in scenes].count(s.name) > 1})
    if repeated:
        raise SceneError(f"scene names must be unique in one report (they name its files); "
                         f"repeated: {', '.join(repeated)}")
    if args.publish:
        args.out, args.full = args.publish, not args.quick
    if quick:
        scenes = [scene.quick_version() for scene in scenes]
    if getattr(args, "device", None):
        scenes = [replace(scene, bem=replace(scene.bem, device=args.device)) for scene in scenes]
    for scene in scenes:   # a GPU asked for where there is none: said before any computing
        if scene.bem.device != "cpu":
            try:
                array_module(scene.bem.device, "--device" if args.device else "[bem] device")
            except ValueError as error:
                raise SceneError(str(error) if args.device else f"scene {scene.name!r}: {error}"
                                 ) from None
    mode = "quick" if quick else ("full" if args.full or not args.scenes else "as written")
    for message in (m for scene in scenes for m in scene_warnings(scene)):
        print(f"warning: {message}", file=sys.stderr)
    command = "python -m validation " + shlex.join(args.argv)
    scene_file_text = (pathlib.Path(names[0]).read_text(encoding="utf-8")
                       if len(names) == 1 and pathlib.Path(names[0]).is_file() else "")

    def work(executor, cache_dir: str | None) -> tuple:
        from validation.atlas.command import atlas_section
        from validation.check.library import is_check_scene, request_of_scene, run_request
        from validation.report.write import write_report
        from validation.judge.decide import run_scenes

        start = time.perf_counter()
        if len(scenes) == 1 and is_check_scene(scenes[0]) and not quick:
            # one scan as one surface (a check's check.toml): the check's report
            result = run_request(request_of_scene(scenes[0]), scenes, scene_file_text,
                                 executor=executor, cache_dir=cache_dir, progress=not args.quiet)
            path = result.write_report(args.out, command=command, executor=executor,
                                       cache_dir=cache_dir)
            return path, result.seconds, time.perf_counter() - start - result.seconds
        sections, jobs = atlas_section()
        results = run_scenes(scenes, executor=executor, cache_dir=cache_dir,
                             progress=not args.quiet)
        seconds = time.perf_counter() - start
        # the figures are drawn on the same workers (or read from the cache)
        path = write_report(results, args.out, seconds=seconds, mode=mode, command=command,
                            executor=executor, cache_dir=cache_dir, sections=sections,
                            figure_jobs=jobs)
        return path, seconds, time.perf_counter() - start - seconds

    return run_pipeline(args, work, "--publish" if args.publish else "--out")


def run_pipeline(args: argparse.Namespace, work, out_option: str = "--out") -> int:
    """Run ``work(executor, cache_dir) -> (report path, computing s, writing s)`` the way every
    report command does: the output and cache folders checked before any computing (exit status
    2 with the reason), FFTW wisdom kept with the cache, realizations on ``--jobs`` worker
    processes or a ``--scheduler`` cluster, and Ctrl-C ending the workers at once (status 130,
    finished realizations kept in the cache)."""
    from validation.report.write import previous_report

    cache_dir = None if args.no_cache else str(args.cache or default_cache_dir())
    # Fail before any computing: an unwritable report or cache folder is found now, not after.
    try:
        try:
            previous_report(args.out)  # replaced when the new report is written, not before
        except ValueError as error:
            raise ValueError(f"{out_option} {error}") from None
        check_directory(args.out, out_option)
        if cache_dir is not None:
            check_directory(cache_dir, "--cache")
        if args.jobs < 1:
            raise ValueError(f"--jobs must be >= 1, got {args.jobs}")
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    # FFTW wisdom is kept with the cache (bem.elastic.wisdom), for this process and the workers
    wisdom = os.environ.get(WISDOM_VARIABLE)
    os.environ[WISDOM_VARIABLE] = cache_dir or ""
    try:
        executor, close, abort = _executor(args)
        try:
            path, seconds, drawn = work(executor, cache_dir)
        except KeyboardInterrupt:
            abort()
            return _interrupted(cache_dir)
        except BaseException:
            abort()
            raise
        close()
    finally:
        if wisdom is None:
            os.environ.pop(WISDOM_VARIABLE, None)
        else:
            os.environ[WISDOM_VARIABLE] = wisdom
    print(f"report written to {path} ({seconds:.1f} s computing, {drawn:.1f} s writing)")
    return 0


def _list(args: argparse.Namespace) -> int:
    for name in builtin_scenes():
        scene = load_scene(name)
        marker = ("+" if name in FULL_ONLY_SCENES else "*") if name in DEFAULT_SCENES else " "
        print(f"{marker} {name:20s} {scene.title}")
    print("(* in the default report; + in the full and published reports only)")
    return 0


def _show(args: argparse.Namespace) -> int:
    from importlib import resources

    if args.scene in builtin_scenes():
        print((resources.files("validation") / "scenes" / f"{args.scene}.toml").read_text(encoding="utf-8"))
    scene = _load_scene(args.scene)
    print(f"# parsed: {scene}")
    return 0


def _bench(args: argparse.Namespace) -> int:
    from validation.campaigns.bench import run_bench

    run_bench(args.out, quick=args.quick)
    return 0


def _stress(args: argparse.Namespace) -> int:
    from validation.campaigns.stress import run_stress

    records = run_stress(args.out, quick=args.quick)
    failures = [r for r in records if r.status == "FAIL"]
    print(f"{len(records)} cases, {len(failures)} failures; table in {args.out}/stress.md")
    return 1 if failures else 0


def _run_options(parser: argparse.ArgumentParser, jobs: int | None = None,
                 jobs_default: str = "CPU count") -> None:
    """Options of every command that runs scenes: workers, cache, cluster, progress."""
    parser.add_argument("--jobs", type=int, default=(os.cpu_count() or 1) if jobs is None else jobs,
                        help=f"worker processes for realizations (default: {jobs_default}; "
                             f"1 = in-process)")
    cache = parser.add_mutually_exclusive_group()
    cache.add_argument("--cache", default=None, help=f"cache folder (default: {default_cache_dir()})")
    cache.add_argument("--no-cache", action="store_true", help="compute everything, store nothing")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="dask.distributed scheduler address; realizations run on that cluster")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar (warnings and errors are still printed)")
    parser.add_argument("--device", choices=DEVICES, default=None,
                        help="where the reference's contact problems are solved: cpu, or gpu "
                             "(CuPy and a CUDA device; the gpu extra); default: each scene's "
                             "[bem] device (cpu)")


def build_parser() -> argparse.ArgumentParser:
    """The command line's parser (its help is the program's documentation of its options)."""
    # the console script (pyproject's [project.scripts]) or python -m validation
    script = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    prog = "asperity-validation" if script == "asperity-validation" else "python -m validation"
    parser = argparse.ArgumentParser(prog=prog, description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    report = sub.add_parser("report", help="run scenes and write the validity report",
                            description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    report.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="built-in scene names or scene files (default: the default scenes, quick)")
    report.add_argument("--out", default="report",
                        help="output folder (default: ./report): new, empty, or holding an "
                             "earlier report, whose Markdown, figures and tables are replaced")
    report.add_argument("--full", action="store_true",
                        help="run the default scenes as written (25 realizations of each paper "
                             "scene, 10 per D of the validity map, 8 per H of the self-affine "
                             "map, 8 per window of the size scene) instead of quick, with what "
                             "quick mode leaves out: the self-affine and size scenes, the "
                             "leakage and the finer reference where its band decides")
    report.add_argument("--quick", action="store_true", help="quick mode also for named scenes")
    _run_options(report)
    report.add_argument("--publish", nargs="?", const="docs/results", default=None, metavar="DIR",
                        help="regenerate the published report in DIR (default docs/results): "
                             "full mode unless --quick, the previous report replaced")
    report.set_defaults(handler=_report)
    from validation.atlas.command import prediction_after, prediction_before
    from validation.check.command import add_parser, run_check

    check = add_parser(sub)
    # one surface is one task: in this process, its FFTs on every core (tiles: one per worker)
    _run_options(check, jobs=0, jobs_default="1, or the CPU count with --tiles")
    check.set_defaults(handler=functools.partial(
        run_check, run_pipeline=run_pipeline,
        prediction=(prediction_before, prediction_after)))
    from validation.atlas.command import add_parsers, run_atlas

    _, atlas = add_parsers(sub)
    _run_options(atlas)
    atlas.set_defaults(handler=functools.partial(run_atlas, executor_of=_executor,
                                                 interrupted=_interrupted))
    listing = sub.add_parser("list", help="list the built-in scenes")
    listing.set_defaults(handler=_list)
    show = sub.add_parser("show", help="print a scene file and its parsed form")
    show.add_argument("scene", metavar="SCENE", help="a built-in scene name or a scene file")
    show.set_defaults(handler=_show)
    bench = sub.add_parser("bench", help="run time against error of every method")
    bench.add_argument("--quick", action="store_true", help="tiny sizes (seconds)")
    bench.add_argument("--out", default="bench-out", help="output folder (default: ./bench-out)")
    bench.set_defaults(handler=_bench)
    stress = sub.add_parser("stress", help="numerical stress campaign")
    stress.add_argument("--quick", action="store_true", help="small sizes (seconds)")
    stress.add_argument("--out", default="stress-out", help="output folder (default: ./stress-out)")
    stress.set_defaults(handler=_stress)
    return parser


#: Options whose value may be written with a leading minus (a wrong value the option's own check
#: then names, rather than argparse's "expected one argument").
VALUE_OPTIONS = ("--e-star", "--pressure", "--short-cutoff", "--physical-size", "--nominal-size",
                 "--file-unit", "--tiles", "--jobs")


#: A length as a value of its own (``7.8um``, ``7.8 um``): the second of two sizes.
_LENGTH_VALUE = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*[A-Za-z\u00b5\u03bc\u00c5\u212b]+\s*")


def _joined_values(argv: list[str]) -> list[str]:
    """``--option -value`` as ``--option=-value`` for :data:`VALUE_OPTIONS`, and the two values
    of ``--physical-size WIDTH HEIGHT`` as one (``WIDTH x HEIGHT``; a second value is a length
    with its unit, never a file's name)."""
    out, k = [], 0
    while k < len(argv):
        if argv[k] == "--physical-size" and k + 2 < len(argv) \
                and _LENGTH_VALUE.fullmatch(argv[k + 2]) and not os.path.exists(argv[k + 2]):
            out.append(f"--physical-size={argv[k + 1]} x {argv[k + 2]}")
            k += 3
            continue
        if argv[k] in VALUE_OPTIONS and k + 1 < len(argv) and argv[k + 1].startswith("-") \
                and not argv[k + 1].startswith("--"):
            out.append(f"{argv[k]}={argv[k + 1]}")
            k += 2
            continue
        out.append(argv[k])
        k += 1
    return out


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(_joined_values(argv))
    args.argv = argv
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, _interrupt_once) if main_thread else None
    try:
        status = args.handler(args)
    except SceneError as error:
        print(f"error: {error}", file=sys.stderr)
        status = 2
    except KeyboardInterrupt:
        print("\ninterrupted", file=sys.stderr)
        status = INTERRUPTED
    # After an interruption SIGINT stays ignored: a further Ctrl-C while the interpreter
    # exits would otherwise end it with a traceback instead of the status.
    if main_thread and status != INTERRUPTED:
        signal.signal(signal.SIGINT, previous)
    return status
