"""Benchmark: wall time of every method for a full load path against its error.

``python -m validation bench [--quick] [--out DIR]``

On the WM surfaces of the paper (D = 2.05 and 2.95, gamma 1.5, M 10, n_max 8, rms slope 0.1,
seed 0, L = 1; the amplitude fixed on the reference grid so that every grid samples one
continuous surface) every method computes the same load path (Load = W/(E* L^2) from 1e-4 to 1e-2)
with area, separation and conductance. The reference is the boundary-element solution on the
finest grid (1024 x 1024, tolerance 1e-10; 64 x 64 in quick mode). Errors, at equal load, are
the largest over the path of

* area: ``|A / A_ref - 1|``; conductance: ``|C / C_ref - 1|``;
* separation: ``|d - d_ref| / sigma_ref`` with sigma_ref the std of the summit heights found on
  the reference grid.

Times are medians of repeated runs (three runs when one run takes under ten seconds, else one;
the ``runs`` column says which), each including what the method needs from the height map:
summit detection for the asperity models, the operator build for the BEM. The BEM rows at the
reference grid measure only the tolerance error; they are listed but kept off the Pareto front
and the figure. The observed order of mesh convergence of the
BEM is ``p = log2(e_N / e_2N)`` for successive grids at the tightest tolerance.

Memory: the peak of numpy allocations (``tracemalloc``) of one BEM solve per grid and of the
discrete model with 10^3..10^5 asperities, reported per unknown, so that linear scaling shows as
a constant number of bytes per unknown.
"""

from __future__ import annotations

import math
import pathlib
import platform
import statistics
import time
import tracemalloc
from dataclasses import dataclass

import numpy as np

from validation.common import models as _models

__all__ = ["BenchRow", "machine_description", "run_bench", "pareto_front", "observed_order"]

#: The exact reference, swept over grids and tolerances (the registry's reference model).
REFERENCE = _models.reference_names()[0]
#: Every method measured: the registry's default models, the reference last.
METHODS = tuple(m for m in _models.default_names() if m != REFERENCE) + (REFERENCE,)
QUANTITIES = ("area", "separation", "conductance")


@dataclass(frozen=True)
class BenchRow:
    """One method at one setting on one surface: time and errors against the reference."""

    D: float
    method: str
    setting: str
    n: int
    tol: float | None
    seconds: float
    runs: int
    area: float
    separation: float
    conductance: float
    converged: bool = True


@dataclass(frozen=True)
class BenchConfig:
    reference_n: int
    reference_tol: float
    bem_grids: tuple[int, ...]
    bem_tols: tuple[float, ...]
    asperity_grids: tuple[int, ...]
    load_count: int
    memory_grids: tuple[int, ...]
    memory_asperities: tuple[int, ...]


FULL = BenchConfig(reference_n=1024, reference_tol=1e-10, bem_grids=(64, 128, 256, 512, 1024),
                   bem_tols=(1e-4, 1e-6, 1e-9), asperity_grids=(256, 512, 1024), load_count=8,
                   memory_grids=(256, 512, 1024), memory_asperities=(1_000, 10_000, 100_000))
QUICK = BenchConfig(reference_n=64, reference_tol=1e-10, bem_grids=(16, 32, 64), bem_tols=(1e-4, 1e-9),
                    asperity_grids=(32, 64), load_count=4, memory_grids=(32, 64),
                    memory_asperities=(100, 1_000))


def _timed(function, *, repeat_below: float = 10.0, repeats: int = 3):
    """Run ``function``; repeat when cheap. Returns (result, median seconds, runs)."""
    start = time.perf_counter()
    result = function()
    times = [time.perf_counter() - start]
    if times[0] < repeat_below:
        for _ in range(repeats - 1):
            start = time.perf_counter()
            function()
            times.append(time.perf_counter() - start)
    return result, statistics.median(times), len(times)


def _errors(curve, reference, sigma: float, method: str = REFERENCE) -> dict[str, float]:
    # a model compared with another field of the reference (Persson's mean gap) says so in the
    # registry
    target = _models.entry(method).reference_fields.get("separation", "separation")
    reference_separation = (reference.separation if target == "separation"
                            else reference.extras[target])
    with np.errstate(divide="ignore", invalid="ignore"):
        area = np.max(np.abs(curve.area / reference.area - 1.0))
        separation = np.max(np.abs(curve.separation - reference_separation)) / sigma
        conductance = np.max(np.abs(curve.conductance / reference.conductance - 1.0))
    return {"area": float(area), "separation": float(separation), "conductance": float(conductance)}


def pareto_front(times: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Boolean mask of the points no other point beats in both time and error (lower is better)."""
    times, errors = np.asarray(times, float), np.asarray(errors, float)
    mask = np.zeros(times.size, dtype=bool)
    for i in range(times.size):
        if not (np.isfinite(times[i]) and np.isfinite(errors[i])):
            continue
        dominated = (times <= times[i]) & (errors <= errors[i]) & ((times < times[i]) | (errors < errors[i]))
        mask[i] = not np.any(dominated)
    return mask


def observed_order(grids, errors) -> list[float]:
    """``log2(e_N / e_2N)`` between successive grids (NaN where an error is zero or missing)."""
    orders = []
    for (n1, e1), (n2, e2) in zip(zip(grids, errors), zip(grids[1:], errors[1:])):
        if e1 > 0 and e2 > 0 and np.isfinite(e1) and np.isfinite(e2):
            orders.append(math.log(e1 / e2) / math.log(n2 / n1))
        else:
            orders.append(float("nan"))
    return orders


def _bench_surface(D: float, config: BenchConfig, log) -> list[BenchRow]:
    import asperity
    import bem
    from validation.surfaces.wm import wm_surface

    loads = np.logspace(-4, -2, config.load_count)  # E* = L = 1: W = Load
    wanted = ("area", "load", "separation", "conductance")

    def surface(n):
        # one continuous surface on every grid: the amplitude is fixed on the reference grid
        return wm_surface(n, D=D, rms_slope=0.1, seed=0, slope_grid=config.reference_n)

    n_ref = config.reference_n
    start = time.perf_counter()
    heights = surface(n_ref)
    reference = bem.contact_curve(heights, 1.0 / n_ref, loads=loads, tol=config.reference_tol,
                                  quantities=wanted)
    sigma = float(np.std(asperity.find_summits(heights, 1.0 / n_ref).height))
    log(f"D={D}: reference BEM N={n_ref} tol={config.reference_tol:g} in "
        f"{time.perf_counter() - start:.1f} s")
    rows = []
    for n in config.bem_grids:
        # On the reference grid only the looser tolerances say something (the error is then
        # the tolerance error alone).
        for tol in (config.bem_tols if n < n_ref else [t for t in config.bem_tols if t > 1e-8]):
            h = surface(n)
            curve, seconds, runs = _timed(lambda: bem.contact_curve(
                h, 1.0 / n, loads=loads, tol=tol, quantities=wanted))
            errors = _errors(curve, reference, sigma)
            rows.append(BenchRow(D, REFERENCE, f"N={n}, tol={tol:g}", n, tol, seconds, runs,
                                 converged=bool(np.all(curve.extras["converged"])), **errors))
            log(f"  bem N={n} tol={tol:g}: {seconds:.3g} s, {errors}")
    for n in config.asperity_grids:
        h = surface(n)
        for method in METHODS[:-1]:
            def run(method=method):
                summits = asperity.find_summits(h, 1.0 / n)
                inputs = _models.ModelInputs(spacing=1.0 / n, nominal_area=1.0, heights=h,
                                             summits=summits, m=1.0)
                return _models.build(method, inputs).at_load(loads, quantities=wanted)
            import warnings
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # validity warnings are part of what is measured
                curve, seconds, runs = _timed(run)
            errors = _errors(curve, reference, sigma, method)
            converged = bool(np.all(curve.extras["converged"]))
            source = "summits" if _models.entry(method).needs_summits else "heights"
            rows.append(BenchRow(D, method, f"{source} of N={n}", n, None, seconds, runs,
                                 converged=converged, **errors))
            log(f"  {method} N={n}: {seconds:.3g} s, {errors}")
    return rows


def _memory(config: BenchConfig, log) -> list[tuple[str, int, float, float]]:
    """Peak numpy memory of a BEM solve per grid and of the discrete model per asperity count."""
    import asperity
    import bem
    from validation.surfaces.wm import wm_surface

    out = []
    for n in config.memory_grids:
        heights = wm_surface(n, D=2.5, rms_slope=0.1, seed=0)
        tracemalloc.start()
        bem.solve_contact(heights, 1.0 / n, load=1e-3, stiffness=True)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        out.append(("bem solve + stiffness", n * n, peak / 2**20, peak / (n * n)))
        log(f"  memory bem N={n}: {peak / 2**20:.1f} MiB")
    rng = np.random.default_rng(0)
    for count in config.memory_asperities:
        side = int(math.ceil(math.sqrt(count)))
        cells = rng.choice(side * side, size=count, replace=False)
        spacing = 1.0 / side
        x, y = (cells % side) * spacing, (cells // side) * spacing
        height = rng.normal(0.0, 1e-3, count)
        radius = np.full(count, 0.05)
        summits = asperity.Summits.from_points(x, y, height, radius, area=1.0, spacing=spacing)
        tracemalloc.start()
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            # from one sigma above the mean summit height down to it
            asperity.DiscreteAsperityModel(summits).at_separation(
                [1e-3, 0.0], quantities=("area", "load", "separation", "conductance"))
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        out.append(("discrete model + stiffness", count, peak / 2**20, peak / count))
        log(f"  memory discrete N={count}: {peak / 2**20:.1f} MiB")
    return out


def machine_description() -> str:
    """The machine and software a benchmark ran on, in one line: architecture, CPU model (from
    ``/proc/cpuinfo`` where the platform does not name it), CPU count, operating system, and the
    versions of this package, Python, numpy, scipy and pyFFTW."""
    import os

    import scipy

    import bem.elastic.fft
    import validation

    parts = [f"asperity-validation {validation.__version__}", f"Python {platform.python_version()}",
             f"numpy {np.__version__}", f"scipy {scipy.__version__}"]
    if bem.elastic.fft.have_pyfftw():
        import pyfftw
        parts.append(f"pyFFTW {pyfftw.__version__}")
    return (f"{platform.machine()} {_processor()} {os.cpu_count()} cores, "
            f"{platform.system()} {platform.release()}; " + ", ".join(parts))


def _processor() -> str:
    """The CPU's model name, or '' where neither the platform nor ``/proc/cpuinfo`` says."""
    if platform.processor():
        return platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as stream:
            for line in stream:
                if line.lower().startswith("model name"):
                    return line.partition(":")[2].strip()
    except OSError:
        pass
    return ""


def run_bench(out: str | pathlib.Path, *, quick: bool = False, log=print) -> pathlib.Path:
    """Run the benchmark and write ``bench.md``, ``bench.csv`` and ``bench.png`` into ``out``."""
    config = QUICK if quick else FULL
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log(machine_description())
    rows: list[BenchRow] = []
    for D in (2.05, 2.95):
        rows += _bench_surface(D, config, log)
    memory = _memory(config, log)

    import csv
    with open(out / "bench.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["D", "method", "setting", "n", "tol", "seconds", "runs", "area_error",
                         "separation_error_sigma", "conductance_error", "converged"])
        for r in rows:
            writer.writerow([r.D, r.method, r.setting, r.n, r.tol, r.seconds, r.runs, r.area,
                             r.separation, r.conductance, r.converged])

    lines = [f"# Run time against error ({'quick' if quick else 'full'})\n",
             f"Machine: {machine_description()}.\n",
             f"Reference: BEM N = {config.reference_n}, tol = {config.reference_tol:g}; "
             f"{config.load_count} loads, Load = 1e-4 … 1e-2 (Load = W/(E* L²)), WM rms slope 0.1. "
             "Errors are the largest over the load path; separation error in units of σ.\n"]
    for D in (2.05, 2.95):
        subset = [r for r in rows if r.D == D]
        lines.append(f"## D = {D}\n")
        lines.append("| method | setting | time (s) | runs | area error | separation error (σ) "
                     "| conductance error | Pareto (area) |")
        lines.append("|---|---|---|---|---|---|---|---|")
        comparable = np.array([not _tolerance_only(r, config) for r in subset])
        front = pareto_front(np.where(comparable, [r.seconds for r in subset], np.inf),
                             np.array([r.area for r in subset]))
        for r, on_front in zip(subset, front):
            setting = r.setting + (" (tolerance error only)" if _tolerance_only(r, config) else "")
            lines.append(f"| {r.method} | {setting} | {r.seconds:.3g} | {r.runs} | {r.area:.2e} | "
                         f"{r.separation:.2e} | {r.conductance:.2e} | {'★' if on_front else ''}"
                         f"{'' if r.converged else ' (not converged)'} |")
        lines.append("")
        tight = min(config.bem_tols)
        bem_rows = [r for r in subset if r.method == REFERENCE and r.tol == tight and r.n < config.reference_n]
        if len(bem_rows) >= 2:
            grids = [r.n for r in bem_rows]
            lines.append("Mesh convergence of the BEM (tol = {:g}):\n".format(tight))
            lines.append("| quantity | " + " | ".join(f"N={n}" for n in grids) + " | observed order p |")
            lines.append("|---|" + "---|" * (len(grids) + 1))
            for q in QUANTITIES:
                errors = [getattr(r, q) for r in bem_rows]
                orders = observed_order(grids, errors)
                lines.append(f"| {q} | " + " | ".join(f"{e:.2e}" for e in errors) + " | "
                             + ", ".join(f"{p:.2f}" for p in orders) + " |")
            lines.append("")
    lines.append("## Peak memory (numpy allocations)\n")
    lines.append("| what | unknowns | peak (MiB) | bytes per unknown |")
    lines.append("|---|---|---|---|")
    for what, unknowns, mib, per in memory:
        lines.append(f"| {what} | {unknowns} | {mib:.1f} | {per:.0f} |")
    lines.append("")
    lines.append("![time against error](bench.png)\n")
    path = out / "bench.md"
    path.write_text("\n".join(lines) + "\n")
    _figure(rows, out / "bench.png", config)
    log(f"benchmark written to {path}")
    return path


def _tolerance_only(row: BenchRow, config: BenchConfig) -> bool:
    """A BEM row on the reference grid: its error is the tolerance error alone."""
    return row.method == REFERENCE and row.n == config.reference_n


def _figure(rows: list[BenchRow], path: pathlib.Path, config: BenchConfig) -> None:
    from validation.report.figures import pyplot, subplots
    from validation.common.labels import MODEL_LABELS, MODEL_STYLES

    plt = pyplot()
    Ds = sorted({r.D for r in rows})
    fig, axes = subplots(len(Ds), len(QUANTITIES), figsize=(4.2 * len(QUANTITIES), 3.6 * len(Ds)),
                          squeeze=False)
    for i, D in enumerate(Ds):
        # the reference grid's own rows measure only the tolerance: not on the time-error plane
        subset = [r for r in rows if r.D == D and not _tolerance_only(r, config)]
        times = np.array([r.seconds for r in subset])
        for j, q in enumerate(QUANTITIES):
            ax = axes[i][j]
            errors = np.array([max(getattr(r, q), 1e-12) for r in subset])
            for method in METHODS:
                mask = np.array([r.method == method for r in subset])
                if mask.any():
                    ax.loglog(times[mask], errors[mask], "o", color=MODEL_STYLES[method]["color"],
                              label=MODEL_LABELS[method], alpha=0.8)
            front = pareto_front(times, errors)
            order = np.argsort(times[front])
            ax.loglog(times[front][order], errors[front][order], "k--", linewidth=1,
                      label="Pareto front")
            ax.set_xlabel("wall time of the load path (s)")
            ax.set_ylabel(f"max {q} error" + (" (σ)" if q == "separation" else " (relative)"))
            ax.set_title(f"D = {D}: {q}", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)
