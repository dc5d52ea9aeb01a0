"""The validity report: Markdown, PNG figures and CSV tables in one folder.

Only this module makes figures; matplotlib is imported here, lazily, with the Agg backend.
Plot functions take an ``ax`` and return what they drew.

Dimensionless quantities (the paper's Section 4, THEORY.md conventions):
``Area = A_real / L^2``, ``Load = W / (E* L^2)``, ``Separation = d / sigma``,
``Conductance = C rho sigma / L^2 = 2 S sigma / (E* L^2) = -2 dLoad/dSeparation``.
"""

from __future__ import annotations

import csv
import datetime
import math
import pathlib
import platform
from dataclasses import dataclass

import numpy as np

from validation.compare import Comparison, compare_realizations
from validation.runner import SceneResult

__all__ = ["write_report", "MODEL_LABELS", "QUANTITY_LABELS"]

MODEL_LABELS = {
    "gw": "original GW",
    "improved_gw": "improved GW",
    "discrete": "discrete (interaction)",
    "discrete_no_interaction": "discrete (no interaction)",
    "bem": "BEM (exact)",
}
MODEL_STYLES = {
    "gw": dict(color="tab:blue", linestyle="--"),
    "improved_gw": dict(color="tab:orange", linestyle="-"),
    "discrete": dict(color="tab:green", linestyle="-"),
    "discrete_no_interaction": dict(color="tab:olive", linestyle=":"),
    "bem": dict(color="black", linestyle="-", linewidth=2.0),
}
QUANTITY_LABELS = {
    "area": "Area = A/L²",
    "load": "Load = W/(E* L²)",
    "separation": "Separation = d/σ",
    "conductance": "Conductance = Cρσ/L²",
    "stiffness": "Stiffness S σ/(E* L²)",
    "contacts": "contacts",
}
#: Quantities drawn on the validity map (contact counts are too noisy to map).
MAP_QUANTITIES = ("area", "separation", "conductance", "stiffness")
ERROR_LABELS = {
    "area": "relative error of area",
    "separation": "error of separation / σ",
    "conductance": "relative error of conductance",
    "stiffness": "relative error of stiffness",
    "contacts": "relative error of contact count",
}


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _subplots(plt, *args, **kwargs):
    return plt.subplots(*args, layout="constrained", **kwargs)


# --------------------------------------------------------------------------------------------
# dimensionless curves

def dimensionless(curve, sigma: float, length: float) -> dict[str, np.ndarray]:
    """The paper's dimensionless arrays of a curve (:func:`asperity.dimensionless`), by name,
    plus the contact count and the reduced stiffness S sigma / (E* L^2) when computed."""
    from asperity import dimensionless as reduce

    reduced = reduce(curve, sigma, length)
    out = {"area": reduced.area, "load": reduced.load, "separation": reduced.separation}
    if reduced.conductance is not None:
        out["conductance"] = reduced.conductance
        out["stiffness"] = reduced.conductance / 2.0
    if curve.contacts is not None:
        out["contacts"] = np.asarray(curve.contacts, dtype=float)
    return out


# --------------------------------------------------------------------------------------------
# plot functions: each takes an ax and returns what it drew

def plot_theory_load(ax, theory: dict, C: float):
    """Figs. 1-2: reduced pressure p̄ against Separation for GW and improved GW."""
    curves = theory[C]
    lines = []
    lines += ax.semilogy(curves.separation, curves.gw_pressure, label="GW (no interaction)",
                         **MODEL_STYLES["gw"])
    lines += ax.semilogy(curves.separation, curves.improved_pressure,
                         label=f"improved GW (m = {theory['m']:g})", **MODEL_STYLES["improved_gw"])
    ax.set_xlabel("Separation (d − μs)/σ")
    ax.set_ylabel(r"$\bar p = p_{nom}\,/\,(\eta E^* R^{1/2} \sigma^{3/2})$")
    ax.set_title(f"C = {C:g}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return lines


def plot_theory_stiffness(ax, theory: dict, C: float):
    """Fig. 3: GW stiffness dW/dd₁ and the true stiffness dW/dd (reduced)."""
    curves = theory[C]
    lines = []
    lines += ax.semilogy(curves.separation, curves.effective_stiffness,
                         label=f"GW stiffness dW/dd₁, C = {C:g}", color="tab:blue", linestyle="--")
    lines += ax.semilogy(curves.separation, curves.improved_stiffness,
                         label=f"true stiffness dW/dd, C = {C:g}", color="tab:orange")
    ax.set_xlabel("Separation (d − μs)/σ")
    ax.set_ylabel(r"$-d\bar p/d(d/\sigma) = S\,/\,(N E^* R^{1/2} \sigma^{1/2})$")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return lines


def plot_against(ax, results, x: str, y: str, *, models, length: float, logx=False, logy=True):
    """Every realization (thin) and the realization mean (thick) of y against x, per model."""
    drawn = []
    for model in models:
        style = MODEL_STYLES.get(model, {})
        xs, ys = [], []
        for r in results:
            values = dimensionless(r.curves[model], r.sigma, length)
            if x not in values or y not in values:
                break
            xs.append(values[x])
            ys.append(values[y])
            drawn += ax.plot(values[x], values[y], color=style.get("color"), alpha=0.25, linewidth=0.7)
        if xs:
            drawn += ax.plot(np.mean(xs, axis=0), np.mean(ys, axis=0), label=MODEL_LABELS[model],
                             **style)
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(QUANTITY_LABELS[x])
    ax.set_ylabel(QUANTITY_LABELS[y])
    ax.grid(True, which="both", alpha=0.3)
    return drawn


def plot_errors(ax, comparison: Comparison, quantity: str, tolerances):
    """Mean error (± one standard deviation over realizations) against Load, per model."""
    drawn = []
    for (model, name), entry in comparison.models.items():
        if name != quantity:
            continue
        style = MODEL_STYLES.get(model, {})
        mean, std = entry.summary.mean, entry.summary.std
        drawn += ax.plot(comparison.load, mean, label=MODEL_LABELS[model], **style)
        drawn.append(ax.fill_between(comparison.load, mean - std, mean + std,
                                     color=style.get("color"), alpha=0.15))
    ref = comparison.reference_error.get(quantity)
    if ref is not None:
        drawn += ax.plot(comparison.load, ref, color="gray", marker="x", linestyle="none",
                         label="BEM reference error (per point, n/2 vs n)")
    for tol in tolerances:
        for sign in (-1, 1):
            drawn.append(ax.axhline(sign * tol, color="red", linewidth=0.6, linestyle=":"))
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=min(tolerances) / 2)
    ax.set_xlabel(QUANTITY_LABELS["load"])
    ax.set_ylabel(ERROR_LABELS.get(quantity, quantity))
    ax.grid(True, which="both", alpha=0.3)
    return drawn


def plot_validity_map(ax, comparisons: list[Comparison], model: str, quantity: str, tolerances):
    """|mean error| of one model in the (Load, D) plane, with the tolerance contours."""
    from matplotlib.colors import LogNorm

    comparisons = sorted(comparisons, key=lambda c: c.D)
    load = comparisons[0].load
    D = np.array([c.D for c in comparisons])
    error = np.array([np.abs(c.models[(model, quantity)].summary.mean)
                      if (model, quantity) in c.models else np.full(load.shape, np.nan)
                      for c in comparisons])
    error = np.clip(error, 1e-4, 10.0)
    mesh = ax.pcolormesh(load, D, error, shading="nearest", norm=LogNorm(1e-3, 3.0), cmap="viridis")
    drawn = [mesh]
    if len(D) > 1 and np.all(np.isfinite(error)):
        drawn.append(ax.contour(load, D, error, levels=sorted(tolerances), colors="white",
                                linewidths=1.0))
    ax.set_xscale("log")
    ax.set_xlabel(QUANTITY_LABELS["load"])
    ax.set_ylabel("fractal dimension D")
    ax.set_title(f"{MODEL_LABELS[model]}: {quantity}", fontsize=9)
    return drawn


# --------------------------------------------------------------------------------------------
# the report

@dataclass
class _Writer:
    folder: pathlib.Path
    lines: list

    def figure(self, fig, name: str, caption: str) -> None:
        path = self.folder / name
        fig.savefig(path, dpi=110)
        _pyplot().close(fig)
        self.lines.append(f"![{caption}]({name})\n")
        self.lines.append(f"*{caption}*\n")


def _md_table(header: list[str], rows: list[list[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(row) + " |" for row in rows]
    return out + [""]


def _theory_section(w: _Writer, result: SceneResult, rows_csv: list) -> None:
    plt = _pyplot()
    theory = result.theory
    for index, C in enumerate(theory["C"]):
        fig, ax = _subplots(plt, figsize=(5.5, 4))
        plot_theory_load(ax, theory, C)
        w.figure(fig, f"{result.scene.name}-fig{index + 1}-C{C:g}.png",
                 f"Load against separation, GW and improved GW, C = {C:g} (paper Fig. {index + 1}).")
        c = theory[C]
        for k in range(c.separation.size):
            rows_csv.append([C, theory["m"], c.separation[k], c.effective_separation[k],
                             c.gw_pressure[k], c.improved_pressure[k], c.gw_stiffness[k],
                             c.effective_stiffness[k], c.improved_stiffness[k]])
    fig, axes = _subplots(plt, 1, len(theory["C"]), figsize=(5.5 * len(theory["C"]), 4), squeeze=False)
    for ax, C in zip(axes[0], theory["C"]):
        plot_theory_stiffness(ax, theory, C)
    w.figure(fig, f"{result.scene.name}-fig3-stiffness.png",
             "GW stiffness dW/dd₁ and the true stiffness dW/dd with interaction (paper Fig. 3).")
    rows = []
    for C in theory["C"]:
        c = theory[C]
        ratio = c.improved_stiffness / c.effective_stiffness
        rows.append([f"{C:g}", f"{ratio.min():.3g}",
                     f"{np.max(c.effective_separation - c.separation):.3g}"])
    w.lines += _md_table(["C", "smallest ratio of true to GW stiffness dW/dd ÷ dW/dd₁",
                          "largest separation shift (d₁ − d)/σ"], rows)


def _surface_section(w: _Writer, result: SceneResult, comparisons: list[Comparison],
                     curve_rows: list, error_rows: list, validity_rows: list) -> None:
    plt = _pyplot()
    scene = result.scene
    L = scene.surface.L
    s = scene.surface
    count = len(next(iter(result.realizations.values())))
    w.lines.append(f"Surface: WM, D = {', '.join(f'{d:g}' for d in s.D)}, γ = {s.gamma:g}, M = {s.M}, "
                   f"n_max = {s.n_max}, rms slope = {s.rms_slope if s.rms_slope else 'from G'}, "
                   f"grid {s.n} × {s.n}, {count} realization(s); E* = {scene.e_star:g}; "
                   f"BEM {'periodic' if scene.bem.periodic else 'non-periodic'}, tol {scene.bem.tol:g}.\n")
    for comparison in comparisons:
        results = result.realizations[comparison.D]
        models = [m for m in ("gw", "improved_gw", "discrete_no_interaction", "discrete", "bem")
                  if m in results[0].curves]
        summit_counts = [r.summit_count for r in results]
        w.lines.append(f"### D = {comparison.D:g}\n")
        if any(summit_counts):
            w.lines.append(f"Summits per realization: {min(summit_counts)}–{max(summit_counts)}; "
                           f"reference area fraction {100 * comparison.area_fraction[0]:.3g} % – "
                           f"{100 * comparison.area_fraction[-1]:.3g} % over the load path.\n")
        for r in results:
            for model, curve in r.curves.items():
                values = dimensionless(curve, r.sigma, L)
                for k in range(curve.load.size):
                    curve_rows.append([scene.name, comparison.D, r.task.seed, r.task.surface.n, model, k,
                                       values["load"][k], values["area"][k], values["separation"][k],
                                       values.get("conductance", [math.nan] * (k + 1))[k],
                                       values.get("contacts", [math.nan] * (k + 1))[k],
                                       curve.load[k], curve.area[k], curve.separation[k],
                                       curve.stiffness[k] if curve.stiffness is not None else math.nan,
                                       curve.conductance[k] if curve.conductance is not None else math.nan,
                                       r.sigma])
        if len(scene.surface.D) == 1:
            tag = f"{scene.name}"
            has_conductance = "conductance" in scene.quantities
            panels = ["area", "load"] + (["conductance"] if has_conductance else [])
            fig, axes = _subplots(plt, 1, len(panels), figsize=(5 * len(panels), 4), squeeze=False)
            for ax, y in zip(axes[0], panels):
                plot_against(ax, results, "separation", y, models=models, length=L)
            axes[0][0].legend(fontsize=8)
            w.figure(fig, f"{tag}-fig4-separation.png",
                     f"Area, load{' and conductance' if has_conductance else ''} against separation, "
                     f"D = {comparison.D:g} (paper Fig. 4, BEM added; thin lines: realizations).")
            panels = ["area"] + (["conductance"] if has_conductance else [])
            fig, axes = _subplots(plt, 1, len(panels), figsize=(5 * len(panels), 4), squeeze=False)
            for ax, y in zip(axes[0], panels):
                plot_against(ax, results, "load", y, models=models, length=L, logx=True)
            axes[0][0].legend(fontsize=8)
            w.figure(fig, f"{tag}-fig5-load.png",
                     f"Area{' and conductance' if has_conductance else ''} against load, "
                     f"D = {comparison.D:g} (paper Fig. 5, BEM added).")
        quantities = sorted({q for (_, q) in comparison.models}, key=["area", "separation", "conductance",
                                                                     "stiffness", "contacts"].index)
        if quantities:
            fig, axes = _subplots(plt, 1, len(quantities), figsize=(5 * len(quantities), 4), squeeze=False)
            for ax, q in zip(axes[0], quantities):
                plot_errors(ax, comparison, q, scene.tolerances)
            axes[0][0].legend(fontsize=7)
            w.figure(fig, f"{scene.name}-errors-D{comparison.D:g}.png",
                     f"Error of each model against the BEM reference at equal load, D = {comparison.D:g} "
                     f"(band: ± one standard deviation over realizations; dotted red: tolerances).")
        rows = []
        for (model, quantity), entry in comparison.models.items():
            ref_max = comparison.reference_error_max(quantity)
            cells = [MODEL_LABELS[model], quantity]
            reference = comparison.reference_error.get(quantity)
            for rng in entry.ranges:
                text = rng.describe()
                if rng.holds_anywhere and reference is not None:
                    # the BEM's own error inside the claimed range, not over the whole path
                    inside = np.abs(reference[rng.first:rng.last + 1])
                    if np.any(np.isfinite(inside)) and np.nanmax(inside) > rng.tolerance / 2:
                        text += " ⚠ finer than the reference resolves"
                cells.append(text)
                validity_rows.append([scene.name, comparison.D, model, quantity, rng.tolerance,
                                      rng.load_min, rng.load_max, rng.area_fraction_min,
                                      rng.area_fraction_max, rng.points, rng.total, ref_max])
            cells.append("not estimated" if not np.isfinite(ref_max) else
                         (f"{ref_max:.2g} σ" if quantity == "separation" else f"{100 * ref_max:.2g} %"))
            failed = entry.unconverged
            cells.append(str(failed) if failed else "–")
            rows.append(cells)
            for k in range(comparison.load.size):
                error_rows.append([scene.name, comparison.D, model, quantity, k, comparison.load[k],
                                   comparison.area_fraction[k], entry.summary.mean[k],
                                   entry.summary.std[k], entry.summary.count])
        header = ["model", "quantity"] + [f"holds within {100 * t:g} % (Load range)"
                                          for t in scene.tolerances] + ["BEM's own error (max)",
                                                                        "unconverged points"]
        w.lines.append("Where each model holds (|mean error| within the tolerance; separation "
                       "errors in units of σ, so 5 % means 0.05 σ):\n")
        w.lines += _md_table(header, rows)
    if len(scene.surface.D) > 1:
        keys = sorted({k for c in comparisons for k in c.models if k[1] in MAP_QUANTITIES},
                      key=lambda k: (list(MODEL_LABELS).index(k[0]), k[1]))
        models = list(dict.fromkeys(k[0] for k in keys))
        quantities = list(dict.fromkeys(k[1] for k in keys))
        fig, axes = _subplots(plt, len(quantities), len(models),
                                 figsize=(3.6 * len(models), 3.0 * len(quantities)), squeeze=False)
        mesh = None
        for i, q in enumerate(quantities):
            for j, m in enumerate(models):
                drawn = plot_validity_map(axes[i][j], comparisons, m, q, scene.tolerances)
                mesh = drawn[0]
        for ax in axes[:-1].ravel():
            ax.set_xlabel("")
        for ax in axes[:, 1:].ravel():
            ax.set_ylabel("")
        fig.colorbar(mesh, ax=axes, label="|mean error| (relative, or /σ for separation)")
        w.figure(fig, f"{scene.name}-validity-map.png",
                 "Validity map: |mean error| of each model against the BEM over load and D; white "
                 f"contours at the tolerances {', '.join(f'{t:g}' for t in scene.tolerances)}.")


def write_report(results: list[SceneResult], folder: str | pathlib.Path, *,
                 seconds: float | None = None, mode: str = "") -> pathlib.Path:
    """Write ``report.md``, PNG figures and CSV tables for ``results`` into ``folder``.

    Returns the path of ``report.md``.
    """
    import bem.fft
    import validation

    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    w = _Writer(folder, [])
    w.lines += [
        "# Where do asperity models hold? Validation against the exact half-space solution\n",
        f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} by asperity-validation "
        f"{validation.__version__} (Python {platform.python_version()}, numpy {np.__version__}, "
        f"FFT backend {'pyFFTW' if bem.fft.have_pyfftw() else 'scipy.fft'})"
        + (f"; mode: {mode}" if mode else "") + (f"; run time {seconds:.1f} s." if seconds is not None else ".")
        + "\n",
        "Dimensionless quantities as in the paper: Area = A/L², Load = W/(E* L²), Separation = d/σ "
        "(σ: standard deviation of the summit heights of each realization), Conductance = Cρσ/L² = "
        "−2 ∂Load/∂Separation. Errors are taken at equal load against the boundary-element (BEM) "
        "solution of the same realization: relative for area and conductance, in units of σ for "
        "separation. A model *holds* over the longest contiguous run of load points where the "
        "magnitude of its mean error is within the tolerance; points where either solver did not "
        "converge count as not holding (their number is given). Where the scene asks for it, the "
        "BEM's own discretisation error (the same continuous surface on grid n against 2n, one "
        "realization) is printed beside each claim, and a range in which it exceeds half the "
        "tolerance is flagged. Contact counts are plotted but not ranged: the BEM counts "
        "connected contact patches, the asperity models asperities in contact.\n",
    ]
    curve_rows, error_rows, validity_rows, theory_rows = [], [], [], []
    for result in results:
        scene = result.scene
        w.lines.append(f"## {scene.title}\n")
        w.lines.append(f"Scene `{scene.name}` ({scene.source}). {scene.description.strip()}\n")
        if scene.kind == "theory":
            _theory_section(w, result, theory_rows)
            continue
        comparisons = []
        if "bem" in scene.models:
            for D, realizations in sorted(result.realizations.items()):
                comparisons.append(compare_realizations(realizations, result.reference_error.get(D),
                                                        tolerances=scene.tolerances))
        else:
            w.lines.append("No BEM reference in this scene: curves only, no validity ranges.\n")
        _surface_section(w, result, comparisons, curve_rows, error_rows, validity_rows)
        times = {}
        for realizations in result.realizations.values():
            for r in realizations:
                for model, t in r.seconds.items():
                    times.setdefault(model, []).append(t)
        if times:
            w.lines.append("Wall time per realization and model (median over realizations; 0 means "
                           "read from the cache): " + ", ".join(
                               f"{MODEL_LABELS[m]} {np.median(t):.2f} s" for m, t in times.items()) + ".\n")

    def write_csv(name, header, rows):
        if rows:
            with open(folder / name, "w", newline="", encoding="utf-8") as stream:
                writer = csv.writer(stream)
                writer.writerow(header)
                writer.writerows(rows)
            w.lines.append(f"- [`{name}`]({name})")

    w.lines.append("## Data\n")
    write_csv("curves.csv", ["scene", "D", "seed", "n", "model", "point", "Load", "Area", "Separation",
                             "Conductance", "contacts", "load_W", "area", "separation_d", "stiffness",
                             "conductance", "sigma"], curve_rows)
    write_csv("errors.csv", ["scene", "D", "model", "quantity", "point", "Load", "area_fraction_bem",
                             "mean_error", "std_error", "realizations"], error_rows)
    write_csv("validity.csv", ["scene", "D", "model", "quantity", "tolerance", "load_min", "load_max",
                               "area_fraction_min", "area_fraction_max", "points", "total",
                               "reference_error_max"], validity_rows)
    write_csv("theory.csv", ["C", "m", "separation", "effective_separation", "gw_pressure",
                             "improved_pressure", "gw_stiffness", "effective_stiffness",
                             "improved_stiffness"], theory_rows)
    w.lines.append("")
    path = folder / "report.md"
    path.write_text("\n".join(w.lines) + "\n", encoding="utf-8")
    return path
