"""Numerical stress campaign: sweeps of the parameters that break numerics.

``python -m validation stress [--quick] [--out DIR]``

Every case runs one public routine at an extreme and records: status, converged, iterations,
final residual, whether any NaN/inf came out, and wall time. Status is

* ``ok``: finished, finite, converged (where the routine iterates);
* ``clear error``: rejected with a ``ValueError`` that says what is wrong (an expected, documented
  limit, e.g. a surface with no summits cannot be fitted with GW);
* ``FAIL``: anything else (an unexpected exception, NaN/inf, non-convergence, a broken invariant).

The quick campaign (small grids and counts) runs inside the test suite; the full one covers
grids up to 2048 x 2048 and 10^5 asperities.
"""

from __future__ import annotations

import math
import pathlib
import time
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["StressRecord", "run_stress", "stress_cases"]


@dataclass(frozen=True)
class StressRecord:
    group: str
    case: str
    status: str
    converged: bool | None
    iterations: int | None
    residual: float | None
    finite: bool
    seconds: float
    note: str = ""


@dataclass(frozen=True)
class _Outcome:
    converged: bool | None = None
    iterations: int | None = None
    residual: float | None = None
    finite: bool = True
    note: str = ""
    invariant: bool = True


def _finite(*arrays) -> bool:
    return all(np.all(np.isfinite(np.asarray(a, dtype=float))) for a in arrays if a is not None)


def _curve_outcome(curve, *, note: str = "", monotone_in_load: bool = True) -> _Outcome:
    extras = curve.extras
    converged = extras.get("converged")
    converged = None if converged is None else bool(np.all(converged))
    iterations = extras.get("iterations")
    iterations = None if iterations is None else int(np.sum(iterations))
    residual = extras.get("residual")
    residual = None if residual is None else float(np.max(residual))
    finite = _finite(curve.load, curve.area, curve.separation)
    for stiffness in (curve.stiffness, curve.conductance):
        # +inf is the right stiffness of full periodic contact; NaN or a negative value is not
        if stiffness is not None and (np.any(np.isnan(stiffness)) or np.any(stiffness < 0)):
            finite = False
    order = np.argsort(curve.load)
    ok = True
    if monotone_in_load and curve.load.size > 1:
        # area grows and separation falls with load (weakly, to rounding)
        area, separation = curve.area[order], curve.separation[order]
        scale = max(float(np.max(np.abs(curve.separation))), 1e-300)
        ok = bool(np.all(np.diff(area) >= -1e-9 * max(area.max(), 1e-300))
                  and np.all(np.diff(separation) <= 1e-9 * scale))
    return _Outcome(converged, iterations, residual, finite,
                    note + ("" if ok else " non-monotone"), ok)


def _wm(n, D=2.5, seed=0):
    from validation.surfaces.wm import wm_surface
    return wm_surface(n, D=D, rms_slope=0.1, seed=seed)


def stress_cases(quick: bool) -> list[tuple[str, str, Callable[[], _Outcome]]]:
    """(group, case, run) triples of the campaign."""
    import asperity
    import bem
    from validation.surfaces.statistics import surface_statistics
    from validation.surfaces.wm import wm_surface

    cases = []
    grid_sizes = (16, 32, 64, 128) if quick else (16, 64, 256, 1024, 2048)
    dimensions = (2.001, 2.05, 2.5, 2.95, 2.999)
    n_small = 32 if quick else 128

    # WM surfaces: D near both limits, every grid size
    for D in dimensions:
        for n in grid_sizes:
            def run(D=D, n=n):
                z = wm_surface(n, D=D, rms_slope=0.1, seed=1)
                s = surface_statistics(z, 1.0 / n)
                return _Outcome(finite=_finite(z, s.rms_height, s.nayak),
                                note=f"rms gradient {s.rms_gradient:.3g}")
            cases.append(("WM surface", f"D={D}, n={n}", run))

    # BEM: load path from first contact to near-full contact
    def bem_path(n, D, loads, periodic=False):
        def run():
            z = _wm(n, D)
            curve = bem.contact_curve(z, 1.0 / n, loads=loads, periodic=periodic,
                                      quantities=("area", "load", "separation", "conductance"))
            out = _curve_outcome(curve)
            return _Outcome(out.converged, out.iterations, out.residual, out.finite,
                            f"area {100 * curve.area_fraction.min():.3g} % – "
                            f"{100 * curve.area_fraction.max():.4g} %" + out.note, out.invariant)
        return run
    loads = np.logspace(-9, 0.5, 8)
    for D in dimensions:
        cases.append(("BEM load path", f"D={D}, n={n_small}, Load 1e-9…3", bem_path(n_small, D, loads)))
    cases.append(("BEM load path", f"periodic, D=2.5, n={n_small}, Load 1e-9…3",
                  bem_path(n_small, 2.5, loads, periodic=True)))
    for n in grid_sizes:
        cases.append(("BEM grid", f"n={n}, Load 1e-3", bem_path(n, 2.5, np.array([1e-3]))))

    def bem_separation(n, separation_fraction):
        def run():
            z = _wm(n)
            d = z.min() + separation_fraction * (z.max() - z.min())
            s = bem.solve_contact(z, 1.0 / n, separation=d, stiffness=True)
            return _Outcome(s.converged, s.iterations, s.residual,
                            _finite(s.pressure, s.load, s.stiffness),
                            f"area {100 * s.area / (1.0) :.4g} %", bool(np.all(s.pressure >= 0)))
        return run
    for fraction in (1.2, 0.999, 0.5, 0.05, 0.001):
        cases.append(("BEM separation", f"d = min + {fraction:g} (max − min)",
                      bem_separation(n_small, fraction)))

    # Special surfaces
    def special(kind):
        n = n_small
        if kind == "plateau":
            z = _wm(n)
            z = np.minimum(z, np.quantile(z, 0.9))
        elif kind == "single spike":
            z = np.zeros((n, n))
            z[n // 2, n // 3] = 1e-2
        else:  # all equal
            z = np.full((n, n), 0.25)
        return z

    for kind in ("plateau", "single spike", "all-equal heights"):
        def run_bem(kind=kind):
            z = special(kind)
            s = bem.solve_contact(z, 1.0 / n_small, load=1e-3, stiffness=True)
            return _Outcome(s.converged, s.iterations, s.residual, _finite(s.pressure, s.stiffness),
                            f"area fraction {s.area:.3g}", bool(np.all(s.pressure >= 0)))
        cases.append(("special surface", f"{kind}: BEM, Load 1e-3", run_bem))

        def run_summits(kind=kind):
            z = special(kind)
            summits = asperity.find_summits(z, 1.0 / n_small)
            note = f"{len(summits)} summits, {summits.rejected} rejected"
            if len(summits) >= 2:
                curve = summits.greenwood_williamson(1.0).at_load(np.logspace(-8, -2, 5))
                model = asperity.DiscreteAsperityModel(summits).at_load(np.logspace(-8, -2, 5))
                return _Outcome(bool(np.all(model.extras["converged"])),
                                int(np.sum(model.extras["iterations"])),
                                float(np.max(model.extras["residual"])),
                                _finite(curve.separation, model.separation), note)
            return _Outcome(note=note)
        cases.append(("special surface", f"{kind}: summits, GW, discrete", run_summits))

    # Discrete model: asperity counts from 1 to 1e5 (random lattice sets), wide separations
    counts = (1, 10, 100, 1000) if quick else (1, 10, 100, 1000, 10_000, 100_000)
    for count in counts:
        def run(count=count):
            rng = np.random.default_rng(count)
            side = max(1, int(math.ceil(math.sqrt(4 * count))))
            cells = rng.choice(side * side, size=count, replace=False)
            spacing = 1.0 / side
            summits = asperity.Summits.from_points((cells % side) * spacing, (cells // side) * spacing,
                                                   rng.normal(0, 1e-3, count),
                                                   rng.uniform(0.01, 0.1, count), area=1.0,
                                                   spacing=spacing)
            sigma = 1e-3
            separations = np.linspace(40 * sigma, -10 * sigma, 12)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", asperity.ValidityWarning)
                curve = asperity.DiscreteAsperityModel(summits).at_separation(separations)
            out = _curve_outcome(curve)
            return _Outcome(out.converged, out.iterations, out.residual, out.finite,
                            f"{count} asperities, separations 40σ…−10σ" + out.note, out.invariant)
        cases.append(("discrete model", f"{count} asperities", run))

    # GW and improved GW: C up to 1e4, separations -10σ..40σ, loads over 15 decades
    for C in (1e-3, 1.0, 50.0, 1e4):
        def run(C=C):
            sigma, radius = 1.0, 1.0
            density = C  # area = 1, R = sigma = 1: C = eta
            model = asperity.ImprovedGreenwoodWilliamson(density, radius, sigma, area=1.0)
            by_separation = model.at_separation(np.linspace(40, -10, 101))
            reference = model.reference_load
            by_load = model.at_load(reference * np.logspace(-12, 3, 61))
            # Subnormal loads (below 2.2e-308) carry too few significant bits for a round trip.
            normal = by_separation.load >= np.finfo(float).tiny
            back = model.at_load(by_separation.load[normal])
            round_trip = float(np.max(np.abs(back.separation - by_separation.separation[normal])))
            a = _curve_outcome(by_separation)
            b = _curve_outcome(by_load)
            return _Outcome(b.converged, None, round_trip, a.finite and b.finite,
                            f"round trip |Δd| ≤ {round_trip:.1e} σ (normal floats)",
                            a.invariant and b.invariant and round_trip < 1e-9)
        cases.append(("improved GW", f"C={C:g}, d 40σ…−10σ, W over 15 decades", run))
    return cases


#: (group, case) -> a phrase of the ValueError the case is expected to raise (a documented limit).
EXPECTED_ERRORS: dict[tuple[str, str], str] = {}


def run_stress(out: str | pathlib.Path | None = None, *, quick: bool = False, log=print
               ) -> list[StressRecord]:
    """Run the campaign; write ``stress.md`` and ``stress.csv`` into ``out`` when given."""
    records = []
    for group, case, run in stress_cases(quick):
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                outcome = run()
            seconds = time.perf_counter() - start
            bad = (not outcome.finite or outcome.converged is False or not outcome.invariant)
            status = "FAIL" if bad else "ok"
            record = StressRecord(group, case, status, outcome.converged, outcome.iterations,
                                  outcome.residual, outcome.finite, seconds, outcome.note)
        except ValueError as error:
            # a documented limit only when the case says it expects this error; any other
            # ValueError (say, from deep inside a root finder) is a failure
            expected = EXPECTED_ERRORS.get((group, case))
            status = "clear error" if expected and expected in str(error) else "FAIL"
            record = StressRecord(group, case, status, None, None, None, True,
                                  time.perf_counter() - start, f"ValueError: {error}")
        except Exception as error:  # noqa: BLE001 - any other exception is a failure to record
            record = StressRecord(group, case, "FAIL", None, None, None, False,
                                  time.perf_counter() - start, f"{type(error).__name__}: {error}")
        records.append(record)
        log(f"{record.status:12s} {group}: {case} ({record.seconds:.2f} s) {record.note}")
    if out is not None:
        out = pathlib.Path(out)
        out.mkdir(parents=True, exist_ok=True)
        _write(records, out, quick)
    return records


def _write(records: list[StressRecord], out: pathlib.Path, quick: bool) -> None:
    import csv

    with open(out / "stress.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["group", "case", "status", "converged", "iterations", "residual", "finite",
                         "seconds", "note"])
        for r in records:
            writer.writerow([r.group, r.case, r.status, r.converged, r.iterations, r.residual,
                             r.finite, f"{r.seconds:.4f}", r.note])
    failures = sum(r.status == "FAIL" for r in records)
    lines = [f"# Stress campaign ({'quick' if quick else 'full'})\n",
             f"{len(records)} cases, {failures} failures.\n",
             "| group | case | status | converged | iterations | residual | finite | time (s) | note |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in records:
        lines.append(f"| {r.group} | {r.case} | {r.status} | {'' if r.converged is None else r.converged} | "
                     f"{'' if r.iterations is None else r.iterations} | "
                     f"{'' if r.residual is None else f'{r.residual:.1e}'} | {r.finite} | "
                     f"{r.seconds:.3g} | {r.note.replace('|', '/')} |")
    (out / "stress.md").write_text("\n".join(lines) + "\n")
