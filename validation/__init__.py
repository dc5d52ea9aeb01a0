"""Validation of asperity contact theories against full boundary-element contact mechanics.

Weierstrass-Mandelbrot surfaces, declarative scenes, a runner that computes only what a scene
asks for, and reports of where each asperity model holds against the exact half-space solution.
"""

from importlib import metadata as _metadata

from validation.surfaces import SurfaceStatistics, surface_statistics, wm_amplitude, wm_surface

try:
    __version__ = _metadata.version("asperity-validation")
except _metadata.PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+source"

__all__ = ["wm_surface", "wm_amplitude", "surface_statistics", "SurfaceStatistics",
           "__version__"]
