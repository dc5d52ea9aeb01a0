"""The error atlas computed: every design point's scene run as any report's (cached and
resumable: an interrupted build resumes from the cache), each theory's error per realization,
quantity and load written as one table, ``atlas.csv`` (:data:`COLUMNS`).
"""

from __future__ import annotations

import csv
import json
import pathlib
import subprocess
import time

import numpy as np

from validation.atlas.design import ATLAS_QUANTITIES, ATLAS_SLOPE, DesignPoint, atlas_design, \
    atlas_scene

__all__ = ["COLUMNS", "atlas_rows", "build_atlas", "git_commit", "read_atlas"]

#: Columns of ``atlas.csv``: the design point and realization (seed), the model, frame and
#: quantity, the load point, Load = p / E*, p / (E* h'_rms), the reference's contact-area
#: fraction on that realization, the model's relative error and the reference band there.
COLUMNS = ("point", "seed", "model", "frame", "quantity", "k", "Load", "load_ratio",
           "area_fraction", "error", "band")


def atlas_rows(point: DesignPoint, result) -> list[tuple]:
    """The rows of :data:`COLUMNS` of one design point's scene result."""
    from validation.judge.analysis import analyse

    comparison = analyse(result).comparisons[0]
    seeds = [r.task.seed for r in result.realizations[comparison.value]]
    rows = []
    for (model, quantity), e in comparison.models.items():
        if quantity not in ATLAS_QUANTITIES or e.errors is None:
            continue
        paths = comparison.paths_of(e.frame)
        band = np.full(comparison.load.shape, np.nan) if e.band is None else e.band
        for i, seed in enumerate(seeds):
            for k, load in enumerate(comparison.load):
                rows.append((point.index, seed, model, e.frame, quantity, k, float(load),
                             float(load) / ATLAS_SLOPE, float(paths[i, k]),
                             float(e.errors[i, k]), float(band[k])))
    return rows


def git_commit() -> str:
    """The commit of the working tree the atlas was computed with ("" outside git)."""
    try:
        return subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                              cwd=pathlib.Path(__file__).parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def build_atlas(out: str | pathlib.Path, *, cache_dir: str | None, executor=None,
                points: tuple[DesignPoint, ...] | None = None, n: int | None = None,
                realizations: int | None = None, progress: bool = False) -> pathlib.Path:
    """Run every design point's scene and write ``atlas.csv`` and ``atlas.json`` (the design,
    the grid, the commit, the computing time) into ``out``; returns the CSV's path.

    Parameters
    ----------
    out : path
        Output folder (made if missing).
    cache_dir : str or None
        The run cache (what is there is not computed again); None: no cache.
    executor : concurrent.futures.Executor, optional
        Where the realizations run.
    points : tuple of DesignPoint, optional
        Default: :func:`validation.atlas.design.atlas_design`.
    n, realizations : int, optional
        Grid and realizations per point (default those of :mod:`.design`).
    """
    from validation.judge.decide import run_scenes

    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    points = atlas_design() if points is None else points
    keywords = {k: v for k, v in (("n", n), ("realizations", realizations)) if v is not None}
    start, rows = time.perf_counter(), []
    for point in points:
        scene = atlas_scene(point, **keywords)
        (result,) = run_scenes([scene], executor=executor, cache_dir=cache_dir,
                               progress=progress)
        rows += atlas_rows(point, result)
        if progress:
            print(f"atlas: {point.name} done ({time.perf_counter() - start:.0f} s)", flush=True)
    path = out / "atlas.csv"
    with open(path, "w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(COLUMNS)
        writer.writerows(rows)
    scene = atlas_scene(points[0], **keywords)
    meta = {"commit": git_commit(), "seconds": time.perf_counter() - start,
            "n": scene.surface.n, "realizations": scene.realizations,
            "points": [dict(index=p.index, hurst=p.hurst, magnification=p.magnification,
                            plateau=p.plateau, family=p.family) for p in points]}
    (out / "atlas.json").write_text(json.dumps(meta, indent=1), encoding="utf-8")
    return path


def read_atlas(path: str | pathlib.Path) -> dict[str, np.ndarray]:
    """``atlas.csv`` as columns (numbers as float arrays, names as string arrays)."""
    with open(path, newline="", encoding="utf-8") as stream:
        reader = csv.reader(stream)
        header = next(reader)
        data = list(zip(*reader))
    text = {"model", "frame", "quantity"}
    return {name: np.array(values, dtype=str if name in text else float)
            for name, values in zip(header, data)}
