"""The error model: each theory's relative error on one surface as a function of its descriptors
and the load, with a 90 % prediction interval (docs/theory.md, "12.2 The atlas and the error model").

For every model, frame and quantity of the atlas, the mean error is a least-squares fit in a
small polynomial basis (:func:`basis`) of the scaled descriptors u = (H, log10 alpha, skewness)
and the scaled load x = log10 p / (E* h'_rms), fitted to every realization's error. The interval
is read from the residuals of the fit with each design point left out in turn (its realizations
predicted by a fit to the other points), so that it covers a surface the fit has not seen: their
size varies over the descriptors (a plateau-honed or a WM surface scatters more about the fit
than a Gaussian self-affine one), so ``ln |residual|`` is fitted linearly in (u, x, x^2), the scale
s(u, x) (:func:`scale_basis`), and the interval is the mean plus s times the 5 % and 95 %
quantiles of the scaled residuals r / s in each third of the load range (the widest of the kinds
of surface, so that each kind is covered), interpolated along the load.
:func:`fit_error_model` returns the model as a plain dict, stored as ``error_model.json`` beside
this module (:func:`load_error_model`).
"""

from __future__ import annotations

import json
import pathlib
from functools import lru_cache

import numpy as np

__all__ = ["MODEL_FILE", "MODEL_VERSION", "PREDICTION_LEVEL", "basis", "fit_error_model",
           "scale_basis",
           "interval_of", "load_error_model", "predict_mean", "verdict_of"]

#: The stored model, beside this module.
MODEL_FILE = pathlib.Path(__file__).with_name("error_model.json")
#: Version of the stored model's layout.
MODEL_VERSION = 2
#: Probability content of the prediction interval.
PREDICTION_LEVEL = 0.9
#: The descriptors the fit uses, as :func:`covariates` computes them.
COVARIATES = ("hurst", "log10_nayak", "skewness", "log10_load_ratio")
#: Load nodes of the interval (the centres of the thirds of the atlas' load range, scaled).
_THIRDS = 3


def basis(u: np.ndarray) -> np.ndarray:
    """The polynomial basis at scaled covariates ``u`` (shape (rows, 4): H, log10 alpha,
    skewness, load, each scaled to about [-1, 1]); shape (rows, 16)."""
    h, a, s, x = (u[:, k] for k in range(4))
    one = np.ones_like(x)
    return np.column_stack([one, h, a, s, x, x * x, x ** 3, h * x, a * x, s * x, h * h, a * a,
                            h * a, h * x * x, a * x * x, s * x * x])


def scale_basis(u: np.ndarray) -> np.ndarray:
    """The basis of ``ln |residual|`` at scaled covariates ``u`` (rows, 4): constant, linear in all
    four, the load squared; shape (rows, 6)."""
    x = u[:, 3]
    return np.column_stack([np.ones_like(x), u, x * x])


def _scale_fit(u: np.ndarray, residual: np.ndarray) -> np.ndarray:
    """Coefficients of ``ln |residual|`` in :func:`scale_basis` (a floor of a thousandth of the
    median ``|residual|`` keeps an exact zero finite)."""
    size = np.abs(residual)
    floor = 1e-3 * max(float(np.median(size)), 1e-12)
    return _fit(scale_basis(u), np.log(size + floor))


def _scaled(values: np.ndarray, scale: dict) -> np.ndarray:
    centre, half = np.asarray(scale["centre"]), np.asarray(scale["half_width"])
    return (values - centre) / half


def _fit(design: np.ndarray, error: np.ndarray) -> np.ndarray:
    coefficients, *_ = np.linalg.lstsq(design, error, rcond=None)
    return coefficients


def _interval_nodes(x: np.ndarray, residual: np.ndarray, nodes: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The 5 % and 95 % quantiles of the residuals in each third of the load range."""
    edges = np.concatenate([[-np.inf], 0.5 * (nodes[1:] + nodes[:-1]), [np.inf]])
    tail = (1 - PREDICTION_LEVEL) / 2
    low, high = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        part = residual[(x >= a) & (x < b)]
        low.append(float(np.quantile(part, tail)))
        high.append(float(np.quantile(part, 1 - tail)))
    return np.array(low), np.array(high)


def _leave_out_residuals(design: np.ndarray, error: np.ndarray, groups: np.ndarray
                         ) -> np.ndarray:
    """Each row's residual from the fit without its design point."""
    residual = np.empty_like(error)
    for group in np.unique(groups):
        out = groups == group
        residual[out] = error[out] - design[out] @ _fit(design[~out], error[~out])
    return residual


def fit_entry(u: np.ndarray, error: np.ndarray, groups: np.ndarray,
              kinds: np.ndarray | None = None) -> dict:
    """One model's, frame's and quantity's fit: coefficients, the scale's coefficients, interval
    nodes, rows used. ``kinds`` (per row, the kind of surface): the interval's quantiles are
    the widest of each kind's, so that it covers each kind and not only the most numerous."""
    keep = np.all(np.isfinite(u), axis=1) & np.isfinite(error)
    u, error, groups = u[keep], error[keep], groups[keep]
    kinds = np.zeros(error.size, dtype=int) if kinds is None else np.asarray(kinds)[keep]
    design = basis(u)
    residual = _leave_out_residuals(design, error, groups)
    spread = _scale_fit(u, residual)
    nodes = np.linspace(-1, 1, 2 * _THIRDS + 1)[1::2]
    scaled = residual / np.exp(scale_basis(u) @ spread)
    bounds = [_interval_nodes(u[kinds == k, 3], scaled[kinds == k], nodes)
              for k in np.unique(kinds)]
    low = np.min([b[0] for b in bounds], axis=0)
    high = np.max([b[1] for b in bounds], axis=0)
    return {"coefficients": _fit(design, error).tolist(), "spread": spread.tolist(),
            "x_nodes": nodes.tolist(), "low": low.tolist(), "high": high.tolist(),
            "rows": int(error.size), "leave_out_rms": float(np.sqrt(np.mean(residual ** 2)))}


def scale_of(values: np.ndarray) -> dict:
    """Centre and half-width of each covariate over the atlas (columns of ``values``)."""
    low, high = np.nanmin(values, axis=0), np.nanmax(values, axis=0)
    return {"centre": ((low + high) / 2).tolist(),
            "half_width": np.maximum((high - low) / 2, 1e-12).tolist()}


def fit_error_model(covariates: np.ndarray, keys: np.ndarray, error: np.ndarray,
                    groups: np.ndarray, *, kinds: np.ndarray | None = None,
                    meta: dict | None = None) -> dict:
    """The error model of an atlas.

    Parameters
    ----------
    covariates : numpy.ndarray
        Per row (realization and load): H, log10 alpha, skewness, log10 p/(E* h'_rms), shape
        (rows, 4).
    keys : numpy.ndarray of str
        Per row, ``"model/frame/quantity"``.
    error : numpy.ndarray
        Per row, the model's relative error (NaN where not compared).
    groups : numpy.ndarray
        Per row, its design point (left out together).
    kinds : numpy.ndarray, optional
        Per row, its kind of surface (:func:`fit_entry`: the interval covers each kind).
    meta : dict, optional
        Stored with the model (atlas commit, grid, ranges, validation, ...).
    """
    covariates = np.asarray(covariates, dtype=float)
    scale = scale_of(covariates)
    u = _scaled(covariates, scale)
    entries = {str(key): fit_entry(u[keys == key], error[keys == key], groups[keys == key],
                                   None if kinds is None else np.asarray(kinds)[keys == key])
               for key in np.unique(keys)}
    return {"version": MODEL_VERSION, "covariates": list(COVARIATES), "scale": scale,
            "level": PREDICTION_LEVEL, "entries": entries, **(meta or {})}


def predict_mean(model: dict, key: str, covariates: np.ndarray) -> np.ndarray:
    """The fitted mean error of ``key`` at ``covariates`` (rows, 4)."""
    u = _scaled(np.atleast_2d(np.asarray(covariates, dtype=float)), model["scale"])
    return basis(u) @ np.asarray(model["entries"][key]["coefficients"])


def interval_of(model: dict, key: str, covariates: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mean, low, high): the fitted error and its 90 % prediction interval at ``covariates``."""
    entry = model["entries"][key]
    mean = predict_mean(model, key, covariates)
    u = _scaled(np.atleast_2d(np.asarray(covariates, dtype=float)), model["scale"])
    size = np.exp(scale_basis(u) @ np.asarray(entry["spread"]))
    low = np.interp(u[:, 3], entry["x_nodes"], entry["low"])
    high = np.interp(u[:, 3], entry["x_nodes"], entry["high"])
    return mean, mean + size * low, mean + size * high


def verdict_of(low: np.ndarray, high: np.ndarray, tolerance: float) -> np.ndarray:
    """"holds" where the whole interval is within the tolerance, "fails" where it is wholly
    beyond it, "undecided" otherwise."""
    low, high = np.asarray(low), np.asarray(high)
    holds = (np.abs(low) <= tolerance) & (np.abs(high) <= tolerance)
    fails = (low > tolerance) | (high < -tolerance)
    return np.where(holds, "holds", np.where(fails, "fails", "undecided"))


@lru_cache(maxsize=2)
def _read(path: str) -> str:
    return pathlib.Path(path).read_text(encoding="utf-8")


def load_error_model(path: str | pathlib.Path | None = None) -> dict:
    """The stored error model (:data:`MODEL_FILE` by default).

    Raises
    ------
    ValueError
        For a file of another layout version.
    """
    model = json.loads(_read(str(MODEL_FILE if path is None else path)))
    if model.get("version") != MODEL_VERSION:
        raise ValueError(f"error model {path or MODEL_FILE} has layout version "
                         f"{model.get('version')!r}; this program reads {MODEL_VERSION}")
    return model
