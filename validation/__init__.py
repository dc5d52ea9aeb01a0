"""Validation of asperity contact theories against full boundary-element contact mechanics.

Weierstrass-Mandelbrot surfaces, declarative scenes, a runner that computes only what a scene
asks for, and reports of where each asperity model holds against the exact half-space solution.

Its sub-packages are layers, in the order data flows; each imports only itself and the layers
below it (``tests/test_import_layers.py``):

* :mod:`~validation.common` -- what every layer shares: the model registry, names and labels of
  models and quantities, the scene field checks, the verdict names;
* :mod:`~validation.surfaces` -- height maps (WM, self-affine, measured) and a scene's ``[surface]``;
* :mod:`~validation.scenes` -- scene files read into frozen scenes;
* :mod:`~validation.run` -- realizations computed and cached over an executor, finer reference
  solves, the plan of looks;
* :mod:`~validation.judge` -- errors against the reference, verdicts, findings, and where
  verdicts stay open, more work asked of the run (:func:`~validation.judge.decide.run_scenes`);
* :mod:`~validation.report` -- Markdown, figures and CSV tables;
* :mod:`~validation.check` -- one measured scan checked: :func:`check_scan` and its result;
* :mod:`~validation.atlas` -- each theory's error predicted from a scan's descriptors by the
  error atlas, no solve: :func:`predict_errors`;
* the top: :mod:`validation.cli`, :mod:`~validation.campaigns` and this package's public names.
"""

from validation._version import __version__
from validation.surfaces.statistics import SurfaceStatistics, surface_statistics
from validation.surfaces.wm import wm_amplitude, wm_surface
from validation.surfaces.self_affine import radial_power_spectrum, self_affine_surface
from validation.surfaces.topography import Topography, read_topography
from validation.surfaces.cutoff import short_wavelength_cutoff
from validation.surfaces.descriptors import SurfaceDescriptors, surface_descriptors
from validation.scenes.scene import Scene, SceneError
from validation.scenes.reader import builtin_scenes, load_scene, parse_scene
from validation.judge.compare import compare_realizations, curve_errors, validity_range
from validation.judge.decide import run_scenes
from validation.check.library import check_scan
from validation.check.result import CheckResult
from validation.atlas.predict import Prediction, predict_errors

__all__ = ["wm_surface", "wm_amplitude", "surface_statistics", "SurfaceStatistics",
           "Scene", "SceneError", "builtin_scenes", "load_scene", "parse_scene", "run_scenes",
           "compare_realizations", "curve_errors", "validity_range", "write_report", "__version__",
           "self_affine_surface", "radial_power_spectrum", "read_topography", "Topography",
           "short_wavelength_cutoff", "check_scan", "CheckResult", "surface_descriptors",
           "SurfaceDescriptors", "predict_errors", "Prediction"]


def write_report(*args, **kwargs):
    """Write the report folder (see :func:`validation.report.write.write_report`; imports matplotlib)."""
    from validation.report.write import write_report as write

    return write(*args, **kwargs)
