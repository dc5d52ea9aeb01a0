"""The error model fitted to a computed atlas, and how well it predicts surfaces it has not seen.

:func:`atlas_table` joins ``atlas.csv`` with each realization's descriptors (its surface made
again from its seed: no solve); :func:`fit_atlas` fits the model (:mod:`validation.atlas.model`) and measures
it: the design points are split into folds, each fold left out of a whole fit (its intervals
included) and predicted, and the share of left-out errors inside their 90 % interval
(coverage) and the agreement of the predicted verdicts with the atlas' own one-surface
verdicts are stored with the model.
"""

from __future__ import annotations

import json
import pathlib

import numpy as np

from validation.atlas.build import read_atlas
from validation.atlas.design import DesignPoint, atlas_scene
from validation.atlas.model import MODEL_FILE, fit_error_model, interval_of, verdict_of
from validation.surfaces.descriptors import surface_descriptors
from validation.surfaces.families import surface_heights

__all__ = ["FOLDS", "TOLERANCE", "atlas_table", "fit_atlas", "one_surface_verdict",
           "validate"]

#: Folds of design points of the validation.
FOLDS = 8
#: The tolerance of the predicted verdicts (the check's largest).
TOLERANCE = 0.2
#: Descriptors of the atlas' range, stored with the model (min and max over its surfaces).
RANGE_DESCRIPTORS = ("hurst", "nayak", "skewness", "magnification", "peak")


def _descriptors(meta: dict) -> dict[tuple[int, int], object]:
    out = {}
    for p in meta["points"]:
        point = DesignPoint(p["index"], p["hurst"], p["magnification"], p["plateau"],
                            p.get("family", "self-affine"))
        scene = atlas_scene(point, n=meta["n"], realizations=meta["realizations"])
        surface = scene.surface.at(scene.surface.sweep_values[0])
        for k in range(scene.realizations):
            seed = scene.seed + k
            out[(point.index, seed)] = surface_descriptors(surface_heights(surface, seed),
                                                           surface.spacing, periodic=True)
    return out


def atlas_table(folder: str | pathlib.Path) -> tuple[dict, dict]:
    """The atlas' columns with its descriptors added (``hurst``, ``log10_nayak``,
    ``skewness``, per row), and its ``atlas.json``."""
    folder = pathlib.Path(folder)
    table = read_atlas(folder / "atlas.csv")
    meta = json.loads((folder / "atlas.json").read_text(encoding="utf-8"))
    descriptors = _descriptors(meta)
    keys = list(zip(table["point"].astype(int), table["seed"].astype(int)))
    for name in ("hurst", "skewness"):
        table[name] = np.array([getattr(descriptors[k], name) for k in keys])
    table["log10_nayak"] = np.log10([descriptors[k].nayak for k in keys])
    table["key"] = np.char.add(np.char.add(np.char.add(table["model"], "/"),
                                           np.char.add(table["frame"], "/")), table["quantity"])
    meta["range"] = {name: [float(min(getattr(d, name) for d in descriptors.values())),
                            float(max(getattr(d, name) for d in descriptors.values()))]
                     for name in RANGE_DESCRIPTORS}
    meta["range"]["load_ratio"] = [float(table["load_ratio"].min()),
                                   float(table["load_ratio"].max())]
    return table, meta


def _covariates(table: dict) -> np.ndarray:
    return np.column_stack([table["hurst"], table["log10_nayak"], table["skewness"],
                            np.log10(table["load_ratio"])])


def one_surface_verdict(error: np.ndarray, band: np.ndarray, tolerance: float) -> np.ndarray:
    """The check's verdict on one surface: holds where ``|error| + band <= tolerance``, fails
    where ``|error| - band > tolerance`` (a band not estimated counts as 0)."""
    band = np.nan_to_num(band, nan=0.0)
    size = np.abs(error)
    return np.where(size + band <= tolerance, "holds",
                    np.where(size - band > tolerance, "fails", "undecided"))


def validate(table: dict, *, folds: int = FOLDS, tolerance: float = TOLERANCE,
             seed: int = 0, kinds: dict[int, str] | None = None) -> dict:
    """Coverage and verdict agreement on design points left out of the whole fit (module
    docstring), overall, per ``model/frame/quantity`` and, with ``kinds`` (design point ->
    kind), per kind of surface."""
    covariates, error = _covariates(table), table["error"]
    kind = np.array([(kinds or {}).get(int(p), "") for p in table["point"]])
    points = np.unique(table["point"])
    fold_of = dict(zip(np.random.default_rng(seed).permutation(points),
                       np.arange(points.size) % folds))
    fold = np.array([fold_of[p] for p in table["point"]])
    low, high = np.full(error.shape, np.nan), np.full(error.shape, np.nan)
    for f in range(folds):
        out = fold == f
        if not out.any() or out.all():    # an empty fold, or nothing left to fit to
            continue
        model = fit_error_model(covariates[~out], table["key"][~out], error[~out],
                                table["point"][~out], kinds=kind[~out])
        for key in np.unique(table["key"][out]):
            rows = out & (table["key"] == key)
            _, low[rows], high[rows] = interval_of(model, key, covariates[rows])
    seen = np.isfinite(error) & np.isfinite(low)
    inside = (error >= low) & (error <= high)
    predicted = verdict_of(low, high, tolerance)
    truth = one_surface_verdict(error, table["band"], tolerance)

    def summary(rows: np.ndarray) -> dict:
        rows = rows & seen
        decided = rows & (predicted != "undecided")
        both = decided & (truth != "undecided")
        return {"rows": int(rows.sum()), "coverage": float(np.mean(inside[rows])),
                "decided": float(np.mean(decided[rows])),
                "agreement": float(np.mean(predicted[both] == truth[both])) if both.any()
                else float("nan"),
                "opposite": float(np.mean(predicted[both] != truth[both])) if both.any()
                else float("nan")}

    return {"folds": folds, "tolerance": tolerance, "all": summary(np.ones_like(seen)),
            "entries": {str(key): summary(table["key"] == key)
                        for key in np.unique(table["key"])},
            "kinds": {str(k): summary(kind == k) for k in np.unique(kind) if k}}


def fit_atlas(folder: str | pathlib.Path, out: str | pathlib.Path | None = MODEL_FILE) -> dict:
    """Fit the error model to the atlas in ``folder``, validate it and write it to ``out``
    (default the package's ``error_model.json``; None: not written); returns the model."""
    table, meta = atlas_table(folder)
    kinds = {p["index"]: _kind(p) for p in meta["points"]}
    model = fit_error_model(_covariates(table), table["key"], table["error"], table["point"],
                            kinds=np.array([kinds[int(p)] for p in table["point"]]),
                            meta={"atlas_commit": meta["commit"], "grid": meta["n"],
                                  "realizations": meta["realizations"],
                                  "design_points": len(meta["points"]),
                                  "atlas_seconds": round(meta["seconds"]),
                                  "tolerance": TOLERANCE, "range": meta["range"],
                                  "families": _families(meta["points"]),
                                  "design_hurst": _measured_hurst(table)})
    model["validation"] = validate(table, kinds=kinds)
    if out is not None:
        pathlib.Path(out).write_text(json.dumps(_rounded(model), indent=1) + "\n",
                                     encoding="utf-8")
    return model


def _measured_hurst(table: dict) -> list[float]:
    """Each design point's H as the descriptors read it (the mean over its realizations: the
    figure's axis), sorted."""
    points = table["point"]
    return sorted(round(float(np.mean(table["hurst"][points == p])), 3)
                  for p in np.unique(points))


def _kind(point: dict) -> str:
    """A design point's kind: "self-affine" (Gaussian), "plateau" (honed) or "wm"."""
    return "wm" if point.get("family") == "wm" else \
        "plateau" if point.get("plateau") is not None else "self-affine"


def _families(points: list[dict]) -> dict[str, int]:
    """Design points per kind: Gaussian self-affine, plateau-honed, WM."""
    kinds = [_kind(p) for p in points]
    return {kind: kinds.count(kind) for kind in ("self-affine", "plateau", "wm")
            if kind in kinds}


def _rounded(value):
    """Floats to 6 significant figures (a small, readable file)."""
    if isinstance(value, float):
        return float(f"{value:.6g}")
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    return value
