"""The atlas' prediction against the check, on scans the atlas never saw.

Each scan is predicted (:func:`validation.atlas.predict.predict_request`, no solve) and checked
(:func:`validation.check_scan`, the solve) with the same options; per scan and in all, over the
cells the check judges in the interface frame and the atlas covers: the share of solved errors
inside the predicted 90 % interval (coverage), and of the cells both decide at tolerance 0.2,
the share with the same verdict (agreement). Scans the atlas leaves out say which descriptor.

The default scans: three synthetic ones (a non-periodic window of a self-affine surface with
its rolloff inside, H = 0.75; a periodic WM surface, D = 2.3, n_max 7, seed 321, read as a
scan (not known to be periodic) with a 16-pixel cutoff at its shortest wave; the
check benchmark's noisy window, H = 0.8, with a 4-pixel cutoff that brings its magnification
inside the atlas) and, where ``--scans`` names a folder holding them, the instrument files
``opd-1.opd`` (Wyko, ``--fill interpolate``) and ``metropro-1.dat`` (with a 6-pixel cutoff).

Usage::

    python benchmarks/predict_against_check.py [--scans DIR] [--cache DIR]
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile
import time

import numpy as np

import validation
from validation.atlas.predict import against_check, predict_request
from validation.check.library import make_request
from validation.surfaces.topography import write_gwyddion_ascii


def synthetic_scans(folder: pathlib.Path) -> list[tuple[str, str, dict]]:
    """(label, path, check options) of the synthetic scans, written into ``folder``."""
    window = validation.self_affine_surface(256, hurst=0.75, rms_slope=0.1, L=256.0,
                                            rolloff=0.2 * 512, window=512, seed=778)
    wm = validation.wm_surface(256, D=2.3, rms_slope=0.1, L=256.0, n_max=7, periodic=True,
                               seed=321)
    noisy = validation.self_affine_surface(512, hurst=0.8, rms_slope=0.3, L=512.0,
                                           window=1024, seed=1)
    noisy = noisy + 0.01 * np.std(noisy) * np.random.default_rng(1).standard_normal(noisy.shape)
    out = []
    # the WM surface's shortest wave is 256 / 1.5^7 = 15 pixels: beyond it the spectrum of a
    # scan read without its period is the window's leakage, so its cutoff is given
    for name, heights, options in (("window-h075", window, {}),
                                   ("wm-d23", wm, {"short_cutoff": "16px"}),
                                   ("noisy-512", noisy, {"short_cutoff": "4px"})):
        path = folder / f"{name}.txt"
        write_gwyddion_ascii(path, heights, spacing=1.0, unit="nm")   # 1 nm pixels
        out.append((name, str(path), options))
    return out


def instrument_scans(folder: pathlib.Path) -> list[tuple[str, str, dict]]:
    """The instrument files found in ``folder``, with their options."""
    known = (("opd-1.opd", {"fill": "interpolate"}), ("metropro-1.dat", {"short_cutoff": "6px"}))
    return [(name, str(folder / name), options) for name, options in known
            if (folder / name).is_file() and (folder / name).stat().st_size > 0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scans", default=None, help="folder with opd-1.opd, metropro-1.dat")
    parser.add_argument("--cache", default=None, help="run cache (default: a temporary one)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = pathlib.Path(scratch)
        cache = args.cache or str(folder / "cache")
        scans = synthetic_scans(folder)
        scans += instrument_scans(pathlib.Path(args.scans)) if args.scans else []
        total = np.zeros(4, dtype=int)
        print("| scan | inside the atlas | cells | inside the 90 % interval | both decide | "
              "agree | check [s] |\n|---|---|---|---|---|---|---|")
        for label, path, options in scans:
            request = make_request(path, cache_dir=cache, **options)
            prediction = predict_request(request)
            if prediction.outside:
                print(f"| {label} | no: {'; '.join(prediction.outside)} | | | | | |", flush=True)
                continue
            start = time.perf_counter()
            result = validation.check_scan(path, cache=cache, **options)
            seconds = time.perf_counter() - start
            compared = against_check(prediction, result)
            counts = np.array([compared.cells, compared.inside, compared.decided,
                               compared.agree])
            total += counts
            print(f"| {label} | yes | {counts[0]} | {counts[1]} ({100 * compared.coverage:.0f} %)"
                  f" | {counts[2]} | {counts[3]} ({100 * compared.agreement:.0f} %) | "
                  f"{seconds:.0f} |", flush=True)
        cells, inside, decided, agree = total
        print(f"| **all** | | {cells} | {inside} ({100 * inside / max(cells, 1):.1f} %) | "
              f"{decided} | {agree} ({100 * agree / max(decided, 1):.1f} %) | |")


if __name__ == "__main__":
    main()
