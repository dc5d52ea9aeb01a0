"""Write the example measured-topography file ``example_topography.txt`` (Gwyddion ASCII).

A stand-in for an AFM scan that the project makes itself: a 128 x 128 self-affine height map
(Hurst exponent 0.8, rolloff at 2.5 µm, rms slope 0.1) over a 10 µm x 10 µm window cut from
a larger periodic surface, so its edges do not match, as on a real scan; a small sample tilt is
added, which ``read_topography``'s plane detrend removes. Heights are written in metres and
the window size in µm, as Gwyddion's "ASCII data matrix" export does.

Run it with the project installed (``pip install -e .``), or from the repository root with
``PYTHONPATH=. python examples/make_example_topography.py``; the output is the same on every
machine up to the last printed digit (numpy's seeded generator).
"""

from __future__ import annotations

import pathlib

import numpy as np

from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.topography import write_gwyddion_ascii

N = 128                 # grid points per side
SIZE_UM = 10.0          # scan size [µm]
TILT = (2e-3, -1e-3)    # sample tilt along x and y [-]


def example_heights() -> tuple[np.ndarray, float]:
    """Heights [µm] (rows = y, columns = x) and spacing [µm] of the example scan."""
    spacing = SIZE_UM / N
    heights = self_affine_surface(N, hurst=0.8, rms_slope=0.1, L=SIZE_UM, rolloff=2.5,
                                  window=2 * N, seed=2026)
    y, x = np.indices(heights.shape) * spacing
    return heights + TILT[0] * x + TILT[1] * y, spacing


def main(path: pathlib.Path | None = None) -> None:
    """Write the example file (default: ``example_topography.txt`` beside this script)."""
    path = pathlib.Path(__file__).with_name("example_topography.txt") if path is None else path
    heights_um, spacing_um = example_heights()
    write_gwyddion_ascii(path, heights_um * 1e-6, spacing_um * 1e-6, unit="m", size_unit="µm",
                         channel="Height (synthetic self-affine)")
    print(f"wrote {path} ({path.stat().st_size / 1024:.0f} kB)")


if __name__ == "__main__":
    main()
