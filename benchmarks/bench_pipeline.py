"""The cost of the whole pipeline in one table: report, figures, load paths, periodic solver.

Rows (each measured in this run, so that a change can be compared with the previous code in one
session: ``--json`` saves a column, ``--compare`` prints it beside the new one):

* **report cold / warm** [s]: ``python -m validation report`` (the default, quick report: the
  scenes and settings of ``python -m validation report --help``, ``--jobs 2``) in a fresh
  process with an empty cache folder (so the FFTW wisdom is measured again too), then again
  with every result cached (the shorter of two runs). Wall time of the whole command, imports
  included, and its process time (every process of it, workers included), with the load
  average before and after the cold run: on a shared machine the process time is the number
  to compare, the wall time an upper bound.
* **seconds per figure** [s]: the figure step of the report (``validation.report.write.write_report``
  on the cached results of the default report's scenes, on a pool of two processes when it
  takes one) over the figures drawn; and its process time (all processes) per figure.
* **load paths**: the 16-point path the report runs per realization, at 512² (WM, D = 2.05,
  rms slope 0.1, seed 0; loads 1e-5 … 1e-2 E* L², tolerance 1e-8, area, load, separation,
  contacts, stiffness and conductance, with the half-grid error estimate), and the 12-point path
  of ``benchmarks/bench_bem.py --path 1024`` (D = 2.5, loads 1e-3 … 3e-2, tolerance 1e-9, area,
  load and separation). Time [s] (the minimum of
  ``--repeat`` runs in one process; the first run of the process, which plans the FFTs, is
  printed too), the FFT pairs executed (every transform pair of every grid: the operator's
  padded pairs, the preconditioner's, the nested coarse solves', the half grid's), their floor
  ``sum over transforms of count x one pair's time`` with one pair timed on the very same
  transform objects right after the path (minimum of repeats), and the path's time over that
  floor: the time not spent in FFTs, independent of how loaded the machine was (1.0 means
  nothing but FFTs).
* **periodic solver** at 1024² (the surface of benchmarks/bench_bem.py, loads 2e-3 / 1e-2 /
  3e-2, cold starts): solve time over fine iterations in units of one 1024² FFT pair, and the
  FFT work alone per iteration (counted pairs of every transform, in the same units).

FFT threads: ``--threads`` (default 1, what a report worker gets on two cores with two jobs).
With one thread, the ratios to the FFT floor and the periodic pairs per iteration are taken in
process time (path and pairs alike), which other jobs on a shared machine inflate far less
than wall time; wall times are printed too, as upper bounds, with the load average.

Usage::

    python benchmarks/bench_pipeline.py [--skip report,figures,paths,path1024,periodic]
        [--repeat N] [--json FILE] [--compare FILE] [--label NAME]

The default report's cold and warm time alone (about a minute on two quiet cores)::

    python benchmarks/bench_pipeline.py --skip figures,paths,periodic
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import pathlib
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
QUANTITIES = ("area", "load", "separation", "contacts", "stiffness", "conductance")


def load_average() -> float:
    return os.getloadavg()[0]


# -- FFT pair counting --------------------------------------------------------------------------


class FFTCounter:
    """Counts forward transforms (one per pair) of every FFT object while active."""

    def __init__(self) -> None:
        self.counts: dict[int, list] = {}  # id -> [object, count]

    @contextlib.contextmanager
    def active(self):
        import bem.elastic.fft

        originals = {}
        for cls in (bem.elastic.fft.RealFFT2, bem.elastic.fft.PaddedRealFFT2):
            original = cls.execute_forward
            originals[cls] = original

            def counted(fft, _original=original):
                entry = self.counts.setdefault(id(fft), [fft, 0])
                entry[1] += 1
                _original(fft)
            cls.execute_forward = counted
        try:
            yield self
        finally:
            for cls, original in originals.items():
                cls.execute_forward = original

    def reset(self) -> None:
        self.counts.clear()

    def groups(self) -> dict[tuple, list]:
        """(class, shape, threads) -> [a representative object, total pairs]."""
        out: dict[tuple, list] = {}
        for fft, count in self.counts.values():
            key = (type(fft).__name__, tuple(fft.shape), fft.threads)
            entry = out.setdefault(key, [fft, 0])
            entry[1] += count
        return out


def pair_seconds(fft, budget: float = 0.3) -> float:
    """The shortest time of one forward + inverse pair of an FFT object (its own buffers):
    process time with one FFT thread (what the machine's other jobs do not inflate), else wall
    time."""
    clock = time.process_time if fft.threads == 1 else time.perf_counter
    times = []
    spent = 0.0
    while len(times) < 3 or (spent < budget and len(times) < 50):
        start = clock()
        fft.execute_forward()
        fft.execute_inverse()
        elapsed = clock() - start
        times.append(elapsed)
        spent += elapsed
    return min(times)


def fft_floor(counter: FFTCounter) -> tuple[int, float, dict]:
    """Total pairs, their floor [s] and the pairs and one-pair time of each transform."""
    pairs, floor, detail = 0, 0.0, {}
    for key, (fft, count) in counter.groups().items():
        one = pair_seconds(fft)
        pairs += count
        floor += count * one
        detail[f"{key[0]}{key[1]}"] = (count, one)
    return pairs, floor, detail


# -- parts --------------------------------------------------------------------------------------


def children_cpu() -> float:
    """Process time [s] of the finished child processes (and theirs) so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_report(source: pathlib.Path, out: pathlib.Path, cache: pathlib.Path
               ) -> tuple[float, float]:
    """Wall and process time [s] of one report command (its workers included)."""
    env = dict(os.environ, PYTHONPATH=str(source))
    env.pop("ASPERITY_FFT_THREADS", None)  # the report's own choice
    start, start_cpu = time.perf_counter(), children_cpu()
    subprocess.run([sys.executable, "-m", "validation", "report", "--out", str(out), "--cache",
                    str(cache), "--quiet", "--jobs", "2"], check=True, env=env, cwd=source,
                   stdout=subprocess.DEVNULL)
    return time.perf_counter() - start, children_cpu() - start_cpu


def figure_step(cache: pathlib.Path, out: pathlib.Path) -> tuple[float, float, int]:
    """The figure step on cached results: (seconds, process seconds of every process, figures)."""
    import inspect
    from concurrent.futures import ProcessPoolExecutor

    from validation.cli import DEFAULT_SCENES, FULL_ONLY_SCENES, _load_scene
    from validation.report.write import write_report
    from validation import run_scenes

    # the scenes of the default report, whose results the cold run left in the cache
    scenes = [_load_scene(name).quick_version() for name in DEFAULT_SCENES
              if name not in FULL_ONLY_SCENES]
    results = run_scenes(scenes, executor=None, cache_dir=str(cache), progress=False)
    options = {}
    pool = None
    if "executor" in inspect.signature(write_report).parameters:
        pool = ProcessPoolExecutor(max_workers=2)
        options["executor"] = pool
    start, start_cpu = time.perf_counter(), time.process_time() + children_cpu()
    try:
        write_report(results, out, seconds=0.0, mode="quick", **options)
    finally:
        if pool is not None:
            pool.shutdown()
    seconds = time.perf_counter() - start
    cpu = time.process_time() + children_cpu() - start_cpu
    return seconds, cpu, len(list(out.glob("*.png")))


def report_part(rows: dict, source: pathlib.Path, figures: bool = True) -> None:
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        before = load_average()
        cold = run_report(source, folder / "report", folder / "cache")
        rows["load average (report cold: before, after)"] = f"{before:.1f}, {load_average():.1f}"
        warm = min(run_report(source, folder / "report", folder / "cache") for _ in range(2))
        if figures:
            seconds, cpu, count = figure_step(folder / "cache", folder / "figures")
    rows["report cold (s), process time (s)"] = f"{cold[0]:.1f}, {cold[1]:.1f}"
    rows["report warm (s), process time (s)"] = f"{warm[0]:.1f}, {warm[1]:.1f}"
    print(f"report: cold {cold[0]:.1f} s ({cold[1]:.1f} s process time), warm {warm[0]:.1f} s "
          f"({warm[1]:.1f} s process time); load average {before:.1f} before", flush=True)
    if figures:
        rows["figure step (s) / figures"] = f"{seconds:.1f} / {count}"
        rows["seconds per figure, process time per figure"] = (f"{seconds / count:.2f}, "
                                                               f"{cpu / count:.2f}")
        print(f"figures: {seconds:.1f} s ({cpu:.1f} s process time) for {count}", flush=True)


def report_path(n: int) -> dict:
    """The path the report runs per realization (paper-wm-d205, seed 0) on n x n."""
    from validation import wm_surface

    heights = wm_surface(n, D=2.05, rms_slope=0.1, L=1.0, gamma=1.5, M=10, n_max=8, seed=0)
    return dict(heights=heights, loads=np.geomspace(1e-5, 1e-2, 16), quantities=QUANTITIES,
                tol=1e-8, error_estimate=True)


def solver_path(n: int) -> dict:
    """The load path of benchmarks/bench_bem.py ``--path``: 12 loads, D = 2.5, tol 1e-9."""
    from validation import wm_surface

    heights = wm_surface(n, D=2.5, rms_slope=0.1, seed=9173, slope_grid=1024)
    return dict(heights=heights, loads=np.geomspace(1e-3, 3e-2, 12))


def path_part(rows: dict, name: str, problem: dict, repeat: int) -> None:
    import bem

    heights = problem.pop("heights")
    n = heights.shape[0]
    counter = FFTCounter()
    times, cpu = [], []
    load_before = load_average()
    with counter.active():
        for _ in range(repeat):
            counter.reset()
            start, start_cpu = time.perf_counter(), time.process_time()
            curve = bem.contact_curve(heights, 1.0 / n, **problem)
            times.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
        pairs, floor, detail = fft_floor(counter)
    seconds = min(times)
    # one FFT thread: the process time is what the path took without the machine's other jobs
    work = min(cpu) if int(os.environ["ASPERITY_FFT_THREADS"]) == 1 else seconds
    rows[f"{name}: load average"] = f"{load_before:.1f}"
    rows[f"{name}: time (s), first run"] = f"{seconds:.1f}, {times[0]:.1f}"
    rows[f"{name}: process time (s)"] = f"{min(cpu):.1f}"
    rows[f"{name}: fine iterations"] = str(int(curve.extras["iterations"].sum()))
    rows[f"{name}: FFT pairs"] = str(pairs)
    rows[f"{name}: FFT floor (s)"] = f"{floor:.1f}"
    rows[f"{name}: time / FFT floor"] = f"{work / floor:.2f}"
    print(f"{name}: {seconds:.1f} s (runs {', '.join(f'{t:.1f}' for t in times)}; process "
          f"{', '.join(f'{t:.1f}' for t in cpu)}), {pairs} FFT pairs, floor {floor:.1f} s, "
          f"ratio {work / floor:.2f}; converged "
          f"{bool(np.all(curve.extras['converged']))}; load {load_before:.1f}", flush=True)
    for key, (pair_count, one) in sorted(detail.items()):
        print(f"    {key}: {pair_count} pairs x {1e3 * one:.2f} ms", flush=True)


def periodic_part(rows: dict, n: int) -> None:
    import bem
    from validation import wm_surface

    heights = wm_surface(n, D=2.5, rms_slope=0.1, seed=9173, slope_grid=1024)
    operator = bem.HalfSpace((n, n), 1.0 / n, periodic=True)
    bem.solve_contact(heights, 1.0 / n, load=2e-3, operator=operator, periodic=True, tol=1e-3)
    counter = FFTCounter()
    per_iteration, fft_only = [], []
    load_before = load_average()
    with counter.active():
        for load in (2e-3, 1e-2, 3e-2):
            counter.reset()
            clock = time.process_time if operator.threads == 1 else time.perf_counter
            start = clock()
            solution = bem.solve_contact(heights, 1.0 / n, load=load, operator=operator,
                                         periodic=True)
            elapsed = clock() - start
            _, floor, _ = fft_floor(counter)
            one = pair_seconds(operator._fft)
            per_iteration.append(elapsed / solution.iterations / one)
            fft_only.append(floor / solution.iterations / one)
    rows[f"periodic {n}²: load average"] = f"{load_before:.1f}"
    rows[f"periodic {n}²: FFT pairs / iteration (time)"] = " / ".join(
        f"{v:.1f}" for v in per_iteration)
    rows[f"periodic {n}²: FFT pairs / iteration (FFTs only)"] = " / ".join(
        f"{v:.2f}" for v in fft_only)
    print(f"periodic {n}²: pairs per iteration {per_iteration}, FFTs alone {fft_only}",
          flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip", default="", help="comma-separated parts to skip: report, "
                        "figures (the figure step after the report), paths, path1024, "
                        "periodic")
    parser.add_argument("--repeat", type=int, default=2, help="runs of the 512² path")
    parser.add_argument("--threads", type=int, default=1, help="FFT threads of the solver")
    parser.add_argument("--json", default=None, help="save the column to this file")
    parser.add_argument("--compare", default=None, help="a saved column to print beside")
    parser.add_argument("--label", default="now")
    args = parser.parse_args()
    skip = set(filter(None, args.skip.split(",")))
    os.environ["ASPERITY_FFT_THREADS"] = str(args.threads)
    import bem
    import validation

    source = pathlib.Path(validation.__file__).resolve().parent.parent
    print(f"source {source}; FFT backend {'pyfftw' if bem.elastic.fft.have_pyfftw() else 'scipy'}, "
          f"threads {args.threads}, load average {load_average():.1f}", flush=True)
    rows: dict[str, str] = {}
    if "report" not in skip:
        report_part(rows, source, figures="figures" not in skip)
    if "paths" not in skip:
        path_part(rows, "16-point path 512²", report_path(512), args.repeat)
        if "path1024" not in skip:
            path_part(rows, "12-point path 1024²", solver_path(1024), 1)
    if "periodic" not in skip:
        periodic_part(rows, 1024)
    columns = {args.label: rows}
    if args.compare:
        columns = {**json.loads(pathlib.Path(args.compare).read_text()), **columns}
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(columns, indent=1))
    names = list(dict.fromkeys(k for column in columns.values() for k in column))
    print("\n| quantity | " + " | ".join(columns) + " |")
    print("|---|" + "---|" * len(columns))
    for name in names:
        print(f"| {name} | " + " | ".join(c.get(name, "–") for c in columns.values()) + " |")


if __name__ == "__main__":
    main()
